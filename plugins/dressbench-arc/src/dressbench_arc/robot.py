"""ArcToShoulder: the gripper swings the gown in to the right shoulder along a circular arc.

Positions are in the human's frame (x forward, y to the human's left, z up; metres). Like the
built-in strategies, the boxes are written relative to the right shoulder.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from dressbench.plugins.robots import (
    OBS_TIME,
    RIGHT_SHOULDER,
    ROBOT_DT,
    ROBOT_MAX_SPEED,
    yaw_quaternion,
)

START_BOX = (np.array([0.40, -0.45, -0.15]), np.array([0.50, -0.35, 0.05]))  # front-right
TARGET_BOX = (np.array([0.17, -0.18, -0.08]), np.array([0.23, -0.12, -0.02]))  # ~0.25 m away
BULGE = 0.10  # m: how far the arc's middle lies off the straight line, toward the front
DURATION = 8.0  # s to travel the arc; the gripper then holds still


@dataclass(frozen=True)
class Arc:
    """A circular arc, ``centre + radius (cos a u + sin a v)`` for the angle a in [0, sweep]."""

    centre: np.ndarray
    radius: float
    u: np.ndarray  # unit vector from the centre to the start
    v: np.ndarray  # unit vector perpendicular to u, in the arc's plane, toward the end
    sweep: float  # rad from the start to the end

    @classmethod
    def through(cls, start: np.ndarray, end: np.ndarray, bulge: float, side: np.ndarray) -> Arc:
        """The arc from ``start`` to ``end`` whose middle lies ``bulge`` m off the chord along
        the unit vector ``side`` (perpendicular to the chord), so the path is a curve."""
        chord = end - start
        half = float(np.linalg.norm(chord)) / 2.0
        radius = (half**2 + bulge**2) / (2.0 * bulge)
        centre = (start + end) / 2.0 - (radius - bulge) * side
        u = (start - centre) / radius
        normal = np.cross(chord, side) / (2.0 * half)
        sweep = 2.0 * np.arctan2(half, radius - bulge)
        return cls(centre, radius, u, np.cross(u, normal), float(sweep))

    def point(self, fraction: float) -> np.ndarray:
        """The point a ``fraction`` in [0, 1] of the way along the arc."""
        angle = self.sweep * fraction
        return self.centre + self.radius * (np.cos(angle) * self.u + np.sin(angle) * self.v)


class ArcToShoulder:
    """Start to the front-right of the human and swing in along an arc over 8 s, then hold.

    The gown is turned once, at reset, so that the sleeve points away from the shoulder as seen
    from the start; the robot's actions move only the position, so it stays turned so.
    """

    api_version: ClassVar[int] = 1

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        """Sample the start and target from ``rng`` and plan the arc; return the start pose."""
        start = RIGHT_SHOULDER + rng.uniform(*START_BOX)
        self.target = RIGHT_SHOULDER + rng.uniform(*TARGET_BOX)
        self.arc = Arc.through(start, self.target, BULGE, forward_side(self.target - start))
        return np.concatenate([start, yaw_quaternion(start - RIGHT_SHOULDER)])

    def act(self, observation: np.ndarray) -> np.ndarray:
        """The velocity that moves the gripper along the arc during the next policy step."""
        t = float(observation[OBS_TIME])
        step = self.arc.point(progress(t + ROBOT_DT)) - self.arc.point(progress(t))
        return np.clip(step / ROBOT_DT / ROBOT_MAX_SPEED, -1.0, 1.0)


def progress(t: float) -> float:
    """The fraction of the arc travelled at time ``t`` s: constant speed, then hold at 1."""
    return min(max(t / DURATION, 0.0), 1.0)


def forward_side(chord: np.ndarray) -> np.ndarray:
    """The horizontal unit vector perpendicular to ``chord`` that points forward (+x), so the
    arc bulges away from the body instead of cutting across the arm."""
    side = np.array([-chord[1], chord[0], 0.0])
    side /= np.linalg.norm(side)
    return side if side[0] >= 0.0 else -side
