"""The paper's three robot strategies (§V), registered as plugins like any third party's.

Boxes are uniform samples with the paper's extents (metres); we write them as
(forward, lateral, vertical) = (x, y, z) in the human's frame, centred relative to the right
shoulder. The centres are ours (the paper gives only "about 0.6 m in front" etc.) and were chosen
so that the fingertip, 0.74 m from the shoulder, can pass through the opening everywhere in the
box: see docs/robots.md.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ..scene.body import RIGHT, SHOULDER_Y, SHOULDER_Z
from .protocols import OBS_TIME, ROBOT_DT, ROBOT_MAX_SPEED

__all__ = [  # the protocol's constants are re-exported for strategy authors
    "FRONT",
    "LINEAR_DURATION",
    "OBS_TIME",
    "RIGHT_SHOULDER",
    "ROBOT_DT",
    "ROBOT_MAX_SPEED",
    "FixedGown",
    "FrontLinear",
    "SideLinear",
    "sample_box",
    "yaw_quaternion",
]

PAPER_STRATEGIES = ("fixed", "front_linear", "side_linear")  # the paper's three, by name
RIGHT_SHOULDER = np.array([0.0, RIGHT * SHOULDER_Y, SHOULDER_Z])  # in the human frame, at rest
FRONT = np.array([0.0, 0.0, 0.0, 1.0])  # sleeve pointing away along +x
LINEAR_DURATION = 10.0  # s, the paper's linear motions


def sample_box(rng: np.random.Generator, centre, extents) -> np.ndarray:
    """A uniform point in the axis-aligned box with this centre and these full extents."""
    return RIGHT_SHOULDER + np.asarray(centre) + (rng.random(3) - 0.5) * np.asarray(extents)


def yaw_quaternion(direction: np.ndarray) -> np.ndarray:
    """The rotation about z that turns the sleeve (+x) toward ``direction``'s horizontal part."""
    angle = np.arctan2(direction[1], direction[0])
    return np.array([0.0, 0.0, np.sin(angle / 2.0), np.cos(angle / 2.0)])


class FixedGown:
    """The gripper holds the gown still in front of the right shoulder (paper §V-A)."""

    api_version: ClassVar[int] = 1
    centre = (0.55, 0.0, -0.05)  # nearer, the hanging gown started inside the arm in 8/30 resets
    extents = (0.1, 0.6, 0.35)  # paper: [0.6, 0.35, 0.1] (lateral, vertical, depth)

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        return np.concatenate([sample_box(rng, self.centre, self.extents), FRONT])

    def act(self, observation: np.ndarray) -> np.ndarray:
        return np.zeros(3)


class _Linear:
    """Start in one box, move at constant velocity to a target in another over 10 s, stay."""

    api_version: ClassVar[int] = 1
    start_centre: tuple[float, float, float]
    start_extents: tuple[float, float, float]
    target_centre: tuple[float, float, float]
    target_extents: tuple[float, float, float]

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        start = sample_box(rng, self.start_centre, self.start_extents)
        target = sample_box(rng, self.target_centre, self.target_extents)
        self._velocity = (target - start) / LINEAR_DURATION
        return np.concatenate([start, self.orientation(target - start)])

    def orientation(self, motion: np.ndarray) -> np.ndarray:
        return FRONT

    def act(self, observation: np.ndarray) -> np.ndarray:
        if observation[OBS_TIME] >= LINEAR_DURATION - 1e-9:
            return np.zeros(3)
        return self._velocity / ROBOT_MAX_SPEED


class FrontLinear(_Linear):
    """From about 0.6 m in front of the shoulder to about 0.2 m (paper §V-B)."""

    start_centre = (0.60, 0.0, -0.05)
    start_extents = (0.1, 0.4, 0.45)  # paper: [0.4, 0.45, 0.1]
    target_centre = (0.20, 0.0, -0.05)
    target_extents = (0.1, 0.3, 0.3)  # paper: [0.3, 0.3, 0.1]


class SideLinear(_Linear):
    """From about 0.6 m to the right of the shoulder to about 0.2 m; the gown is turned so the
    opening faces along the motion's horizontal direction (paper §V-C)."""

    start_centre = (0.10, -0.60, -0.05)
    start_extents = (0.5, 0.1, 0.3)  # paper: [0.1, 0.3, 0.5]
    target_centre = (0.10, -0.20, -0.05)
    target_extents = (0.3, 0.1, 0.3)  # paper: [0.1, 0.3, 0.3]

    def orientation(self, motion: np.ndarray) -> np.ndarray:
        return yaw_quaternion(-motion)  # the sleeve points back along the approach
