"""The gripper's hold on the gown, as a rigid hoop the human's body cannot pass through.

The gripper holds the whole armhole loop and the shoulder seam, so that part of the gown is
rigid. The cloth's pinned vertices follow it, but a light cloth cannot stop an arm, and a penalty
spring stiff enough to stop one is unstable at dt = 0.01 s. So the held part is also a kinematic
body in DART: chains of thin capsules along the loop and the seam. DART's contact solver keeps
the human's capsules out of it, which is what stops an arm from sweeping into the opening
across its rim.
"""

from __future__ import annotations

import dartpy as dart
import numpy as np

from .geometry import quat_matrix, rotation_z_to
from .human import Human


class Hoop:
    """Kinematic capsule chains through the held vertices, moved with the gripper."""

    def __init__(self, human: Human, ring: np.ndarray, radius: float = 0.006) -> None:
        """``ring`` is the held loop (a closed polyline) in the gown's frame."""
        self.skeleton = dart.dynamics.Skeleton("gripper_hoop")
        joint, body = self.skeleton.createFreeJointAndBodyNodePair()
        body.setName("hoop")
        closed = np.vstack([ring, ring[:1]])
        for a, b in zip(closed[:-1], closed[1:], strict=True):
            _add_capsule(body, a, b, radius)
        self.skeleton.setMobile(False)
        self._joint = joint
        self._body = body
        human.world.addSkeleton(self.skeleton)
        self._body_of_shape = {
            human_body.getShapeNode(k).getName(): i
            for i, human_body in enumerate(human.bodies)
            for k in range(human_body.getNumShapeNodes())
        }
        self._world = human.world
        self._pose: np.ndarray | None = None

    def set_pose(self, pose: np.ndarray) -> None:
        """Place the hoop at a gripper pose (x, y, z, qx, qy, qz, qw)."""
        if self._pose is not None and np.array_equal(pose, self._pose):
            return  # a still gripper: DART keeps the hoop where it is
        self._pose = np.array(pose, dtype=float)
        tf = dart.math.Isometry3()
        tf.set_translation(pose[:3])
        tf.set_rotation(quat_matrix(pose[3:]))
        self._joint.setTransform(tf)

    def contacts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The last DART step's hoop contacts: human body index, point, force on the body."""
        bodies, points, forces = [], [], []
        result = self._world.getLastCollisionResult()
        if not result.inCollision(self._body):  # the common case, without a Python loop
            return np.zeros(0, dtype=int), np.zeros((0, 3)), np.zeros((0, 3))
        for c in result.getContacts():
            names = (
                c.collisionObject1.getShapeFrame().getName(),
                c.collisionObject2.getShapeFrame().getName(),
            )
            if not any(n.startswith("hoop") for n in names):
                continue
            human_first = names[0] in self._body_of_shape
            body = self._body_of_shape.get(names[0] if human_first else names[1])
            if body is None:
                continue
            bodies.append(body)
            points.append(np.asarray(c.point))
            force = np.asarray(c.force)  # DART: the force on the first object
            forces.append(force if human_first else -force)
        if not bodies:
            return np.zeros(0, dtype=int), np.zeros((0, 3)), np.zeros((0, 3))
        return np.array(bodies), np.array(points), np.array(forces)


def _add_capsule(body: dart.dynamics.BodyNode, a: np.ndarray, b: np.ndarray, radius: float) -> None:
    axis = b - a
    length = float(np.linalg.norm(axis))
    node = body.createShapeNode(dart.dynamics.CapsuleShape(radius, length))
    tf = dart.math.Isometry3()
    tf.set_translation((a + b) / 2.0)
    tf.set_rotation(rotation_z_to(axis / length))
    node.setRelativeTransform(tf)
    node.createCollisionAspect()
    node.createVisualAspect()
    node.createDynamicsAspect()
