"""FollowTask: a non-learned human that pushes its fingertip along the task vector."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from dressbench.observation import observation_layout
from dressbench.scene.human import Human


class FollowTask:
    """Each step, nudge the right arm's joint targets by a fixed-gain Jacobian-transpose step
    along the observation's task vector (a unit vector).

    Unlike the built-in ``scripted`` human it has no approach phase, no damped least squares
    and ignores the haptic forces: a deliberately simple baseline to compare learned humans to.
    """

    api_version: ClassVar[int] = 1
    robot: str | None = "arc"
    ablation: str = "complete"
    gain = 0.3  # rad of joint-target change per metre of fingertip Jacobian

    def __init__(self) -> None:
        self._body = Human()  # the body model, used for kinematics only
        self._arm = self._body.actuated_index[3:]  # the right arm's; the spine holds its pose

    def reset(self, seed: int | None = None) -> None:
        """Nothing to reset: the policy is deterministic and keeps no state."""

    def act(self, observation: np.ndarray) -> np.ndarray:
        """PD targets in [-1, 1]^11: the current pose plus ``gain * J^T task``."""
        obs = np.asarray(observation, dtype=float)
        layout = observation_layout(self.ablation)
        q = np.arctan2(obs[layout.sin_q], obs[layout.cos_q])
        jacobian = self._body.fingertip_jacobian(q)[:, self._arm]
        target = q.copy()
        target[self._arm] += self.gain * jacobian.T @ obs[layout.task]
        return self._body.action_for(target)
