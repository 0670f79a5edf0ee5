"""Procedural hospital-gown triangle mesh (pure NumPy/SciPy, no downloaded assets).

The gown is sewn from a flat T-shaped pattern: a front sheet and a back sheet share the
vertices of their seams (shoulders/sleeve tops, sleeve underarms, body sides); the hem, the
neck, the two cuffs and a slit down the middle of the back stay open. The cloth's rest state
is the flat ``pattern``; ``positions`` is an initial 3-D shape in the GARMENT FRAME, where the
right armhole (the "garment feature" a robot gripper holds) is a circle in the y-z plane
centred at the origin, the right sleeve is an inflated prism along +x and the body lies
towards -x.  See docs/garment.md for the dimensions and the design choices.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from ..files import write_text

FRONT, BACK, SEAM = 0, 1, 2  # values of Gown.sheet (SEAM: vertex shared by both sheets)
BODY, RIGHT_SLEEVE, LEFT_SLEEVE = 0, 1, 2  # values of Gown.region

_TOL = 1e-9  # m; geometric comparison tolerance in pattern space


@dataclass(frozen=True)
class GownConfig:
    """Dimensions, resolution and material of the procedural gown (SI units)."""

    target_vertices: int = 2000  # resolution: h is chosen so the vertex count is close to this
    body_width: float = 0.60  # W: half the body circumference, m
    body_length: float = 0.80  # Hb: shoulder to hem, m
    sleeve_length: float = 0.25  # Ls: armhole to cuff, m
    sleeve_width: float = 0.30  # Sw: half the sleeve circumference, m (hospital gowns: wide)
    neck_half_width: float = 0.10  # half the width of the neck opening on the top edge, m
    areal_density: float = 0.13  # kg/m^2, cotton hospital gown
    layer_gap: float = 0.01  # initial front-to-back distance of the flat double layer, m
    slit_gap: float = 0.008  # initial depth offset between the back halves at the slit, m
    blend_length: float = 1.0  # distance from the armhole at which the initial shape is flat, m

    def __post_init__(self) -> None:
        if self.target_vertices < 100:
            raise ValueError("target_vertices must be at least 100")
        positive = (
            "body_width",
            "body_length",
            "sleeve_length",
            "sleeve_width",
            "neck_half_width",
            "areal_density",
            "layer_gap",
            "blend_length",
        )
        for name in positive:
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be positive")
        if self.slit_gap < 0.0:
            raise ValueError("slit_gap must be non-negative")
        if not self.neck_half_width < 0.5 * self.body_width:
            raise ValueError("neck_half_width must be smaller than body_width / 2")
        if not self.sleeve_width < self.body_length:
            raise ValueError("sleeve_width must be smaller than body_length")

    @property
    def pattern_area(self) -> float:
        """Area of one T-shaped sheet (body + two sleeves), m^2."""
        return self.body_width * self.body_length + 2.0 * self.sleeve_length * self.sleeve_width


@dataclass(frozen=True, eq=False)
class Gown:
    """A sewn gown mesh with its rest state, masses, feature loop and geodesic field.

    Vertex-index arrays are int32, geometry float64.  ``pattern`` is the rest state: every
    rest quantity (edge/bend rest lengths, areas, masses, geodesic) is measured on it.
    """

    positions: np.ndarray  # (V,3) initial 3-D positions in the garment frame, m
    pattern: np.ndarray  # (V,2) flat-pattern coordinates (u, v), the cloth's rest state, m
    triangles: np.ndarray  # (F,3) int32, outward oriented
    edges: np.ndarray  # (E,2) int32 unique undirected edges, i < j, sorted
    bend_pairs: np.ndarray  # (B,2) int32 vertices opposite each interior edge
    bend_edges: np.ndarray  # (B,2) int32 the interior (hinge) edge of each bend pair
    edge_rest: np.ndarray  # (E,) rest lengths from the pattern, m
    bend_rest: np.ndarray  # (B,) hinge-unfolded-flat rest distances of bend_pairs, m
    rest_areas: np.ndarray  # (F,) triangle areas on the pattern, m^2
    masses: np.ndarray  # (V,) lumped masses, kg
    feature_loop: np.ndarray  # (L,) int32 ordered right armhole, [0] = top seam vertex
    geodesic: np.ndarray  # (V,) edge-graph distance to the loop / geodesic_scale, in [0, 1]
    geodesic_scale: float  # unnormalized distance of the farthest vertex, m
    sheet: np.ndarray  # (V,) int8: FRONT, BACK or SEAM (shared by both sheets)
    region: np.ndarray  # (V,) int8: BODY, RIGHT_SLEEVE or LEFT_SLEEVE
    grid: np.ndarray  # (3, nu, nv) vertex id of each pattern-grid node on the front and the two
    #                   back halves, -1 where the node is not on that piece (seams share ids)
    side: np.ndarray  # (V,) int8: -1 wearer's right (u < 0), +1 left, 0 front centre line;
    #                    the back slit's two copies of u = 0 take the side of their half
    h: float  # nominal grid spacing of the pattern, m
    loop_radius: float  # radius of the circle the feature loop lies on, m
    loop_rest_length: float  # rest (pattern) perimeter of the feature loop, m
    config: GownConfig

    @property
    def num_vertices(self) -> int:
        return int(self.positions.shape[0])

    @property
    def num_triangles(self) -> int:
        return int(self.triangles.shape[0])

    @property
    def total_mass(self) -> float:
        return float(self.masses.sum())


@dataclass(frozen=True)
class _Grid:
    """Pattern grid: column u values, row v values and the indices of the key lines."""

    us: np.ndarray  # (nu,) column u coordinates, increasing
    vs: np.ndarray  # (nv,) row v coordinates, increasing (v = 0 at the hem)
    i_rarm: int  # column u = -W/2 (right armhole / right side seam)
    i_neck_r: int  # column u = -neck_half_width
    i_mid: int  # column u = 0 (back slit)
    i_neck_l: int  # column u = +neck_half_width
    i_larm: int  # column u = +W/2
    j_arm: int  # row v = Hb - Sw (underarm)

    @property
    def j_top(self) -> int:
        return len(self.vs) - 1


@dataclass(frozen=True)
class _Nodes:
    """Vertex numbering of the grid nodes on the three layers (front, back u<=0, back u>=0)."""

    vid: np.ndarray  # (3, nu, nv) vertex id per layer and node, -1 outside the garment
    layer: np.ndarray  # (V,) layer of the vertex's owner: 0 front, 1/2 back halves
    col: np.ndarray  # (V,) column index i
    row: np.ndarray  # (V,) row index j
    seam: np.ndarray  # (V,) bool, vertex shared by front and back
    cell_in: np.ndarray  # (nu-1, nv-1) bool, cell is part of the T


def _segment_cells(length: float, h: float, minimum: int = 1) -> int:
    """Number of grid cells for a pattern segment so that the spacing is close to h."""
    return max(minimum, int(round(length / h)))


def _make_grid(cfg: GownConfig, h: float) -> _Grid:
    """Grid with lines exactly at the cuffs, armholes, neck corners, centre and underarm."""
    half, nw = 0.5 * cfg.body_width, cfg.neck_half_width
    ls, sw, hb = cfg.sleeve_length, cfg.sleeve_width, cfg.body_length
    n_sleeve = _segment_cells(ls, h)
    n_side = _segment_cells(half - nw, h)
    n_neck = _segment_cells(nw, h)
    col_breaks = np.array([-half - ls, -half, -nw, 0.0, nw, half, half + ls])
    col_counts = [n_sleeve, n_side, n_neck, n_neck, n_side, n_sleeve]
    n_band = _segment_cells(sw, h, minimum=2)  # >= 2 so no cell has three seam vertices
    n_low = _segment_cells(hb - sw, h)
    us = _breaks_to_lines(col_breaks, col_counts)
    vs = _breaks_to_lines(np.array([0.0, hb - sw, hb]), [n_low, n_band])
    starts = np.cumsum([0, *col_counts])
    return _Grid(
        us=us,
        vs=vs,
        i_rarm=int(starts[1]),
        i_neck_r=int(starts[2]),
        i_mid=int(starts[3]),
        i_neck_l=int(starts[4]),
        i_larm=int(starts[5]),
        j_arm=n_low,
    )


def _breaks_to_lines(breaks: np.ndarray, counts: list[int]) -> np.ndarray:
    """Concatenate uniform subdivisions of consecutive breakpoint intervals."""
    parts = [
        np.linspace(a, b, n, endpoint=False)
        for a, b, n in zip(breaks[:-1], breaks[1:], counts, strict=True)
    ]
    return np.concatenate([*parts, breaks[-1:]])


def _number_nodes(g: _Grid) -> _Nodes:
    """Assign vertex ids: seams share the front id, the back slit column is duplicated."""
    nu, nv = len(g.us), len(g.vs)
    i = np.arange(nu)[:, None]
    j = np.arange(nv)[None, :]
    in_band = j >= g.j_arm
    node_in = ((i >= g.i_rarm) & (i <= g.i_larm)) | in_band
    top = (j == g.j_top) & ((i <= g.i_neck_r) | (i >= g.i_neck_l))
    underarm = (j == g.j_arm) & ((i <= g.i_rarm) | (i >= g.i_larm))
    side = ((i == g.i_rarm) | (i == g.i_larm)) & (j <= g.j_arm)
    seam = (top | underarm | side) & node_in
    valid = np.stack([node_in, node_in & (i <= g.i_mid), node_in & (i >= g.i_mid)])
    owner = valid.copy()
    owner[1:] &= ~seam
    vid = np.full(valid.shape, -1, dtype=np.int64)
    vid[owner] = np.arange(int(owner.sum()))
    for k in (1, 2):
        shared = valid[k] & seam
        vid[k][shared] = vid[0][shared]
    layer, col, row = np.nonzero(owner)
    ci = np.arange(nu - 1)[:, None]
    cj = np.arange(nv - 1)[None, :]
    cell_in = ((ci >= g.i_rarm) & (ci < g.i_larm)) | (cj >= g.j_arm)
    return _Nodes(vid=vid, layer=layer, col=col, row=row, seam=seam[col, row], cell_in=cell_in)


def _choose_spacing(cfg: GownConfig) -> tuple[float, _Grid, _Nodes]:
    """Pick h (from a small scan around the area estimate) whose vertex count is nearest."""
    h0 = float(np.sqrt(2.0 * cfg.pattern_area / cfg.target_vertices))
    best: tuple[int, float, _Grid, _Nodes] | None = None
    for h in h0 * np.exp(np.linspace(-0.25, 0.25, 51)):
        grid = _make_grid(cfg, float(h))
        nodes = _number_nodes(grid)
        err = abs(len(nodes.layer) - cfg.target_vertices)
        if best is None or err < best[0]:
            best = (err, float(h), grid, nodes)
    assert best is not None
    return best[1], best[2], best[3]


def _triangulate(g: _Grid, n: _Nodes) -> np.ndarray:
    """Two triangles per cell with alternating diagonals; front CCW, back CW in (u, v)."""
    ci, cj = np.nonzero(n.cell_in)
    flip = (ci + cj) % 2 == 1
    out = []
    for layer in (0, 1):
        k = np.zeros_like(ci) if layer == 0 else np.where(ci < g.i_mid, 1, 2)
        a, b = n.vid[k, ci, cj], n.vid[k, ci + 1, cj]
        c, d = n.vid[k, ci + 1, cj + 1], n.vid[k, ci, cj + 1]
        t1 = np.where(flip[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1))
        t2 = np.where(flip[:, None], np.stack([b, c, d], 1), np.stack([a, c, d], 1))
        tris = np.concatenate([t1, t2])
        out.append(tris if layer == 0 else tris[:, [0, 2, 1]])
    return np.concatenate(out).astype(np.int32)


def _edges_and_hinges(tris: np.ndarray, nv: int) -> tuple[np.ndarray, ...]:
    """Unique edges plus, for every interior edge, its hinge edge and two opposite vertices."""
    half = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]).astype(np.int64)
    opposite = np.concatenate([tris[:, 2], tris[:, 0], tris[:, 1]]).astype(np.int64)
    lo, hi = half.min(1), half.max(1)
    keys = lo * nv + hi
    order = np.argsort(keys, kind="stable")
    sk = keys[order]
    uniq, counts = np.unique(sk, return_counts=True)
    if counts.max() > 2:
        raise RuntimeError("gown mesh is non-manifold (an edge has more than two triangles)")
    edges = np.stack([uniq // nv, uniq % nv], 1)
    first = np.nonzero(sk[:-1] == sk[1:])[0]
    hinge_keys = sk[first]
    bend_edges = np.stack([hinge_keys // nv, hinge_keys % nv], 1)
    bend_pairs = np.stack([opposite[order[first]], opposite[order[first + 1]]], 1)
    return edges, bend_edges, bend_pairs


def _unfolded_distance(p: np.ndarray, hinge: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """Distance between the two wing tips when the hinge's two triangles are unfolded flat.

    Each tip is expressed in its own triangle's frame (along-edge coordinate s, distance r
    from the edge line) and the wings are laid on opposite sides of the edge: exact for
    hinges inside one sheet, and a zero-rest-curvature (flat) seam for hinges across a seam,
    where the folded-flat pattern would otherwise put both tips on the same side.
    """
    a, b = p[hinge[:, 0]], p[hinge[:, 1]]
    e = b - a
    e /= np.linalg.norm(e, axis=1, keepdims=True)
    d1, d2 = p[pairs[:, 0]] - a, p[pairs[:, 1]] - a
    s1, s2 = (d1 * e).sum(1), (d2 * e).sum(1)
    r1 = np.abs(d1[:, 0] * e[:, 1] - d1[:, 1] * e[:, 0])
    r2 = np.abs(d2[:, 0] * e[:, 1] - d2[:, 1] * e[:, 0])
    return np.hypot(s1 - s2, r1 + r2)


def _triangle_areas(p: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Unsigned areas of 2-D triangles."""
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    return 0.5 * np.abs(cross)


