"""The deformation score measures what the body does to the gown: the gown keeps its shape where
nothing pushes it, stretch needs force, and no triangle straddles a limb (docs/cloth.md).

Each cause found behind the old artifacts has its own test below the acceptance tests.
"""

from functools import cache

import numpy as np
import pytest
from capsules import capsule_depth, limb_depth

import dressbench
from dressbench.plugins import load_human, load_robot
from dressbench.plugins.protocols import OBS_TIME, ROBOT_MAX_SPEED
from dressbench.plugins.robots import LINEAR_DURATION
from dressbench.scene.garment import BACK, GownConfig, make_gown
from dressbench.scene.geometry import transform_points
from dressbench.scene.world import Scene, SceneConfig, tethers

ROBOTS = ("fixed", "front_linear", "side_linear")


def episode(robot: str, human: str, seed: int, vertices: int = 2000, horizon: int = 400):
    """Yield the env after every step of one seeded episode."""
    env = _env(robot, vertices, horizon)
    policy = load_human(human)
    observations, _ = env.reset(seed=seed)
    policy.reset(seed)
    while env.agents:
        actions = {
            "human": policy.act(observations["human"]),
            "robot": env.robot_strategy.act(observations["robot"]),
        }
        observations, _, _, _, infos = env.step(actions)
        assert not infos["human"]["sim_failure"], infos["human"]["failure_reason"]
        yield env, infos["human"]


@cache
def _env(robot: str, vertices: int, horizon: int):
    return dressbench.make_env(robot, gown_vertices=vertices, horizon=horizon)


