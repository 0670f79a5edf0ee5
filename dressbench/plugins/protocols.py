"""What a plugin is: the three interfaces third-party packages implement.

A plugin registers a *class* (or any zero-argument factory) under an entry point of group
``dressbench.robots``, ``dressbench.humans`` or ``dressbench.profiles``. dressbench calls it once
per environment to get a fresh instance, so instances may keep per-episode state. Every
interface carries an integer ``api_version`` that dressbench checks on load.
"""

from __future__ import annotations

from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

from ..scene.body import N_ACTIONS, BodyLimits
from ..scene.clock import POLICY_DT

ROBOT_API_VERSION = 1
HUMAN_API_VERSION = 1
PROFILE_API_VERSION = 1
ROBOT_MAX_SPEED = 0.1  # m/s: the gripper speed a robot action of 1 means
ROBOT_DT = POLICY_DT  # s: one policy step, over which a robot action is applied
ROBOT_ACTION_SIZE = 3  # the gripper's velocity
HUMAN_ACTION_SIZE = N_ACTIONS  # PD targets (or torques) of the human's actuated joints
# The robot's observation, block by block in order (sizes): where each lies is derived from them
ROBOT_OBS_BLOCKS = (
    ("gripper_position", 3), ("gripper_velocity", 3), ("time", 1), ("gripper_force", 3),
    ("fingertip", 3), ("wrist", 3), ("elbow", 3), ("shoulder", 3),  # the right arm's points
)  # fmt: skip
_ENDS = np.cumsum([size for _, size in ROBOT_OBS_BLOCKS]).tolist()
ROBOT_OBS = {name: slice(end - size, end)
             for (name, size), end in zip(ROBOT_OBS_BLOCKS, _ENDS, strict=True)}  # fmt: skip
ROBOT_OBS_SIZE = _ENDS[-1]
OBS_TIME = ROBOT_OBS["time"].start  # index of the time (s) in the robot's observation
ROBOT_GROUP = "dressbench.robots"
HUMAN_GROUP = "dressbench.humans"
PROFILE_GROUP = "dressbench.profiles"
TYPICAL_PROFILE = "typical"  # the body as scene/body.py plans it: every env's default profile


@runtime_checkable
class RobotStrategy(Protocol):
    """Where the gripper holds the gown at the start, and how it moves it.

    Poses are ``(x, y, z, qx, qy, qz, qw)`` in the human's frame (x forward, y to the human's
    left, z up; metres). The identity rotation presents the armhole to the human with the
    sleeve pointing away along +x. The robot's observation and action are documented in
    ``docs/env.md``: the action is the gripper's velocity, 3 numbers in [-1, 1] times
    ``ROBOT_MAX_SPEED`` metres per second.
    """

    api_version: ClassVar[int]

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        """Sample an episode from ``rng``; return the initial gripper pose, shape (7,)."""
        ...

    def act(self, observation: np.ndarray) -> np.ndarray:
        """The robot action for a robot observation, shape (3,)."""
        ...


@runtime_checkable
class HumanPolicy(Protocol):
    """A human model: an action in [-1, 1]^11 for each human observation.

    ``robot`` and ``ablation`` name the strategy and ablation it was trained for (``robot`` is
    None for a policy meant for any strategy). ``actuation`` says how its actions drive its
    joints (``scene.actuation.ACTUATIONS``); a human without the attribute acts by "pd"
    (``contract.DEFAULT_ACTUATION``). Every env that runs a human is built with both
    (``factory.make_human_env(robot, human=...)``).
    """

    api_version: ClassVar[int]
    robot: str | None
    ablation: str
    # ``actuation: str`` and ``profile: str | None`` are optional, so not members: isinstance
    # holds for humans without them

    def reset(self, seed: int | None = None) -> None:
        """Start an episode; stochastic policies reseed from ``seed``."""
        ...

    def act(self, observation: np.ndarray) -> np.ndarray:
        """The human action for a human observation, shape (11,)."""
        ...


@runtime_checkable
class CapabilityProfile(Protocol):
    """How one person's body differs from the typical one: range of motion, strength and
    involuntary motion (docs/profiles.md).

    ``body`` narrows the typical body's joint ranges and torque caps; ``involuntary`` draws an
    episode's involuntary joint accelerations from the env's generator. A profile only
    describes the body: the physics applies it, the policy still chooses every voluntary action.
    """

    api_version: ClassVar[int]

    def body(self, typical: BodyLimits) -> BodyLimits:
        """The person's ranges and torque caps, given the typical body's (``typical.rest`` is the
        rest pose, which the ranges must keep); every range within the typical one, every cap
        above 0 and at most the typical one."""
        ...

    def involuntary(self, rng: np.random.Generator, frames: int, dt: float) -> np.ndarray | None:
        """Involuntary joint accelerations (rad/s^2) for the ``frames`` simulation steps of
        ``dt`` seconds of one episode, shape (frames, N_DOFS), drawn from ``rng`` only; None
        for none."""
        ...
