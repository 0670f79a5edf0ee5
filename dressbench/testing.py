"""Checks for plugin authors: does a robot strategy, human policy or capability profile keep the
protocol?

    from dressbench.testing import check_human_plugin, check_profile_plugin, check_robot_plugin
    check_robot_plugin("my_robot")        # a registered name, or an instance
    check_human_plugin(MyHuman())
    check_profile_plugin("my_profile")

Each runs the plugin in a small real environment and raises ``AssertionError`` with a message
that says what is wrong: the contract's own (``dressbench.plugins.contract``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .factory import DEFAULT_ROBOT
from .plugins import (
    HUMAN_API_VERSION,
    PROFILE_API_VERSION,
    ROBOT_API_VERSION,
    load_human,
    load_profile,
    load_robot,
)
from .plugins.contract import (
    CHECK_VERTICES,
    api_version_problem,
    human_action_problem,
    human_declaration_problem,
    involuntary_problem,
    profile_limits_problem,
    robot_action_problem,
    start_pose_problem,
)
from .plugins.protocols import HUMAN_ACTION_SIZE
from .scene.body import body_limits
from .scene.clock import FRAME_SKIP, SIM_DT

CHECK_STEPS = 10


def check_robot_plugin(robot: str | Any, steps: int = CHECK_STEPS) -> None:
    """Seeded reset poses, finite unit-quaternion poses inside the workspace, (3,) finite
    actions, a running env."""
    from .factory import make_env

    name = robot if isinstance(robot, str) else type(robot).__name__
    strategy = load_robot(robot) if isinstance(robot, str) else robot
    _require(name, api_version_problem(strategy, ROBOT_API_VERSION))
    poses = [strategy.reset(np.random.default_rng(s)) for s in (0, 0, 1)]
    for pose in poses:
        _require(name, start_pose_problem(pose))
    seeded = np.array_equal(poses[0], poses[1])
    _require(name, None if seeded else "reset must draw only from the rng it is given: one seed "
                                       "gave two poses")  # fmt: skip
    env = make_env(strategy, gown_vertices=CHECK_VERTICES, horizon=steps)
    observations, _ = env.reset(seed=0)
    for _ in range(steps):
        action = strategy.act(observations["robot"])
        _require(name, robot_action_problem(action))
        robot_action = np.asarray(action, dtype=float)
        observations, *_ = env.step({"robot": robot_action, "human": np.zeros(HUMAN_ACTION_SIZE)})


def check_human_plugin(
    human: str | Any, robot: str = DEFAULT_ROBOT, steps: int = CHECK_STEPS
) -> None:
    """What it declares (robot, ablation, actuation), finite actions of the human's size on the
    observation of the env it was made for."""
    from .factory import make_human_env

    name = human if isinstance(human, str) else type(human).__name__
    policy = load_human(human) if isinstance(human, str) else human
    _require(name, api_version_problem(policy, HUMAN_API_VERSION))
    _require(name, human_declaration_problem(policy))
    env = make_human_env(
        policy.robot or robot, human=policy, gown_vertices=CHECK_VERTICES, horizon=steps
    )
    observation, _ = env.reset(seed=0)
    policy.reset(0)
    for _ in range(steps):
        action = policy.act(observation)
        _require(name, human_action_problem(action))
        observation, *_ = env.step(action)


def check_profile_plugin(profile: str | Any, steps: int = CHECK_STEPS) -> None:
    """A body within the typical one, finite involuntary motion of the episode's shape that one
    seed repeats, and a small env with that body running ``steps`` steps."""
    from .config import EnvConfig
    from .env import HUMAN, ROBOT, DressingEnv
    from .plugins.robots import FixedGown

    name = profile if isinstance(profile, str) else type(profile).__name__
    instance = load_profile(profile) if isinstance(profile, str) else profile
    _require(name, api_version_problem(instance, PROFILE_API_VERSION))
    typical = body_limits()
    _require(name, profile_limits_problem(instance.body(typical), typical))
    frames = steps * FRAME_SKIP
    motions = [instance.involuntary(np.random.default_rng(0), frames, SIM_DT) for _ in range(2)]
    _require(name, involuntary_problem(motions[0], frames))
    seeded = (motions[0] is None) == (motions[1] is None) and np.array_equal(*motions)
    _require(name, None if seeded else "involuntary must draw only from the rng it is given: "
                                       "one seed gave two motions")  # fmt: skip
    config = EnvConfig(gown_vertices=CHECK_VERTICES, horizon=steps, profile=name)
    env = DressingEnv(FixedGown(), config, profile=instance)
    env.reset(seed=0)
    for _ in range(steps):
        env.step({ROBOT: np.zeros(3), HUMAN: np.zeros(HUMAN_ACTION_SIZE)})


def _require(name: str, problem: str | None) -> None:
    """Raise ``AssertionError`` with the plugin's name and the contract's problem, if any."""
    if problem:
        raise AssertionError(f"{name}: {problem}")
