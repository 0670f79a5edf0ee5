"""The simulated human: a 22-DOF DART upper body with capsule geometry and haptic sensors.

Frame: x forward, y to the human's left, z up; the pelvis is welded at the origin. At q = 0 the
body is in a T-pose (arms straight out along ±y, palms down); joint ranges and the rest pose are
expressed relative to that. Dimensions, masses and ranges are documented in ``docs/human.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import dartpy as dart
import numpy as np

from .actuation import check_actuation
from .body import BODY, N_ACTIONS, N_DOFS, JointSpec
from .clock import POLICY_DT, SIM_DT
from .geometry import GRAVITY, rotation_z_to

_ORIGIN = np.zeros(3)


@dataclass(frozen=True)
class HumanConfig:
    """How the human is actuated; see docs/human.md for the mapping."""

    actuation: str = "pd"  # one of actuation.ACTUATIONS
    kp: float = 100.0  # computed-torque PD gains (critically damped: kd = 2 sqrt(kp))
    kd: float = 20.0
    max_speed: float = 3.0  # rad/s: the PD never asks a joint to move faster (see docs)
    torque_scale: float = 10.0  # the paper's mapping, used with actuation="torque"
    self_collision: bool = True
    specs: tuple[JointSpec, ...] = BODY


class Human:
    """A DART skeleton in its own world, with capsules, sensors and the arm chain."""

    N_DOFS = N_DOFS
    N_ACTIONS = N_ACTIONS

    def __init__(self, config: HumanConfig = HumanConfig(), dt: float = SIM_DT) -> None:
        check_actuation(config.actuation)
        self.config = config
        self.skeleton, self._bodies = _build_skeleton(config.specs)
        self.world = dart.simulation.World()
        self.world.setTimeStep(dt)
        self.world.setGravity(list(GRAVITY))
        self.world.setCollisionDetector(dart.collision.BulletCollisionDetector())
        self.world.addSkeleton(self.skeleton)
        self.skeleton.setSelfCollisionCheck(config.self_collision)
        self.skeleton.setAdjacentBodyCheck(False)

        specs = [s for s in config.specs if s.kind != "weld"]
        self.body_names = [s.name for s in config.specs]
        self.lower = np.concatenate([s.lower for s in specs])
        self.upper = np.concatenate([s.upper for s in specs])
        self.rest = np.concatenate([s.rest for s in specs])
        self.max_torque = np.concatenate([s.max_torque for s in specs])
        self.actuated = np.concatenate([[s.actuated] * len(s.rest) for s in specs])
        assert self.lower.size == self.N_DOFS and self.actuated.sum() == self.N_ACTIONS
        self.actuated_index = np.flatnonzero(self.actuated)
        self.target = self.rest.copy()
        self._torque_action = np.zeros(self.N_ACTIONS)
        self.torque = np.zeros(self.N_DOFS)

        caps = [(i, c) for i, s in enumerate(config.specs) for c in s.capsules]
        self.capsule_body = np.array([i for i, _ in caps], dtype=np.int32)
        self.capsule_radius = np.array([c[2] for _, c in caps])
        origins = np.array([s.origin for s in config.specs])
        self._capsule_local = np.array(
            [[np.subtract(c[0], origins[i]), np.subtract(c[1], origins[i])] for i, c in caps]
        )  # (C, 2, 3) endpoints in body frames
        sens = [(i, p) for i, s in enumerate(config.specs) for p in s.sensors]
        self.sensor_body = np.array([i for i, _ in sens], dtype=np.int32)
        self._sensor_local = np.array([np.subtract(p, origins[i]) for i, p in sens])
        self._chain = [self.body_names.index(n) for n in ("hand_r", "forearm_r", "upper_arm_r")]
        self._tip_local = (
            np.array(config.specs[self._chain[0]].capsules[0][1]) - origins[self._chain[0]]
        )
        self.torso_index = self.body_names.index("torso")
        self.reset()

    # ----------------------------------------------------------------------------- state
    def reset(self, q: np.ndarray | None = None, involuntary: np.ndarray | None = None) -> None:
        """Put the body at rest (or at ``q``), motionless, with the PD target at rest (at the
        pose itself when actions move the target, so that doing nothing holds it).

        ``involuntary``: joint accelerations (rad/s^2), one row of N_DOFS per simulation step
        from now on, that the body makes besides what it is asked to (a tremor); after the
        last row, none. None: no involuntary motion.
        """
        self._involuntary = involuntary
        self._frame = 0
        pose = self.rest if q is None else np.asarray(q, dtype=float)
        self.skeleton.setPositions(pose)
        self.skeleton.setVelocities(np.zeros(self.N_DOFS))
        self.skeleton.clearExternalForces()
        self.target = (pose if self.config.actuation == "delta" else self.rest).copy()
        self._torque_action[:] = 0.0
        self.world.reset()
        # a fresh detector: Bullet keeps contact manifolds between queries, which would let
        # one episode's last contacts change the next episode's first step
        self.world.setCollisionDetector(dart.collision.BulletCollisionDetector())

    @property
    def bodies(self) -> list:
        """The DART body nodes, in the order of ``body_names``."""
        return list(self._bodies)

    @property
    def q(self) -> np.ndarray:
        return np.asarray(self.skeleton.getPositions())

    @property
    def dq(self) -> np.ndarray:
        return np.asarray(self.skeleton.getVelocities())

    def body_transforms(self) -> np.ndarray:
        """(N_bodies, 4, 4) world transforms of every body node."""
        return np.array([b.getWorldTransform().matrix() for b in self._bodies])

    def capsules(self, transforms: np.ndarray) -> np.ndarray:
        """(C, 2, 3) world endpoints of the collision capsules."""
        T = transforms[self.capsule_body]
        return np.einsum("cij,ckj->cki", T[:, :3, :3], self._capsule_local) + T[:, None, :3, 3]

    def sensors(self, transforms: np.ndarray) -> np.ndarray:
        """(22, 3) world positions of the haptic sensors."""
        T = transforms[self.sensor_body]
        return np.einsum("cij,cj->ci", T[:, :3, :3], self._sensor_local) + T[:, :3, 3]

    def arm_chain(self, transforms: np.ndarray) -> np.ndarray:
        """(4, 3) right-arm points distal to proximal: fingertip, wrist, elbow, shoulder."""
        hand = transforms[self._chain[0]]
        tip = hand[:3, :3] @ self._tip_local + hand[:3, 3]
        return np.vstack([tip] + [transforms[i][:3, 3] for i in self._chain])

    def fingertip_jacobian(self, q: np.ndarray) -> np.ndarray:
        """(3, 22) world-frame Jacobian of the fingertip at configuration ``q`` (sets q)."""
        return self.hand_jacobians(q)[0]

    def hand_jacobians(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(3, 22) world-frame Jacobians of the fingertip and the wrist at ``q`` (sets q)."""
        self.skeleton.setPositions(q)
        hand = self._bodies[self._chain[0]]
        world = dart.dynamics.Frame.World()
        tip = self.skeleton.getLinearJacobian(hand, self._tip_local, world)
        wrist = self.skeleton.getLinearJacobian(hand, _ORIGIN, world)
        return np.asarray(tip), np.asarray(wrist)

    def torso_up(self, transforms: np.ndarray) -> np.ndarray:
        return transforms[self.torso_index][:3, 2].copy()

    # ----------------------------------------------------------------------------- control
    def set_action(self, action: np.ndarray) -> None:
        """Map an action in [-1, 1]^11 to PD targets (or torques); see docs/human.md. Its shape
        and finiteness are the plugin contract's, checked by the env's step."""
        a = np.clip(np.asarray(action, dtype=float), -1.0, 1.0)
        if self.config.actuation == "torque":
            self._torque_action = a
            return
        i = self.actuated_index
        rest, lo, hi = self.rest[i], self.lower[i], self.upper[i]
        if self.config.actuation == "delta":
            self.target[i] = np.clip(self.target[i] + a * self.delta_step, lo, hi)
            return
        self.target[i] = np.where(a >= 0.0, rest + a * (hi - rest), rest + a * (rest - lo))

    @property
    def delta_step(self) -> float:
        """How far (rad) a full "delta" action moves a target: as far as the PD's speed limit
        lets a joint follow in one policy step."""
        return self.config.max_speed * POLICY_DT

    def outstretched(self) -> np.ndarray:
        """The rest pose with the right arm straight ahead at shoulder height, elbow straight."""
        q = self.rest.copy()
        q[8:12] = [0.0, 0.0, np.pi / 2, 0.0]  # shoulder elevation, middle axis, swing; elbow
        return q

    def reaching_pose(
        self, tip: np.ndarray, direction: np.ndarray, iterations: int = 60
    ) -> np.ndarray:
        """A pose, from rest, with the fingertip near ``tip`` and the hand pointing along the
        unit ``direction``: damped least squares on the right arm's actuated joints, kept within
        their ranges (kinematics only; it leaves the skeleton in that pose)."""
        arm = self.actuated_index[3:]  # clavicle, shoulder, elbow, wrist
        wrist_target = tip - np.linalg.norm(self._tip_local) * np.asarray(direction)
        q = self.rest.copy()
        for _ in range(iterations):
            tip_jac, wrist_jac = self.hand_jacobians(q)
            now_tip, now_wrist = self.arm_chain(self.body_transforms())[:2]
            error = np.concatenate([tip - now_tip, wrist_target - now_wrist])
            if np.linalg.norm(error) < 1e-3:
                break
            jac = np.vstack([tip_jac[:, arm], wrist_jac[:, arm]])
            step = jac.T @ np.linalg.solve(jac @ jac.T + 0.05**2 * np.eye(6), error)
            q[arm] = np.clip(q[arm] + step, self.lower[arm], self.upper[arm])
        return q

    def action_for(self, q_target: np.ndarray) -> np.ndarray:
        """The PD action whose targets are ``q_target`` on the actuated DOFs (clipped to range)."""
        i = self.actuated_index
        rest, lo, hi = self.rest[i], self.lower[i], self.upper[i]
        d = np.asarray(q_target, dtype=float)[i] - rest
        a = np.where(d >= 0.0, d / (hi - rest), d / (rest - lo))
        return np.clip(a, -1.0, 1.0)

    def step(self, body_forces: np.ndarray, body_torques: np.ndarray) -> None:
        """One DART step: fresh computed-torque PD, then the cloth's external wrenches."""
        skel = self.skeleton
        q, dq = self.q, self.dq
        cfg = self.config
        speed = np.clip(cfg.kp / cfg.kd * (self.target - q), -cfg.max_speed, cfg.max_speed)
        mass = np.asarray(skel.getMassMatrix())
        inertial = mass @ (cfg.kd * (speed - dq))
        shake = self._shake(mass)
        if shake is not None:
            inertial += shake
        bias = np.asarray(skel.getCoriolisAndGravityForces())
        tau = _within_limits(inertial, bias, self.max_torque)
        if self.config.actuation == "torque":
            tau[self.actuated_index] = self.config.torque_scale * self._torque_action
            if shake is not None:
                tau[self.actuated_index] += shake[self.actuated_index]
        self.torque = np.clip(tau, -self.max_torque, self.max_torque)  # the last commanded
        skel.setForces(self.torque)
        for k in np.flatnonzero(
            np.any(body_forces != 0.0, axis=1) | np.any(body_torques != 0.0, axis=1)
        ):
            self._bodies[k].addExtForce(body_forces[k], _ORIGIN, False, True)  # at the body origin
            self._bodies[k].addExtTorque(body_torques[k], False)
        self.world.step()

    def _shake(self, mass: np.ndarray) -> np.ndarray | None:
        """This step's involuntary torque, M(q) times its row of involuntary accelerations (so
        that it moves those joints, and only those, by that much), or None; advances a row."""
        if self._involuntary is None or self._frame >= len(self._involuntary):
            return None
        row = self._involuntary[self._frame]
        self._frame += 1
        return mass @ row

    def is_finite(self) -> bool:
        return bool(np.isfinite(self.q).all() and np.isfinite(self.dq).all())


