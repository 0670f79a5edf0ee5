"""The simulated human: a 22-DOF DART upper body with capsule geometry and haptic sensors.

Frame: x forward, y to the human's left, z up; the pelvis is welded at the origin. At q = 0 the
body is in a T-pose (arms straight out along ±y, palms down); joint ranges and the rest pose are
expressed relative to that. Dimensions, masses and ranges are documented in ``docs/human.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import dartpy as dart
import numpy as np

from .geometry import rotation_z_to

RIGHT, LEFT = -1.0, 1.0  # the sign of y on each side of the body
_ORIGIN = np.zeros(3)


@dataclass(frozen=True)
class JointSpec:
    """One joint and the body it moves; the body frame is world-aligned at q = 0."""

    name: str
    parent: str | None
    kind: str  # "weld", "euler" (XYZ), "universal" or "revolute"
    origin: tuple[float, float, float]  # joint position in the world at q = 0
    dofs: tuple[str, ...] = ()  # one name per degree of freedom
    axes: tuple[tuple[float, float, float], ...] = ()  # revolute/universal axes
    lower: tuple[float, ...] = ()
    upper: tuple[float, ...] = ()
    rest: tuple[float, ...] = ()
    max_torque: tuple[float, ...] = ()  # N m, a safety bound (see docs/human.md)
    actuated: bool = False
    mass: float = 1.0
    capsules: tuple[tuple[tuple[float, float, float], tuple[float, float, float], float], ...] = ()
    sensors: tuple[tuple[float, float, float], ...] = ()  # world points at q = 0


def _arm(side: float) -> list[JointSpec]:
    """Clavicle, upper arm, forearm and hand on one side (side = RIGHT or LEFT)."""
    s = side
    p = "r" if side == RIGHT else "l"
    sh = (0.0, 0.19 * s, 0.50)  # glenohumeral joint
    el = (0.0, sh[1] + 0.30 * s, 0.50)
    wr = (0.0, el[1] + 0.26 * s, 0.50)
    tip = (0.0, wr[1] + 0.18 * s, 0.50)
    # Euler XYZ at the shoulder: x elevates the arm in the frontal plane (+ = down for the
    # right arm), y is the middle axis (kept within ±1.2 rad, away from the Euler singularity),
    # z swings it horizontally (+ = forward for the right arm).
    m = -s  # mirror factor: right-arm conventions read positively
    return [
        JointSpec(
            name=f"clavicle_{p}",
            parent="torso",
            kind="universal",
            dofs=(f"clavicle_{p}_elevation", f"clavicle_{p}_protraction"),
            origin=(0.02, 0.03 * s, 0.47),
            axes=((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
            lower=_mirror((-0.35, -0.30), (0.35, 0.50), m)[0],
            upper=_mirror((-0.35, -0.30), (0.35, 0.50), m)[1],
            rest=(0.0, 0.0),
            max_torque=(180.0, 180.0),
            actuated=side == RIGHT,
            mass=0.6,
            capsules=(((0.02, 0.05 * s, 0.48), (0.0, 0.15 * s, 0.50), 0.045),),
            sensors=((0.02, 0.07 * s, 0.485), (0.0, 0.14 * s, 0.50)),
        ),
        JointSpec(
            name=f"upper_arm_{p}",
            parent=f"clavicle_{p}",
            kind="euler",
            dofs=(f"shoulder_{p}_elevation", f"shoulder_{p}_middle", f"shoulder_{p}_swing"),
            origin=sh,
            lower=_mirror((-1.6, -1.2, -0.8), (1.6, 1.2, 2.3), m)[0],
            upper=_mirror((-1.6, -1.2, -0.8), (1.6, 1.2, 2.3), m)[1],
            rest=tuple(m * v for v in (1.30, 0.0, 0.15)),
            max_torque=(180.0, 120.0, 180.0),
            actuated=side == RIGHT,
            mass=2.1,
            capsules=((sh, el, 0.045),),
            sensors=(_lerp(sh, el, 0.3), _lerp(sh, el, 0.75)),
        ),
        JointSpec(
            name=f"forearm_{p}",
            parent=f"upper_arm_{p}",
            kind="revolute",
            dofs=(f"elbow_{p}_flexion",),
            origin=el,
            axes=((0.0, 0.0, m),),  # + flexes the forearm forward from the T-pose
            lower=(0.0,),
            upper=(2.6,),
            rest=(0.3,),
            max_torque=(150.0,),
            actuated=side == RIGHT,
            mass=1.2,
            capsules=((el, wr, 0.038),),
            sensors=(_lerp(el, wr, 0.3), _lerp(el, wr, 0.75)),
        ),
        JointSpec(
            name=f"hand_{p}",
            parent=f"forearm_{p}",
            kind="universal",
            dofs=(f"wrist_{p}_flexion", f"wrist_{p}_deviation"),
            origin=wr,
            axes=((0.0, 0.0, m), (1.0, 0.0, 0.0)),  # flexion, then radial/ulnar deviation
            lower=(-1.2, -0.35),
            upper=(1.2, 0.5),
            rest=(0.0, 0.0),
            max_torque=(30.0, 30.0),
            actuated=side == RIGHT,
            mass=0.45,
            capsules=((wr, tip, 0.03),),
            sensors=(_lerp(wr, tip, 0.35), _lerp(wr, tip, 0.8)),
        ),
    ]


def _mirror(lo: tuple[float, ...], hi: tuple[float, ...], m: float) -> tuple[tuple, tuple]:
    """Limits for a mirrored side: negate and swap bounds when m = -1."""
    if m > 0:
        return lo, hi
    return tuple(-h for h in hi), tuple(-v for v in lo)


def _lerp(a: tuple, b: tuple, t: float) -> tuple[float, float, float]:
    return tuple(float(x + t * (y - x)) for x, y in zip(a, b, strict=True))


def body_specs() -> list[JointSpec]:
    """The whole body: pelvis, torso, head, and both arms (22 DOF, 11 actuated)."""
    return [
        JointSpec(
            name="pelvis",
            parent=None,
            kind="weld",
            origin=(0.0, 0.0, 0.0),
            mass=10.0,
            capsules=(((0.0, -0.08, 0.0), (0.0, 0.08, 0.0), 0.11),),
            sensors=((0.0, -0.08, 0.0), (0.0, 0.08, 0.0)),
        ),
        JointSpec(
            name="torso",
            parent="pelvis",
            kind="euler",
            dofs=("spine_bend", "spine_flexion", "spine_twist"),
            origin=(0.0, 0.0, 0.10),
            # x: lateral bend, y: flexion (+ = forward), z: axial twist
            lower=(-0.5, -0.4, -0.7),
            upper=(0.5, 1.0, 0.7),
            rest=(0.0, 0.0, 0.0),
            max_torque=(450.0, 450.0, 240.0),
            actuated=True,
            mass=26.0,
            capsules=(
                ((0.0, -0.06, 0.22), (0.0, 0.06, 0.22), 0.12),
                ((0.0, -0.06, 0.40), (0.0, 0.06, 0.40), 0.105),
            ),
            sensors=((0.0, 0.0, 0.22), (0.0, 0.0, 0.40)),
        ),
        JointSpec(
            name="head",
            parent="torso",
            kind="euler",
            dofs=("neck_bend", "neck_flexion", "neck_twist"),
            origin=(0.0, 0.0, 0.53),
            lower=(-0.6, -0.7, -1.0),
            upper=(0.6, 0.8, 1.0),
            rest=(0.0, 0.0, 0.0),
            max_torque=(75.0, 75.0, 75.0),
            mass=5.5,
            capsules=(
                ((0.0, 0.0, 0.57), (0.0, 0.0, 0.62), 0.05),
                ((0.01, 0.0, 0.68), (0.01, 0.0, 0.74), 0.095),
            ),
            sensors=((0.0, 0.0, 0.58), (0.01, 0.0, 0.71)),
        ),
        *_arm(RIGHT),
        *_arm(LEFT),
    ]


@dataclass(frozen=True)
class HumanConfig:
    """How the human is actuated; see docs/human.md for the mapping."""

    actuation: str = (
        "pd"  # "pd": action = absolute PD target around rest; "torque": action x 10 N m
    )
    kp: float = 100.0  # computed-torque PD gains (critically damped: kd = 2 sqrt(kp))
    kd: float = 20.0
    max_speed: float = 3.0  # rad/s: the PD never asks a joint to move faster (see docs)
    torque_scale: float = 10.0  # the paper's mapping, used with actuation="torque"
    self_collision: bool = True
    specs: tuple[JointSpec, ...] = field(default_factory=lambda: tuple(body_specs()))


class Human:
    """A DART skeleton in its own world, with capsules, sensors and the arm chain."""

    N_DOFS = 22
    N_ACTIONS = 11

    def __init__(self, config: HumanConfig = HumanConfig(), dt: float = 0.01) -> None:
        if config.actuation not in ("pd", "torque"):
            raise ValueError(f"unknown actuation {config.actuation!r}: use 'pd' or 'torque'")
        self.config = config
        self.skeleton, self._bodies = _build_skeleton(config.specs)
        self.world = dart.simulation.World()
        self.world.setTimeStep(dt)
        self.world.setGravity([0.0, 0.0, -9.81])
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
    def reset(self, q: np.ndarray | None = None) -> None:
        """Put the body at rest (or at ``q``), motionless, with the PD target at rest."""
        self.skeleton.setPositions(self.rest if q is None else np.asarray(q, dtype=float))
        self.skeleton.setVelocities(np.zeros(self.N_DOFS))
        self.skeleton.clearExternalForces()
        self.target = self.rest.copy()
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
        """Map an action in [-1, 1]^11 to PD targets (or torques); see docs/human.md."""
        a = np.asarray(action, dtype=float)
        if a.shape != (self.N_ACTIONS,):
            raise ValueError(f"human action must have shape ({self.N_ACTIONS},), got {a.shape}")
        if not np.isfinite(a).all():
            raise ValueError(f"human action must be finite, got {a.tolist()}")
        a = np.clip(a, -1.0, 1.0)
        if self.config.actuation == "torque":
            self._torque_action = a
            return
        i = self.actuated_index
        rest, lo, hi = self.rest[i], self.lower[i], self.upper[i]
        self.target[i] = np.where(a >= 0.0, rest + a * (hi - rest), rest + a * (rest - lo))

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
        inertial = np.asarray(skel.getMassMatrix()) @ (cfg.kd * (speed - dq))
        bias = np.asarray(skel.getCoriolisAndGravityForces())
        tau = _within_limits(inertial, bias, self.max_torque)
        if self.config.actuation == "torque":
            tau[self.actuated_index] = self.config.torque_scale * self._torque_action
        self.torque = np.clip(tau, -self.max_torque, self.max_torque)  # the last commanded
        skel.setForces(self.torque)
        for k in np.flatnonzero(
            np.any(body_forces != 0.0, axis=1) | np.any(body_torques != 0.0, axis=1)
        ):
            self._bodies[k].addExtForce(body_forces[k], _ORIGIN, False, True)  # at the body origin
            self._bodies[k].addExtTorque(body_torques[k], False)
        self.world.step()

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