def _column_profiles(cfg: GownConfig, g: _Grid) -> tuple[np.ndarray, np.ndarray, float]:
    """Front-sheet cross-section (y, z) of every pattern column, arc-length exact.

    Walking down a column from the top seam, the band segments (top seam to underarm) of
    the round armhole turn like a regular polygon, then the lower body goes straight down.
    A column's headings are the armhole's scaled by a weight w (1 on the right sleeve and at
    the armhole, 0 from ``blend_length`` into the body on), so every column keeps its rest
    length while the section flattens from the circle to a flat sheet.  w(t) is chosen so
    that the band's height grows linearly with the distance t from the armhole, and every
    column is shifted so that the underarm row is a straight line at z = -radius: the
    mismatch between the round armhole and the flat body becomes a uniform shear of the
    band only, and the lower body hangs unstrained.  Returns Y, Z (nu, nv) and the radius.
    """
    m_band = g.j_top - g.j_arm
    seg = np.diff(g.vs)  # segment j joins rows j and j+1
    k = g.j_top - 1 - np.arange(len(seg))  # band segment index counted from the top
    heading = np.where(k < m_band, 0.5 * np.pi - np.pi * (k + 0.5) / m_band, 0.0)
    band_step = cfg.sleeve_width / m_band
    radius = band_step / (2.0 * np.sin(0.5 * np.pi / m_band))

    def profile(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ang = w[:, None] * heading[None, :]
        return _sum_above(seg * np.sin(ang)), radius - _sum_above(seg * np.cos(ang))

    w_table = np.linspace(0.0, 1.0, 513)
    height_table = radius - profile(w_table)[1][:, g.j_arm]  # increases as w decreases
    t = g.us + 0.5 * cfg.body_width  # distance from the armhole into the body (<0: sleeve)
    frac = np.clip(t / cfg.blend_length, 0.0, 1.0)
    height = 2.0 * radius + frac * (cfg.sleeve_width - 2.0 * radius)
    w = np.interp(height, height_table[::-1], w_table[::-1])
    y, z = profile(w)
    return y, z - (z[:, g.j_arm : g.j_arm + 1] + radius), radius


def _sum_above(steps: np.ndarray) -> np.ndarray:
    """(nu, nv-1) per-segment steps -> (nu, nv) sums over the segments above each row."""
    above = np.cumsum(steps[:, ::-1], axis=1)[:, ::-1]
    return np.concatenate([above, np.zeros((steps.shape[0], 1))], axis=1)


def _initial_positions(cfg: GownConfig, g: _Grid, n: _Nodes) -> tuple[np.ndarray, float]:
    """Garment-frame positions: x = -(u + W/2); each column placed on its cross-section.

    Off the seams, body vertices are pushed layer_gap/2 away from the mid-plane y = 0 so the
    front and back layers never touch.  Where a column's layers are free (below mid-band in
    the body, above it in the neck) the push is a plain offset, which strains nothing; where
    they meet at a seam the profile runs along y into the seam, so there the push is
    hypot(Y, gap/2), which only lifts nearly flat profiles and barely stretches the edges
    leaving the seam.  The back half at u >= 0 is pushed a further slit_gap backwards near
    the slit (tapering to 0 at the neck corners), so the duplicated slit vertices separate.
    """
    Y, Z, radius = _column_profiles(cfg, g)
    u = g.us[n.col]
    t = u + 0.5 * cfg.body_width
    Yv = Y[n.col, n.row]
    c = np.where(t > _TOL, 0.5 * cfg.layer_gap, 0.0)
    lower = n.row <= g.j_arm + (g.j_top - g.j_arm) // 2
    top_sewn = (n.col <= g.i_neck_r) | (n.col >= g.i_neck_l)
    underarm_sewn = (n.col <= g.i_rarm) | (n.col >= g.i_larm)
    near_seam = np.where(lower, underarm_sewn, top_sewn)
    depth = np.where(near_seam, np.hypot(Yv, c), Yv + c)
    slit = np.clip(1.0 - u / cfg.neck_half_width, 0.0, 1.0) * cfg.slit_gap
    depth = depth + np.where(n.layer == 2, slit, 0.0)
    y = np.where(n.seam, 0.0, np.where(n.layer == 0, depth, -depth))
    return np.stack([-t, y, Z[n.col, n.row]], 1), radius


def _feature_loop(g: _Grid, n: _Nodes, positions: np.ndarray) -> np.ndarray:
    """Right armhole: front column up, back column down; start at top, normal +x."""
    rows = np.arange(g.j_arm, g.j_top + 1)
    front = n.vid[0, g.i_rarm, rows]
    back = n.vid[1, g.i_rarm, rows[-2:0:-1]]
    loop = np.concatenate([front, back])
    loop = np.roll(loop, -(len(rows) - 1))  # top seam vertex first
    p = positions[loop]
    normal_x = np.sum(p[:, 1] * np.roll(p[:, 2], -1) - p[:, 2] * np.roll(p[:, 1], -1))
    if normal_x < 0.0:
        loop = np.concatenate([loop[:1], loop[:0:-1]])
    return loop.astype(np.int32)


def _geodesic(
    pattern: np.ndarray, edges: np.ndarray, rest: np.ndarray, sources: np.ndarray
) -> tuple[np.ndarray, float]:
    """Shortest edge-path distance (pattern lengths) to the nearest source, normalized."""
    nv = pattern.shape[0]
    graph = coo_matrix((rest, (edges[:, 0], edges[:, 1])), shape=(nv, nv)).tocsr()
    dist = dijkstra(graph, directed=False, indices=sources, min_only=True)
    scale = float(dist.max())
    return dist / scale, scale


def _regions(g: _Grid, n: _Nodes) -> np.ndarray:
    """Label right sleeve (armhole column included), left sleeve and body vertices."""
    band = n.row >= g.j_arm
    right = band & (n.col <= g.i_rarm)
    left = band & (n.col >= g.i_larm)
    return np.select([right, left], [RIGHT_SLEEVE, LEFT_SLEEVE], BODY).astype(np.int8)


def straight_pairs(gown: Gown, step: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertex pairs ``step`` grid nodes apart along one row or column of one piece, and their
    pattern distance.

    A straight grid line inside one flat piece is a geodesic of the rest state, so the pattern
    distance bounds how far apart the pair can get without stretching the fabric between them.
    """
    pairs = []
    for piece in gown.grid:
        for lines in (piece, piece.T):  # rows (fixed v) and columns (fixed u)
            for line in lines:
                ids = line[line >= 0]  # each row or column of a piece is one contiguous run
                if len(ids) > step:
                    pairs.append(np.stack([ids[:-step], ids[step:]], 1))
    if not pairs:
        return np.zeros((0, 2), np.int32), np.zeros(0)
    pairs = np.unique(np.sort(np.concatenate(pairs), axis=1), axis=0).astype(np.int32)
    rest = np.linalg.norm(gown.pattern[pairs[:, 0]] - gown.pattern[pairs[:, 1]], axis=1)
    return pairs, rest


def make_gown(config: GownConfig | None = None) -> Gown:
    """Build the sewn hospital-gown mesh, its rest state and its right-armhole feature."""
    cfg = GownConfig() if config is None else config
    h, grid, nodes = _choose_spacing(cfg)
    nv = len(nodes.layer)
    pattern = np.stack([grid.us[nodes.col], grid.vs[nodes.row]], 1)
    tris = _triangulate(grid, nodes)
    edges, bend_edges, bend_pairs = _edges_and_hinges(tris, nv)
    edge_rest = np.linalg.norm(pattern[edges[:, 0]] - pattern[edges[:, 1]], axis=1)
    bend_rest = _unfolded_distance(pattern, bend_edges, bend_pairs)
    areas = _triangle_areas(pattern, tris)
    masses = np.bincount(
        tris.ravel(), weights=np.repeat(areas * cfg.areal_density / 3.0, 3), minlength=nv
    )
    positions, radius = _initial_positions(cfg, grid, nodes)
    loop = _feature_loop(grid, nodes, positions)
    loop_len = float(np.linalg.norm(pattern[loop] - pattern[np.roll(loop, -1)], axis=1).sum())
    geodesic, scale = _geodesic(pattern, edges, edge_rest, loop)
    sheet = np.where(nodes.seam, SEAM, np.where(nodes.layer == 0, FRONT, BACK)).astype(np.int8)
    return Gown(
        positions=positions,
        pattern=pattern,
        triangles=tris,
        edges=edges.astype(np.int32),
        bend_pairs=bend_pairs.astype(np.int32),
        bend_edges=bend_edges.astype(np.int32),
        edge_rest=edge_rest,
        bend_rest=bend_rest,
        rest_areas=areas,
        masses=masses,
        feature_loop=loop,
        geodesic=geodesic,
        geodesic_scale=scale,
        sheet=sheet,
        region=_regions(grid, nodes),
        grid=nodes.vid.astype(np.int32),
        side=np.where(
            nodes.layer == 1, -1, np.where(nodes.layer == 2, 1, np.sign(pattern[:, 0]))
        ).astype(np.int8),
        h=h,
        loop_radius=radius,
        loop_rest_length=loop_len,
        config=cfg,
    )


def write_obj(gown: Gown, path: str | os.PathLike, positions: np.ndarray | None = None) -> Path:
    """Write the gown as a Wavefront OBJ (vertices in dressbench's order, 1-based triangles),
    so another simulator (``dressbench bench --compare pybullet``) loads the same garment.

    ``positions`` (V, 3) places it (e.g. held at a gripper pose); default: ``gown.positions``.
    """
    points = gown.positions if positions is None else np.asarray(positions, dtype=float)
    if points.shape != gown.positions.shape:
        raise ValueError(f"positions must have shape {gown.positions.shape}, got {points.shape}")
    vertices = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in points]
    faces = [f"f {a} {b} {c}" for a, b, c in gown.triangles + 1]
    header = f"# dressbench gown: {gown.num_vertices} vertices, {gown.num_triangles} triangles"
    write_text(path, "\n".join([header, *vertices, *faces]) + "\n")
    return Path(path)
