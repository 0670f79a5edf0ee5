"""Position-based (XPBD) cloth in Warp kernels, with two-way capsule contact and friction.

One ``step`` advances the cloth by one simulation step: integrate, drive the pinned vertices
with the gripper, then iterate distance constraints (stretch, shear, bending, spans), tethers to
the pinned vertices and capsule collisions; finally the velocity update with Coulomb friction,
and the contact wrenches that go back to the body. All of it is captured once as a Warp graph,
so a step is a single replay. The distance constraints run Gauss-Seidel in colour order:
constraints of one colour share no vertex, so each colour is race-free in parallel on CUDA, and
on the CPU (where a kernel runs serially) the independence of neighbours keeps the pipeline full.

The arrays are grouped as in Newton's XPBD solver: the model (what the cloth is, fixed), its
state (positions, velocities), the control (the gripper and the body's capsules for the next
step), the per-step contacts and the outputs read back by the scene. Kernels: ``cloth_kernels``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import warp as wp

from . import cloth_kernels as k
from .clock import SIM_DT
from .geometry import GRAVITY

MAX_CAPSULES = 32  # the broadphase keeps one bit per capsule in an int32


@dataclass(frozen=True)
class ClothConfig:
    """Solver settings; see docs/cloth.md for how they were chosen."""

    iterations: int = 14  # constraint iterations per substep
    substeps: int = 1  # substeps per simulation step
    stretch_compliance: float = 0.0  # m/N, XPBD compliance of mesh edges (0: inextensible)
    bend_compliance: float = 0.5  # m/N, of the cross edges that resist folding (soft)
    bend_iterations: int = 2  # bending is soft: it converges in the first few iterations
    shear_iterations: int = 5  # the grid's diagonals: fabric shears easily
    contact_every: int = 2  # tethers and collisions every this many iterations, and the last
    tether_slack: float = 0.0  # tethers allow this fraction beyond the rest geodesic length
    span_steps: tuple[int, ...] = (4, 12)  # grid steps of the long-range straight spans
    span_slack: float = 0.005  # spans allow this fraction beyond their rest length
    span_iterations: int = 3  # spans carry the load early; the edges then refine it locally
    thickness: float = 0.005  # m, cloth half-thickness kept between a vertex and a capsule
    friction: float = 0.5  # Coulomb coefficient between cloth and skin
    tension_stiffness: float = 300.0  # N/m per edge: the tension a stretched edge pulls with
    damping: float = 2.0  # 1/s, linear velocity damping: air drag on a light fabric
    broadphase_margin: float = 0.05  # m, capsules nearer than this are tested in a substep
    gravity: tuple[float, float, float] = GRAVITY
    launch_per_color: bool | None = None  # None: one launch per colour on CUDA, one in all on CPU


@dataclass(frozen=True)
class ClothMesh:
    """What the cloth is made of: the gown's mesh, its constraints and its held vertices."""

    positions: np.ndarray  # (N, 3) m
    masses: np.ndarray  # (N,) kg
    triangles: np.ndarray  # (T, 3)
    rest_areas: np.ndarray  # (T,) m^2
    edges: np.ndarray  # (E, 2) mesh edges: the stretch and shear constraints
    edge_rest: np.ndarray  # (E,) m
    shear_edges: np.ndarray  # (E,) bool: the grid's diagonals
    bend_pairs: np.ndarray  # (B, 2) vertices across an edge: the bending constraints
    bend_rest: np.ndarray  # (B,) m
    pinned: np.ndarray  # vertices the gripper holds
    tether_anchor: np.ndarray  # (N,) each vertex's pinned anchor, -1 for none
    tether_length: np.ndarray  # (N,) m, the rest geodesic to it
    spans: np.ndarray  # (S, 2) pairs along straight pattern lines (long-range, one-sided)
    span_rest: np.ndarray  # (S,) m


