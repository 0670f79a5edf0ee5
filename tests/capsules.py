"""Depth of points inside the human's capsules, for the tests that keep things out of the skin."""

import numpy as np

from dressbench.scene.world import Scene


def capsule_depth(points: np.ndarray, capsules: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(P, C) how deep each point lies inside each capsule (negative outside)."""
    a, b = capsules[:, 0], capsules[:, 1]
    ab = b - a
    p = points[:, None, :]
    t = np.clip(((p - a) * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    return radii - np.linalg.norm(p - (a + t[..., None] * ab), axis=-1)


def limb_depth(scene: Scene, points: np.ndarray) -> np.ndarray:
    """(P, C) how deep each point lies inside each of the human's capsules."""
    return capsule_depth(points, scene.human.capsules(scene.transforms), scene.human.capsule_radius)
