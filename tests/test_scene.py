"""The coupled scene: the gown hangs and settles, the sleeve goes over an arm, the cloth pushes
back, the same inputs give the same trajectory, and bad input is refused or flagged."""

import numpy as np
import pytest
from capsules import limb_depth

from dressbench import metrics
from dressbench.bench import reach_action
from dressbench.plugins.robots import RIGHT_SHOULDER as SHOULDER
from dressbench.scene.geometry import transform_points
from dressbench.scene.world import Scene
from dressbench.state import measure

FRONT = np.array([0.0, 0.0, 0.0, 1.0])  # the sleeve points forward, away from the human


def pose(position, quaternion=FRONT) -> np.ndarray:
    return np.concatenate([position, quaternion])


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene()


def edge_stretch(scene: Scene, x: np.ndarray) -> np.ndarray:
    e = scene.gown.edges
    return np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1) / scene.gown.edge_rest - 1.0


def kinetic_energy(scene: Scene) -> float:
    return float(0.5 * (scene.gown.masses * (scene.cloth.velocities() ** 2).sum(axis=1)).sum())


def test_the_gown_hanging_from_a_still_gripper_settles(scene):
    grip = pose(SHOULDER + [1.2, 0.0, 0.0])  # out of the human's reach
    scene.reset(grip)
    scene.cloth.set_state(transform_points(grip, scene.gown.positions))  # unsettled start
    energy = []
    for _ in range(400):
        info = scene.step(np.zeros(11), grip)
        assert not info.sim_failure
        energy.append(kinetic_energy(scene))
    x = scene.cloth_positions()
    assert np.isfinite(x).all()
    assert max(energy) > 1e-3  # it really was moving
    assert energy[-1] < 1e-6  # joules, for a 150 g gown: at rest
    stretch = edge_stretch(scene, x)
    p95 = np.percentile(stretch, 95)
    print(f"rest stretch: median {np.median(stretch):.4f}, p95 {p95:.4f}, max {stretch.max():.4f}")
    assert np.median(np.abs(stretch)) < 0.01
    assert p95 < 0.08
    assert stretch.max() < 0.7  # a few edges where the unheld left half hangs from the right


def test_the_sleeve_slides_over_an_outstretched_arm(scene):
    q = scene.human.outstretched()
    scene.reset(pose(SHOULDER + [1.05, 0.0, 0.0]), human_q=q)
    hold = scene.human.action_for(q)
    start, end = SHOULDER + [1.05, 0.0, 0.0], SHOULDER + [0.35, 0.0, 0.0]
    touched = False
    for k in range(1, 151):
        grip = pose(start + (end - start) * min(1.0, k / 120))
        info = scene.step(hold, grip)
        assert not info.sim_failure
        touched |= assert_contact_invariants(scene)
    assert touched
    state = measure(scene)
    assert state.containment.contained
    assert state.arm_progress > 0.2  # the hand and part of the forearm are through


def assert_contact_invariants(scene: Scene) -> bool:
    """Pins follow the gripper, nothing is inside the skin, every contact force reaches the body
    and exactly one sensor. Returns whether there was contact."""
    x = scene.cloth_positions()
    held = transform_points(scene.gripper_pose, scene.gown.positions[scene.pinned])
    assert np.abs(x[scene.pinned] - held).max() < 1e-3
    assert_no_deep_penetration(scene, x)
    np.testing.assert_allclose(
        scene.haptic_forces.sum(axis=0), scene.contact_force, atol=1e-4, rtol=1e-4
    )
    contacts = scene.cloth.contacts_now()
    np.testing.assert_allclose(
        contacts["force"].sum(axis=0), scene.cloth.body_wrenches()[0].sum(axis=0), atol=1e-4
    )
    return len(contacts["vertex"]) > 0


def assert_no_deep_penetration(scene: Scene, x: np.ndarray) -> None:
    free = np.setdiff1d(np.arange(len(x)), scene.pinned)
    depth = limb_depth(scene, x[free]).max()
    assert depth < 1e-3, f"a cloth vertex is {depth * 1e3:.1f} mm inside a capsule"


def test_the_cloth_stops_an_arm_sweeping_into_the_opening_across_its_rim(scene):
    """The arm swings in from the side, already past the opening's plane: the held rim stops
    it, so the metric never counts the arm as contained."""
    grip = pose(SHOULDER + [0.45, 0.0, 0.02])
    scene.reset(grip)
    peak = 0.0
    touched = False
    for k in range(120):
        scene.step(reach_action(k), grip)
        assert not measure(scene).containment.contained
        touched |= assert_contact_invariants(scene)
        peak = max(peak, float(np.linalg.norm(scene.contact_force)))
    assert touched
    assert peak > 5.0  # newtons: the rim pushed back on the arm


