"""The human's body plan as data: its joints, ranges, masses, capsules and haptic sensors.

The simulation (``human.py``) builds a DART skeleton from it; everything that only needs the
body's sizes (22 degrees of freedom, 11 actuated, 22 sensors) reads them here, without DART.
Frame: x forward, y to the human's left, z up; the pelvis at the origin; q = 0 is a T-pose.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

RIGHT, LEFT = -1.0, 1.0  # the sign of y on each side of the body
# m, the arm's segments (docs/human.md): the depths of dressing's stages are read off them
UPPER_ARM_LENGTH, FOREARM_LENGTH, HAND_LENGTH = 0.30, 0.26, 0.18
ARM_LENGTH = HAND_LENGTH + FOREARM_LENGTH + UPPER_ARM_LENGTH  # shoulder to fingertip
SHOULDER_Y, SHOULDER_Z = 0.19, 0.50  # m, each glenohumeral joint's |y| and height at q = 0


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
    sh = (0.0, SHOULDER_Y * s, SHOULDER_Z)  # glenohumeral joint
    el = (0.0, sh[1] + UPPER_ARM_LENGTH * s, SHOULDER_Z)  # the arm level in the T-pose
    wr = (0.0, el[1] + FOREARM_LENGTH * s, SHOULDER_Z)
    tip = (0.0, wr[1] + HAND_LENGTH * s, SHOULDER_Z)
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


BODY: tuple[JointSpec, ...] = tuple(body_specs())
N_DOFS = sum(len(spec.dofs) for spec in BODY)  # 22
N_ACTIONS = sum(len(spec.dofs) for spec in BODY if spec.actuated)  # 11: the human's action
N_SENSORS = sum(len(spec.sensors) for spec in BODY)  # 22 haptic sensors
DOF_NAMES = tuple(dof for spec in BODY for dof in spec.dofs)  # the order of q and of limits


@dataclass(frozen=True)
class BodyLimits:
    """What a body can do, one entry per degree of freedom in ``DOF_NAMES`` order: its joint
    ranges (rad), its torque caps (N m) and its rest pose (rad), which every range contains."""

    lower: np.ndarray
    upper: np.ndarray
    max_torque: np.ndarray
    rest: np.ndarray


def body_limits(specs: tuple[JointSpec, ...] = BODY) -> BodyLimits:
    """The ranges, torque caps and rest pose of a body plan."""
    moving = [spec for spec in specs if spec.dofs]
    return BodyLimits(*(np.concatenate([getattr(spec, name) for spec in moving])
                        for name in ("lower", "upper", "max_torque", "rest")))  # fmt: skip


def with_limits(specs: tuple[JointSpec, ...], limits: BodyLimits) -> tuple[JointSpec, ...]:
    """The body plan ``specs`` with the ranges and torque caps of ``limits`` (its rest pose
    kept): how a capability profile's body becomes the one the physics builds."""
    changed, start = [], 0
    for spec in specs:
        part = slice(start, start + len(spec.dofs))
        start = part.stop
        values = {name: tuple(float(v) for v in getattr(limits, name)[part])
                  for name in ("lower", "upper", "max_torque")}  # fmt: skip
        changed.append(replace(spec, **values) if spec.dofs else spec)
    return tuple(changed)
