"""Specification of the procedural hospital gown (dressbench.scene.garment)."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from scipy.spatial import cKDTree

from dressbench.scene.garment import (
    BACK,
    BODY,
    FRONT,
    LEFT_SLEEVE,
    RIGHT_SLEEVE,
    SEAM,
    Gown,
    GownConfig,
    make_gown,
)

TARGETS = (1000, 2000, 4000)


@pytest.fixture(scope="module")
def gowns() -> dict[int, Gown]:
    return {n: make_gown(GownConfig(target_vertices=n)) for n in TARGETS}


@pytest.fixture(scope="module")
def gown(gowns: dict[int, Gown]) -> Gown:
    return gowns[2000]


@pytest.fixture(params=TARGETS, ids=lambda n: f"V{n}")
def any_gown(request: pytest.FixtureRequest, gowns: dict[int, Gown]) -> Gown:
    return gowns[request.param]


# ----------------------------------------------------------------------------- helpers


def directed_edges(tris: np.ndarray) -> np.ndarray:
    return np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])


def undirected_counts(tris: np.ndarray) -> Counter:
    return Counter(map(tuple, np.sort(directed_edges(tris), axis=1).tolist()))


def boundary_loops(tris: np.ndarray) -> list[list[int]]:
    """Boundary half-edges chained into loops (asserts each boundary vertex has one exit)."""
    counts = undirected_counts(tris)
    nxt: dict[int, int] = {}
    for a, b in directed_edges(tris).tolist():
        if counts[(min(a, b), max(a, b))] == 1:
            assert a not in nxt, f"vertex {a} is pinched (two boundary exits)"
            nxt[a] = b
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = nxt[v]
        assert v == start, "boundary does not close into a loop"
        loops.append(loop)
    return loops


def triangle_normals(p: np.ndarray, tris: np.ndarray) -> np.ndarray:
    return np.cross(p[tris[:, 1]] - p[tris[:, 0]], p[tris[:, 2]] - p[tris[:, 0]])


def signed_pattern_areas(g: Gown) -> np.ndarray:
    a, b, c = (g.pattern[g.triangles[:, k]] for k in range(3))
    return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


def triangle_sheet(g: Gown) -> np.ndarray:
    """FRONT/BACK per triangle: the sheet of its non-seam vertices (every one has some)."""
    s = g.sheet[g.triangles]
    assert (s != SEAM).any(axis=1).all()
    return np.where((s == FRONT).any(axis=1), FRONT, BACK)


def edge_lengths(p: np.ndarray, edges: np.ndarray) -> np.ndarray:
    return np.linalg.norm(p[edges[:, 0]] - p[edges[:, 1]], axis=1)


# ------------------------------------------------------------------------ resolution


@pytest.mark.parametrize("target", TARGETS)
def test_vertex_count_is_close_to_target(gowns: dict[int, Gown], target: int) -> None:
    assert abs(gowns[target].num_vertices - target) <= 0.15 * target


def test_feature_loop_has_a_sensible_count_at_default_resolution(gown: Gown) -> None:
    assert 15 <= len(gown.feature_loop) <= 25  # the paper's had 18, around a narrower opening


def test_resolution_refines_monotonically(gowns: dict[int, Gown]) -> None:
    hs = [gowns[n].h for n in TARGETS]
    loops = [len(gowns[n].feature_loop) for n in TARGETS]
    assert hs[0] > hs[1] > hs[2]
    assert loops[0] < loops[1] < loops[2]


def test_default_config_and_determinism() -> None:
    a, b = make_gown(), make_gown(GownConfig())
    assert a.config == GownConfig()
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.positions, b.positions)


# ------------------------------------------------------------------- arrays and pattern


def test_array_shapes_and_dtypes(any_gown: Gown) -> None:
    g = any_gown
    nv, nf, ne, nb = g.num_vertices, g.num_triangles, len(g.edges), len(g.bend_pairs)
    expected = {
        "positions": ((nv, 3), np.float64),
        "pattern": ((nv, 2), np.float64),
        "triangles": ((nf, 3), np.int32),
        "edges": ((ne, 2), np.int32),
        "bend_pairs": ((nb, 2), np.int32),
        "bend_edges": ((nb, 2), np.int32),
        "edge_rest": ((ne,), np.float64),
        "bend_rest": ((nb,), np.float64),
        "rest_areas": ((nf,), np.float64),
        "masses": ((nv,), np.float64),
        "feature_loop": ((len(g.feature_loop),), np.int32),
        "geodesic": ((nv,), np.float64),
        "sheet": ((nv,), np.int8),
        "region": ((nv,), np.int8),
    }
    for name, (shape, dtype) in expected.items():
        arr = getattr(g, name)
        assert arr.shape == shape, name
        assert arr.dtype == dtype, name
        assert np.isfinite(arr).all(), name


def test_pattern_is_the_t_shape_with_grid_lines_on_the_key_seams(gown: Gown) -> None:
    c, (u, v) = gown.config, gown.pattern.T
    half = 0.5 * c.body_width
    cuff = half + c.sleeve_length
    assert np.isclose(u.min(), -cuff) and np.isclose(u.max(), cuff)
    assert np.isclose(v.min(), 0.0) and np.isclose(v.max(), c.body_length)
    in_sleeves = np.abs(u) > half + 1e-9
    assert (v[in_sleeves] >= c.body_length - c.sleeve_width - 1e-9).all()
    columns = np.unique(np.round(u, 9))
    for line in (-half, -c.neck_half_width, 0.0, c.neck_half_width, half):
        assert np.isclose(columns, line, atol=1e-9).any(), f"no grid column at u = {line}"
    assert np.isclose(v, c.body_length - c.sleeve_width, atol=1e-9).any()
    spacings = np.diff(columns)
    assert spacings.max() < 1.3 * gown.h and spacings.min() > 0.7 * gown.h


def test_seam_vertices_lie_exactly_on_the_sewn_lines(gown: Gown) -> None:
    c, (u, v) = gown.config, gown.pattern[gown.sheet == SEAM].T
    half, arm = 0.5 * c.body_width, c.body_length - c.sleeve_width
    top = np.isclose(v, c.body_length) & (np.abs(u) >= c.neck_half_width - 1e-9)
    underarm = np.isclose(v, arm) & (np.abs(u) >= half - 1e-9)
    side = np.isclose(np.abs(u), half) & (v <= arm + 1e-9)
    assert (top | underarm | side).all()


def test_front_and_back_are_separate_except_at_seams_and_the_back_is_split(gown: Gown) -> None:
    # Every non-seam (u, v) node exists on the front and on the back; the back slit column
    # u = 0 exists twice on the back (open-back gown).
    keys = Counter(map(tuple, np.round(gown.pattern, 9).tolist()))
    multiplicity = np.array([keys[k] for k in map(tuple, np.round(gown.pattern, 9).tolist())])
    on_slit = np.isclose(gown.pattern[:, 0], 0.0)
    assert (multiplicity[gown.sheet == SEAM] == 1).all()
    assert (multiplicity[(gown.sheet != SEAM) & ~on_slit] == 2).all()
    assert (multiplicity[on_slit] == 3).all()
    assert (gown.sheet[on_slit] == BACK).sum() == 2 * (gown.sheet[on_slit] == FRONT).sum()


# -------------------------------------------------------------------------- topology


def test_mesh_is_a_manifold_with_boundary(any_gown: Gown) -> None:
    tris = any_gown.triangles
    counts = undirected_counts(tris)
    assert set(counts.values()) <= {1, 2}
    assert (tris[:, 0] != tris[:, 1]).all() and (tris[:, 1] != tris[:, 2]).all()
    assert (tris[:, 0] != tris[:, 2]).all()
    assert len(np.unique(np.sort(tris, axis=1), axis=0)) == len(tris)
    assert np.array_equal(np.unique(tris), np.arange(any_gown.num_vertices))
    assert (any_gown.rest_areas > 0.1 * any_gown.h**2).all()  # not degenerate


def test_orientation_is_consistent(any_gown: Gown) -> None:
    # Each directed edge occurs once: interior edges are traversed in opposite directions.
    directed = directed_edges(any_gown.triangles)
    assert len(np.unique(directed, axis=0)) == len(directed)


def test_front_is_counterclockwise_and_back_clockwise_on_the_pattern(gown: Gown) -> None:
    # Seen from the front (u to the right, v up) front normals face the viewer, back ones away.
    area = signed_pattern_areas(gown)
    sheet = triangle_sheet(gown)
    assert (area[sheet == FRONT] > 0).all() and (area[sheet == BACK] < 0).all()


def test_normals_point_out_of_the_garment_in_3d(gown: Gown) -> None:
    p, tris = gown.positions, gown.triangles
    n = triangle_normals(p, tris)
    centroid = p[tris].mean(axis=1)
    sleeve = (gown.region[tris] == RIGHT_SLEEVE).all(axis=1)
    assert ((n[sleeve, 1:] * centroid[sleeve, 1:]).sum(axis=1) > 0).all()  # away from x axis
    arm = gown.config.body_length - gown.config.sleeve_width
    lower = (gown.pattern[tris, 1] < arm - 1e-9).all(axis=1)
    sheet = triangle_sheet(gown)
    assert (n[lower & (sheet == FRONT), 1] > 0).all()
    assert (n[lower & (sheet == BACK), 1] < 0).all()


def test_open_boundaries_are_the_hem_with_back_slit_and_neck_plus_two_cuffs(
    any_gown: Gown,
) -> None:
    # The back slit runs from the neck to the hem, so neck, slit and hem form ONE boundary
    # loop; the other two are the cuffs.  Genus 0 with 3 boundaries: V - E + F = -1.
    g, c = any_gown, any_gown.config
    loops = boundary_loops(g.triangles)
    assert len(loops) == 3
    u, v = g.pattern.T
    cuff_u = 0.5 * c.body_width + c.sleeve_length
    expected = {
        "right cuff": np.isclose(u, -cuff_u),
        "left cuff": np.isclose(u, cuff_u),
        "hem+slit+neck": np.isclose(v, 0.0)
        | (np.isclose(u, 0.0) & (g.sheet == BACK))
        | (np.isclose(v, c.body_length) & (np.abs(u) <= c.neck_half_width + 1e-9)),
    }
    kinds = Counter()
    for loop in loops:
        for kind, members in expected.items():
            if members[loop].any():
                assert set(np.nonzero(members)[0].tolist()) <= set(loop), kind
                kinds[kind] += 1
    assert kinds == {"right cuff": 1, "left cuff": 1, "hem+slit+neck": 1}
    assert g.num_vertices - len(g.edges) + g.num_triangles == -1


def test_edges_are_the_unique_triangle_edges(any_gown: Gown) -> None:
    g = any_gown
    assert (g.edges[:, 0] < g.edges[:, 1]).all()
    expected = np.unique(np.sort(directed_edges(g.triangles), axis=1), axis=0)
    np.testing.assert_array_equal(g.edges, expected)


# ---------------------------------------------------------------------- rest state


def test_edge_rest_lengths_are_pattern_distances(any_gown: Gown) -> None:
    g = any_gown
    np.testing.assert_allclose(g.edge_rest, edge_lengths(g.pattern, g.edges), rtol=1e-12)
    assert (g.edge_rest > 0.5 * g.h).all() and (g.edge_rest < 2.0 * g.h).all()


def test_bend_pairs_are_the_wing_tips_of_every_interior_edge(gown: Gown) -> None:
    counts = undirected_counts(gown.triangles)
    interior = sorted(k for k, n in counts.items() if n == 2)
    assert len(gown.bend_pairs) == len(interior)
    assert sorted(map(tuple, gown.bend_edges.tolist())) == interior
    tri_sets = {frozenset(t) for t in gown.triangles.tolist()}
    for (a, b), (c, d) in zip(gown.bend_edges.tolist(), gown.bend_pairs.tolist(), strict=True):
        assert frozenset((a, b, c)) in tri_sets and frozenset((a, b, d)) in tri_sets
        assert c != d


def test_bend_rest_is_the_flat_unfolded_distance(gown: Gown) -> None:
    g = gown
    p = g.pattern
    tip_gap = edge_lengths(p, g.bend_pairs)
    tri_sheet = triangle_sheet(g)
    sheet_of = {frozenset(t): s for t, s in zip(g.triangles.tolist(), tri_sheet, strict=True)}
    same = np.array(
        [
            sheet_of[frozenset((a, b, c))] == sheet_of[frozenset((a, b, d))]
            for (a, b), (c, d) in zip(g.bend_edges.tolist(), g.bend_pairs.tolist(), strict=True)
        ]
    )
    # Inside one flat sheet the hinge's wings already lie on opposite sides: plain distance.
    np.testing.assert_allclose(g.bend_rest[same], tip_gap[same], rtol=1e-12)
    # Across a seam the wings are folded onto each other on the pattern; the rest value is
    # the unfolded (flat, zero rest curvature) distance: longer than the folded one and no
    # longer than the path through the hinge's midpoint.
    seam = ~same
    assert seam.sum() > 0
    mid = 0.5 * (p[g.bend_edges[:, 0]] + p[g.bend_edges[:, 1]])
    via_mid = np.linalg.norm(p[g.bend_pairs[:, 0]] - mid, axis=1) + np.linalg.norm(
        p[g.bend_pairs[:, 1]] - mid, axis=1
    )
    assert (g.bend_rest[seam] > tip_gap[seam] + 0.5 * g.h).all()
    assert (g.bend_rest <= via_mid + 1e-12).all()
    # Mirror-image wings (same pattern point on both sheets) unfold to twice their height.
    a, b = p[g.bend_edges[:, 0]], p[g.bend_edges[:, 1]]
    e = (b - a) / np.linalg.norm(b - a, axis=1, keepdims=True)
    rel = p[g.bend_pairs[:, 0]] - a
    height = np.abs(rel[:, 0] * e[:, 1] - rel[:, 1] * e[:, 0])
    mirror = seam & (tip_gap < 1e-12)
    assert mirror.sum() > 0
    np.testing.assert_allclose(g.bend_rest[mirror], 2.0 * height[mirror], rtol=1e-12)


def test_rest_areas_cover_both_sheets(any_gown: Gown) -> None:
    g = any_gown
    assert (g.rest_areas > 0).all()
    assert np.isclose(g.rest_areas.sum(), 2.0 * g.config.pattern_area, rtol=1e-12)
    np.testing.assert_allclose(g.rest_areas, np.abs(signed_pattern_areas(g)), rtol=1e-12)


def test_masses_are_lumped_area_times_density(any_gown: Gown) -> None:
    g, c = any_gown, any_gown.config
    assert (g.masses > 0).all()
    total = 2.0 * c.pattern_area * c.areal_density
    assert np.isclose(g.masses.sum(), total, rtol=1e-12)
    assert np.isclose(g.total_mass, total, rtol=1e-12)
    assert 0.1 < total < 0.2  # a cotton gown weighs ~150 g


# -------------------------------------------------------------------- feature loop


def test_feature_loop_is_the_closed_right_armhole(any_gown: Gown) -> None:
    g, c = any_gown, any_gown.config
    loop = g.feature_loop
    assert len(np.unique(loop)) == len(loop)
    edge_set = set(map(tuple, g.edges.tolist()))
    for a, b in zip(loop.tolist(), np.roll(loop, -1).tolist(), strict=True):
        assert (min(a, b), max(a, b)) in edge_set
    u, v = g.pattern[loop].T
    arm = c.body_length - c.sleeve_width
    assert np.allclose(u, -0.5 * c.body_width)
    assert (v >= arm - 1e-9).all() and (v <= c.body_length + 1e-9).all()
    # Both sheets' armhole columns, joined at the shoulder seam and the underarm.
    assert (g.sheet[loop] == SEAM).sum() == 2
    assert (g.sheet[loop] == FRONT).sum() == (g.sheet[loop] == BACK).sum()
    all_column = np.isclose(g.pattern[:, 0], -0.5 * c.body_width) & (g.pattern[:, 1] >= arm - 1e-9)
    assert set(np.nonzero(all_column)[0].tolist()) == set(loop.tolist())
    assert np.isclose(g.loop_rest_length, 2.0 * c.sleeve_width)
    np.testing.assert_allclose(
        edge_lengths(g.pattern, np.stack([loop, np.roll(loop, -1)], 1)).sum(), g.loop_rest_length
    )


def test_feature_loop_lies_on_a_circle_in_the_yz_plane(any_gown: Gown) -> None:
    g = any_gown
    p = g.positions[g.feature_loop]
    assert np.allclose(p[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.hypot(p[:, 1], p[:, 2]), g.loop_radius, rtol=1e-12)
    # The loop's polygon is isometric to its rest length (its circle's circumference is
    # larger by the factor (pi/L) / sin(pi/L), under 1.2% for L >= 12).
    closed = np.stack([g.feature_loop, np.roll(g.feature_loop, -1)], 1)
    np.testing.assert_allclose(
        edge_lengths(g.positions, closed).sum(), g.loop_rest_length, rtol=1e-12
    )
    circumference = 2.0 * np.pi * g.loop_radius
    assert g.loop_rest_length < circumference < 1.012 * g.loop_rest_length


def test_feature_loop_starts_at_the_top_seam_and_its_normal_is_plus_x(any_gown: Gown) -> None:
    g = any_gown
    p = g.positions[g.feature_loop]
    np.testing.assert_allclose(p[0], [0.0, 0.0, g.loop_radius], atol=1e-12)
    assert g.sheet[g.feature_loop[0]] == SEAM
    assert np.isclose(g.pattern[g.feature_loop[0], 1], g.config.body_length)
    normal = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)  # right-hand rule
    np.testing.assert_allclose(normal / np.linalg.norm(normal), [1.0, 0.0, 0.0], atol=1e-12)


# --------------------------------------------------------------------- 3-D layout


def test_sleeve_is_toward_plus_x_and_body_toward_minus_x(gown: Gown) -> None:
    x = gown.positions[:, 0]
    assert (x[gown.region == RIGHT_SLEEVE] >= -1e-12).all()
    assert (x[gown.region == RIGHT_SLEEVE] > 0.9 * gown.config.sleeve_length).any()
    assert (x[gown.region != RIGHT_SLEEVE] <= 1e-12).all()
    assert (x[gown.region == LEFT_SLEEVE] < -gown.config.body_width + 1e-9).all()
    assert (gown.positions[gown.region == BODY, 2] < -0.5 * gown.config.body_length).any()


def test_right_sleeve_is_inflated_isometrically(any_gown: Gown) -> None:
    g = any_gown
    inside = (g.region[g.edges] == RIGHT_SLEEVE).all(axis=1)
    assert inside.sum() > 50
    np.testing.assert_allclose(
        edge_lengths(g.positions, g.edges[inside]), g.edge_rest[inside], rtol=1e-9
    )
    sleeve = g.positions[g.region == RIGHT_SLEEVE]
    np.testing.assert_allclose(np.hypot(sleeve[:, 1], sleeve[:, 2]), g.loop_radius, rtol=1e-9)


def test_body_layout_is_only_mildly_strained(any_gown: Gown) -> None:
    # The body is not isometric (the round armhole flattens into a double layer), but its
    # initial strain stays small so the simulation settles it gently.
    g = any_gown
    strain = np.abs(edge_lengths(g.positions, g.edges) / g.edge_rest - 1.0)
    assert np.median(strain) < 0.005
    assert np.percentile(strain, 99) < 0.06
    assert strain.max() < 0.25
    arm = g.config.body_length - g.config.sleeve_width
    lower = (g.pattern[g.edges, 1] < arm - 1e-9).all(axis=1)
    # Below the armpits only the layer_gap/2 step off the seams strains: sqrt(1 + (gap/2h)^2).
    assert strain[lower].max() < np.sqrt(1.0 + (0.5 * g.config.layer_gap / (0.9 * g.h)) ** 2) - 1


def test_layers_stay_apart_in_the_initial_positions(any_gown: Gown) -> None:
    g = any_gown
    y = g.positions[:, 1]
    assert (y[g.sheet == FRONT] > 0).all() and (y[g.sheet == BACK] < 0).all()
    assert np.allclose(y[g.sheet == SEAM], 0.0)
    close = cKDTree(g.positions).query_pairs(0.005, output_type="ndarray")
    edge_set = set(map(tuple, g.edges.tolist()))
    assert all(tuple(sorted(pair)) in edge_set for pair in close.tolist())


# ------------------------------------------------------------------------ geodesic


def test_geodesic_is_zero_on_the_loop_and_normalized(any_gown: Gown) -> None:
    g = any_gown
    assert (g.geodesic[g.feature_loop] == 0.0).all()
    off_loop = np.setdiff1d(np.arange(g.num_vertices), g.feature_loop)
    assert (g.geodesic[off_loop] > 0).all()
    assert g.geodesic.max() == 1.0
    assert g.geodesic_scale > g.config.body_width  # far side of the gown is that far


def test_geodesic_is_lipschitz_along_edges(any_gown: Gown) -> None:
    g = any_gown
    jump = np.abs(g.geodesic[g.edges[:, 0]] - g.geodesic[g.edges[:, 1]])
    assert (jump <= g.edge_rest / g.geodesic_scale + 1e-12).all()


def test_geodesic_grows_toward_the_far_end(any_gown: Gown) -> None:
    g, c = any_gown, any_gown.config
    u, v = g.pattern.T
    # Along the shoulder seam line (front top row) it increases both ways from the armhole.
    top = np.nonzero(np.isclose(v, c.body_length) & (g.sheet != BACK))[0]
    top = top[np.argsort(u[top])]
    arm = np.searchsorted(u[top], -0.5 * c.body_width - 1e-9)
    assert (np.diff(g.geodesic[top[arm:]]) > 0).all()
    assert (np.diff(g.geodesic[top[: arm + 1]]) < 0).all()
    # The left cuff and the hem are far away; the farthest point of all is at the bottom of
    # the back slit on the left back half, reached only around the side or over the shoulder.
    left_cuff = np.isclose(u, 0.5 * c.body_width + c.sleeve_length)
    hem = np.isclose(v, 0.0)
    assert g.geodesic[left_cuff].min() > 0.7
    armpit_to_hem = c.body_length - c.sleeve_width  # no path along the cloth is shorter
    assert g.geodesic[hem].min() >= armpit_to_hem / g.geodesic_scale - 1e-9
    far = int(np.argmax(g.geodesic))
    assert g.sheet[far] == BACK and np.isclose(u[far], 0.0) and np.isclose(v[far], 0.0)
    assert g.positions[far, 0] < -0.4 * c.body_width


def test_geodesic_bias_of_edge_graph_distance_is_bounded(any_gown: Gown) -> None:
    # On the front sheet the exact geodesic is the pattern distance to the armhole segment;
    # shortest edge paths never undercut it and overshoot it by the known metrication bias.
    g, c = any_gown, any_gown.config
    u, v = g.pattern.T
    arm = c.body_length - c.sleeve_width
    exact = np.hypot(u + 0.5 * c.body_width, v - np.clip(v, arm, c.body_length))
    graph = g.geodesic * g.geodesic_scale
    front = g.sheet != BACK
    assert (graph[front] >= exact[front] - 1e-12).all()
    assert (graph[front] <= 1.10 * exact[front] + 2.0 * g.h).all()
    far = front & (exact > 0.3)
    assert np.mean(graph[far] / exact[far]) < 1.05


# -------------------------------------------------------------------------- config


@pytest.mark.parametrize(
    "bad",
    [
        {"target_vertices": 10},
        {"body_width": 0.0},
        {"sleeve_width": -0.1},
        {"neck_half_width": 0.4},
        {"sleeve_width": 0.9},
        {"slit_gap": -0.01},
    ],
)
def test_invalid_config_is_rejected(bad: dict) -> None:
    with pytest.raises(ValueError):
        GownConfig(**bad)


def test_dimensions_follow_the_config() -> None:
    c = GownConfig(
        target_vertices=800,
        body_width=0.7,
        body_length=0.9,
        sleeve_length=0.2,
        sleeve_width=0.25,
        neck_half_width=0.12,
        areal_density=0.15,
    )
    g = make_gown(c)
    assert np.isclose(np.ptp(g.pattern[:, 0]), c.body_width + 2 * c.sleeve_length)
    assert np.isclose(np.ptp(g.pattern[:, 1]), c.body_length)
    assert np.isclose(g.loop_rest_length, 2 * c.sleeve_width)
    assert np.isclose(g.total_mass, 2 * c.pattern_area * c.areal_density)
    assert len(boundary_loops(g.triangles)) == 3
