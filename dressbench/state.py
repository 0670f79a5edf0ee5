"""The per-step summary of a scene that the reward, the observation and the metrics all read.

Computed once per policy step so that no quantity (the feature plane, the containment test, the
maximum area ratio) is evaluated twice.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import metrics
from .scene.world import Scene


@dataclass(frozen=True, eq=False)
class DressingState:
    """Everything a policy step measured, in world coordinates."""

    cloth: np.ndarray  # (V, 3) vertex positions
    joints: np.ndarray  # (4, 3) fingertip, wrist, elbow, shoulder
    plane: metrics.FeaturePlane
    containment: metrics.Containment
    max_area_ratio: float
    effector_contacts: np.ndarray  # cloth vertices the hand touched during the step
    task_vector: np.ndarray  # (3,) unit
    torso_up: np.ndarray  # (3,)

    @property
    def arm_progress(self) -> float:
        return self.containment.depth

    @property
    def progress_reward(self) -> float:
        return metrics.progress_reward(self.joints, self.plane, self.containment)


def measure(scene: Scene) -> DressingState:
    """Summarize the scene after a step."""
    gown = scene.gown
    x = scene.cloth_positions()
    joints = scene.arm_chain()
    plane = metrics.feature_plane(x[gown.feature_loop])
    containment = metrics.limb_containment(joints, plane)
    contacts = scene.effector_contacts()
    return DressingState(
        cloth=x,
        joints=joints,
        plane=plane,
        containment=containment,
        max_area_ratio=scene.cloth.max_area_ratio(),
        effector_contacts=contacts,
        task_vector=metrics.task_vector(
            joints[0], plane, containment.contained, contacts, x, gown.triangles, gown.geodesic
        ),
        torso_up=scene.human.torso_up(scene.transforms),
    )