@dataclass(frozen=True)
class ContactBodies:
    """The body the cloth touches: capsules on bodies, haptic sensors, the end effector."""

    n_bodies: int
    capsule_body: np.ndarray  # (C,) body of each capsule
    capsule_radius: np.ndarray  # (C,) m
    n_sensors: int
    effector_body: int  # the body whose contacts count as the end effector's


def init_warp() -> None:
    """Initialise Warp; if nothing chose a kernel cache before, use dressbench's own
    (``DRESSBENCH_WARP_CACHE``, default ~/.cache/dressbench/warp) and keep Warp's info lines
    (its banner, module loads) out of the output: stdout is for dressbench's results."""
    if wp.config.kernel_cache_dir is None:  # Warp fills it in when it initialises
        default = str(Path.home() / ".cache" / "dressbench" / "warp")
        wp.config.kernel_cache_dir = os.environ.get("DRESSBENCH_WARP_CACHE", default)
        wp.config.log_level = wp.LOG_WARNING  # no banner, no module-load lines
    wp.init()


def color_constraints(pairs: np.ndarray) -> np.ndarray:
    """Greedy colouring: no two constraints of one colour share a vertex (construction only)."""
    used: dict[int, int] = {}
    colors = np.empty(len(pairs), dtype=np.int64)
    for n, (i, j) in enumerate(pairs.tolist()):
        taken = used.get(i, 0) | used.get(j, 0)
        c = (~taken & (taken + 1)).bit_length() - 1  # lowest free colour
        colors[n] = c
        used[i] = used.get(i, 0) | (1 << c)
        used[j] = used.get(j, 0) | (1 << c)
    return colors


def _write(array: wp.array, data: np.ndarray) -> None:
    """Copy host data into a Warp array: in place through a cached view on the CPU."""
    if array.device.is_cpu:
        view = getattr(array, "_host_view", None)
        if view is None:
            view = array._host_view = array.numpy()
        view[...] = data
    else:
        array.assign(np.ascontiguousarray(data, dtype=np.float32))


class _DistanceSet:
    """One family of distance constraints (stretch, shear, bending or spans), sorted by colour.

    ``alpha_tilde`` (compliance / h^2) > 0 makes them soft (XPBD, with multipliers); 0 makes
    them hard, solved with each end's share of the correction precomputed (the pins never
    change). ``one_sided`` constraints only keep their ends from moving farther apart than the
    rest length."""

    def __init__(
        self, pairs, rest, alpha_tilde: float, inv_mass, device, one_sided: bool = False
    ) -> None:
        pairs = np.asarray(pairs, dtype=np.int32).reshape(-1, 2)
        colors = color_constraints(pairs)
        order = np.argsort(colors, kind="stable")
        counts = np.bincount(colors, minlength=1)
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        self.color_ranges = list(zip(starts.tolist(), counts.tolist(), strict=True))
        self.size = len(pairs)
        self.one_sided = one_sided
        pairs, rest = pairs[order], np.asarray(rest, dtype=float)[order]
        self.pairs = wp.array(pairs, dtype=wp.vec2i, device=device)
        self.rest = wp.array(rest, dtype=float, device=device)
        self.alpha_tilde = float(alpha_tilde)
        if one_sided and self.alpha_tilde > 0.0:
            raise ValueError("one-sided distance constraints are hard (alpha_tilde = 0)")
        self.lam = wp.zeros(self.size if self.soft else 0, dtype=float, device=device)
        w = np.asarray(inv_mass, dtype=float)[pairs]
        total = w.sum(axis=1, keepdims=True)
        share = np.divide(w, total, out=np.zeros_like(w), where=total > 0.0)
        self.share_rest = wp.array(np.column_stack([share, rest]), dtype=wp.vec3, device=device)

    @property
    def soft(self) -> bool:
        return self.alpha_tilde > 0.0


