"""The ``family`` robot strategy: a seeded draw of a strategy per episode, wide enough to hold
the built-in strategies and the example ``arc`` plugin, whose humans are meant for any strategy."""

import numpy as np
import pytest
from capsules import capsule_depth

from dressbench.evaluation import leaderboard_cells
from dressbench.factory import make_env, make_human_env
from dressbench.metrics import feature_plane
from dressbench.plugins import load_robot
from dressbench.plugins.contract import start_pose_problem, trains_generalists
from dressbench.plugins.family import KINDS, Family, cylindrical, episode_members
from dressbench.plugins.protocols import OBS_TIME, ROBOT_DT, ROBOT_MAX_SPEED
from dressbench.plugins.robots import LINEAR_DURATION
from dressbench.scene.geometry import transform_points
from dressbench.scene.world import Scene, SceneConfig
from dressbench.training.curriculum import CurriculumConfig, NearStarts

DRAWS = 400


def members(seed: int, draws: int = DRAWS):
    family, rng = Family(), np.random.default_rng(seed)
    for _ in range(draws):
        start = family.reset(rng)
        yield start, family.member


def test_a_member_is_drawn_from_the_envs_rng_alone():
    first = [start for start, _ in members(3, 50)]
    again = [start for start, _ in members(3, 50)]
    other = [start for start, _ in members(4, 50)]
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    assert not all(np.array_equal(a, b) for a, b in zip(first, other, strict=True))


def test_every_draw_is_a_valid_start_in_the_familys_support_and_every_kind_is_drawn():
    kinds = set()
    for start, member in members(0):
        kinds.add(member.kind)
        assert start_pose_problem(start) is None
        assert Family.config.holds(start, member.target)
    assert kinds == set(KINDS)


def play(strategy, start: np.ndarray, seconds: float) -> tuple[np.ndarray, float]:
    """Integrate a strategy's actions from ``start`` without a scene: the gripper's end and the
    largest action entry it asked for."""
    position, observation, largest = start[:3].copy(), np.zeros(22), 0.0
    for k in range(int(seconds / ROBOT_DT)):
        observation[:3], observation[OBS_TIME] = position, k * ROBOT_DT
        action = np.asarray(strategy.act(observation))
        largest = max(largest, float(np.abs(action).max()))
        position += action * ROBOT_MAX_SPEED * ROBOT_DT
    return position, largest


def test_a_moving_member_reaches_its_target_within_the_grippers_speed_and_stays():
    family, rng = Family(), np.random.default_rng(1)
    moving = 0
    while moving < 40:
        start = family.reset(rng)
        member = family.member
        if member.kind not in ("straight", "curve"):
            continue
        moving += 1
        end, largest = play(family, start, member.duration + member.pause + 2.0)
        assert np.linalg.norm(end - member.target) < 1e-3
        assert largest <= 1.0


def test_a_pause_holds_the_gripper_still_on_its_way():
    family, rng = Family(), np.random.default_rng(2)
    while True:
        family.reset(rng)
        member = family.member
        if member.kind == "straight" and member.pause > 0.0:
            break
    stop = member.duration * member.pause_at
    during = [member.position(stop + f * member.pause) for f in (0.0, 0.5, 1.0)]
    assert np.allclose(during[0], during[1]) and np.allclose(during[1], during[2])
    assert not np.allclose(member.position(stop / 2), during[0])


def builtin_starts_and_targets(name: str, draws: int = 300):
    """(start pose, target) of a strategy's resets: a linear one's target is where its 10 s of
    motion ends, a still one's its start, the arc's its own."""
    strategy, rng = load_robot(name), np.random.default_rng(0)
    observation = np.zeros(22)
    for _ in range(draws):
        start = strategy.reset(rng)
        if hasattr(strategy, "target"):
            yield start, np.asarray(strategy.target)
        else:
            velocity = np.asarray(strategy.act(observation)) * ROBOT_MAX_SPEED
            yield start, start[:3] + velocity * LINEAR_DURATION


