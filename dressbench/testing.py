"""Checks for plugin authors: does a robot strategy or human policy keep the protocol?

    from dressbench.testing import check_robot_plugin, check_human_plugin
    check_robot_plugin("my_robot")        # a registered name, or an instance
    check_human_plugin(MyHuman())

Each runs the plugin in a small real environment and raises ``AssertionError`` with a message
that says what is wrong.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .plugins import HUMAN_API_VERSION, ROBOT_API_VERSION, load_human, load_robot
from .plugins.protocols import HUMAN_ACTION_SIZE

CHECK_STEPS = 10
CHECK_VERTICES = 600  # a coarse gown keeps the check fast


def check_robot_plugin(robot: str | Any, steps: int = CHECK_STEPS) -> None:
    """Seeded reset poses, finite unit-quaternion poses inside the workspace, (3,) finite
    actions, a running env."""
    from .env import start_pose_problem
    from .factory import make_env

    name = robot if isinstance(robot, str) else type(robot).__name__
    strategy = load_robot(robot) if isinstance(robot, str) else robot
    _check_version(name, strategy, ROBOT_API_VERSION)
    poses = [np.asarray(strategy.reset(np.random.default_rng(s)), dtype=float) for s in (0, 0, 1)]
    for pose in poses:
        _require(pose.shape == (7,), f"{name}.reset must return a (7,) pose, got {pose.shape}")
        _require(np.isfinite(pose).all(), f"{name}.reset returned a non-finite pose {pose}")
        _require(
            abs(np.linalg.norm(pose[3:]) - 1.0) < 1e-6,
            f"{name}.reset's quaternion (qx, qy, qz, qw) must have unit length, got {pose[3:]}",
        )
        problem = start_pose_problem(pose)  # what the env refuses, the workspace among it
        _require(problem is None, f"{name}.{problem}")
    _require(
        np.array_equal(poses[0], poses[1]),
        f"{name}.reset must draw only from the rng it is given: one seed gave two poses",
    )
    env = make_env(strategy, gown_vertices=CHECK_VERTICES, horizon=steps)
    observations, _ = env.reset(seed=0)
    for _ in range(steps):
        action = np.asarray(strategy.act(observations["robot"]), dtype=float)
        _require(action.shape == (3,), f"{name}.act must return shape (3,), got {action.shape}")
        _require(np.isfinite(action).all(), f"{name}.act returned a non-finite action {action}")
        observations, *_ = env.step({"robot": action, "human": np.zeros(HUMAN_ACTION_SIZE)})


def check_human_plugin(human: str | Any, robot: str = "fixed", steps: int = CHECK_STEPS) -> None:
    """Declared robot and ablation, finite actions of the human's size on the observation it was
    made for."""
    from .factory import make_human_env
    from .observation import ABLATIONS

    name = human if isinstance(human, str) else type(human).__name__
    policy = load_human(human) if isinstance(human, str) else human
    _check_version(name, policy, HUMAN_API_VERSION)
    _require(
        policy.ablation in ABLATIONS,
        f"{name}.ablation must be one of {', '.join(ABLATIONS)}, got {policy.ablation!r}",
    )
    env = make_human_env(
        policy.robot or robot, gown_vertices=CHECK_VERTICES, horizon=steps,
        ablation=policy.ablation,
    )  # fmt: skip
    observation, _ = env.reset(seed=0)
    policy.reset(0)
    for _ in range(steps):
        action = np.asarray(policy.act(observation), dtype=float)
        shape = (HUMAN_ACTION_SIZE,)
        _require(action.shape == shape, f"{name}.act must return shape {shape}, got {action.shape}")
        _require(np.isfinite(action).all(), f"{name}.act returned a non-finite action {action}")
        observation, *_ = env.step(action)


def _check_version(name: str, plugin: Any, expected: int) -> None:
    version = getattr(plugin, "api_version", None)
    _require(version == expected, f"{name}.api_version must be {expected}, got {version!r}")


def _require(condition: bool, message: str) -> None:
    if not condition:
        raise AssertionError(message)
