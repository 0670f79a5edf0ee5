"""One coupled dressing scene: the DART human, the Warp gown, and the gripper that holds it.

A ``Scene.step`` is one policy step: ``frame_skip`` simulation steps of ``dt`` each. In every
simulation step the human moves first (PD control plus the cloth's contact wrenches from the
previous step), then the cloth moves against the human's new capsules and the gripper's pose.
Contact forces are summed into the haptic sensors over the policy step and averaged.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from .body import BodyLimits, with_limits
from .clock import FRAME_SKIP, SIM_DT
from .cloth import Cloth, ClothConfig, ClothMesh, ContactBodies
from .garment import BACK, SEAM, Gown, GownConfig, make_gown, straight_pairs
from .geometry import interpolate_pose, quat_matrix, transform_points
from .gripper import GripperConfig, Hoop
from .human import Human, HumanConfig

IDENTITY_POSE = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])  # x y z qx qy qz qw


@dataclass(frozen=True)
class SceneConfig:
    """Physics settings of the whole scene (no RL here)."""

    gown: GownConfig = field(default_factory=GownConfig)
    cloth: ClothConfig = field(default_factory=ClothConfig)
    human: HumanConfig = field(default_factory=HumanConfig)
    gripper: GripperConfig = field(default_factory=GripperConfig)
    dt: float = SIM_DT  # s, one simulation step
    frame_skip: int = FRAME_SKIP  # simulation steps per policy step (see scene/clock.py)
    settle_steps: int = 200  # simulation steps to let the held gown come to rest, once
    max_speed: float = 30.0  # m/s, a faster cloth vertex means the simulation ran away
    max_distance: float = 3.0  # m from the gripper, a farther cloth vertex means the same
    max_joint_speed: float = 100.0  # rad/s, a faster human joint means the body blew up
    device: str = "cpu"


def actuated_scene(actuation: str, scene: SceneConfig | None = None) -> SceneConfig:
    """``scene`` (default settings if None) with the human driven by ``actuation``."""
    scene = scene or SceneConfig()
    return replace(scene, human=replace(scene.human, actuation=actuation))


def limited_scene(limits: BodyLimits, scene: SceneConfig) -> SceneConfig:
    """``scene`` with the human's joint ranges and torque caps those of ``limits``."""
    specs = with_limits(scene.human.specs, limits)
    return replace(scene, human=replace(scene.human, specs=specs))


@dataclass
class StepInfo:
    """What one policy step measured besides the state."""

    sim_failure: bool = False
    reason: str = ""


