"""Small rigid-body helpers shared by the scene: poses, rotations, point transforms.

A pose is ``(x, y, z, qx, qy, qz, qw)``: a position and a unit quaternion, scalar last.
"""

from __future__ import annotations

import numpy as np

GRAVITY = (0.0, 0.0, -9.81)  # m/s², the world's (z is up): the body's and the cloth's


def quat_matrix(q: np.ndarray) -> np.ndarray:
    """The rotation matrix of a quaternion (qx, qy, qz, qw), normalized first."""
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def transform_points(pose: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply a pose to (N, 3) points."""
    return points @ quat_matrix(pose[3:]).T + pose[:3]


def interpolate_pose(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    """Linear position, normalized-linear rotation (the robot moves slowly between steps)."""
    qa, qb = a[3:], b[3:]
    if qa @ qb < 0.0:
        qb = -qb
    q = (1.0 - t) * qa + t * qb
    return np.concatenate([(1.0 - t) * a[:3] + t * b[:3], q / np.linalg.norm(q)])


def rotation_z_to(direction: np.ndarray) -> np.ndarray:
    """A rotation taking the local z axis to the unit vector ``direction``."""
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(z, direction)
    c = float(z @ direction)
    if np.linalg.norm(v) < 1e-9:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


def capsule_depth(points: np.ndarray, capsules: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(P, C) how deep each point lies inside each capsule (segment ``capsules[c]``, radius
    ``radii[c]``); negative outside."""
    a, b = capsules[:, 0], capsules[:, 1]
    ab = b - a
    p = points[:, None, :]
    t = np.clip(((p - a) * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    return radii - np.linalg.norm(p - (a + t[..., None] * ab), axis=-1)
