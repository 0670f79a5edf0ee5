"""Position-based (XPBD) cloth in Warp kernels, with two-way capsule contact and friction.

One ``step(dt)`` advances the cloth by one simulation step: integrate, drive the pinned
vertices with the gripper, then iterate distance constraints (stretch + bending), tethers to the
pinned vertices, and capsule collisions; finally velocity update with Coulomb friction and the
contact wrenches that go back to the body. All of it is captured once as a Warp graph, so a step
is a single replay. The distance constraints run Gauss-Seidel in colour order: constraints of one
colour share no vertex, so each colour is race-free in parallel on CUDA, and on the CPU (where a
kernel runs serially) the independence of neighbours keeps the pipeline full.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import warp as wp

_CACHE = os.environ.get(
    "DRESSBENCH_WARP_CACHE", str(Path.home() / ".cache" / "dressbench" / "warp")
)
wp.config.kernel_cache_dir = _CACHE
wp.config.quiet = True

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
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    launch_per_color: bool | None = None  # None: one launch per colour on CUDA, one in all on CPU


@wp.func
def closest_on_segment(p: wp.vec3, a: wp.vec3, b: wp.vec3) -> float:
    ab = b - a
    denom = wp.dot(ab, ab)
    if denom < 1.0e-12:
        return 0.0
    return wp.clamp(wp.dot(p - a, ab) / denom, 0.0, 1.0)


@wp.kernel
def _integrate(
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    v: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    gravity: wp.vec3,
    damping: float,
    h: float,
    contact_cap: wp.array(dtype=int),
    contact_push: wp.array(dtype=wp.vec3),
    tension: wp.array(dtype=wp.vec3),
    normals: wp.array(dtype=wp.vec3),
):
    """Predict positions under gravity and drag; clear the step's per-vertex accumulators."""
    i = wp.tid()
    x_prev[i] = x[i]
    contact_cap[i] = -1
    contact_push[i] = wp.vec3(0.0)
    tension[i] = wp.vec3(0.0)
    normals[i] = wp.vec3(0.0)
    if inv_mass[i] > 0.0:
        vi = (v[i] + gravity * h) * wp.max(0.0, 1.0 - damping * h)
        v[i] = vi
        x[i] = x[i] + vi * h


@wp.kernel
def _drive_pins(
    x: wp.array(dtype=wp.vec3),
    pin_index: wp.array(dtype=int),
    pin_local: wp.array(dtype=wp.vec3),
    gripper_prev: wp.array(dtype=wp.transform),
    gripper: wp.array(dtype=wp.transform),
    alpha: wp.array(dtype=float),
    substep: int,
):
    k = wp.tid()
    t = alpha[substep]
    pa = wp.transform_point(gripper_prev[0], pin_local[k])
    pb = wp.transform_point(gripper[0], pin_local[k])
    x[pin_index[k]] = pa + (pb - pa) * t


@wp.kernel
def _broadphase(
    x: wp.array(dtype=wp.vec3),
    cap_a: wp.array(dtype=wp.vec3),
    cap_b: wp.array(dtype=wp.vec3),
    cap_r: wp.array(dtype=float),
    cap_lo: wp.array(dtype=wp.vec3),
    cap_hi: wp.array(dtype=wp.vec3),
    n_caps: int,
    reach: float,
    mask: wp.array(dtype=int),
):
    """One bit per capsule within ``reach`` of the vertex (its box, then the exact distance)."""
    i = wp.tid()
    p = x[i]
    m = int(0)
    for c in range(n_caps):
        lo = cap_lo[c]
        hi = cap_hi[c]
        if (
            p[0] > lo[0]
            and p[1] > lo[1]
            and p[2] > lo[2]
            and p[0] < hi[0]
            and p[1] < hi[1]
            and p[2] < hi[2]
        ):
            a = cap_a[c]
            b = cap_b[c]
            if wp.length(p - (a + (b - a) * closest_on_segment(p, a, b))) < cap_r[c] + reach:
                m = m | (1 << c)
    mask[i] = m


@wp.kernel
def _zero_float(a: wp.array(dtype=float)):
    a[wp.tid()] = 0.0