class _Model:
    """What the cloth is, on the device: masses, constraints, pins, tethers, triangles, and the
    capsules' radii and bodies. Fixed after construction."""

    def __init__(self, mesh: ClothMesh, bodies: ContactBodies, config: ClothConfig, h, device):
        def arr(a, dtype):
            return wp.array(np.ascontiguousarray(a), dtype=dtype, device=device)

        self.n = len(mesh.positions)
        self.pinned = np.asarray(mesh.pinned, dtype=np.int32)
        self.triangles = np.asarray(mesh.triangles, dtype=np.int32)
        masses = np.asarray(mesh.masses, dtype=float)
        inv_mass = np.where(masses > 0, 1.0 / np.maximum(masses, 1e-12), 0.0)
        inv_mass[self.pinned] = 0.0
        self.inv_mass = arr(inv_mass, float)
        self.mass = arr(masses, float)
        shear = np.asarray(mesh.shear_edges, dtype=bool)
        edges, edge_rest = np.asarray(mesh.edges), np.asarray(mesh.edge_rest)
        stiff = config.stretch_compliance / h**2
        self.stretch = _DistanceSet(edges[~shear], edge_rest[~shear], stiff, inv_mass, device)
        self.shear = _DistanceSet(edges[shear], edge_rest[shear], stiff, inv_mass, device)
        soft = config.bend_compliance / h**2
        self.bend = _DistanceSet(mesh.bend_pairs, mesh.bend_rest, soft, inv_mass, device)
        span_length = np.asarray(mesh.span_rest) * (1.0 + config.span_slack)
        self.spans = _DistanceSet(mesh.spans, span_length, 0.0, inv_mass, device, one_sided=True)
        self.tether_anchor = arr(mesh.tether_anchor, int)
        self.tether_length = arr(
            np.asarray(mesh.tether_length) * (1.0 + config.tether_slack), float
        )
        self.tris = arr(self.triangles, wp.vec3i)
        self.rest_area = arr(mesh.rest_areas, float)
        self.pin_index = arr(self.pinned, int)
        self.pin_local = arr(np.asarray(mesh.positions)[self.pinned], wp.vec3)
        self.substep_fraction = arr(np.arange(1, config.substeps + 1) / config.substeps, float)
        self.cap_r = arr(bodies.capsule_radius, float)
        self.cap_body = arr(bodies.capsule_body, int)


class _State:
    """Where the cloth is: positions, their start-of-step copy, velocities."""

    def __init__(self, positions: np.ndarray, device) -> None:
        self.x = wp.array(positions, dtype=wp.vec3, device=device)
        self.x_prev = wp.array(positions, dtype=wp.vec3, device=device)
        self.v = wp.zeros(len(positions), dtype=wp.vec3, device=device)


class _Control:
    """What moves the cloth in the next step: the gripper's and the capsules' poses at its
    start and end (with the capsules' boxes for the broadphase), the body and sensor frames."""

    def __init__(self, radii: wp.array, bodies: ContactBodies, device) -> None:
        identity = np.array([[0, 0, 0, 0, 0, 0, 1]], dtype=np.float32)
        self.gripper = wp.array(identity, dtype=wp.transform, device=device)
        self.gripper_prev = wp.array(identity, dtype=wp.transform, device=device)
        vec3s = {"dtype": wp.vec3, "device": device}
        n = radii.shape[0]
        self.capsules = k.Capsules()
        for name in ("a", "b", "a_prev", "b_prev", "lo", "hi"):
            setattr(self.capsules, name, wp.zeros(n, **vec3s))
        self.capsules.r = radii
        self.capsules.count = n
        self.body_origin = wp.zeros(bodies.n_bodies, **vec3s)
        self.sensors = wp.zeros(bodies.n_sensors, **vec3s)


