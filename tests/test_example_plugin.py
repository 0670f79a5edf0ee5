"""The example plugin package ``plugins/dressbench-arc``: found through its entry points, works.

The project's setup script installs it; without it these tests fail, on purpose.
"""

import numpy as np
import pytest

import dressbench
from dressbench import plugins
from dressbench.env import HUMAN, ROBOT
from dressbench.observation import N_DOFS
from dressbench.plugins.robots import RIGHT_SHOULDER, ROBOT_DT
from dressbench.preflight import profile_problem
from dressbench.scene.body import DOF_NAMES
from dressbench.testing import check_human_plugin, check_robot_plugin

SMALL = {"gown_vertices": 600}  # fast tests: a coarse gown
INSTALL = "install it with: .venv/bin/pip install -e plugins/dressbench-arc"
ARC_STEPS = round(8.0 / ROBOT_DT)  # the arc takes 8 s
REACH = slice(3 * N_DOFS + 3, 3 * N_DOFS + 6)  # fingertip - armhole centre, human observation


@pytest.mark.parametrize(
    "records, name",
    [
        (plugins.robot_plugins, "arc"),
        (plugins.human_plugins, "follow_task"),
        (plugins.profile_plugins, "stiff_elbow"),
    ],
)
def test_dressbench_finds_the_example_through_its_entry_points(records, name):
    found = records()
    assert name in found, f"plugin {name!r} not found: {INSTALL}"
    plugin = found[name]
    assert (plugin.package, plugin.version) == ("dressbench-arc", "0.1.0")
    assert plugin.status == "ok", plugin.error


def test_the_example_passes_the_plugin_checks_the_readme_shows():
    check_robot_plugin("arc")
    check_human_plugin("follow_task")


def test_the_example_profile_passes_its_check_and_stiffens_the_elbow():
    assert profile_problem("stiff_elbow") is None
    env = dressbench.make_env("fixed", profile="stiff_elbow", horizon=40, **SMALL)
    elbow = DOF_NAMES.index("elbow_r_flexion")
    assert env.scene.human.upper[elbow] == np.pi / 2
    env.reset(seed=0)
    for _ in range(40):  # the largest flexion the PD can ask for
        env.step({ROBOT: np.zeros(3), HUMAN: np.ones(11)})
        assert env.scene.human.q[elbow] < np.pi / 2 + 0.1


def test_arc_initial_poses_are_seeded():
    robot = plugins.load_robot("arc")
    first, again = (robot.reset(np.random.default_rng(5)) for _ in range(2))
    other = robot.reset(np.random.default_rng(6))
    np.testing.assert_array_equal(first, again)
    assert not np.allclose(first, other)


def test_arc_swings_in_to_the_shoulder_and_holds():
    env = dressbench.make_env("arc", horizon=ARC_STEPS + 60, **SMALL)
    obs, _ = env.reset(seed=0)
    robot, pose = env.robot_strategy, env.scene.gripper_pose.copy()
    path = [obs[ROBOT][:3]]
    while env.agents:
        obs, _, terminations, _, _ = env.step({ROBOT: robot.act(obs[ROBOT]), HUMAN: np.zeros(11)})
        assert not terminations[ROBOT], "the simulation failed"
        path.append(obs[ROBOT][:3])
    path = np.array(path, dtype=float)
    start, end = path[0], path[ARC_STEPS]

    from_shoulder = start - RIGHT_SHOULDER
    assert from_shoulder[0] > 0.3 and from_shoulder[1] < -0.3  # front-right of the human
    yaw = 2.0 * np.arctan2(pose[5], pose[6])  # the sleeve (+x) turned away from the shoulder
    assert np.isclose(yaw, np.arctan2(from_shoulder[1], from_shoulder[0]))
    chord = (end - start) / np.linalg.norm(end - start)
    off_chord = np.linalg.norm(np.cross(path[:ARC_STEPS] - start, chord), axis=1)
    assert off_chord.max() > 0.05  # a curve, not a line
    radii = np.linalg.norm(path[: ARC_STEPS + 1] - robot.arc.centre, axis=1)
    assert np.ptp(radii) < 1e-3  # a circular one
    assert np.linalg.norm(end - robot.target) < 1e-3
    assert 0.2 < np.linalg.norm(end - RIGHT_SHOULDER) < 0.3
    assert np.linalg.norm(path[ARC_STEPS - 5] - end) > 0.005  # still moving just before 8 s
    assert np.abs(path[ARC_STEPS:] - end).max() < 1e-6  # then holds still


def test_follow_task_human_runs_with_the_arc():
    env = dressbench.make_human_env("arc", **SMALL)
    human = plugins.load_human("follow_task")
    assert (human.robot, human.ablation) == ("arc", "complete")
    human.reset(seed=0)
    obs, _ = env.reset(seed=0)
    reach = [np.linalg.norm(obs[REACH])]
    for _ in range(30):
        action = np.asarray(human.act(obs))
        assert action.shape == (11,) and np.isfinite(action).all()
        assert np.abs(action).max() <= 1.0
        obs, _, terminated, truncated, _ = env.step(action)
        assert not (terminated or truncated)
        reach.append(np.linalg.norm(obs[REACH]))
    assert reach[-1] < reach[0]  # following the task vector brings the hand to the opening
