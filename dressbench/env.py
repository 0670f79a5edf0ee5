"""The two-agent dressing environment (PettingZoo ``ParallelEnv``): a robot and a human.

The robot strategy named at construction samples each episode (where the gripper starts, how
the gown is turned); the robot *agent*'s actions move the gripper. The human agent sees the
paper's observation and earns the paper's reward; the robot shares that reward (cooperative).
Everything is documented in docs/env.md.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from .config import EnvConfig
from .metrics import deformation_reward, geodesic_contact_reward, upright_reward
from .observation import human_observation, observation_size
from .plugins.contract import (
    WORKSPACE,
    describe_profile,
    describe_robot,
    involuntary_problem,
    missing_members,
    profile_limits_problem,
    start_pose_problem,
    step_action_problem,
)
from .plugins.protocols import (
    HUMAN_ACTION_SIZE,
    ROBOT_ACTION_SIZE,
    ROBOT_DT,
    ROBOT_MAX_SPEED,
    ROBOT_OBS_SIZE,
    TYPICAL_PROFILE,
)
from .scene.body import body_limits
from .scene.world import Scene, SceneConfig, limited_scene
from .state import DressingState, measure

HUMAN, ROBOT = "human", "robot"
FAILURE_STEP_REWARD = -17.0  # per remaining step: fingertip 1 m off, deformation maxed


class DressingEnv(ParallelEnv):
    """Robot-assisted dressing with a robot strategy and a human to be trained, whose body is
    that of the capability profile ``profile`` (an instance of the plugin ``config.profile``
    names; None: the typical body, unchanged)."""

    metadata = {
        "name": "dressbench_v0",
        "render_modes": ["rgb_array"],
        "render_fps": round(1 / ROBOT_DT),
    }

    def __init__(
        self,
        robot: Any,
        config: EnvConfig | None = None,
        render_mode: str | None = None,
        *,
        robot_name: str | None = None,
        robot_origin: str | None = None,
        profile: Any | None = None,
        profile_origin: str | None = None,
    ) -> None:
        if missing_members(robot):
            raise TypeError(
                "the robot must be a robot strategy: a plugin name such as 'fixed', or an "
                f"object with reset(rng) and act(observation); got {robot!r}"
            )
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"unknown render_mode {render_mode!r}: use None or 'rgb_array'")
        self.config = config or EnvConfig()
        self.robot_strategy = robot
        self.robot_name = robot_name  # the plugin name it was loaded as, if any: for messages
        self.robot_origin = robot_origin  # and the package that provides it
        self.render_mode = render_mode
        self.possible_agents = [ROBOT, HUMAN]
        self.agents: list[str] = []
        self.profile = profile
        self.profile_origin = profile_origin  # the package that provides it: for messages
        self.scene = Scene(self._profiled(self.config.scene_config()))
        self._rng = np.random.default_rng()
        self._renderer = None
        self._obs: dict[str, np.ndarray] = {}

    # ----------------------------------------------------------------------------- spaces
    @functools.cache  # noqa: B019 - one env, two agents: the same objects
    def observation_space(self, agent: str) -> spaces.Box:
        size = observation_size(self.config.ablation) if agent == HUMAN else ROBOT_OBS_SIZE
        return spaces.Box(-np.inf, np.inf, (size,), np.float32)

    @functools.cache  # noqa: B019
    def action_space(self, agent: str) -> spaces.Box:
        size = HUMAN_ACTION_SIZE if agent == HUMAN else ROBOT_ACTION_SIZE
        return spaces.Box(-1.0, 1.0, (size,), np.float32)

    # ----------------------------------------------------------------------------- episode
    def reset(self, seed: int | None = None, options: dict | None = None):
        """Start an episode. ``options["human_start"]``, if given, is a callable that receives
        the reset scene (the gown held where the robot strategy put it) and returns the human's
        start pose, or None for the rest pose: how a training curriculum starts the hand near
        the opening."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        pose = self.robot_strategy.reset(self._rng)
        problem = start_pose_problem(pose)
        if problem:  # e.g. a zero quaternion would give NaN observations, scored as a failure
            robot = describe_robot(self.robot_strategy, self.robot_name, self.robot_origin)
            raise ValueError(f"{robot}: {problem}")
        pose = np.asarray(pose, dtype=float)
        motion = self._involuntary()
        self.scene.reset(pose, involuntary=motion)
        human_start = (options or {}).get("human_start")
        if human_start is not None:
            q = human_start(self.scene)
            if q is not None:
                self.scene.reset(pose, human_q=q, involuntary=motion)
        self.agents = list(self.possible_agents)
        self._t = 0
        self._gripper_velocity = np.zeros(3)
        self._gripper_force = np.zeros(3)
        self._momentum = self._cloth_momentum()
        state = measure(self.scene)
        self._max_deformation = state.max_area_ratio
        self._obs = self._observe(state)
        info = self._human_info(state, clipped=0)
        return dict(self._obs), {ROBOT: {}, HUMAN: info}

    def step(self, actions: dict[str, np.ndarray]):
        if not self.agents:
            raise RuntimeError("step() called on a finished episode: call reset() first")
        human_action, human_clipped = _checked(actions, HUMAN, HUMAN_ACTION_SIZE)
        robot_action, robot_clipped = _checked(actions, ROBOT, ROBOT_ACTION_SIZE)
        self._gripper_velocity = robot_action * ROBOT_MAX_SPEED
        pose = self.scene.gripper_pose.copy()
        pose[:3] = np.clip(pose[:3] + self._gripper_velocity * ROBOT_DT, *WORKSPACE)
        result = self.scene.step(human_action, pose)
        self._t += 1
        truncated = self._t >= self.config.horizon
        if not result.sim_failure:
            self._gripper_force = self._force_on_gripper()
            state = measure(self.scene)
            observations = self._observe(state)
            if not all(np.isfinite(o).all() for o in observations.values()):
                result = self.scene.fail("non-finite observation")  # never hand a learner inf
        if result.sim_failure:
            reward = FAILURE_STEP_REWARD * (self.config.horizon - self._t + 1)
            human_info = {
                "arm_progress": 0.0,
                "max_deformation": self._max_deformation,
                "contact_force": 0.0,
                "sim_failure": True,
                "failure_reason": result.reason,
                "clipped_actions": human_clipped,
            }
        else:
            self._max_deformation = max(self._max_deformation, state.max_area_ratio)
            terms = self.reward_terms(state)
            reward = float(sum(terms.values()))
            self._obs = observations
            human_info = self._human_info(state, human_clipped) | {"reward_terms": terms}
        terminated = result.sim_failure
        rewards = {ROBOT: reward, HUMAN: reward}
        terminations = {a: terminated for a in self.agents}
        truncations = {a: truncated and not terminated for a in self.agents}
        infos = {
            ROBOT: {"clipped_actions": robot_clipped, "sim_failure": result.sim_failure},
            HUMAN: human_info,
        }
        observations = dict(self._obs)
        if terminated or truncated:
            self.agents = []
        return observations, rewards, terminations, truncations, infos

    # ----------------------------------------------------------------------------- profile
    def _profiled(self, scene: SceneConfig) -> SceneConfig:
        """``scene`` with the human's ranges and torque caps those of the profile's body."""
        if self.profile is None:
            if self.config.profile != TYPICAL_PROFILE:
                raise ValueError(
                    f"the env's profile is {self.config.profile!r}, but no instance of it was "
                    "given: make the env with dressbench.make_env, which loads the plugin"
                )
            return scene
        typical = body_limits(scene.human.specs)
        limits = self.profile.body(typical)
        self._require(profile_limits_problem(limits, typical))
        return limited_scene(limits, scene)

    def _involuntary(self) -> np.ndarray | None:
        """The episode's involuntary joint accelerations, drawn by the profile from the env's
        generator (after the robot strategy's draws), or None."""
        if self.profile is None:
            return None
        frames = self.config.horizon * self.scene.config.frame_skip
        motion = self.profile.involuntary(self._rng, frames, self.scene.config.dt)
        self._require(involuntary_problem(motion, frames))
        return None if motion is None else np.asarray(motion, dtype=float)

    def _require(self, problem: str | None) -> None:
        """Raise the profile's contract ``problem``, if any, as a ValueError naming it."""
        if problem:
            raise ValueError(f"{describe_profile(self.config.profile, self.profile_origin)}: "
                             f"{problem}")  # fmt: skip

    # ----------------------------------------------------------------------------- reward
    def reward_terms(self, state: DressingState) -> dict[str, float]:
        """The weighted reward terms of a state (paper §III-B); they sum to the reward."""
        w = self.config.reward
        terms = {
            "progress": w.progress * state.progress_reward,
            "geodesic": w.geodesic
            * geodesic_contact_reward(
                state.containment.contained, state.effector_contacts, self.scene.gown.geodesic
            ),
            "upright": w.upright * upright_reward(state.torso_up),
        }
        if self.config.ablation != "no_haptics":
            terms["deformation"] = w.deformation * deformation_reward(
                state.max_area_ratio, w.deformation_threshold, w.deformation_scale
            )
        return terms

    # ----------------------------------------------------------------------------- observations
    def _observe(self, state: DressingState) -> dict[str, np.ndarray]:
        human = human_observation(self.scene, state, self.config.ablation)
        robot = np.concatenate(
            [
                self.scene.gripper_pose[:3],
                self._gripper_velocity,
                [self._t * ROBOT_DT],
                self._gripper_force,
                state.joints.ravel(),
            ]
        ).astype(np.float32)
        return {ROBOT: robot, HUMAN: human}

    def _human_info(self, state: DressingState, clipped: int) -> dict[str, Any]:
        return {
            "arm_progress": state.arm_progress,
            "max_deformation": self._max_deformation,
            "contact_force": float(np.linalg.norm(self.scene.contact_force)),
            "sim_failure": False,
            "clipped_actions": clipped,
        }

    def _cloth_momentum(self) -> np.ndarray:
        return self.scene.gown.masses @ self.scene.cloth.velocities()

    def _force_on_gripper(self) -> np.ndarray:
        """Newton on the whole gown: what the gripper must supply besides gravity and the body."""
        momentum = self._cloth_momentum()
        rate = (momentum - self._momentum) / ROBOT_DT
        self._momentum = momentum
        gravity = self.scene.gown.masses.sum() * np.asarray(self.scene.config.cloth.gravity)
        on_cloth_by_gripper = rate - gravity + self.scene.contact_force
        return -on_cloth_by_gripper

    # ----------------------------------------------------------------------------- render
    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            return None
        if self._renderer is None:
            from .render import Renderer

            self._renderer = Renderer()
        return self._renderer.render(self.scene, caption=f"t = {self._t * ROBOT_DT:.2f} s")

    def close(self) -> None:
        self._renderer = None

    def state(self) -> np.ndarray:
        """The full cloth state (vertex positions), for agents that want more than O."""
        return self.scene.cloth_positions()


def _checked(actions: dict[str, np.ndarray], agent: str, size: int) -> tuple[np.ndarray, int]:
    """Validate an agent's action: the right shape and finite, else ValueError; clip to range."""
    if agent not in actions:
        raise ValueError(f"missing action for agent {agent!r}")
    problem = step_action_problem(agent, actions[agent], size)
    if problem:
        raise ValueError(problem)
    a = np.asarray(actions[agent], dtype=float)
    clipped = int(np.count_nonzero(np.abs(a) > 1.0))
    return np.clip(a, -1.0, 1.0), clipped
