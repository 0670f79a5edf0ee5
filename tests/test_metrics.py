"""Analytic checks of the reward terms and metrics (paper §III-B, §III-C)."""

import numpy as np
import pytest

from dressbench.metrics import (
    arm_progress,
    deformation_reward,
    feature_plane,
    geodesic_contact_reward,
    geodesic_gradient,
    limb_containment,
    max_area_ratio,
    points_in_polygon,
    progress_reward,
    task_vector,
    triangle_areas,
    upright_reward,
)

HAND, FOREARM, UPPER_ARM = 0.1, 0.25, 0.3
PLANE_X, RADIUS = 0.5, 0.1
X_AXIS = np.array([1.0, 0.0, 0.0])


def circle_loop(n: int = 18) -> np.ndarray:
    """Loop of radius 0.1 in the y-z plane at x = 0.5, ordered so its normal is +x."""
    angles = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return np.stack([np.full(n, PLANE_X), RADIUS * np.cos(angles), RADIUS * np.sin(angles)], axis=1)


def straight_arm(tip_x: float, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    """Arm pointing along +x: fingertip at tip_x, wrist, elbow and shoulder behind it."""
    offsets = np.cumsum([0.0, HAND, FOREARM, UPPER_ARM])
    return np.stack([tip_x - offsets, np.full(4, y), np.full(4, z)], axis=1)


def flat_grid(n: int = 11, spacing: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """Square grid mesh in the z = 0 plane: positions (n*n, 3) and triangles."""
    xs, ys = np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing, indexing="ij")
    positions = np.stack([xs.ravel(), ys.ravel(), np.zeros(n * n)], axis=1)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + n, a + n + 1, a + 1
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return positions, triangles


def grid_vertex(x: float, y: float, n: int = 11, spacing: float = 0.1) -> int:
    """Index of the flat_grid vertex at (x, y)."""
    return int(round(x / spacing)) * n + int(round(y / spacing))


@pytest.fixture
def plane():
    return feature_plane(circle_loop())


# --- feature plane -------------------------------------------------------------------------


def test_plane_of_circle(plane):
    np.testing.assert_allclose(plane.centroid, [PLANE_X, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(plane.normal, X_AXIS, atol=1e-12)
    np.testing.assert_allclose(plane.basis @ plane.basis.T, np.eye(2), atol=1e-12)
    np.testing.assert_allclose(plane.basis @ plane.normal, 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(plane.polygon, axis=1), RADIUS)


def test_projected_polygon_is_counter_clockwise_about_normal(plane):
    y, z = plane.polygon.T
    signed_area = 0.5 * np.sum(y * np.roll(z, -1) - np.roll(y, -1) * z)
    assert signed_area > 0.0


def test_reversing_loop_flips_normal():
    reversed_plane = feature_plane(circle_loop()[::-1])
    np.testing.assert_allclose(reversed_plane.normal, -X_AXIS, atol=1e-12)


def test_tilted_noisy_loop_fits_plane():
    rng = np.random.default_rng(0)
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    loop = circle_loop() @ rotation.T + 0.001 * rng.normal(size=(18, 3))
    fitted = feature_plane(loop)
    assert fitted.normal @ (rotation @ X_AXIS) > 0.999


def test_point_in_non_convex_polygon():
    c_shape = np.array(
        [[-1, -1], [1, -1], [1, -0.5], [-0.5, -0.5], [-0.5, 0.5], [1, 0.5], [1, 1], [-1, 1]]
    )
    points = [[0.5, 0.0], [-0.8, 0.0], [0.5, -0.8], [2.0, 0.0], [-2.0, 0.0]]
    expected = [False, True, True, False, False]  # the last point's ray crosses the C twice
    np.testing.assert_array_equal(points_in_polygon(points, c_shape), expected)


# --- containment and progress --------------------------------------------------------------


def test_hand_crossing_is_bone_one_with_depth_past_plane(plane):
    result = limb_containment(straight_arm(PLANE_X + 0.05), plane)
    assert result.contained and result.bone == 1
    assert result.depth == pytest.approx(0.05)
    np.testing.assert_allclose(result.point, [PLANE_X, 0.0, 0.0], atol=1e-12)


def test_forearm_crossing_adds_hand_length(plane):
    wrist_past_plane = 0.07
    result = limb_containment(straight_arm(PLANE_X + HAND + wrist_past_plane), plane)
    assert result.contained and result.bone == 2
    assert result.depth == pytest.approx(HAND + wrist_past_plane)


def test_upper_arm_crossing_adds_hand_and_forearm(plane):
    elbow_past_plane = 0.02
    result = limb_containment(straight_arm(PLANE_X + HAND + FOREARM + elbow_past_plane), plane)
    assert result.bone == 3
    assert result.depth == pytest.approx(HAND + FOREARM + elbow_past_plane)


def test_progress_is_depth_when_contained(plane):
    joints = straight_arm(PLANE_X + 0.05, y=0.03)
    assert progress_reward(joints, plane) == pytest.approx(0.05)
    assert arm_progress(joints, plane) == pytest.approx(0.05)


def test_crossing_outside_circle_is_not_contained(plane):
    joints = straight_arm(PLANE_X + 0.05, y=0.3)
    result = limb_containment(joints, plane)
    assert not result.contained and result.bone == 0 and result.depth == 0.0
    assert np.all(np.isnan(result.point))
    expected = -np.linalg.norm(plane.centroid - joints[0])
    assert progress_reward(joints, plane) == pytest.approx(expected)
    assert arm_progress(joints, plane) == 0.0


def test_arm_short_of_plane_is_penalised_by_distance(plane):
    joints = straight_arm(PLANE_X - 0.2)
    assert progress_reward(joints, plane) == pytest.approx(-0.2)
    assert arm_progress(joints, plane) == 0.0


def test_first_bone_crossing_inside_wins(plane):
    # Wrist inside the sleeve, hand bent back so the fingertip re-crosses outside the rim.
    joints = straight_arm(PLANE_X + HAND + 0.05)
    joints[0] = [PLANE_X - 0.05, 0.3, 0.0]
    result = limb_containment(joints, plane)
    assert result.bone == 2
    assert result.depth == pytest.approx(0.05 + np.linalg.norm(joints[0] - joints[1]))


def test_crossing_in_notch_of_c_shaped_loop_is_not_contained():
    yz = 0.1 * np.array(
        [[-1, -1], [1, -1], [1, -0.5], [-0.5, -0.5], [-0.5, 0.5], [1, 0.5], [1, 1], [-1, 1]]
    )
    c_plane = feature_plane(np.column_stack([np.full(len(yz), PLANE_X), yz]))
    np.testing.assert_allclose(c_plane.normal, X_AXIS, atol=1e-12)
    assert not limb_containment(straight_arm(PLANE_X + 0.05, y=0.05), c_plane).contained
    assert limb_containment(straight_arm(PLANE_X + 0.05, y=-0.08), c_plane).contained


def test_wrist_on_plane_counts_once_with_hand_length(plane):
    result = limb_containment(straight_arm(PLANE_X + HAND), plane)
    assert result.bone == 1 and result.depth == pytest.approx(HAND)


# --- degenerate and NaN input --------------------------------------------------------------


@pytest.mark.filterwarnings("error")
def test_collinear_loop_contains_nothing():
    line = np.column_stack([np.full(18, PLANE_X), np.linspace(-0.1, 0.1, 18), np.zeros(18)])
    flat = feature_plane(line)
    assert np.linalg.norm(flat.normal) == pytest.approx(1.0)
    joints = straight_arm(PLANE_X + 0.05)
    assert not limb_containment(joints, flat).contained
    assert np.isfinite(progress_reward(joints, flat))


@pytest.mark.filterwarnings("error")
def test_zero_length_hand_is_skipped(plane):
    joints = straight_arm(PLANE_X + HAND + 0.05)
    joints[0] = joints[1]
    result = limb_containment(joints, plane)
    assert result.bone == 2 and result.depth == pytest.approx(0.05)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("x", [PLANE_X, PLANE_X - 0.1])
def test_arm_parallel_to_plane_never_crosses(plane, x):
    joints = np.column_stack(
        [np.full(4, x), np.cumsum([0.0, HAND, FOREARM, UPPER_ARM]), np.zeros(4)]
    )
    assert not limb_containment(joints, plane).contained
    assert np.isfinite(progress_reward(joints, plane))


def test_nan_input_does_not_raise(plane):
    nan_joints = np.full((4, 3), np.nan)
    assert not limb_containment(nan_joints, plane).contained
    nan_plane = feature_plane(np.full((18, 3), np.nan))
    assert not limb_containment(straight_arm(PLANE_X + 0.05), nan_plane).contained
    assert np.isnan(progress_reward(straight_arm(PLANE_X + 0.05), nan_plane))


# --- deformation ---------------------------------------------------------------------------


def test_area_of_unit_right_triangle():
    positions = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_allclose(triangle_areas(positions, [[0, 1, 2]]), [0.5])


def test_areas_match_cross_product_on_random_mesh():
    rng = np.random.default_rng(1)
    positions = rng.normal(size=(50, 3))
    triangles = rng.integers(0, 50, size=(80, 3))
    corners = positions[triangles]
    reference = 0.5 * np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    np.testing.assert_allclose(triangle_areas(positions, triangles), reference)


def test_max_area_ratio_finds_the_single_scaled_triangle():
    rng = np.random.default_rng(2)
    rest = rng.normal(size=(5, 3, 3))  # five separate triangles
    triangles = np.arange(15).reshape(5, 3)
    rest_areas = triangle_areas(rest.reshape(-1, 3), triangles)
    current = rest.copy()
    centre = current[3].mean(axis=0)
    current[3] = centre + 3.0 * (current[3] - centre)
    assert max_area_ratio(current.reshape(-1, 3), triangles, rest_areas) == pytest.approx(9.0)


def test_deformation_reward_shape():
    assert -1e-9 < deformation_reward(1.0) < 0.0
    assert deformation_reward(17.0) == pytest.approx(-1.0)
    assert deformation_reward(1000.0) == pytest.approx(-2.0)
    assert deformation_reward(5.0, threshold=3.0) == pytest.approx(-1.0)
    ratios = np.linspace(1.0, 30.0, 50)
    assert np.all(np.diff([deformation_reward(r) for r in ratios]) <= 0.0)


# --- geodesic contact and upright ----------------------------------------------------------


def test_geodesic_contact_reward_cases():
    geodesic = np.array([0.9, 0.4, 0.7, 0.1])
    assert geodesic_contact_reward(False, [], geodesic) == 0.0
    assert geodesic_contact_reward(True, [], geodesic) == 1.0
    assert geodesic_contact_reward(True, [0], geodesic) == 1.0
    assert geodesic_contact_reward(False, [0, 1, 2], geodesic) == pytest.approx(0.6)


@pytest.mark.parametrize(
    ("up", "expected"),
    [
        ([0, 0, 1], 0.0),
        ([0, 0, 3], 0.0),
        ([1, 0, 0], -np.pi / 2),
        ([0, -1, 1], -np.pi / 4),
        ([0, 0, -1], -np.pi),
    ],
)
def test_upright_reward_is_minus_tilt(up, expected):
    assert upright_reward(up) == pytest.approx(expected)


# --- geodesic gradient and task vector -----------------------------------------------------


@pytest.mark.parametrize(
    "vertex", [grid_vertex(0.5, 0.5), grid_vertex(0.0, 0.0), grid_vertex(1.0, 0.3)]
)
def test_gradient_of_linear_field_on_flat_grid(vertex):
    positions, triangles = flat_grid()
    np.testing.assert_allclose(
        geodesic_gradient(positions, triangles, positions[:, 0], vertex), X_AXIS, atol=1e-12
    )
    field = 2.0 * positions[:, 0] + 3.0 * positions[:, 1]
    np.testing.assert_allclose(
        geodesic_gradient(positions, triangles, field, vertex), [2.0, 3.0, 0.0], atol=1e-12
    )


def test_gradient_at_isolated_vertex_is_zero():
    positions, triangles = flat_grid()
    positions = np.vstack([positions, [5.0, 5.0, 5.0]])
    field = np.zeros(len(positions))
    np.testing.assert_array_equal(
        geodesic_gradient(positions, triangles, field, len(positions) - 1), 0.0
    )


def test_task_vector_points_to_centroid_without_contact(plane):
    positions, triangles = flat_grid()
    vector = task_vector([0.0, 0.0, 0.0], plane, False, [], positions, triangles, positions[:, 0])
    np.testing.assert_allclose(vector, X_AXIS, atol=1e-12)


def test_task_vector_follows_normal_when_contained(plane):
    positions, triangles = flat_grid()
    fingertip = [PLANE_X + 0.05, 0.0, 0.0]  # past the centroid: the centroid lies behind it
    vector = task_vector(fingertip, plane, True, [3], positions, triangles, positions[:, 0])
    np.testing.assert_allclose(vector, plane.normal, atol=1e-12)


def test_task_vector_descends_geodesic_at_nearest_contact(plane):
    positions, triangles = flat_grid()
    geodesic = np.abs(positions[:, 0] - 0.5)  # valley along x = 0.5
    left, right = grid_vertex(0.2, 0.5), grid_vertex(0.7, 0.4)  # g = 0.3 and 0.2: right wins
    vector = task_vector([0, 0, 0], plane, False, [left, right], positions, triangles, geodesic)
    np.testing.assert_allclose(vector, -X_AXIS, atol=1e-12)


@pytest.mark.filterwarnings("error")
def test_task_vector_is_unit_on_degenerate_input(plane):
    positions, triangles = flat_grid()
    flat_field = np.zeros(len(positions))
    cases = [
        task_vector([0, 0, 0], plane, False, [5], positions, triangles, flat_field),
        task_vector(plane.centroid, plane, False, [], positions, triangles, flat_field),
        task_vector(plane.centroid, plane, False, [5], positions, triangles, flat_field),
        task_vector([0, 0, 0], plane, False, [5], np.zeros_like(positions), triangles, flat_field),
    ]
    for vector in cases:
        assert np.all(np.isfinite(vector)) and np.linalg.norm(vector) == pytest.approx(1.0)
    np.testing.assert_allclose(cases[0], X_AXIS, atol=1e-12)  # flat field: head for the centroid