@pytest.mark.parametrize("name", ["fixed", "front_linear", "side_linear", "arc"])
def test_the_builtin_strategies_and_the_arc_plugin_lie_in_the_familys_support(name):
    for start, target in builtin_starts_and_targets(name):
        moving = np.linalg.norm(target - start[:3]) > 1e-9
        assert Family.config.holds(start, target if moving else None), (start, target)


def test_what_the_gripper_holds_is_outside_the_resting_human_at_every_start_and_target():
    scene = Scene(SceneConfig())
    human = scene.human
    human.reset()
    capsules = human.capsules(human.body_transforms())
    held = scene.gown.positions[scene.pinned]
    for start, member in members(5, 200):
        for position in member.ends:
            pose = np.concatenate([position, start[3:]])
            depth = capsule_depth(transform_points(pose, held), capsules, human.capsule_radius)
            assert depth.max() < 0.0, (member.kind, cylindrical(position))


def test_a_reactive_member_brings_the_opening_toward_the_hand_in_the_scene():
    env = make_env("family", gown_vertices=300, horizon=120, actuation="delta")
    for seed in range(50):
        observations, _ = env.reset(seed=seed)
        if env.robot_strategy.member.kind == "reactive":
            break
    member = env.robot_strategy.member
    hold = np.zeros(env.action_space("human").shape)  # delta actuation: the arm holds still

    def gap(observation):  # from the gripper to where the member heads, before the fingertip
        tip, elbow = observation[10:13], observation[16:19]
        goal = tip + member.standoff * (tip - elbow) / np.linalg.norm(tip - elbow)
        return float(np.linalg.norm(goal - observation[:3]))

    before = gap(observations["robot"])
    for _ in range(120):
        observations, *_ = env.step({"robot": env.robot_strategy.act(observations["robot"]),
                                     "human": hold})  # fmt: skip
    assert gap(observations["robot"]) < before - min(0.05, before / 2)


def test_the_family_trains_generalists_and_is_scored_only_when_asked_for():
    assert trains_generalists(Family) and not trains_generalists(load_robot("fixed"))
    default = {cell.robot for cell in leaderboard_cells(humans=["passive"], gown_vertices=300)}
    asked = {cell.robot for cell in leaderboard_cells(["family"], ["passive"], gown_vertices=300)}
    assert "family" not in default and {"fixed", "front_linear"} <= default
    assert asked == {"family"}


def test_the_curriculum_places_each_near_start_for_that_episodes_member():
    """Near starts follow the member of each episode: along its first move where that brings the
    opening onto the hand, along the opening's axis where it holds still; where the arm cannot
    point exactly so (a member far to the side), nearly so."""
    env = NearStarts(make_human_env("family", actuation="delta", gown_vertices=300),
                     CurriculumConfig(share=1.0, held_share=1.0))  # fmt: skip
    seen, alignment = set(), []
    for seed in range(12):
        _, info = env.reset(seed=seed)
        move = env.unwrapped.robot_next_move()
        scene = env.unwrapped.env.scene
        tip, wrist = scene.human.arm_chain(scene.human.body_transforms())[:2]
        plane = feature_plane(scene.cloth_positions()[scene.gown.feature_loop])
        onto_hand = np.dot(move, plane.normal) < -1e-9
        along = -move / np.linalg.norm(move) if onto_hand else plane.normal
        alignment.append(np.dot((tip - wrist) / np.linalg.norm(tip - wrist), along))
        assert 0.0 < info["near_start"] <= 0.05  # the first level
        assert np.linalg.norm(plane.centroid - tip) < info["near_start"] + 0.05
        seen.add(onto_hand)
    assert seen == {True, False}  # members of both kinds in a dozen episodes
    assert min(alignment) > 0.95 and np.median(alignment) > 0.999


def test_the_member_an_episode_faced_is_known_from_its_seed_alone():
    env = make_env("family", gown_vertices=300, horizon=2)
    seeds = [11, 12, 13, 14]
    faced = []
    for seed in seeds:
        env.reset(seed=seed)
        faced.append(env.robot_strategy.member)
    for member, known in zip(faced, episode_members(seeds), strict=True):
        assert member.kind == known.kind and np.array_equal(member.start, known.start)
