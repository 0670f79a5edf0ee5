"""The built-in robots and humans register like third-party plugins and keep the protocol."""

import numpy as np
import pytest

import dressbench
from dressbench import plugins
from dressbench.plugins.robots import RIGHT_SHOULDER
from dressbench.testing import check_human_plugin, check_robot_plugin

ROBOTS = ["fixed", "front_linear", "side_linear"]
HUMANS = ["passive", "random", "reach", "scripted"]


def test_the_builtins_register_through_entry_points():
    robots, humans = plugins.robot_plugins(), plugins.human_plugins()
    for name in ROBOTS:
        assert robots[name].ok and robots[name].package == "dressbench"
    for name in HUMANS:
        assert humans[name].ok and humans[name].package == "dressbench"


@pytest.mark.parametrize("name", ROBOTS)
def test_builtin_robots_pass_the_plugin_check(name):
    check_robot_plugin(name)


@pytest.mark.parametrize("name", HUMANS)
def test_builtin_humans_pass_the_plugin_check(name):
    check_human_plugin(name)


def test_the_check_names_what_is_wrong():
    class NoQuaternion:
        api_version = 1

        def reset(self, rng):
            return np.zeros(7)

        def act(self, observation):
            return np.zeros(3)

    with pytest.raises(AssertionError, match="expected a unit quaternion"):
        check_robot_plugin(NoQuaternion())


def boxes(name: str, seeds=range(200)) -> np.ndarray:
    robot = plugins.load_robot(name)
    return np.array([robot.reset(np.random.default_rng(s)) for s in seeds])


def test_fixed_gown_samples_the_papers_box_in_front_of_the_shoulder():
    poses = boxes("fixed")
    extent = poses[:, :3].max(0) - poses[:, :3].min(0)
    np.testing.assert_allclose(extent, [0.1, 0.6, 0.35], atol=0.03)  # depth, lateral, vertical
    assert (poses[:, 0] > RIGHT_SHOULDER[0] + 0.35).all()  # in front of the shoulder


def test_linear_strategies_move_to_their_target_in_10_s_then_hold():
    for name in ("front_linear", "side_linear"):
        env = dressbench.make_env(name, gown_vertices=600, horizon=260)
        observations, _ = env.reset(seed=3)
        start = observations["robot"][:3].copy()
        for _ in range(260):
            action = env.robot_strategy.act(observations["robot"])
            observations, *_ = env.step({"robot": action, "human": np.zeros(11)})
        end = observations["robot"][:3]
        assert np.linalg.norm(end - start) > 0.2
        assert np.allclose(observations["robot"][3:6], 0.0)  # still after 10 s


def test_side_linear_turns_the_sleeve_away_from_the_approach():
    robot = plugins.load_robot("side_linear")
    pose = robot.reset(np.random.default_rng(0))
    yaw = 2 * np.arctan2(pose[5], pose[6])
    assert np.cos(yaw + np.pi / 2) > 0.9  # the sleeve points to the human's right (-y)


def test_unknown_names_suggest_the_nearest():
    with pytest.raises(plugins.UnknownPluginError, match="did you mean 'front_linear'"):
        dressbench.make_env("front_liner")


def test_reach_holds_the_arm_straight_out_ahead_whatever_it_sees():
    """The `reach` baseline: a still, outstretched arm, so a leaderboard shows what the robot
    strategy achieves on its own."""
    env = dressbench.make_human_env("fixed", horizon=40, gown_vertices=600)
    human = plugins.load_human("reach")
    observation, _ = env.reset(seed=0)
    first = human.act(observation)
    for _ in range(40):
        action = human.act(observation)
        np.testing.assert_array_equal(action, first)
        observation, *_ = env.step(action)
    tip, wrist, elbow, shoulder = env.env.scene.arm_chain()
    arm = tip - shoulder
    assert arm[0] > 0.6 and abs(arm[2]) < 0.1  # ahead at shoulder height
    bend = np.dot(_unit(wrist - elbow), _unit(elbow - shoulder))
    assert bend > 0.98  # the elbow straight


def _unit(v):
    return v / np.linalg.norm(v)
