"""The start-state curriculum's near starts (docs/training.md): where the coach puts the hand."""

from __future__ import annotations

import numpy as np
import pytest

from dressbench.factory import make_human_env
from dressbench.metrics import feature_plane
from dressbench.training.curriculum import CurriculumConfig, NearStarts, approach_line


def near_start(robot: str, seed: int):
    """A near start of the first level: the robot's first move, the hand's points, the opening."""
    human_env = make_human_env(robot, actuation="delta")
    env = NearStarts(human_env, CurriculumConfig(share=1.0, held_share=1.0))
    _, info = env.reset(seed=seed)
    move = env.unwrapped.robot_next_move()
    scene = env.unwrapped.env.scene
    tip, wrist = scene.human.arm_chain(scene.human.body_transforms())[:2]
    plane = feature_plane(scene.cloth_positions()[scene.gown.feature_loop])
    env.close()
    return info["near_start"], move, tip, wrist, plane


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("robot", ["front_linear", "side_linear"])
def test_a_near_start_lies_on_the_path_the_robot_moves_the_opening_along(robot):
    distance, move, tip, wrist, plane = near_start(robot, seed=3)
    approach = -unit(move)  # the opening comes toward the hand
    assert np.dot(unit(tip - wrist), approach) > 0.999  # the hand points along the path
    assert np.dot(approach, plane.normal) < 0.98  # which is not the opening's axis
    to_centre = plane.centroid - tip
    assert np.dot(to_centre, approach) == pytest.approx(distance, abs=2e-3)
    assert np.linalg.norm(to_centre - np.dot(to_centre, approach) * approach) < 2e-3


def test_a_near_start_on_a_gown_held_still_points_the_hand_along_the_openings_axis():
    distance, move, tip, wrist, plane = near_start("fixed", seed=3)
    assert np.all(move == 0.0)
    assert np.dot(unit(tip - wrist), plane.normal) > 0.999
    assert np.dot(plane.centroid - tip, plane.normal) == pytest.approx(distance, abs=2e-3)


class Counting:
    """A robot strategy with a memory: it moves toward the human twice, then sideways."""

    api_version = 1

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        self.acts = 0
        return np.array([0.6, 0.0, -0.05, 0.0, 0.0, 0.0, 1.0])

    def act(self, observation: np.ndarray) -> np.ndarray:
        self.acts += 1
        return np.array([-0.5, 0.0, 0.0]) if self.acts <= 2 else np.array([0.0, 0.5, 0.0])


def test_asking_for_the_robots_first_move_leaves_the_strategy_and_its_episode_unchanged():
    def episode(ask: bool) -> tuple[list[np.ndarray | None], np.ndarray]:
        env = make_human_env(Counting())
        env.reset(seed=5)
        moves, rest = [], np.zeros(env.action_space.shape)
        for _ in range(3):
            moves.append(env.robot_next_move() if ask else None)
            env.step(rest)
        env.close()
        return moves, env.env.scene.gripper_pose.copy()

    (first, second, third), asked = episode(ask=True)
    assert np.dot(first, second) > 0.0 and np.dot(second, third) == 0.0  # each the next one
    assert np.array_equal(asked, episode(ask=False)[1])


@pytest.mark.parametrize("robot", ["front_linear", "side_linear"])
def test_the_moving_strategies_bring_the_opening_onto_the_hand_from_their_first_move(robot):
    env = make_human_env(robot, gown_vertices=600)
    for seed in range(10):
        env.reset(seed=seed)
        assert approach_line(env.env.scene, env.robot_next_move()).onto_hand
    env.close()


@pytest.mark.parametrize(("robot", "near"), [("front_linear", True), ("fixed", False)])
def test_the_share_of_near_starts_is_held_share_where_the_robot_does_not_bring_the_opening(
    robot, near
):
    config = CurriculumConfig(share=1.0, held_share=0.0)
    env = NearStarts(make_human_env(robot, gown_vertices=600), config, seed=2)
    starts = [env.reset(seed=1)[1]["near_start"]] + [env.reset()[1]["near_start"] for _ in range(3)]
    assert all((d > 0.0) == near for d in starts)
    env.close()


def test_the_judges_trials_all_start_near_and_training_goes_back_to_its_share():
    env = NearStarts(
        make_human_env("fixed", gown_vertices=600), CurriculumConfig(share=0.0, held_share=0.0)
    )
    env.set_trials(True)
    trials = [env.reset(seed=seed)[1]["near_start"] for seed in (1, 2)]
    env.set_trials(False)
    assert all(0.0 < d <= env.reach for d in trials) and env.reset(seed=3)[1]["near_start"] == 0
    env.close()


def test_a_curriculum_with_an_unknown_judge_is_refused():
    with pytest.raises(ValueError, match="unknown judge"):
        CurriculumConfig(judge="eyeballed")
