"""The two-agent environment and the human's single-agent view, as the spec describes them."""

import json
import subprocess
import sys

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env
from pettingzoo.test import parallel_api_test
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import dressbench
from dressbench.env import HUMAN, ROBOT

SMALL = {"gown_vertices": 600}  # fast tests: a coarse gown


def test_pettingzoo_parallel_api():
    parallel_api_test(dressbench.make_env("fixed", horizon=30, **SMALL), num_cycles=40)


@pytest.mark.parametrize("robot", ["fixed", "front_linear", "side_linear"])
def test_single_agent_view_passes_gymnasium_and_sb3_checks(robot):
    env = dressbench.make_human_env(robot, horizon=20, **SMALL)
    gym_check_env(env, skip_render_check=True)
    sb3_check_env(env)


@pytest.mark.parametrize(
    "ablation, size", [("complete", 163), ("no_haptics", 75), ("no_task", 160)]
)
def test_observation_sizes_follow_the_paper(ablation, size):
    env = dressbench.make_env("fixed", ablation=ablation, **SMALL)
    obs, _ = env.reset(seed=0)
    assert obs[HUMAN].shape == (size,) == env.observation_space(HUMAN).shape
    assert obs[ROBOT].shape == (22,) == env.observation_space(ROBOT).shape
    assert env.action_space(HUMAN).shape == (11,) and env.action_space(ROBOT).shape == (3,)


def rollout(seed: int, steps: int = 50) -> tuple[np.ndarray, np.ndarray]:
    env = dressbench.make_human_env("front_linear", **SMALL)
    obs, _ = env.reset(seed=seed)
    action_rng = np.random.default_rng(seed)
    observations, rewards = [obs], []
    for _ in range(steps):
        obs, reward, *_ = env.step(action_rng.uniform(-1, 1, 11))
        observations.append(obs)
        rewards.append(reward)
    return np.array(observations), np.array(rewards)


def test_a_seed_reproduces_50_steps_exactly():
    obs1, rew1 = rollout(7)
    obs2, rew2 = rollout(7)
    np.testing.assert_array_equal(obs1, obs2)
    np.testing.assert_array_equal(rew1, rew2)
    obs3, _ = rollout(8, steps=1)
    assert not np.array_equal(obs1[0], obs3[0])  # another seed, another episode


def test_a_seed_reproduces_an_episode_in_another_process():
    obs, rewards = rollout(3, steps=20)
    code = (
        "import json, sys; sys.path.insert(0, 'tests'); from test_env import rollout; "
        "o, r = rollout(3, steps=20); print(json.dumps([o.tolist(), r.tolist()]))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=300
    ).stdout
    other_obs, other_rewards = json.loads(out.strip().splitlines()[-1])
    np.testing.assert_array_equal(obs, np.array(other_obs, dtype=np.float32))
    np.testing.assert_array_equal(rewards, np.array(other_rewards))


@pytest.fixture(scope="module")
def env():
    return dressbench.make_env("fixed", **SMALL)


def actions(human=None, robot=None):
    return {
        HUMAN: np.zeros(11) if human is None else human,
        ROBOT: np.zeros(3) if robot is None else robot,
    }


@pytest.mark.parametrize(
    "bad, message",
    [
        (actions(human=np.zeros(10)), "shape"),
        (actions(human=np.full(11, np.nan)), "finite"),
        (actions(robot=np.array([0.0, np.inf, 0.0])), "finite"),
        ({HUMAN: np.zeros(11)}, "missing"),
    ],
)
def test_malformed_actions_raise_a_clear_value_error(env, bad, message):
    env.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        env.step(bad)


def test_out_of_range_actions_are_clipped_and_counted(env):
    env.reset(seed=0)
    human = np.zeros(11)
    human[:3] = [2.0, -5.0, 1.5]
    *_, infos = env.step(actions(human=human, robot=np.array([3.0, 0.0, 0.0])))
    assert infos[HUMAN]["clipped_actions"] == 3
    assert infos[ROBOT]["clipped_actions"] == 1


def test_every_human_step_reports_progress_deformation_force_and_failure(env):
    env.reset(seed=1)
    for _ in range(3):
        _, rewards, _, _, infos = env.step(actions())
        info = infos[HUMAN]
        for key in ("arm_progress", "max_deformation", "contact_force", "sim_failure"):
            assert key in info
        assert info["max_deformation"] >= 1.0
        assert rewards[HUMAN] == pytest.approx(sum(info["reward_terms"].values()))
        assert rewards[ROBOT] == rewards[HUMAN]  # cooperative


def test_the_horizon_truncates(env):
    short = dressbench.make_env("fixed", horizon=3, **SMALL)
    short.reset(seed=0)
    for _ in range(3):
        _, _, terminations, truncations, _ = short.step(actions())
    assert truncations == {ROBOT: True, HUMAN: True}
    assert terminations == {ROBOT: False, HUMAN: False}
    assert short.agents == []


def test_a_simulation_failure_terminates_with_a_flag(env):
    env.reset(seed=0)
    env.scene.human.skeleton.setVelocities(np.full(22, np.nan))
    obs, rewards, terminations, truncations, infos = env.step(actions())
    assert terminations[HUMAN] and infos[HUMAN]["sim_failure"]
    assert all(np.isfinite(o).all() for o in obs.values())
    assert rewards[HUMAN] < 0


def test_the_no_haptics_ablation_drops_the_deformation_term():
    env = dressbench.make_env("fixed", ablation="no_haptics", **SMALL)
    env.reset(seed=0)
    *_, infos = env.step(actions())
    assert set(infos[HUMAN]["reward_terms"]) == {"progress", "geodesic", "upright"}


def test_unknown_options_are_refused():
    with pytest.raises(TypeError, match="unknown option"):
        dressbench.make_env("fixed", gown_resolution=100)
    with pytest.raises(ValueError, match="ablation"):
        dressbench.make_env("fixed", ablation="no_arms")


def test_rgb_array_rendering_returns_a_picture():
    env = dressbench.make_env("fixed", render_mode="rgb_array", **SMALL)
    env.reset(seed=0)
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 50  # not a blank image
    assert dressbench.make_env("fixed", **SMALL).render() is None


def test_a_scene_whose_steps_do_not_add_up_to_the_policy_step_is_refused():
    from dataclasses import replace

    from dressbench.config import EnvConfig
    from dressbench.scene.world import SceneConfig

    EnvConfig(scene=replace(SceneConfig(), dt=0.005, frame_skip=8))  # a finer physics is fine
    with pytest.raises(ValueError, match="the policy step is 0.04 s"):
        EnvConfig(scene=replace(SceneConfig(), frame_skip=2))
