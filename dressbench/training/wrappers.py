"""Gymnasium wrappers a training env gets between the human env and the learner."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ..observation import check_haptic_scale, scale_haptics


class ScaledHaptics(gym.ObservationWrapper):
    """The observation with its haptic forces on ``scale`` (see ``observation.scale_haptics``);
    the exported policy records the scale and applies it itself when it acts."""

    def __init__(self, env: gym.Env, ablation: str, scale: str) -> None:
        super().__init__(env)
        check_haptic_scale(scale)
        self.ablation = ablation
        self.scale = scale

    def observation(self, observation: np.ndarray) -> np.ndarray:
        return scale_haptics(observation, self.ablation, self.scale)
