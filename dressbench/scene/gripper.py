"""The gripper's hold on the gown: a rigid hoop that the robot drives with limited force.

The gripper holds the whole armhole loop, so that part of the gown is rigid. The cloth's pinned
vertices follow it, but a light cloth cannot stop an arm, and a penalty spring stiff enough to
stop one is unstable at dt = 0.01 s. So the held part is also a body in DART: a chain of thin
capsules along the loop. DART's contact solver keeps the human's capsules out of it, which is
what stops an arm from sweeping into the opening across its rim.

The hoop is driven by a servo toward the pose the robot commands, with a force limit (the
robot's compliance), rather than placed there: DART's contacts ignore the motion of a placed
(immobile) body and undo a penetration at 1 mm/s, so a robot path that ran into the arm went
through it, the rim cutting 2-4 cm into a forearm and the cloth beside the pins stretching up
to 28 times its area (docs/scene.md). Driven, the rim pushes the arm out of its way, and where
the arm cannot move (a joint at its limit) the gripper stops, as a force-limited robot does.
"""

from __future__ import annotations

from dataclasses import dataclass

import dartpy as dart
import numpy as np

from .geometry import quat_matrix, rotation_z_to
from .human import Human


@dataclass(frozen=True)
class GripperConfig:
    """How the robot drives the held rim."""

    # N: the most the robot pushes on the body with; ISO/TS 15066 allows 140-160 N of
    # quasi-static contact on the hand and forearm
    max_force: float = 150.0
    max_torque: float = 15.0  # N m, about the rim: the force limit at its 0.1 m radius
    mass: float = 2.0  # kg, the rim and gripper as they move under contact
    radius: float = 0.006  # m, of the rim's capsules


class Hoop:
    """A capsule chain through the held loop, servoed to the gripper's commanded pose."""

    def __init__(
        self, human: Human, ring: np.ndarray, config: GripperConfig = GripperConfig()
    ) -> None:
        """``ring`` is the held loop (a closed polyline) in the gown's frame."""
        self.dt = human.world.getTimeStep()
        self.skeleton = dart.dynamics.Skeleton("gripper_hoop")
        joint, body = self.skeleton.createFreeJointAndBodyNodePair()
        body.setName("hoop")
        closed = np.vstack([ring, ring[:1]])
        for a, b in zip(closed[:-1], closed[1:], strict=True):
            _add_capsule(body, a, b, config.radius)
        body.setMass(config.mass)
        # m r^2, a ring's moment about its axis, taken for all three axes (the servo, not the
        # inertia, decides how the rim moves)
        inertia = config.mass * float(np.mean(np.sum(ring**2, axis=1)))
        body.setMomentOfInertia(inertia, inertia, inertia, 0.0, 0.0, 0.0)
        body.setGravityMode(False)  # the robot carries its weight
        joint.setActuatorType(dart.dynamics.ActuatorType.SERVO)
        limit = np.array([config.max_torque] * 3 + [config.max_force] * 3)
        joint.setForceUpperLimits(limit)
        joint.setForceLowerLimits(-limit)
        self._joint = joint
        self._body = body
        human.world.addSkeleton(self.skeleton)
        self._body_of_shape = {
            human_body.getShapeNode(k).getName(): i
            for i, human_body in enumerate(human.bodies)
            for k in range(human_body.getNumShapeNodes())
        }
        self._world = human.world

    def reset(self, pose: np.ndarray) -> None:
        """Place the hoop at a gripper pose (x, y, z, qx, qy, qz, qw), motionless."""
        tf = dart.math.Isometry3()
        tf.set_translation(pose[:3])
        tf.set_rotation(quat_matrix(pose[3:]))
        self._joint.setTransform(tf)
        self._joint.setVelocities(np.zeros(6))

    def drive(self, pose: np.ndarray) -> None:
        """Command the velocity that reaches ``pose`` in the next DART step; the servo gets
        there unless that takes more than the force limits against the body."""
        # a FreeJoint's positions: its rotation vector and its position; its velocities: the
        # angular and linear velocity, all in the world frame (DART's own quaternion maths:
        # scipy's Rotation costs ~0.1 ms a call, eight times a policy step)
        now = np.asarray(self._joint.getPositions())
        target = dart.math.Quaternion()
        target.set_wxyz(pose[6], pose[3], pose[4], pose[5])
        turn = dart.math.quatToExp(target.multiply(dart.math.expToQuat(now[:3]).conjugate()))
        move = np.asarray(pose[:3], dtype=float) - now[3:]
        self._joint.setCommands(np.concatenate([turn, move]) / self.dt)

    def pose(self) -> np.ndarray:
        """Where the hoop is: (x, y, z, qx, qy, qz, qw)."""
        now = np.asarray(self._joint.getPositions())
        quaternion = dart.math.expToQuat(now[:3])
        return np.concatenate([now[3:], quaternion.xyz(), [quaternion.w()]])

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
