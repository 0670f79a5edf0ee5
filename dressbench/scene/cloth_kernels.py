"""The cloth's Warp kernels (see ``cloth.py`` for how a step launches them).

Each kernel's parameters list what it only reads, then what it writes (arrays it updates in
place, such as the positions a constraint moves, count as written): the launches pass them as
``inputs=`` and ``outputs=``.
"""

from __future__ import annotations

import warp as wp


@wp.func
def closest_on_segment(p: wp.vec3, a: wp.vec3, b: wp.vec3) -> float:
    ab = b - a
    denom = wp.dot(ab, ab)
    if denom < 1.0e-12:
        return 0.0
    return wp.clamp(wp.dot(p - a, ab) / denom, 0.0, 1.0)


@wp.struct
class Capsules:
    """The body's collision capsules at the start (``_prev``) and end of the step: endpoints,
    radii, and each one's box grown by the broadphase's reach."""

    a: wp.array(dtype=wp.vec3)
    b: wp.array(dtype=wp.vec3)
    a_prev: wp.array(dtype=wp.vec3)
    b_prev: wp.array(dtype=wp.vec3)
    r: wp.array(dtype=float)
    lo: wp.array(dtype=wp.vec3)
    hi: wp.array(dtype=wp.vec3)
    count: int


@wp.kernel
def integrate(
    inv_mass: wp.array(dtype=float),
    gravity: wp.vec3,
    damping: float,
    h: float,
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    v: wp.array(dtype=wp.vec3),
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
def drive_pins(
    pin_index: wp.array(dtype=int),
    pin_local: wp.array(dtype=wp.vec3),
    gripper_prev: wp.array(dtype=wp.transform),
    gripper: wp.array(dtype=wp.transform),
    fraction: wp.array(dtype=float),
    substep: int,
    x: wp.array(dtype=wp.vec3),
):
    """Move the held vertices with the gripper, ``fraction[substep]`` of the way through the
    step."""
    k = wp.tid()
    t = fraction[substep]
    pa = wp.transform_point(gripper_prev[0], pin_local[k])
    pb = wp.transform_point(gripper[0], pin_local[k])
    x[pin_index[k]] = pa + (pb - pa) * t


@wp.kernel
def broadphase(
    x: wp.array(dtype=wp.vec3),
    caps: Capsules,
    reach: float,
    mask: wp.array(dtype=int),
):
    """One bit per capsule within ``reach`` of the vertex (its box, then the exact distance)."""
    i = wp.tid()
    p = x[i]
    m = int(0)
    for c in range(caps.count):
        lo = caps.lo[c]
        hi = caps.hi[c]
        if (
            p[0] > lo[0]
            and p[1] > lo[1]
            and p[2] > lo[2]
            and p[0] < hi[0]
            and p[1] < hi[1]
            and p[2] < hi[2]
        ):
            a = caps.a[c]
            b = caps.b[c]
            if wp.length(p - (a + (b - a) * closest_on_segment(p, a, b))) < caps.r[c] + reach:
                m = m | (1 << c)
    mask[i] = m


@wp.kernel
def zero_float(a: wp.array(dtype=float)):
    a[wp.tid()] = 0.0


@wp.kernel
def zero_vec3(a: wp.array(dtype=wp.vec3)):
    a[wp.tid()] = wp.vec3(0.0)


@wp.kernel
def solve_soft_distance(
    inv_mass: wp.array(dtype=float),
    pairs: wp.array(dtype=wp.vec2i),
    rest: wp.array(dtype=float),
    alpha_tilde: float,
    offset: int,
    x: wp.array(dtype=wp.vec3),
    lam: wp.array(dtype=float),
):
    """One soft XPBD distance constraint (``alpha_tilde`` = compliance / h^2 > 0), in place."""
    k = wp.tid() + offset
    i = pairs[k][0]
    j = pairs[k][1]
    wi = inv_mass[i]
    wj = inv_mass[j]
    d = x[i] - x[j]
    length = wp.length(d)
    w = wi + wj + alpha_tilde
    if length < 1.0e-9 or w == 0.0:
        return
    dlam = (-(length - rest[k]) - alpha_tilde * lam[k]) / w
    lam[k] = lam[k] + dlam
    corr = d / length * dlam
    x[i] = x[i] + corr * wi
    x[j] = x[j] - corr * wj


@wp.kernel
def solve_hard_distance(
    pairs: wp.array(dtype=wp.vec2i),
    share_rest: wp.array(dtype=wp.vec3),
    one_sided: int,
    offset: int,
    x: wp.array(dtype=wp.vec3),
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
def push_out(p: wp.vec3, p_prev: wp.vec3, caps: Capsules, c: int, thickness: float) -> wp.vec3:
    """The displacement that takes point ``p`` out of capsule ``c`` to its radius +
    ``thickness``, on the side it was on at the start of the step (zero if it is outside).

    A thin limb can move more than its radius in a step relative to the cloth; pushed out along
    the nearest normal, a point that crossed the axis would pass through the limb."""
    a = caps.a[c]
    b = caps.b[c]
    a_prev = caps.a_prev[c]
    b_prev = caps.b_prev[c]
    radius = caps.r[c]
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
def tether_and_collide(
    x_prev: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    anchor: wp.array(dtype=int),
    max_length: wp.array(dtype=float),
    mask: wp.array(dtype=int),
    caps: Capsules,
    thickness: float,
    x: wp.array(dtype=wp.vec3),
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
            push = push_out(p, x_prev[i], caps, c, thickness)
            if wp.length_sq(push) > 0.0:
                p = p + push
                contact_push[i] = contact_push[i] + push
                contact_cap[i] = c
        m = m >> 1
        c += 1
    x[i] = p


@wp.kernel
def collide_triangles(
    x_prev: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    tris: wp.array(dtype=wp.vec3i),
    mask: wp.array(dtype=int),
    caps: Capsules,
    thickness: float,
    x: wp.array(dtype=wp.vec3),
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
            push = push_out(p, p_prev, caps, c, thickness)
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
def finish(
    x: wp.array(dtype=wp.vec3),
    x_prev: wp.array(dtype=wp.vec3),
    inv_mass: wp.array(dtype=float),
    mass: wp.array(dtype=float),
    caps: Capsules,
    h: float,
    mu: float,
    contact_cap: wp.array(dtype=int),
    contact_push: wp.array(dtype=wp.vec3),
    tension: wp.array(dtype=wp.vec3),
    gripper: wp.array(dtype=wp.transform),
    v: wp.array(dtype=wp.vec3),
    contact_force: wp.array(dtype=wp.vec3),
    contact_point: wp.array(dtype=wp.vec3),
    extremes: wp.array(dtype=float),
):
    """New velocities with friction; the force each contact puts on the body; the step's
    largest speed and distance from the gripper (the divergence watch)."""
    i = wp.tid()
    vi = (x[i] - x_prev[i]) / h
    f = wp.vec3(0.0)
    c = contact_cap[i]
    if c >= 0 and inv_mass[i] > 0.0:  # held vertices' contacts are the hoop's, in DART
        a = caps.a[c]
        b = caps.b[c]
        t = closest_on_segment(x[i], a, b)
        q = a + (b - a) * t
        vs = ((a - caps.a_prev[c]) * (1.0 - t) + (b - caps.b_prev[c]) * t) / h
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
        contact_point[i] = q + n * caps.r[c]
    v[i] = vi
    contact_force[i] = f
    wp.atomic_max(extremes, 0, wp.length(vi))
    wp.atomic_max(extremes, 1, wp.length(x[i] - wp.transform_get_translation(gripper[0])))


@wp.kernel
def edge_tension(
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
def max_area_ratio(
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
def vertex_normals(
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
def sum_body_wrenches(
    contact_cap: wp.array(dtype=int),
    contact_force: wp.array(dtype=wp.vec3),
    contact_point: wp.array(dtype=wp.vec3),
    cap_body: wp.array(dtype=int),
    body_origin: wp.array(dtype=wp.vec3),
    effector_body: int,
    weight: float,
    body_force: wp.array(dtype=wp.vec3),
    body_torque: wp.array(dtype=wp.vec3),
    effector_contact: wp.array(dtype=int),
):
    """Sum each contact (``weight`` of its force, a substep's share) into its body's wrench
    about the body origin; mark the vertices that touch the end effector."""
    i = wp.tid()
    c = contact_cap[i]
    if c < 0:
        return
    b = cap_body[c]
    f = contact_force[i] * weight
    wp.atomic_add(body_force, b, f)
    wp.atomic_add(body_torque, b, wp.cross(contact_point[i] - body_origin[b], f))
    if b == effector_body:
        effector_contact[i] = 1


@wp.kernel
def bin_to_sensors(
    normals: wp.array(dtype=wp.vec3),
    contact_cap: wp.array(dtype=int),
    contact_force: wp.array(dtype=wp.vec3),
    contact_point: wp.array(dtype=wp.vec3),
    sensors: wp.array(dtype=wp.vec3),
    n_sensors: int,
    weight: float,
    sensor_force: wp.array(dtype=wp.vec3),
    sensor_side: wp.array(dtype=float),
):
    """Add each contact's force to its nearest haptic sensor, with the side of the cloth it
    pressed: the force on the cloth is -f, so along the outward normal means from inside."""
    i = wp.tid()
    if contact_cap[i] < 0:
        return
    f = contact_force[i] * weight
    p = contact_point[i]
    best = int(0)
    best_d = float(1.0e30)
    for s in range(n_sensors):
        d = wp.length_sq(sensors[s] - p)
        if d < best_d:
            best_d = d
            best = s
    wp.atomic_add(sensor_force, best, f)
    wp.atomic_add(sensor_side, best, -wp.dot(f, wp.normalize(normals[i])))
