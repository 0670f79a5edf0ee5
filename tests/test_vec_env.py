"""Training's envs on every core: SharedCoreVecEnv steps env 0 in the training process and the
rest in workers, and gives the episodes one process would."""

import json
import multiprocessing
from functools import partial

import numpy as np
import pandas as pd
import pytest
from stable_baselines3.common.vec_env import DummyVecEnv

from dressbench.factory import make_human_env
from dressbench.training import TrainConfig, train
from dressbench.training.curriculum import CurriculumConfig, NearStarts
from dressbench.training.vec_env import SharedCoreVecEnv


def near_start_env(rank: int):
    """A small env whose episodes end after 4 steps, with the curriculum's near starts."""
    env = make_human_env("fixed", gown_vertices=600, horizon=4)
    return NearStarts(env, CurriculumConfig(share=1.0, held_share=1.0), seed=rank)


def rollout(venv, steps: int) -> list:
    venv.seed(7)
    observations = [venv.reset()]
    shape = (steps, venv.num_envs, *venv.action_space.shape)
    actions = np.random.default_rng(0).uniform(-1, 1, shape)
    for action in actions:
        observation, reward, done, infos = venv.step(action)
        observations.append((observation, reward, done, [i.get("near_start") for i in infos]))
    venv.close()
    return observations


@pytest.mark.parametrize("per_process", [1, 2], ids=["one-env-a-process", "groups-of-two"])
def test_a_group_here_and_the_rest_in_workers_give_the_episodes_of_one_process(per_process):
    factories = [partial(near_start_env, rank) for rank in range(3)]
    shared = rollout(SharedCoreVecEnv(factories, per_process), steps=6)  # past an episode's end
    single = rollout(DummyVecEnv(factories), steps=6)
    np.testing.assert_array_equal(shared[0], single[0])
    for (obs_a, rew_a, done_a, info_a), (obs_b, rew_b, done_b, info_b) in zip(
        shared[1:], single[1:], strict=True
    ):
        np.testing.assert_allclose(obs_a, obs_b, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(rew_a, rew_b, rtol=1e-6, atol=1e-6)
        np.testing.assert_array_equal(done_a, done_b)
        assert info_a == info_b
    assert shared[4][2].all()  # each episode ended at its 4th step


@pytest.mark.parametrize("per_process", [1, 2], ids=["one-env-a-process", "groups-of-two"])
def test_methods_and_attributes_reach_the_envs_they_name_wherever_they_run(per_process):
    venv = SharedCoreVecEnv([partial(near_start_env, rank) for rank in range(4)], per_process)
    try:
        venv.env_method("set_reach", 0.2, indices=[0, 2])
        assert venv.get_attr("reach") == pytest.approx([0.2, 0.05, 0.2, 0.05])
        venv.set_attr("reach", 0.3, indices=[1, 3])
        assert venv.get_attr("reach", indices=[2, 3]) == pytest.approx([0.2, 0.3])
        assert venv.env_is_wrapped(NearStarts) == [True] * 4
    finally:
        venv.close()


def test_it_needs_two_groups():
    with pytest.raises(ValueError, match="2 groups of 2 envs"):
        SharedCoreVecEnv([partial(near_start_env, rank) for rank in range(2)], per_process=2)


def broken_env():
    raise ValueError("robot plugin 'wobbly' cannot be built")


def test_an_error_in_a_worker_is_raised_again_in_the_training_process():
    with pytest.raises(ValueError, match="'wobbly' cannot be built"):
        SharedCoreVecEnv([partial(near_start_env, 0), partial(near_start_env, 1), broken_env])
    assert not multiprocessing.active_children()  # the group built before it was ended too
    venv = SharedCoreVecEnv([partial(near_start_env, rank) for rank in range(2)])
    try:
        with pytest.raises(AttributeError, match="no_such_method"):
            venv.env_method("no_such_method", indices=1)
        assert venv.get_attr("reach", indices=1) == pytest.approx([0.05])  # it serves on
    finally:
        venv.close()


@pytest.mark.parametrize("per_process", [1, 2], ids=["one-env-a-process", "groups-of-two"])
def test_a_run_with_two_env_processes_trains_and_coaches_them_all(tmp_path, per_process):
    coach = CurriculumConfig(
        share=1.0, held_share=1.0, judge="mean", trials=3, judge_every=128, promote_at=0.0
    )
    config = TrainConfig(gown_vertices=600, horizon=32, samples_per_update=128, envs=2,
                         envs_per_process=per_process,
                         timesteps=256, curriculum=coach, name="two", out=str(tmp_path / "runs"),
                         policies=str(tmp_path / "policies"))  # fmt: skip
    assert json.loads(train(config, progress=False).read_text())["steps"] == 256
    logged = pd.read_csv(tmp_path / "runs" / "two" / "logs" / "progress.csv")
    assert logged["curriculum/reach"].iloc[-1] > coach.first_reach