class _Contacts:
    """Per-vertex scratch of one step: capsules near each vertex, the capsule it touches and
    how far it was pushed, the pull of its stretched edges, its normal, and the force and
    point of its contact on the body."""

    def __init__(self, n: int, device) -> None:
        vec3s = {"dtype": wp.vec3, "device": device}
        self.mask = wp.zeros(n, dtype=int, device=device)
        self.cap = wp.full(n, -1, dtype=int, device=device)
        self.push = wp.zeros(n, **vec3s)
        self.tension = wp.zeros(n, **vec3s)
        self.normals = wp.zeros(n, **vec3s)
        self.force = wp.zeros(n, **vec3s)
        self.point = wp.zeros(n, **vec3s)


class _Outputs:
    """What the scene reads back: each body's wrench from the last step, and (accumulated since
    ``clear_haptics``) the sensor forces and sides, the end effector's contacts, and the largest
    speed and distance from the gripper."""

    def __init__(self, n: int, bodies: ContactBodies, device) -> None:
        vec3s = {"dtype": wp.vec3, "device": device}
        self.body_force = wp.zeros(bodies.n_bodies, **vec3s)
        self.body_torque = wp.zeros(bodies.n_bodies, **vec3s)
        self.sensor_force = wp.zeros(bodies.n_sensors, **vec3s)
        self.sensor_side = wp.zeros(bodies.n_sensors, dtype=float, device=device)
        self.effector_contact = wp.zeros(n, dtype=int, device=device)
        self.extremes = wp.zeros(2, dtype=float, device=device)  # max speed, max distance
        self.ratio = wp.zeros(1, dtype=float, device=device)  # the max area ratio, on demand


