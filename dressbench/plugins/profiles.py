"""Built-in capability profiles: the typical body, a stiff shoulder, a weak arm and a tremor.

Each narrows the typical body (``scene/body.py``) or adds involuntary motion; the parameters and
their sources are in docs/human.md ("Capability profiles"). A subclass that changes a class
attribute is another profile (``class Weaker(WeakArm): strength = 0.1``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import ClassVar

import numpy as np

from ..scene.body import DOF_NAMES, N_DOFS, BodyLimits

RIGHT_SHOULDER = ("shoulder_r_elevation", "shoulder_r_middle", "shoulder_r_swing")
RIGHT_ELBOW_AND_WRIST = ("elbow_r_flexion", "wrist_r_flexion", "wrist_r_deviation")
RIGHT_ARM = ("clavicle_r_elevation", "clavicle_r_protraction", *RIGHT_SHOULDER,
             *RIGHT_ELBOW_AND_WRIST)  # fmt: skip


def dof_indices(names: tuple[str, ...]) -> np.ndarray:
    """The positions of named degrees of freedom in q (``DOF_NAMES``)."""
    return np.array([DOF_NAMES.index(name) for name in names], dtype=int)


class Typical:
    """The body as it is planned: the typical ranges and torque caps, no involuntary motion."""

    api_version: ClassVar[int] = 1

    def body(self, typical: BodyLimits) -> BodyLimits:
        return typical

    def involuntary(self, rng: np.random.Generator, frames: int, dt: float) -> None:
        return None


class LimitedShoulder(Typical):
    """A stiff right shoulder (as in adhesive capsulitis, or after a stroke): each of its three
    ranges narrowed to ``share`` of the typical one, about the rest pose, so that the arm
    neither rises far above shoulder height nor swings far forward."""

    share: ClassVar[float] = 0.5  # Assistive Gym's most limited draw (joint limits x 0.5-1)
    joints: ClassVar[tuple[str, ...]] = RIGHT_SHOULDER

    def body(self, typical: BodyLimits) -> BodyLimits:
        i = dof_indices(self.joints)
        lower, upper, rest = typical.lower.copy(), typical.upper.copy(), typical.rest[i]
        lower[i] = rest + self.share * (typical.lower[i] - rest)
        upper[i] = rest + self.share * (typical.upper[i] - rest)
        return replace(typical, lower=lower, upper=upper)


class WeakArm(Typical):
    """One-sided weakness (hemiparesis): the torque caps of the right arm's joints, clavicle to
    wrist, scaled to ``strength`` of the typical ones."""

    strength: ClassVar[float] = 0.25  # Assistive Gym's weakest draw (strength x 0.25-1)
    joints: ClassVar[tuple[str, ...]] = RIGHT_ARM

    def body(self, typical: BodyLimits) -> BodyLimits:
        torque = typical.max_torque.copy()
        torque[dof_indices(self.joints)] *= self.strength
        return replace(typical, max_torque=torque)


class Tremor(Typical):
    """An involuntary oscillation of the right arm in the band of essential tremor: on each
    joint of ``amplitudes``, a sum of ``components`` sinusoids of frequencies drawn uniformly
    from ``band`` and random phases, of that RMS displacement, as joint accelerations. Above
    the PD's bandwidth (1.6 Hz) a joint moves by about that displacement."""

    band: ClassVar[tuple[float, float]] = (5.0, 7.0)  # Hz, within essential tremor's 4-12 Hz
    # RMS displacement (rad): +-10 degrees (Assistive Gym's tremor) as three standard deviations
    # at the elbow and wrist, a third of that at the heavier shoulder
    amplitudes: ClassVar[dict[str, float]] = {
        **dict.fromkeys(RIGHT_ELBOW_AND_WRIST, np.radians(10.0) / 3.0),
        **dict.fromkeys(RIGHT_SHOULDER, np.radians(10.0) / 9.0),
    }
    components: ClassVar[int] = 8

    def involuntary(self, rng: np.random.Generator, frames: int, dt: float) -> np.ndarray:
        names = tuple(self.amplitudes)
        shape = (self.components, len(names))
        frequency = rng.uniform(*self.band, size=shape)
        phase = rng.uniform(0.0, 2.0 * np.pi, size=shape)
        # equal components whose RMS adds up to the joint's: each sine's RMS is amplitude / sqrt 2
        size = np.array([self.amplitudes[n] for n in names]) * np.sqrt(2.0 / self.components)
        omega = 2.0 * np.pi * frequency
        t = np.arange(frames)[:, None, None] * dt
        motion = np.zeros((frames, N_DOFS))
        motion[:, dof_indices(names)] = -(size * omega**2 * np.sin(omega * t + phase)).sum(axis=1)
        return motion