@wp.kernel
def _zero_vec3(a: wp.array(dtype=wp.vec3)):
    a[wp.tid()] = wp.vec3(0.0)


@wp.kernel
def _solve_distance(
    x: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    pairs: wp.array(dtype=wp.vec2i),
    rest: wp.array(dtype=float),
    alpha: float,
    lam: wp.array(dtype=float),
    offset: int,
):
    """One soft XPBD distance constraint (compliance ``alpha`` > 0), in place."""
    k = wp.tid() + offset
    i = pairs[k][0]
    j = pairs[k][1]
    wi = inv_mass[i]
    wj = inv_mass[j]
    d = x[i] - x[j]
    length = wp.length(d)
    w = wi + wj + alpha
    if length < 1.0e-9 or w == 0.0:
        return
    dlam = (-(length - rest[k]) - alpha * lam[k]) / w
    lam[k] = lam[k] + dlam
    corr = d / length * dlam
    x[i] = x[i] + corr * wi
    x[j] = x[j] - corr * wj


@wp.kernel
def _solve_hard_distance(
    x: wp.array(dtype=wp.vec3),
    pairs: wp.array(dtype=wp.vec2i),
    share_rest: wp.array(dtype=wp.vec3),
    one_sided: int,
    offset: int,
):
    """One hard (PBD) distance constraint, in place: each end moves by its share of the
    correction (its inverse mass over the pair's, precomputed with the rest length in
    ``share_rest``). ``one_sided`` only pulls ends that are farther apart than the rest."""
    k = wp.tid() + offset
    i = pairs[k][0]
    j = pairs[k][1]
    c = share_rest[k]
    d = x[i] - x[j]
    length = wp.length(d)
    if length < 1.0e-9 or (one_sided != 0 and length <= c[2]):
        return
    corr = d * ((c[2] - length) / length)
    x[i] = x[i] + corr * c[0]
    x[j] = x[j] - corr * c[1]


@wp.func
def push_out(
    p: wp.vec3,
    p_prev: wp.vec3,
    a: wp.vec3,
    b: wp.vec3,
    a_prev: wp.vec3,
    b_prev: wp.vec3,
    radius: float,
    thickness: float,
) -> wp.vec3:
    """The displacement that takes point ``p`` out of a capsule to ``radius + thickness``, on
    the side it was on at the start of the step (zero if it is outside).

    A thin limb can move more than its radius in a step relative to the cloth; pushed out along
    the nearest normal, a point that crossed the axis would pass through the limb."""
    q = a + (b - a) * closest_on_segment(p, a, b)
    d = p - q
    dist = wp.length(d)
    r = radius + thickness
    if dist >= r:
        return wp.vec3(0.0)
    n = wp.vec3(0.0, 0.0, 1.0)
    if dist > 1.0e-9:
        n = d / dist
    d_prev = p_prev - (a_prev + (b_prev - a_prev) * closest_on_segment(p_prev, a_prev, b_prev))
    if wp.length(d_prev) > radius and wp.dot(d_prev, n) < 0.0:
        n = wp.normalize(d_prev)  # it came from the other side: back out there
        dist = wp.dot(d, n)
    return n * (r - dist)


@wp.kernel
def _tether_and_collide(
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    anchor: wp.array(dtype=int),
    max_length: wp.array(dtype=float),
    mask: wp.array(dtype=int),
    cap_a: wp.array(dtype=wp.vec3),
    cap_b: wp.array(dtype=wp.vec3),
    cap_a_prev: wp.array(dtype=wp.vec3),
    cap_b_prev: wp.array(dtype=wp.vec3),
    cap_r: wp.array(dtype=float),
    n_caps: int,
    thickness: float,
    contact_cap: wp.array(dtype=int),
    contact_push: wp.array(dtype=wp.vec3),
):
    """Keep each free vertex within its tether's length of its pinned anchor, then push it out
    of the capsules (see ``push_out``)."""
    i = wp.tid()
    if inv_mass[i] == 0.0:
        return
    p = x[i]
    a = anchor[i]
    if a >= 0:
        d = p - x[a]
        length = wp.length(d)
        if length > max_length[i]:
            p = x[a] + d * (max_length[i] / length)
    m = mask[i]
    c = int(0)
    while m != 0:  # only the capsules the broadphase found near
        if m & 1:
            push = push_out(
                p, x_prev[i], cap_a[c], cap_b[c], cap_a_prev[c], cap_b_prev[c], cap_r[c], thickness
            )
            if wp.length_sq(push) > 0.0:
                p = p + push
                contact_push[i] = contact_push[i] + push
                contact_cap[i] = c
        m = m >> 1
        c += 1
    x[i] = p


