"""A warm-up of the deformation term: the human first learns to get its arm in, then to do it
gently, while the reward grows into the paper's.

Early in training a policy that touches the gown is punished by r_d before it has found the
opening, and learns to keep away from the cloth (docs/training.md). The warm-up leaves r_d out
until ``start`` environment steps and brings it in linearly to its full weight at ``end``; from
there on the policy trains on the paper's reward, unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import gymnasium as gym
import numpy as np


@dataclass(frozen=True)
class WarmupConfig:
    """When the deformation term comes in, in environment steps of the whole run."""

    start: int = 250_000  # until here r_d counts for nothing
    end: int = 500_000  # from here r_d has its full weight

    def __post_init__(self) -> None:
        if not 0 <= self.start <= self.end:
            raise ValueError(f"need 0 <= start <= end, got {self.start} and {self.end}")

    def share(self, steps: int) -> float:
        """The fraction of r_d's weight that applies after ``steps`` environment steps."""
        if steps >= self.end:
            return 1.0
        return float(np.clip((steps - self.start) / (self.end - self.start), 0.0, 1.0))


class DeformationShare(gym.Wrapper):
    """Scales the deformation term of each step's reward by ``share`` (the env reports its
    weighted terms in ``info["reward_terms"]``; a failed step has none and is left as it is)."""

    def __init__(self, env: gym.Env, share: float = 0.0) -> None:
        super().__init__(env)
        self.share = share

    def set_share(self, share: float) -> None:
        self.share = float(share)

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        deformation = info.get("reward_terms", {}).get("deformation", 0.0)
        return observation, reward - (1.0 - self.share) * deformation, terminated, truncated, info