class Scene:
    """The coupled physics. Construct once, ``reset`` per episode, ``step`` per policy step."""

    def __init__(self, config: SceneConfig = SceneConfig()) -> None:
        self.config = config
        self.gown: Gown = make_gown(config.gown)
        self.human = Human(config.human, dt=config.dt)
        g = self.gown
        self.pinned = np.sort(g.feature_loop)  # the gripper holds the sleeve's opening
        anchor, length = tethers(g, self.pinned)
        spans = [straight_pairs(g, k) for k in config.cloth.span_steps]
        mesh = ClothMesh(
            positions=g.positions,
            masses=g.masses,
            triangles=g.triangles,
            rest_areas=g.rest_areas,
            edges=g.edges,
            edge_rest=g.edge_rest,
            shear_edges=np.all(np.abs(np.diff(g.pattern[g.edges], axis=1)[:, 0]) > 1e-9, axis=1),
            bend_pairs=g.bend_pairs,
            bend_rest=g.bend_rest,
            pinned=self.pinned,
            tether_anchor=anchor,
            tether_length=length,
            spans=np.concatenate([p for p, _ in spans] or [np.zeros((0, 2), np.int32)]),
            span_rest=np.concatenate([r for _, r in spans] or [np.zeros(0)]),
        )
        bodies = ContactBodies(
            n_bodies=len(self.human.body_names),
            capsule_body=self.human.capsule_body,
            capsule_radius=self.human.capsule_radius,
            n_sensors=len(self.human.sensor_body),
            effector_body=self.human.body_names.index("hand_r"),
        )
        self.cloth = Cloth(mesh, bodies, config.cloth, dt=config.dt, device=config.device)
        self.hoop = Hoop(self.human, g.positions[g.feature_loop], config.gripper)
        self._rest_shape = _settled_shape(self)
        self.gripper_pose = IDENTITY_POSE.copy()
        self.failed = False
        self.failure_reason = ""
        self.time = 0.0
        self.haptic_forces = np.zeros((len(self.human.sensor_body), 3))
        self.haptic_sides = np.zeros(len(self.human.sensor_body))
        self.contact_force = np.zeros(3)  # total cloth force on the body, mean over the step

    # ----------------------------------------------------------------------------- episode
    def reset(
        self,
        gripper_pose: np.ndarray,
        human_q: np.ndarray | None = None,
        involuntary: np.ndarray | None = None,
    ) -> None:
        """Human at rest (or ``human_q``), making the ``involuntary`` joint accelerations if
        given (``Human.reset``); the settled gown held at ``gripper_pose``."""
        self.human.reset(human_q, involuntary)
        self.gripper_pose = np.asarray(gripper_pose, dtype=float).copy()
        self.cloth.set_state(transform_points(self.gripper_pose, self._rest_shape))
        self.cloth.set_gripper(self.gripper_pose, self.gripper_pose)
        self.hoop.reset(self.gripper_pose)
        self._transforms = self.human.body_transforms()
        self._capsules = self.human.capsules(self._transforms)
        self._body_forces = np.zeros((len(self.human.body_names), 3))
        self._body_torques = np.zeros_like(self._body_forces)
        self.cloth.clear_haptics()
        self.haptic_forces[:] = 0.0
        self.haptic_sides[:] = 0.0
        self.contact_force = np.zeros(3)
        self.failed = False
        self.failure_reason = ""
        self.time = 0.0

    def step(self, action: np.ndarray, gripper_pose: np.ndarray) -> StepInfo:
        """Advance one policy step, the gripper driven toward ``gripper_pose`` (where it ends,
        ``gripper_pose`` after the step, is short of it where the body stopped the rim); never
        raises on divergence."""
        if self.failed:
            return StepInfo(True, self.failure_reason)
        if not np.isfinite(action).all():  # a NaN target would poison the body's whole state
            return self.fail("the human's action is not finite")
        self.human.set_action(action)
        start, end = self.gripper_pose, np.asarray(gripper_pose, dtype=float)
        self.cloth.clear_haptics()
        n = self.config.frame_skip
        self.contact_force = np.zeros(3)
        hoop_forces = np.zeros_like(self.haptic_forces)
        hoop_sides = np.zeros_like(self.haptic_sides)
        for k in range(1, n + 1):
            self._frame(interpolate_pose(start, end, k / n))
            self.contact_force += self._body_forces.sum(axis=0) / n
            self._add_hoop_contacts(self.gripper_pose, hoop_forces, hoop_sides)
        self.contact_force += hoop_forces.sum(axis=0) / n
        forces, sides = self.cloth.haptics()
        self.haptic_forces = (forces + hoop_forces) / n
        self.haptic_sides = sides + hoop_sides
        self.time += n * self.config.dt
        reason = self._divergence()
        if reason:
            self.failed = True
            self.failure_reason = reason
        return StepInfo(self.failed, self.failure_reason)

    def _frame(self, command: np.ndarray) -> None:
        """One simulation step: the human and the driven rim in DART, then the cloth against
        the human's new capsules, its held loop moved to where the rim went."""
        human = self.human
        capsules_prev, held_prev = self._capsules, self.gripper_pose
        self.hoop.drive(command)
        human.step(self._body_forces, self._body_torques)
        self.gripper_pose = self.hoop.pose()
        T = human.body_transforms()
        self._transforms = T
        self._capsules = human.capsules(T)
        self.cloth.set_body(capsules_prev, self._capsules, T[:, :3, 3], human.sensors(T))
        self.cloth.set_gripper(held_prev, self.gripper_pose)
        self.cloth.step()
        self._body_forces, self._body_torques = self.cloth.body_wrenches()

    def fail(self, reason: str) -> StepInfo:
        """End the episode as failed from outside the physics (e.g. a non-finite reading)."""
        self.failed = True
        self.failure_reason = reason
        return StepInfo(True, reason)

    def _add_hoop_contacts(
        self, gripper: np.ndarray, forces: np.ndarray, sides: np.ndarray
    ) -> None:
        """Sum the held rim's contacts (solved by DART) into the nearest haptic sensors."""
        _, points, body_forces = self.hoop.contacts()
        if len(points) == 0:
            return
        sensors = self.human.sensors(self._transforms)
        nearest = np.argmin(((points[:, None] - sensors[None]) ** 2).sum(-1), axis=1)
        np.add.at(forces, nearest, body_forces)
        # pushing the rim along the opening's normal (into the sleeve) is an inner contact
        normal = quat_matrix(gripper[3:])[:, 0]
        np.add.at(sides, nearest, -(body_forces @ normal))

    def _divergence(self) -> str:
        if not self.cloth.is_finite():
            return "non-finite cloth state"
        if not self.human.is_finite():
            return "non-finite human state"
        joint_speed = float(np.abs(self.human.dq).max())
        if joint_speed > self.config.max_joint_speed:
            return f"joint speed {joint_speed:.3g} rad/s above {self.config.max_joint_speed} rad/s"
        speed, distance = self.cloth.extremes_since_clear()
        if speed > self.config.max_speed:
            return f"cloth speed {speed:.3g} m/s above {self.config.max_speed} m/s"
        if distance > self.config.max_distance:
            return f"cloth {distance:.3g} m from the gripper, beyond {self.config.max_distance} m"
        return ""

    # ----------------------------------------------------------------------------- state
    @property
    def transforms(self) -> np.ndarray:
        return self._transforms

    def cloth_positions(self) -> np.ndarray:
        return self.cloth.positions()

    def arm_chain(self) -> np.ndarray:
        return self.human.arm_chain(self._transforms)

    def effector_contacts(self) -> np.ndarray:
        return self.cloth.effector_contacts()