@wp.kernel
def _collide_triangles(
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    tris: wp.array(dtype=wp.vec3i),
    mask: wp.array(dtype=int),
    cap_a: wp.array(dtype=wp.vec3),
    cap_b: wp.array(dtype=wp.vec3),
    cap_a_prev: wp.array(dtype=wp.vec3),
    cap_b_prev: wp.array(dtype=wp.vec3),
    cap_r: wp.array(dtype=float),
    n_caps: int,
    thickness: float,
    contact_cap: wp.array(dtype=int),
    contact_push: wp.array(dtype=wp.vec3),
):
    """Push each triangle's centroid out of the capsules, moving its free vertices.

    Vertex contacts alone let a limb slip between the vertices of a triangle and part the
    fabric around itself (the triangle then straddles the limb, stretched for free)."""
    k = wp.tid()
    i0 = tris[k][0]
    i1 = tris[k][1]
    i2 = tris[k][2]
    m = mask[i0] | mask[i1] | mask[i2]
    w = inv_mass[i0] + inv_mass[i1] + inv_mass[i2]
    if m == 0 or w == 0.0:
        return
    p = (x[i0] + x[i1] + x[i2]) / 3.0
    p_prev = (x_prev[i0] + x_prev[i1] + x_prev[i2]) / 3.0
    c = int(0)
    while m != 0:
        if m & 1:
            push = push_out(
                p, p_prev, cap_a[c], cap_b[c], cap_a_prev[c], cap_b_prev[c], cap_r[c], thickness
            )
            if wp.length_sq(push) > 0.0:
                # the least-mass-weighted move of the vertices that moves the centroid by push
                s = 3.0 / w
                p = p + push
                for v in range(3):
                    vi = tris[k][v]
                    dv = push * (inv_mass[vi] * s)
                    wp.atomic_add(x, vi, dv)  # triangles share vertices: atomic on a GPU
                    if inv_mass[vi] > 0.0:
                        wp.atomic_add(contact_push, vi, dv)
                        contact_cap[vi] = c
        m = m >> 1
        c += 1


@wp.kernel
def _finish(
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    v: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    mass: wp.array(dtype=float),
    cap_a: wp.array(dtype=wp.vec3),
    cap_b: wp.array(dtype=wp.vec3),
    cap_a_prev: wp.array(dtype=wp.vec3),
    cap_b_prev: wp.array(dtype=wp.vec3),
    cap_r: wp.array(dtype=float),
    h: float,
    mu: float,
    contact_cap: wp.array(dtype=int),
    contact_push: wp.array(dtype=wp.vec3),
    contact_force: wp.array(dtype=wp.vec3),
    contact_point: wp.array(dtype=wp.vec3),
    tension: wp.array(dtype=wp.vec3),
    gripper: wp.array(dtype=wp.transform),
    extremes: wp.array(dtype=float),
):
    """New velocities with friction; the force each contact puts on the body; the step's
    largest speed and distance from the gripper (the divergence watch)."""
    i = wp.tid()
    vi = (x[i] - x_prev[i]) / h
    f = wp.vec3(0.0)
    c = contact_cap[i]
    if c >= 0 and inv_mass[i] > 0.0:  # held vertices' contacts are the hoop's, in DART
        t = closest_on_segment(x[i], cap_a[c], cap_b[c])
        q = cap_a[c] + (cap_b[c] - cap_a[c]) * t
        vs = ((cap_a[c] - cap_a_prev[c]) * (1.0 - t) + (cap_b[c] - cap_b_prev[c]) * t) / h
        d = x[i] - q
        n = wp.normalize(d)
        vrel = vi - vs
        vn = wp.dot(vrel, n)
        vt = vrel - n * vn
        vt_len = wp.length(vt)
        dvn = wp.length(contact_push[i]) / h
        dv_friction = wp.vec3(0.0)
        if vt_len > 1.0e-9:
            dv_friction = -vt * wp.min(1.0, mu * dvn / vt_len)
        vi = vi + dv_friction
        # the cloth's momentum change from contact, returned to the body with opposite sign
        f = -(contact_push[i] / h + dv_friction) * (mass[i] / h)
        # and the fabric's tension that presses the vertex onto the body: the body holds it
        # (with friction along the surface), so the reaction of the held cloth reaches the limb
        pull = tension[i]
        pull_n = wp.dot(pull, n)
        if pull_n < 0.0:
            along = pull - n * pull_n
            along_len = wp.length(along)
            f = f + n * pull_n
            if along_len > 1.0e-9:
                f = f + along * wp.min(1.0, -mu * pull_n / along_len)
        contact_point[i] = q + n * cap_r[c]
    v[i] = vi
    contact_force[i] = f
    wp.atomic_max(extremes, 0, wp.length(vi))
    wp.atomic_max(extremes, 1, wp.length(x[i] - wp.transform_get_translation(gripper[0])))