def triangle_areas(x: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    a, b, c = x[triangles[:, 0]], x[triangles[:, 1]], x[triangles[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def yarn_edges(gown) -> np.ndarray:
    """The edges along the pattern's rows and columns (the fabric's warp and weft); the others
    are the grid's diagonals, which measure shear, not stretch."""
    d = np.abs(np.diff(gown.pattern[gown.edges], axis=1)[:, 0])
    return np.any(d < 1e-9, axis=1)


# ------------------------------------------------------------------------------ acceptance
@pytest.mark.parametrize("vertices", [2000, 1000])
@pytest.mark.parametrize("robot", ROBOTS)
def test_a_hanging_gown_keeps_its_shape(robot, vertices):
    """Passive human, 400 steps, 3 seeds: area ratio <= 1.10 and yarn-edge stretch <= 10%
    (docs/cloth.md). Measured with 14 iterations: 1.06-1.08 and 8-9% at 2,000 vertices,
    1.08-1.09 and 9-10% at 1,000. The grid's diagonals shear by up to 29%: a draped woven
    fabric shears, and shear does not enlarge a triangle (docs/cloth.md)."""
    worst_ratio, worst_yarn, worst_shear = 0.0, 0.0, 0.0
    for seed in range(3):
        for env, info in episode(robot, "passive", seed, vertices):
            gown = env.scene.gown
            x = env.scene.cloth_positions()
            stretch = np.linalg.norm(x[gown.edges[:, 0]] - x[gown.edges[:, 1]], axis=1)
            stretch = stretch / gown.edge_rest - 1.0
            yarn = yarn_edges(gown)
            worst_ratio = max(worst_ratio, info["max_deformation"])
            worst_yarn = max(worst_yarn, stretch[yarn].max())
            worst_shear = max(worst_shear, stretch[~yarn].max())
    print(f"{robot} {vertices}: {worst_ratio:.3f} {worst_yarn:.3f} {worst_shear:.3f}")
    assert worst_ratio <= 1.10
    assert worst_yarn <= 0.10
    assert worst_shear <= 0.32


def test_the_sleeve_slid_over_an_outstretched_arm_barely_stretches():
    from dressbench.calibration import sleeve_over_arm

    scene = Scene(SceneConfig())
    for seconds in (9.6, 1.6):
        ratio, force = sleeve_over_arm(scene, seconds)
        assert ratio <= 1.5
        assert force > 1.0  # it did touch the arm


@pytest.mark.parametrize("robot", ROBOTS)
def test_stretch_needs_force_and_happens_at_the_body(robot):
    """Scripted and random humans: no step stretches a triangle past 1.5 while the body feels
    less than 2 N, and a triangle stretched past 2 lies within 5 cm of a limb."""
    for human in ("scripted", "random"):
        for seed in range(2):
            for env, info in episode(robot, human, seed):
                scene = env.scene
                x = scene.cloth_positions()
                ratios = triangle_areas(x, scene.gown.triangles) / scene.gown.rest_areas
                worst = int(np.argmax(ratios))
                if ratios[worst] > 1.5:
                    assert info["contact_force"] >= 2.0, (human, seed, ratios[worst])
                if ratios[worst] > 2.0:
                    centroid = x[scene.gown.triangles[worst]].mean(axis=0)[None]
                    depth = limb_depth(scene, centroid)
                    assert -depth.max() <= 0.05, (human, seed, ratios[worst])


@pytest.mark.parametrize("robot", ROBOTS)
def test_no_triangle_straddles_a_limb(robot):
    """A triangle whose centroid is inside a capsule is a penetration too."""
    limit = SceneConfig().cloth.thickness + 0.005
    for human in ("scripted", "random"):
        for seed in range(2):
            for env, _ in episode(robot, human, seed, horizon=200):
                scene = env.scene
                centroids = scene.cloth_positions()[scene.gown.triangles].mean(axis=1)
                depth = limb_depth(scene, centroids)
                assert depth.max() <= limit, (human, seed, depth.max())


# ------------------------------------------------------------------------------ the causes
def test_no_tether_crosses_the_open_back():
    """The back slit's two copies of u = 0 are apart on the garment: a vertex of one back half
    is tethered to a held vertex of the other only along the cloth (the old tethers took the
    straight pattern line across the slit for u = 0, and pulled the slit shut at rest)."""
    gown = make_gown(GownConfig())
    anchor, length = tethers(gown, np.sort(gown.feature_loop))
    free = anchor >= 0
    back = gown.sheet == BACK
    slit = back & (np.abs(gown.pattern[:, 0]) < 1e-9)
    assert set(np.unique(gown.side[slit])) == {-1, 1}  # the two copies, one per half
    left = slit & (gown.side > 0) & free
    straight = np.linalg.norm(gown.pattern[left] - gown.pattern[anchor[left]], axis=1)
    assert (gown.side[anchor[left]] < 0).all()  # the loop is on the right
    assert (length[left] > straight + 0.1).all()  # around the neck or the side, not across


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_gripper_holds_nothing_inside_the_body(robot):
    """At every start and target of a strategy, what the gripper holds is outside the resting
    human (the old hold also pinned 0.2 m lines of the gown's body, which front_linear drove
    into the head: the cloth beside them stretched 3x with no force)."""
    strategy = load_robot(robot)
    scene = Scene(SceneConfig())
    human = scene.human
    human.reset()
    capsules = human.capsules(human.body_transforms())
    held_in_gown_frame = scene.gown.positions[scene.pinned]
    rng = np.random.default_rng(0)
    start_observation = np.zeros(22)
    start_observation[OBS_TIME] = 0.0
    for _ in range(30):
        start = strategy.reset(rng)
        velocity = np.asarray(strategy.act(start_observation)) * ROBOT_MAX_SPEED
        end = np.concatenate([start[:3] + velocity * LINEAR_DURATION, start[3:]])
        for pose in (start, end):
            held = transform_points(pose, held_in_gown_frame)
            assert capsule_depth(held, capsules, human.capsule_radius).max() < 0.0


def test_a_limb_swept_through_the_gown_carries_it_instead_of_parting_it():
    """A fast, thin hand swept across the hanging gown: every triangle stays out of it (vertex
    contacts alone let it slip between vertices and part the fabric around itself)."""
    from dressbench.bench import reach_action

    scene = Scene(SceneConfig())
    grip = np.array([0.45, -0.04, 0.52, 0.0, 0.0, 0.0, 1.0])  # beside the opening
    scene.reset(grip)
    limit = scene.config.cloth.thickness + 0.005
    for k in range(100):
        scene.step(reach_action(k, period=100), grip)
        centroids = scene.cloth_positions()[scene.gown.triangles].mean(axis=1)
        depth = limb_depth(scene, centroids)
        assert depth.max() <= limit


def test_fabric_pressed_by_a_limb_pushes_back_on_it():
    """The sleeve over an outstretched arm: the body feels the fabric's tension (newtons), not
    just the momentum of a few grams of cloth (millinewtons before)."""
    from dressbench.calibration import sleeve_over_arm

    scene = Scene(SceneConfig())
    _, force = sleeve_over_arm(scene, 4.8)
    assert force > 2.0
