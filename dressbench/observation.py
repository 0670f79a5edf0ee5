"""The human's observation (paper §III-C): 163 numbers for the complete model.

Order: cos q (22), sin q (22), q-dot (22), feature centroid (3), fingertip - centroid (3),
haptic forces (22 x 3), contact surface signs (22), task vector (3). The ablations drop blocks:
``no_haptics`` the forces and signs (75 numbers left), ``no_task`` the task vector (160).
A learned policy may read the forces on a log scale (``scale_haptics``), a choice it records.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .scene.body import N_DOFS, N_SENSORS

if TYPE_CHECKING:  # annotations only: the layout and scaling load without the physics
    from .scene.world import Scene
    from .state import DressingState

ABLATIONS = ("complete", "no_haptics", "no_task")
NEWTONS = "newtons"  # the forces as measured (the paper): what a policy that names no scale reads
HAPTIC_SCALES = (NEWTONS, "log")  # or log(1 + |f| / 1 N)


@dataclass(frozen=True)
class ObservationLayout:
    """Where each block sits in an ablation's observation vector, for plugin authors
    (``obs[layout.task]``); None where the ablation drops the block."""

    cos_q: slice
    sin_q: slice
    dq: slice
    centroid: slice  # of the sleeve opening's feature loop
    tip_offset: slice  # fingertip - centroid
    forces: slice | None  # haptic forces, (N_SENSORS, 3) row by row
    signs: slice | None  # contact surface signs, one per sensor
    task: slice | None  # the task vector
    size: int


@functools.cache  # read on every step by the scripted human and the trained policies
def observation_layout(ablation: str = "complete") -> ObservationLayout:
    """The layout of the observation of ``ablation``."""
    check_ablation(ablation)
    sizes = {"cos_q": N_DOFS, "sin_q": N_DOFS, "dq": N_DOFS, "centroid": 3, "tip_offset": 3}
    if ablation != "no_haptics":
        sizes |= {"forces": 3 * N_SENSORS, "signs": N_SENSORS}
    if ablation != "no_task":
        sizes["task"] = 3
    blocks: dict[str, slice | None] = {"forces": None, "signs": None, "task": None}
    start = 0
    for name, size in sizes.items():
        blocks[name] = slice(start, start + size)
        start += size
    return ObservationLayout(**blocks, size=start)


def observation_size(ablation: str = "complete") -> int:
    """Length of the observation vector for an ablation."""
    return observation_layout(ablation).size


def check_ablation(ablation: str) -> None:
    if ablation not in ABLATIONS:
        raise ValueError(f"unknown ablation {ablation!r}: choose one of {', '.join(ABLATIONS)}")


def check_haptic_scale(scale: str) -> None:
    if scale not in HAPTIC_SCALES:
        choices = ", ".join(HAPTIC_SCALES)
        raise ValueError(f"unknown haptic scale {scale!r}: choose one of {choices}")


def scale_haptics(observation: np.ndarray, ablation: str, scale: str) -> np.ndarray:
    """``observation`` (any leading shape) with its haptic forces on ``scale``.

    "log" keeps each sensor force's direction and maps its magnitude to log(1 + |f| / 1 N): a
    rigid rim's hundreds of newtons and cloth's single newtons on skin then share one range, which
    a running normalisation of the raw forces (dominated by the rare rim spikes) does not give.
    """
    check_haptic_scale(scale)
    block = observation_layout(ablation).forces
    if scale == NEWTONS or block is None:
        return observation
    out = np.array(observation, dtype=np.float32)
    forces = out[..., block].reshape(*out.shape[:-1], N_SENSORS, 3)
    magnitude = np.linalg.norm(forces, axis=-1, keepdims=True)
    factor = np.log1p(magnitude) / np.maximum(magnitude, 1e-12)
    out[..., block] = (forces * factor).reshape(*out.shape[:-1], 3 * N_SENSORS)
    return out


def surface_signs(sides: np.ndarray, forces: np.ndarray, eps: float = 1e-9) -> np.ndarray:
    """+1 inner-surface contact, -1 outer, 0 none, per sensor."""
    touching = np.linalg.norm(forces, axis=1) > eps
    return np.where(touching, np.sign(sides), 0.0)


def human_observation(scene: Scene, state: DressingState, ablation: str = "complete") -> np.ndarray:
    """The observation vector for the human policy."""
    q, dq = scene.human.q, scene.human.dq
    centroid = state.plane.centroid
    blocks = [np.cos(q), np.sin(q), dq, centroid, state.joints[0] - centroid]
    if ablation != "no_haptics":
        forces = scene.haptic_forces
        blocks += [forces.ravel(), surface_signs(scene.haptic_sides, forces)]
    if ablation != "no_task":
        blocks.append(state.task_vector)
    return np.concatenate(blocks).astype(np.float32)