@wp.kernel
def _edge_tension(
    x: wp.array(dtype=wp.vec3),
    pairs: wp.array(dtype=wp.vec2i),
    rest: wp.array(dtype=float),
    stiffness: float,
    tension: wp.array(dtype=wp.vec3),
):
    """Each stretched edge pulls its two vertices toward each other with stiffness x stretch."""
    k = wp.tid()
    i = pairs[k][0]
    j = pairs[k][1]
    d = x[j] - x[i]
    length = wp.length(d)
    if length > rest[k]:
        f = d * (stiffness * (length - rest[k]) / length)
        wp.atomic_add(tension, i, f)
        wp.atomic_sub(tension, j, f)


@wp.kernel
def _max_area_ratio(
    x: wp.array(dtype=wp.vec3),
    tris: wp.array(dtype=wp.vec3i),
    rest_area: wp.array(dtype=float),
    out: wp.array(dtype=float),
):
    k = wp.tid()
    a = x[tris[k][0]]
    area = 0.5 * wp.length(wp.cross(x[tris[k][1]] - a, x[tris[k][2]] - a))
    wp.atomic_max(out, 0, area / rest_area[k])


@wp.kernel
def _vertex_normals(
    x: wp.array(dtype=wp.vec3), tris: wp.array(dtype=wp.vec3i), normals: wp.array(dtype=wp.vec3)
):
    k = wp.tid()
    a = tris[k][0]
    b = tris[k][1]
    c = tris[k][2]
    n = wp.cross(x[b] - x[a], x[c] - x[a])
    wp.atomic_add(normals, a, n)
    wp.atomic_add(normals, b, n)
    wp.atomic_add(normals, c, n)


@wp.kernel
def _aggregate(
    x: wp.array(dtype=wp.vec3),
    normals: wp.array(dtype=wp.vec3),
    contact_cap: wp.array(dtype=int),
    contact_force: wp.array(dtype=wp.vec3),
    contact_point: wp.array(dtype=wp.vec3),
    cap_body: wp.array(dtype=int),
    body_origin: wp.array(dtype=wp.vec3),
    sensors: wp.array(dtype=wp.vec3),
    n_sensors: int,
    effector_body: int,
    weight: float,
    body_force: wp.array(dtype=wp.vec3),
    body_torque: wp.array(dtype=wp.vec3),
    sensor_force: wp.array(dtype=wp.vec3),
    sensor_side: wp.array(dtype=float),
    effector_contact: wp.array(dtype=int),
):
    """Sum each contact into its body's wrench and its nearest haptic sensor."""
    i = wp.tid()
    c = contact_cap[i]
    if c < 0:
        return
    b = cap_body[c]
    f = contact_force[i] * weight
    p = contact_point[i]
    wp.atomic_add(body_force, b, f)
    wp.atomic_add(body_torque, b, wp.cross(p - body_origin[b], f))
    best = int(0)
    best_d = float(1.0e30)
    for s in range(n_sensors):
        d = wp.length_sq(sensors[s] - p)
        if d < best_d:
            best_d = d
            best = s
    wp.atomic_add(sensor_force, best, f)
    # force on the cloth is -f: along the outward normal means pushed from inside
    wp.atomic_add(sensor_side, best, -wp.dot(f, wp.normalize(normals[i])))
    if b == effector_body:
        effector_contact[i] = 1


