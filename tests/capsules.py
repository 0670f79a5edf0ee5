"""Depth of points inside the human's capsules, for the tests that keep things out of the skin."""

import numpy as np

from dressbench.scene.geometry import capsule_depth
from dressbench.scene.world import Scene

__all__ = ["capsule_depth", "limb_depth"]


def limb_depth(scene: Scene, points: np.ndarray) -> np.ndarray:
    """(P, C) how deep each point lies inside each of the human's capsules."""
    return capsule_depth(points, scene.human.capsules(scene.transforms), scene.human.capsule_radius)