def _within_limits(inertial: np.ndarray, bias: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """Computed torque ``s * M acc + bias`` with the largest s in [0, 1] that respects the
    joint torque limits: scaling the whole PD acceleration keeps the joints decoupled, where
    clipping joints one by one made the light distal links unstable."""
    room = np.divide(
        np.sign(inertial) * limit - bias, inertial, out=np.full_like(inertial, np.inf),
        where=inertial != 0.0,
    )  # fmt: skip
    scale = float(np.clip(np.min(room, initial=1.0), 0.0, 1.0))
    return np.clip(scale * inertial + bias, -limit, limit)


def _build_skeleton(specs: tuple[JointSpec, ...]) -> tuple[dart.dynamics.Skeleton, list]:
    """Create the skeleton from the specs, each body frame world-aligned at q = 0."""
    skel = dart.dynamics.Skeleton("human")
    bodies: dict[str, dart.dynamics.BodyNode] = {}
    origins = {s.name: np.array(s.origin) for s in specs}
    for s in specs:
        parent = bodies.get(s.parent) if s.parent else None
        create = {
            "weld": skel.createWeldJointAndBodyNodePair,
            "euler": skel.createEulerJointAndBodyNodePair,
            "universal": skel.createUniversalJointAndBodyNodePair,
            "revolute": skel.createRevoluteJointAndBodyNodePair,
        }[s.kind]
        joint, body = create(parent) if parent is not None else create()
        joint.setName(s.name)
        body.setName(s.name)
        offset = dart.math.Isometry3()
        offset.set_translation(origins[s.name] - (origins[s.parent] if s.parent else 0.0))
        joint.setTransformFromParentBodyNode(offset)
        if s.kind == "revolute":
            joint.setAxis(np.array(s.axes[0]))
        elif s.kind == "universal":
            joint.setAxis1(np.array(s.axes[0]))
            joint.setAxis2(np.array(s.axes[1]))
        for k in range(len(s.rest)):
            joint.setDofName(k, s.dofs[k], True)
            joint.setPositionLowerLimit(k, s.lower[k])
            joint.setPositionUpperLimit(k, s.upper[k])
        if s.kind != "weld":
            joint.setLimitEnforcement(True)
        _add_geometry(body, s, origins[s.name])
        bodies[s.name] = body
    return skel, [bodies[s.name] for s in specs]


def _add_geometry(body: dart.dynamics.BodyNode, spec: JointSpec, origin: np.ndarray) -> None:
    """Capsule shapes (collision + visual) and a mass with the capsules' inertia."""
    moment = np.zeros((3, 3))
    com = np.zeros(3)
    volumes = []
    for a, b, r in spec.capsules:
        a, b = np.subtract(a, origin), np.subtract(b, origin)
        axis = b - a
        h = float(np.linalg.norm(axis))
        shape = dart.dynamics.CapsuleShape(r, h)
        tf = dart.math.Isometry3()
        tf.set_translation((a + b) / 2.0)
        tf.set_rotation(rotation_z_to(axis / h))
        node = body.createShapeNode(shape)
        node.setRelativeTransform(tf)
        node.createCollisionAspect()
        node.createVisualAspect()
        node.createDynamicsAspect()
        volumes.append((shape.getVolume(), (a + b) / 2.0, tf.rotation(), shape))
    total = sum(v for v, *_ in volumes)
    for v, centre, rot, shape in volumes:
        share = spec.mass * v / total
        com += share * centre
        moment += rot @ np.asarray(shape.computeInertia(share)) @ rot.T
    com /= spec.mass
    for v, centre, _, _ in volumes:  # parallel-axis shift to the common centre of mass
        share = spec.mass * v / total
        d = centre - com
        moment += share * (d @ d * np.eye(3) - np.outer(d, d))
    inertia = dart.dynamics.Inertia(spec.mass, com, moment)
    body.setInertia(inertia)