class Cloth:
    """The cloth on a Warp device and its captured step graph."""

    def __init__(
        self,
        mesh: ClothMesh,
        bodies: ContactBodies,
        config: ClothConfig = ClothConfig(),
        dt: float = SIM_DT,
        device: str = "cpu",
    ) -> None:
        if len(bodies.capsule_radius) > MAX_CAPSULES:
            raise ValueError(f"at most {MAX_CAPSULES} capsules, got {len(bodies.capsule_radius)}")
        init_warp()
        self.config = config
        self.device = wp.get_device(device)
        self.dt = dt
        self.bodies = bodies
        self.capsule_radius = np.asarray(bodies.capsule_radius, dtype=float)
        self._reach = config.thickness + config.broadphase_margin  # of the broadphase
        self.model = _Model(mesh, bodies, config, dt / config.substeps, self.device)
        self.state = _State(np.asarray(mesh.positions), self.device)
        self.control = _Control(self.model.cap_r, bodies, self.device)
        self.contacts = _Contacts(self.model.n, self.device)
        self.outputs = _Outputs(self.model.n, bodies, self.device)
        self._graph = None

    # ----------------------------------------------------------------------------- inputs
    def set_state(self, positions: np.ndarray, velocities: np.ndarray | None = None) -> None:
        """Overwrite vertex positions (and velocities, default zero)."""
        _write(self.state.x, positions)
        _write(self.state.v, np.zeros_like(positions) if velocities is None else velocities)

    def set_gripper(self, previous: np.ndarray, current: np.ndarray) -> None:
        """Gripper poses (x, y, z, qx, qy, qz, qw) at the start and end of the next step."""
        _write(self.control.gripper_prev, np.asarray(previous)[None])
        _write(self.control.gripper, np.asarray(current)[None])

    def set_body(
        self,
        capsules_prev: np.ndarray,
        capsules: np.ndarray,
        body_origins: np.ndarray,
        sensors: np.ndarray,
    ) -> None:
        """Capsule endpoints (C, 2, 3) at the start and end of the next step, and frames."""
        control, caps = self.control, self.control.capsules
        _write(caps.a_prev, capsules_prev[:, 0])
        _write(caps.b_prev, capsules_prev[:, 1])
        _write(caps.a, capsules[:, 0])
        _write(caps.b, capsules[:, 1])
        margin = self.capsule_radius[:, None] + self._reach
        _write(caps.lo, capsules.min(axis=1) - margin)
        _write(caps.hi, capsules.max(axis=1) + margin)
        _write(control.body_origin, body_origins)
        _write(control.sensors, sensors)

    def clear_haptics(self) -> None:
        """Start a new accumulation of sensor forces and end-effector contacts."""
        out = self.outputs
        out.sensor_force.zero_()
        out.sensor_side.zero_()
        out.effector_contact.zero_()
        out.extremes.zero_()

    # ----------------------------------------------------------------------------- stepping
    def step(self) -> None:
        """Advance by dt (captured as a graph on first use, replayed after)."""
        if self._graph is None:
            wp.load_module(k, device=self.device)  # compile outside the capture
            with wp.ScopedCapture(device=self.device) as capture:
                self._launch_step()
            self._graph = capture.graph
        wp.capture_launch(self._graph)

    def _launch(self, kernel, dim: int, inputs: list, outputs: list) -> None:
        wp.launch(kernel, dim, inputs=inputs, outputs=outputs, device=self.device)

    def _launch_step(self) -> None:
        cfg, m, s, c, ct, out = (self.config, self.model, self.state, self.control,
                                 self.contacts, self.outputs)  # fmt: skip
        h = self.dt / cfg.substeps
        self._launch(k.zero_vec3, self.bodies.n_bodies, [], [out.body_force])
        self._launch(k.zero_vec3, self.bodies.n_bodies, [], [out.body_torque])
        for substep in range(cfg.substeps):
            self._launch(k.integrate, m.n, [m.inv_mass, wp.vec3(*cfg.gravity), cfg.damping, h],
                         [s.x, s.x_prev, s.v, ct.cap, ct.push, ct.tension, ct.normals])  # fmt: skip
            self._launch(k.drive_pins, len(m.pinned),
                         [m.pin_index, m.pin_local, c.gripper_prev, c.gripper,
                          m.substep_fraction, substep], [s.x])  # fmt: skip
            self._launch(k.broadphase, m.n, [s.x, c.capsules, self._reach], [ct.mask])
            for constraints in (m.stretch, m.shear, m.bend):
                if constraints.soft:
                    self._launch(k.zero_float, constraints.size, [], [constraints.lam])
            for it in range(cfg.iterations):
                self._solve(m.stretch)
                if it < cfg.shear_iterations:
                    self._solve(m.shear)
                if it < cfg.bend_iterations:
                    self._solve(m.bend)
                if it < cfg.span_iterations:
                    self._solve(m.spans)
                if (cfg.iterations - 1 - it) % cfg.contact_every == 0:  # always the last one
                    self._collide()
            self._launch(k.edge_tension, m.stretch.size,
                         [s.x, m.stretch.pairs, m.stretch.rest, cfg.tension_stiffness],
                         [ct.tension])  # fmt: skip
            self._launch(k.finish, m.n,
                         [s.x, s.x_prev, m.inv_mass, m.mass, c.capsules, h, cfg.friction, ct.cap,
                          ct.push, ct.tension,
                          c.gripper],
                         [s.v, ct.force, ct.point, out.extremes])  # fmt: skip
            self._launch(k.vertex_normals, len(m.triangles), [s.x, m.tris], [ct.normals])
            weight = 1.0 / cfg.substeps  # the body wrench is the substep average
            self._launch(k.sum_body_wrenches, m.n,
                         [ct.cap, ct.force, ct.point, m.cap_body, c.body_origin,
                          self.bodies.effector_body, weight],
                         [out.body_force, out.body_torque, out.effector_contact])  # fmt: skip
            self._launch(k.bin_to_sensors, m.n,  # the sensors accumulate over steps
                         [ct.normals, ct.cap, ct.force, ct.point, c.sensors,
                          self.bodies.n_sensors, weight],
                         [out.sensor_force, out.sensor_side])  # fmt: skip

    def _collide(self) -> None:
        """Tethers and capsule collisions of the vertices, then of the triangles' centroids."""
        m, s, c, ct = self.model, self.state, self.control, self.contacts
        capsules = [c.capsules, self.config.thickness]
        self._launch(k.tether_and_collide, m.n,
                     [s.x_prev, m.inv_mass, m.tether_anchor, m.tether_length, ct.mask, *capsules],
                     [s.x, ct.cap, ct.push])  # fmt: skip
        self._launch(k.collide_triangles, len(m.triangles),
                     [s.x_prev, m.inv_mass, m.tris, ct.mask, *capsules],
                     [s.x, ct.cap, ct.push])  # fmt: skip

    def _solve(self, constraints: _DistanceSet) -> None:
        """Gauss-Seidel over the constraints, colour by colour.

        Constraints of one colour share no vertex, so a colour is race-free in parallel (one
        launch per colour on CUDA); on the CPU the kernel runs serially, so one launch over all
        colours in order is the same sweep, and the independence keeps the pipeline full.
        """
        per_color = self.config.launch_per_color
        if per_color is None:
            per_color = self.device.is_cuda
        ranges = constraints.color_ranges if per_color else [(0, constraints.size)]
        m, x = self.model, self.state.x
        for start, count in ranges:
            if not count:
                continue
            if constraints.soft:
                self._launch(k.solve_soft_distance, count,
                             [m.inv_mass, constraints.pairs, constraints.rest,
                              constraints.alpha_tilde, start], [x, constraints.lam])  # fmt: skip
            else:
                self._launch(k.solve_hard_distance, count,
                             [constraints.pairs, constraints.share_rest,
                              int(constraints.one_sided), start], [x])  # fmt: skip

    # ----------------------------------------------------------------------------- outputs
    def positions(self) -> np.ndarray:
        return self.state.x.numpy().astype(np.float64)

    def velocities(self) -> np.ndarray:
        return self.state.v.numpy().astype(np.float64)

    def max_area_ratio(self) -> float:
        """Largest triangle area over its rest area (the deformation metric), on the device."""
        m, ratio = self.model, self.outputs.ratio
        ratio.zero_()
        self._launch(k.max_area_ratio, len(m.triangles), [self.state.x, m.tris, m.rest_area],
                     [ratio])  # fmt: skip
        return float(ratio.numpy()[0])

    def extremes_since_clear(self) -> tuple[float, float]:
        """Largest vertex speed and distance from the gripper since ``clear_haptics``."""
        speed, distance = self.outputs.extremes.numpy()
        return float(speed), float(distance)

    def is_finite(self) -> bool:
        return bool(np.isfinite(self.state.x.numpy()).all() and
                    np.isfinite(self.state.v.numpy()).all())  # fmt: skip

    def body_wrenches(self) -> tuple[np.ndarray, np.ndarray]:
        """Per-body force and torque (about the body origin) from the last step, world frame."""
        out = self.outputs
        return out.body_force.numpy().astype(np.float64), out.body_torque.numpy().astype(float)

    def haptics(self) -> tuple[np.ndarray, np.ndarray]:
        """Summed sensor forces on the body and the signed inner/outer contact measure."""
        out = self.outputs
        return out.sensor_force.numpy().astype(np.float64), out.sensor_side.numpy().astype(float)

    def effector_contacts(self) -> np.ndarray:
        """Indices of vertices that touched the end effector since ``clear_haptics``."""
        return np.flatnonzero(self.outputs.effector_contact.numpy())

    def contacts_now(self) -> dict[str, np.ndarray]:
        """The last step's contacts: vertex, body, force on the body, and contact point."""
        ct = self.contacts
        cap = ct.cap.numpy()
        idx = np.flatnonzero(cap >= 0)
        return {
            "vertex": idx,
            "body": self.model.cap_body.numpy()[cap[idx]],
            "force": ct.force.numpy()[idx].astype(np.float64),
            "point": ct.point.numpy()[idx].astype(np.float64),
        }
