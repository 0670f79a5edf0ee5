"""A torn gown ends the episode: training episodes stop where the gown's max area ratio passes a
limit (by default the deformation threshold itself), so forcing the gown costs the human the rest
of its dressing, not a few steps of r_d.

r_d saturates (its tanh is flat beyond a ratio of about 3.5 with dressbench's calibration), and
the hand forcing the opening lasts a few of 400 steps, so on the paper's reward alone pushing
through pays (docs/training.md, "Where the deformation comes from"). Clegg et al.'s own code
ends an episode above a ratio of 20, about where their r_d saturates. The limit is a rule of
training only: evaluation always runs whole episodes and scores the deformation they reach.
"""

from __future__ import annotations

from dataclasses import dataclass

import gymnasium as gym

from ..config import RewardConfig


@dataclass(frozen=True)
class TearConfig:
    """Where a training episode counts the gown as torn."""

    # max area ratio; the default is the deformation threshold (2.02: r_d = -0.1), the line a
    # careful human stays under (docs/experiments/2026-12-02-tear-limit-at-threshold.md)
    ratio: float = RewardConfig().limit

    def __post_init__(self) -> None:
        if not self.ratio > 1.0:
            raise ValueError(f"the tear limit is an area ratio above 1, got {self.ratio}")


class TornGown(gym.Wrapper):
    """Ends an episode (``terminated``) at the step its max area ratio passes ``ratio``, once
    the deformation term has its full weight (the warm-up's end, if the env has one);
    ``info["torn"]`` says whether it did."""

    def __init__(self, env: gym.Env, config: TearConfig) -> None:
        super().__init__(env)
        self.config = config

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        torn = (
            not info.get("sim_failure", False)
            and info.get("max_deformation", 0.0) > self.config.ratio
            and self._deformation_counts()
        )
        return observation, reward, terminated or torn, truncated, info | {"torn": float(torn)}

    def _deformation_counts(self) -> bool:
        try:
            return self.env.get_wrapper_attr("share") >= 1.0
        except AttributeError:  # no warm-up: r_d counts from the first step
            return True
