"""A gymnasium view of the human agent, with the robot driven by its strategy."""

from __future__ import annotations

import copy
from typing import Any

import gymnasium as gym
import numpy as np

from .env import HUMAN, ROBOT, ROBOT_MAX_SPEED, DressingEnv
from .plugins.contract import describe_robot, robot_action_problem


class HumanEnv(gym.Env):
    """The human's side of a ``DressingEnv``: what stable-baselines3 trains on."""

    metadata = DressingEnv.metadata

    def __init__(self, env: DressingEnv) -> None:
        self.env = env
        self.render_mode = env.render_mode
        self.observation_space = env.observation_space(HUMAN)
        self.action_space = env.action_space(HUMAN)
        self._robot_obs: np.ndarray | None = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        observations, infos = self.env.reset(seed=seed, options=options)
        self._robot_obs = observations[ROBOT]
        return observations[HUMAN], infos[HUMAN]

    def robot_next_move(self) -> np.ndarray | None:
        """The gripper velocity (m/s) the robot strategy will command at its next step, asked of
        a copy so the strategy itself is untouched; None if it cannot be copied."""
        try:
            strategy = copy.deepcopy(self.env.robot_strategy)
        except (TypeError, copy.Error):  # e.g. it holds a handle or a lock
            return None
        return np.asarray(strategy.act(self._robot_obs), dtype=float) * ROBOT_MAX_SPEED

    def step(self, action: np.ndarray):
        strategy = self.env.robot_strategy
        robot_action = strategy.act(self._robot_obs)
        problem = robot_action_problem(robot_action)
        if problem:
            robot = describe_robot(strategy, self.env.robot_name, self.env.robot_origin)
            raise ValueError(f"{robot}: {problem}")
        robot_action = np.asarray(robot_action, dtype=float)
        observations, rewards, terminations, truncations, infos = self.env.step(
            {HUMAN: action, ROBOT: robot_action}
        )
        self._robot_obs = observations[ROBOT]
        return (
            observations[HUMAN],
            rewards[HUMAN],
            terminations[HUMAN],
            truncations[HUMAN],
            infos[HUMAN],
        )

    def render(self) -> Any:
        return self.env.render()

    def close(self) -> None:
        self.env.close()