def tethers(gown: Gown, pinned: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each vertex's tether: its nearest pinned vertex and the geodesic length to it.

    Where a vertex and a pinned vertex lie on one sheet of the flat pattern, not across the open
    back, the straight pattern distance is the exact geodesic; elsewhere the shortest path along
    mesh edges (a few percent long) bounds it. A tether that is too long lets the gown sag.
    """
    e = gown.edges
    n = len(gown.pattern)
    graph = coo_matrix(
        (np.concatenate([gown.edge_rest] * 2), (np.r_[e[:, 0], e[:, 1]], np.r_[e[:, 1], e[:, 0]])),
        shape=(n, n),
    ).tocsr()
    along_edges = dijkstra(graph, indices=pinned)  # (P, V)
    straight = np.linalg.norm(gown.pattern[None, :] - gown.pattern[pinned, None], axis=-1)
    sheet, p_sheet = gown.sheet[None, :], gown.sheet[pinned, None]
    same_sheet = (sheet == p_sheet) | (sheet == SEAM) | (p_sheet == SEAM)
    across_slit = ((sheet == BACK) | (p_sheet == BACK)) & (
        gown.side[None, :] * gown.side[pinned, None] < 0
    )
    length = np.where(same_sheet & ~across_slit, np.minimum(straight, along_edges), along_edges)
    nearest = np.argmin(length, axis=0)
    anchor = pinned[nearest].astype(np.int32)
    anchor[pinned] = -1
    return anchor, length[nearest, np.arange(n)]


_SETTLED: dict[tuple, np.ndarray] = {}


def _settled_shape(scene: Scene) -> np.ndarray:
    """The gown hanging at rest from an identity gripper pose, simulated once per process."""
    cfg = scene.config
    key = (cfg.gown, cfg.cloth, cfg.settle_steps, cfg.dt, cfg.device)
    if key not in _SETTLED:
        cloth = scene.cloth
        far = np.full((len(scene.human.capsule_radius), 2, 3), 100.0)
        far[:, 1, 0] += 0.1
        cloth.set_state(scene.gown.positions)
        cloth.set_gripper(IDENTITY_POSE, IDENTITY_POSE)
        cloth.set_body(
            far,
            far,
            np.zeros((len(scene.human.body_names), 3)),
            np.full((len(scene.human.sensor_body), 3), 100.0),
        )
        for _ in range(cfg.settle_steps):
            cloth.step()
        _SETTLED[key] = cloth.positions()
    return _SETTLED[key]