def color_constraints(pairs: np.ndarray) -> np.ndarray:
    """Greedy colouring: no two constraints of one colour share a vertex (construction only)."""
    used: dict[int, int] = {}
    colors = np.empty(len(pairs), dtype=np.int64)
    for k, (i, j) in enumerate(pairs.tolist()):
        taken = used.get(i, 0) | used.get(j, 0)
        c = (~taken & (taken + 1)).bit_length() - 1  # lowest free colour
        colors[k] = c
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

    ``alpha_tilde`` > 0 makes them soft (XPBD, with multipliers); 0 makes them hard, solved
    with each end's share of the correction precomputed (the pins never change). ``one_sided``
    constraints only keep their ends from moving farther apart than the rest length."""

    def __init__(
        self, pairs, rest, alpha_tilde: float, inv_mass, arr, device, one_sided: bool = False
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
        self.pairs = arr(pairs, wp.vec2i)
        self.rest = arr(rest, float)
        self.alpha = float(alpha_tilde)
        if one_sided and self.alpha > 0.0:
            raise ValueError("one-sided distance constraints are hard (alpha_tilde = 0)")
        self.lam = wp.zeros(self.size if self.alpha > 0.0 else 0, dtype=float, device=device)
        w = np.asarray(inv_mass, dtype=float)[pairs]
        total = w.sum(axis=1, keepdims=True)
        share = np.divide(w, total, out=np.zeros_like(w), where=total > 0.0)
        self.share_rest = arr(np.column_stack([share, rest]), wp.vec3)


class Cloth:
    """Cloth state on a Warp device and its captured step graph."""

    def __init__(
        self,
        positions: np.ndarray,
        masses: np.ndarray,
        triangles: np.ndarray,
        rest_areas: np.ndarray,
        edges: np.ndarray,
        edge_rest: np.ndarray,
        bend_pairs: np.ndarray,
        bend_rest: np.ndarray,
        pinned: np.ndarray,
        tether_anchor: np.ndarray,
        tether_length: np.ndarray,
        n_bodies: int,
        n_sensors: int,
        effector_body: int,
        capsule_body: np.ndarray,
        capsule_radius: np.ndarray,
        config: ClothConfig = ClothConfig(),
        dt: float = 0.01,
        device: str = "cpu",
        shear_edges: np.ndarray | None = None,
        spans: np.ndarray | None = None,
        span_rest: np.ndarray | None = None,
    ) -> None:
        """``shear_edges`` marks the edges (the grid's diagonals) that resist shear, not
        stretch: a woven fabric shears easily, so they are solved in fewer iterations.
        ``spans`` are vertex pairs along straight lines of the flat pattern, kept no farther
        apart than ``span_rest`` (1 + slack): they carry a load across many edges in one
        projection, where the edges alone would need many iterations."""
        if len(capsule_radius) > MAX_CAPSULES:
            raise ValueError(f"at most {MAX_CAPSULES} capsules, got {len(capsule_radius)}")
        wp.init()
        self.config = config
        self.device = wp.get_device(device)
        self.dt = dt
        self.n = len(positions)
        self.n_caps = len(capsule_radius)
        self.n_bodies = n_bodies
        self.n_sensors = n_sensors
        self.effector_body = effector_body
        self.pinned = np.asarray(pinned, dtype=np.int32)
        self.triangles = np.asarray(triangles, dtype=np.int32)
        d = self.device

        def arr(a, dtype):
            return wp.array(np.ascontiguousarray(a), dtype=dtype, device=d)

        inv_mass = np.where(masses > 0, 1.0 / np.maximum(masses, 1e-12), 0.0)
        inv_mass[self.pinned] = 0.0
        h = dt / config.substeps
        self.x = arr(positions, wp.vec3)
        self.x_prev = arr(positions, wp.vec3)
        self.v = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.inv_mass = arr(inv_mass, float)
        self.mass = arr(masses, float)
        shear = np.zeros(len(edges), bool) if shear_edges is None else np.asarray(shear_edges)
        alpha = config.stretch_compliance / h**2
        self.constraint_sets = [
            _DistanceSet(edges[~shear], edge_rest[~shear], alpha, inv_mass, arr, d),
            _DistanceSet(edges[shear], edge_rest[shear], alpha, inv_mass, arr, d),
            _DistanceSet(bend_pairs, bend_rest, config.bend_compliance / h**2, inv_mass, arr, d),
        ]
        if spans is None:
            spans, span_rest = np.zeros((0, 2), np.int32), np.zeros(0)
        span_length = np.asarray(span_rest) * (1.0 + config.span_slack)
        self.spans = _DistanceSet(spans, span_length, 0.0, inv_mass, arr, d, one_sided=True)
        self.anchor = arr(tether_anchor, int)
        self.tether_length = arr(tether_length * (1.0 + config.tether_slack), float)
        self.tris = arr(self.triangles, wp.vec3i)
        self.pin_index = arr(self.pinned, int)
        self.pin_local = arr(positions[self.pinned], wp.vec3)
        identity = np.array([[0, 0, 0, 0, 0, 0, 1]], dtype=np.float32)
        self.gripper = arr(identity, wp.transform)
        self.gripper_prev = arr(identity, wp.transform)
        self.alpha_sub = arr(np.arange(1, config.substeps + 1) / config.substeps, float)
        self.cap_a = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_b = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_a_prev = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_b_prev = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_r = arr(capsule_radius, float)
        self.capsule_radius = np.asarray(capsule_radius, dtype=float)
        self._reach = config.thickness + config.broadphase_margin  # of the broadphase
        self.cap_lo = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_hi = wp.zeros(self.n_caps, dtype=wp.vec3, device=d)
        self.cap_body = arr(capsule_body, int)
        self.mask = wp.zeros(self.n, dtype=int, device=d)
        self.contact_cap = wp.full(self.n, -1, dtype=int, device=d)
        self.contact_push = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.contact_force = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.contact_point = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.normals = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.tension = wp.zeros(self.n, dtype=wp.vec3, device=d)
        self.body_origin = wp.zeros(n_bodies, dtype=wp.vec3, device=d)
        self.body_force = wp.zeros(n_bodies, dtype=wp.vec3, device=d)
        self.body_torque = wp.zeros(n_bodies, dtype=wp.vec3, device=d)
        self.sensors = wp.zeros(n_sensors, dtype=wp.vec3, device=d)
        self.sensor_force = wp.zeros(n_sensors, dtype=wp.vec3, device=d)
        self.sensor_side = wp.zeros(n_sensors, dtype=float, device=d)
        self.effector_contact = wp.zeros(self.n, dtype=int, device=d)
        self.extremes = wp.zeros(2, dtype=float, device=d)  # max speed, max distance to gripper
        self.rest_area = arr(rest_areas, float)
        self._ratio = wp.zeros(1, dtype=float, device=d)
        self._graph = None

    # ----------------------------------------------------------------------------- inputs
    def set_state(self, positions: np.ndarray, velocities: np.ndarray | None = None) -> None:
        """Overwrite vertex positions (and velocities, default zero)."""
        _write(self.x, positions)
        _write(self.v, np.zeros_like(positions) if velocities is None else velocities)

    def set_gripper(self, previous: np.ndarray, current: np.ndarray) -> None:
        """Gripper poses (x, y, z, qx, qy, qz, qw) at the start and end of the next step."""
        _write(self.gripper_prev, np.asarray(previous)[None])
        _write(self.gripper, np.asarray(current)[None])

    def set_body(
        self,
        capsules_prev: np.ndarray,
        capsules: np.ndarray,
        body_origins: np.ndarray,
        sensors: np.ndarray,
    ) -> None:
        """Capsule endpoints (C, 2, 3) at the start and end of the next step, and frames."""
        _write(self.cap_a_prev, capsules_prev[:, 0])
        _write(self.cap_b_prev, capsules_prev[:, 1])
        _write(self.cap_a, capsules[:, 0])
        _write(self.cap_b, capsules[:, 1])
        margin = self.capsule_radius[:, None] + self._reach
        _write(self.cap_lo, capsules.min(axis=1) - margin)
        _write(self.cap_hi, capsules.max(axis=1) + margin)
        _write(self.body_origin, body_origins)
        _write(self.sensors, sensors)

    def clear_haptics(self) -> None:
        """Start a new accumulation of sensor forces and end-effector contacts."""
        self.sensor_force.zero_()
        self.sensor_side.zero_()
        self.effector_contact.zero_()
        self.extremes.zero_()

    # ----------------------------------------------------------------------------- stepping
    def step(self) -> None:
        """Advance by dt (captured as a graph on first use, replayed after)."""
        if self._graph is None:
            wp.load_module(__name__, device=self.device)  # compile outside the capture
            with wp.ScopedCapture(device=self.device) as capture:
                self._launch_step()
            self._graph = capture.graph
        wp.capture_launch(self._graph)

    def _launch_step(self) -> None:
        cfg = self.config
        d = self.device
        n = self.n
        h = self.dt / cfg.substeps
        wp.launch(_zero_vec3, self.n_bodies, [self.body_force], device=d)
        wp.launch(_zero_vec3, self.n_bodies, [self.body_torque], device=d)
        for s in range(cfg.substeps):
            wp.launch(
                _integrate,
                n,
                [
                    self.x,
                    self.x_prev,
                    self.v,
                    self.inv_mass,
                    wp.vec3(*cfg.gravity),
                    cfg.damping,
                    h,
                    self.contact_cap,
                    self.contact_push,
                    self.tension,
                    self.normals,
                ],
                device=d,
            )
            wp.launch(
                _drive_pins,
                len(self.pinned),
                [
                    self.x,
                    self.pin_index,
                    self.pin_local,
                    self.gripper_prev,
                    self.gripper,
                    self.alpha_sub,
                    s,
                ],
                device=d,
            )
            wp.launch(
                _broadphase,
                n,
                [
                    self.x,
                    self.cap_a,
                    self.cap_b,
                    self.cap_r,
                    self.cap_lo,
                    self.cap_hi,
                    self.n_caps,
                    self._reach,
                    self.mask,
                ],
                device=d,
            )
            for cs in self.constraint_sets:
                if cs.alpha > 0.0:  # hard constraints carry no multiplier
                    wp.launch(_zero_float, cs.size, [cs.lam], device=d)
            stretch, shear, bend = self.constraint_sets
            for it in range(cfg.iterations):
                self._solve(stretch)
                if it < cfg.shear_iterations:
                    self._solve(shear)
                if it < cfg.bend_iterations:
                    self._solve(bend)
                if it < cfg.span_iterations:
                    self._solve(self.spans)
                if (cfg.iterations - 1 - it) % cfg.contact_every == 0:  # always the last one
                    wp.launch(
                        _tether_and_collide,
                        n,
                        [
                            self.x,
                            self.x_prev,
                            self.inv_mass,
                            self.anchor,
                            self.tether_length,
                            self.mask,
                            self.cap_a,
                            self.cap_b,
                            self.cap_a_prev,
                            self.cap_b_prev,
                            self.cap_r,
                            self.n_caps,
                            cfg.thickness,
                            self.contact_cap,
                            self.contact_push,
                        ],
                        device=d,
                    )
                    wp.launch(
                        _collide_triangles,
                        len(self.triangles),
                        [
                            self.x,
                            self.x_prev,
                            self.inv_mass,
                            self.tris,
                            self.mask,
                            self.cap_a,
                            self.cap_b,
                            self.cap_a_prev,
                            self.cap_b_prev,
                            self.cap_r,
                            self.n_caps,
                            cfg.thickness,
                            self.contact_cap,
                            self.contact_push,
                        ],
                        device=d,
                    )
            wp.launch(
                _edge_tension,
                stretch.size,
                [self.x, stretch.pairs, stretch.rest, cfg.tension_stiffness, self.tension],
                device=d,
            )
            wp.launch(
                _finish,
                n,
                [
                    self.x,
                    self.x_prev,
                    self.v,
                    self.inv_mass,
                    self.mass,
                    self.cap_a,
                    self.cap_b,
                    self.cap_a_prev,
                    self.cap_b_prev,
                    self.cap_r,
                    h,
                    cfg.friction,
                    self.contact_cap,
                    self.contact_push,
                    self.contact_force,
                    self.contact_point,
                    self.tension,
                    self.gripper,
                    self.extremes,
                ],
                device=d,
            )
            wp.launch(
                _vertex_normals, len(self.triangles), [self.x, self.tris, self.normals], device=d
            )
            wp.launch(
                _aggregate,
                n,
                [
                    self.x,
                    self.normals,
                    self.contact_cap,
                    self.contact_force,
                    self.contact_point,
                    self.cap_body,
                    self.body_origin,
                    self.sensors,
                    self.n_sensors,
                    self.effector_body,
                    1.0 / cfg.substeps,
                    self.body_force,
                    self.body_torque,
                    self.sensor_force,
                    self.sensor_side,
                    self.effector_contact,
                ],
                device=d,
            )
            # the body wrench is the substep average; the sensors accumulate over steps

    def _solve(self, cs: _DistanceSet) -> None:
        """Gauss-Seidel over the constraints, colour by colour.

        Constraints of one colour share no vertex, so a colour is race-free in parallel (one
        launch per colour on CUDA); on the CPU the kernel runs serially, so one launch over all
        colours in order is the same sweep, and the independence keeps the pipeline full.
        """
        per_color = self.config.launch_per_color
        if per_color is None:
            per_color = self.device.is_cuda
        ranges = cs.color_ranges if per_color else [(0, cs.size)]
        for start, count in ranges:
            if not count:
                continue
            if cs.alpha > 0.0:
                inputs = [self.x, self.inv_mass, cs.pairs, cs.rest, cs.alpha, cs.lam, start]
                wp.launch(_solve_distance, count, inputs, device=self.device)
            else:
                inputs = [self.x, cs.pairs, cs.share_rest, int(cs.one_sided), start]
                wp.launch(_solve_hard_distance, count, inputs, device=self.device)

    # ----------------------------------------------------------------------------- outputs
    def positions(self) -> np.ndarray:
        return self.x.numpy().astype(np.float64)

    def max_area_ratio(self) -> float:
        """Largest triangle area over its rest area (the deformation metric), on the device."""
        self._ratio.zero_()
        wp.launch(
            _max_area_ratio,
            len(self.triangles),
            [self.x, self.tris, self.rest_area, self._ratio],
            device=self.device,
        )
        return float(self._ratio.numpy()[0])

    def extremes_since_clear(self) -> tuple[float, float]:
        """Largest vertex speed and distance from the gripper since ``clear_haptics``."""
        speed, distance = self.extremes.numpy()
        return float(speed), float(distance)

    def is_finite(self) -> bool:
        return bool(np.isfinite(self.x.numpy()).all() and np.isfinite(self.v.numpy()).all())

    def velocities(self) -> np.ndarray:
        return self.v.numpy().astype(np.float64)

    def body_wrenches(self) -> tuple[np.ndarray, np.ndarray]:
        """Per-body force and torque (about the body origin) from the last step, world frame."""
        return self.body_force.numpy().astype(np.float64), self.body_torque.numpy().astype(
            np.float64
        )

    def haptics(self) -> tuple[np.ndarray, np.ndarray]:
        """Summed sensor forces on the body and the signed inner/outer contact measure."""
        return self.sensor_force.numpy().astype(np.float64), self.sensor_side.numpy().astype(
            np.float64
        )

    def effector_contacts(self) -> np.ndarray:
        """Indices of vertices that touched the end effector since ``clear_haptics``."""
        return np.flatnonzero(self.effector_contact.numpy())

    def contacts(self) -> dict[str, np.ndarray]:
        """The last step's contacts: vertex, body, force on the body, and contact point."""
        cap = self.contact_cap.numpy()
        idx = np.flatnonzero(cap >= 0)
        return {
            "vertex": idx,
            "body": self.cap_body.numpy()[cap[idx]],
            "force": self.contact_force.numpy()[idx].astype(np.float64),
            "point": self.contact_point.numpy()[idx].astype(np.float64),
        }