def test_a_free_gripper_goes_exactly_where_the_robot_commands(scene):
    start = pose(SHOULDER + [1.2, 0.0, 0.0])  # out of the human's reach
    scene.reset(start)
    for k in range(1, 21):
        turn = k * 0.02  # about z, while it moves
        command = pose(start[:3] + [0.004 * k, 0.002 * k, -0.001 * k],
                       [0.0, 0.0, np.sin(turn / 2), np.cos(turn / 2)])  # fmt: skip
        scene.step(np.zeros(11), command)
        np.testing.assert_allclose(scene.gripper_pose, command, atol=1e-9)


def test_the_robot_cannot_push_the_held_rim_through_the_body(scene):
    """A path into the chest: the rim stays outside the skin and the gripper stops short, held
    back by its force limit, where a placed rim went through (docs/scene.md)."""
    start = SHOULDER + [0.45, 0.19, -0.12]  # in front of the chest, the opening facing it
    scene.reset(pose(start))
    rim = scene.gown.positions[scene.gown.feature_loop]
    deepest = -np.inf
    for k in range(1, 51):  # 0.5 m toward the human in 2 s, to behind the chest's centre
        command = pose(start - [0.01 * k, 0.0, 0.0])
        scene.step(np.zeros(11), command)
        ring = transform_points(scene.gripper_pose, rim)
        deepest = max(deepest, float(limb_depth(scene, ring).max()))
    assert deepest < 0.0  # the rim's 6 mm capsules keep its loop out of the skin
    assert scene.gripper_pose[0] - command[0] > 0.1  # it stopped against the chest


def test_the_same_actions_give_the_same_trajectory(scene):
    def run() -> tuple[np.ndarray, np.ndarray]:
        grip = pose(SHOULDER + [0.45, 0.0, 0.02])
        scene.reset(grip)
        for k in range(40):
            scene.step(reach_action(k, period=80), grip)
        return scene.cloth_positions(), scene.human.q

    x1, q1 = run()
    x2, q2 = run()
    np.testing.assert_array_equal(x1, x2)
    np.testing.assert_array_equal(q1, q2)


def test_an_action_of_the_wrong_shape_is_refused(scene):
    scene.reset(pose(SHOULDER + [0.45, 0.0, 0.0]))
    with pytest.raises(ValueError):
        scene.step(np.zeros(10), scene.gripper_pose)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_a_non_finite_action_ends_the_episode_flagged_with_the_state_untouched(scene, bad):
    scene.reset(pose(SHOULDER + [0.45, 0.0, 0.0]))
    q = scene.human.q.copy()
    info = scene.step(np.full(11, bad), scene.gripper_pose)
    assert info.sim_failure and "not finite" in info.reason
    np.testing.assert_array_equal(scene.human.q, q)


def test_a_diverging_cloth_ends_with_a_failure_flag_not_an_exception(scene):
    grip = pose(SHOULDER + [0.45, 0.0, 0.0])
    scene.reset(grip)
    x = scene.cloth_positions()
    scene.cloth.set_state(x, np.full_like(x, 200.0))  # a cloth flung off at 350 m/s
    info = scene.step(np.zeros(11), grip)
    assert info.sim_failure and "cloth speed" in info.reason
    assert scene.step(np.zeros(11), grip).sim_failure  # it stays failed until a reset

    scene.reset(grip)
    scene.human.skeleton.setVelocities(np.full(22, np.nan))  # a blown-up body
    info = scene.step(np.zeros(11), grip)
    assert info.sim_failure and "non-finite" in info.reason

    scene.reset(grip)
    scene.human.skeleton.setVelocities(np.full(22, 1e6))  # finite, but no body moves so
    info = scene.step(np.zeros(11), grip)
    assert info.sim_failure and "joint speed" in info.reason

    scene.reset(grip)
    assert not scene.step(np.zeros(11), grip).sim_failure


def test_the_device_area_ratio_matches_the_reference_metric(scene):
    grip = pose(SHOULDER + [0.45, 0.0, 0.02])
    scene.reset(grip)
    for k in range(30):
        scene.step(reach_action(k, period=60), grip)
    x = scene.cloth_positions()
    expected = metrics.max_area_ratio(x, scene.gown.triangles, scene.gown.rest_areas)
    assert scene.cloth.max_area_ratio() == pytest.approx(expected, rel=1e-5)
