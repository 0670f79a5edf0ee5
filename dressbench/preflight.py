"""What a plugin must pass before an evaluation runs it: one ``reset`` and one ``act`` in a real
(small) env, and a policy's metadata against the observation it will get.

``dressbench plugins`` only checks that a plugin imports and has the protocol's names; a robot
whose ``reset`` returns a (6,) pose, or a policy file whose ``obs_dim`` contradicts its
ablation, passes that and would abort a leaderboard in a worker. These checks run in the
calling process first, so that ``leaderboard`` skips such plugins with one line each and
``evaluate`` refuses them with one line.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .plugins import load_robot
from .plugins.protocols import HUMAN_ACTION_SIZE
from .plugins.registry import _one_line

CHECK_VERTICES = 300  # the gown of the check's env: coarse, the check is about interfaces
CHECK_HORIZON = 2
CHECK_SEED = 0


def robot_problem(name: str) -> str | None:
    """Why the robot strategy ``name`` cannot be evaluated, or None: a fresh instance's start
    pose for seed 0 (``start_pose_problem``), then one ``act`` on the robot observation of a
    real env, and one env step with that action."""
    from .config import EnvConfig  # here: it loads the physics
    from .env import HUMAN, ROBOT, DressingEnv, robot_action_problem, start_pose_problem
    from .factory import robot_origin

    try:
        robot = load_robot(name)
        problem = start_pose_problem(robot.reset(np.random.default_rng(CHECK_SEED)))
        if problem:
            return problem
        config = EnvConfig(gown_vertices=CHECK_VERTICES, horizon=CHECK_HORIZON)
        env = DressingEnv(robot, config, robot_name=name, robot_origin=robot_origin(name))
        observations, _ = env.reset(seed=CHECK_SEED)
        action = robot.act(observations[ROBOT])
        problem = robot_action_problem(action)
        if problem:
            return problem
        env.step({ROBOT: np.asarray(action, dtype=float), HUMAN: np.zeros(HUMAN_ACTION_SIZE)})
    except Exception as exc:  # a plugin may raise anything; say what, in one line
        return f"its check (one reset and one act) failed: {_one_line(exc)}"
    return None


def human_metadata_problem(policy: Any) -> str | None:
    """Why a human policy's declared metadata cannot be right, or None: ``ablation`` one of
    ABLATIONS, ``robot`` None or a name, and ``obs_dim`` (when it has one, as a trained policy
    does) the length of that ablation's observation."""
    from .observation import ABLATIONS, observation_size

    ablation = getattr(policy, "ablation", None)
    if not isinstance(ablation, str) or ablation not in ABLATIONS:
        return f"it declares ablation {ablation!r}; expected one of {', '.join(ABLATIONS)}"
    robot = getattr(policy, "robot", None)
    if robot is not None and not isinstance(robot, str):
        return f"it declares robot {robot!r}; expected a robot strategy name or None"
    obs_dim = getattr(policy, "obs_dim", None)
    size = observation_size(ablation)
    if obs_dim is not None and obs_dim != size:
        return (
            f"its obs_dim is {obs_dim}, but ablation {ablation!r} observes {size} numbers "
            "(the file's ablation does not match the network)"
        )
    return None


def human_problem(policy: Any, observation: np.ndarray) -> str | None:
    """Why a human policy cannot be evaluated, or None: its metadata (``human_metadata_problem``),
    then ``reset(0)`` and one ``act`` on ``observation`` (a real one, of its ablation), which
    must return HUMAN_ACTION_SIZE finite numbers."""
    problem = human_metadata_problem(policy)
    if problem:
        return problem
    try:
        policy.reset(CHECK_SEED)
        action = np.asarray(policy.act(observation), dtype=float)
    except Exception as exc:
        return (
            f"act failed on a {policy.ablation!r} observation of {observation.size} numbers: "
            f"{_one_line(exc)}"
        )
    if action.shape != (HUMAN_ACTION_SIZE,):
        return f"act returned an action of shape {action.shape}, expected ({HUMAN_ACTION_SIZE},)"
    if not np.isfinite(action).all():
        return "act returned a non-finite action"
    return None


class Observations:
    """A real human observation of each ablation, from one small env per ablation with a robot
    that passed ``robot_problem`` (the observation's length depends only on the ablation)."""

    def __init__(self, robot: str) -> None:
        self.robot = robot
        self._cache: dict[str, np.ndarray] = {}

    def __call__(self, ablation: str) -> np.ndarray:
        if ablation not in self._cache:
            from .factory import make_human_env

            env = make_human_env(
                self.robot, ablation=ablation, gown_vertices=CHECK_VERTICES, horizon=CHECK_HORIZON
            )
            self._cache[ablation], _ = env.reset(seed=CHECK_SEED)
        return self._cache[ablation]
