"""Training throughput beside the bare env step (``dressbench bench --train``, docs/benchmark.md).

A short run of the default recipe trains in a temporary folder (its run folder and its policy
file are thrown away), and its environment steps per second are set against the cores' worth
of single-process env steps: the aim is ``TARGET_SHARE`` of (cores x the single env step).
Between the two, the run's own envs stepped alone (its env processes at once, no learner) tell
the cores' scaling apart from what the training loop costs."""

from __future__ import annotations

import tempfile
import time
from collections.abc import Iterator
from itertools import chain
from pathlib import Path

import numpy as np

from ..bench import TRAIN_STEPS, BenchOptions, Rows, bench_env, timing_row
from ..bench import bench_rows as physics_rows
from . import require_train_extra
from .config import TrainConfig

BENCH_RUN = "bench"  # the run's name inside the temporary folder
TARGET_SHARE = 0.85  # training's aim: this share of (env processes x the single env step)


def bench_rows(options: BenchOptions) -> Iterator[Rows]:
    """``dressbench.bench.bench_rows``, then with ``train`` a short training run beside the env
    step at each resolution (the training gown where none is given), with the lines of its
    shares (``shares``). PyBullet and the ``train`` extra are looked for now, before any row."""
    rows = physics_rows(options)
    if not options.train:
        return rows
    require_train_extra()
    return chain(rows, _training_rows(options))


def _training_rows(options: BenchOptions) -> Iterator[Rows]:
    for n in options.vertices or (TrainConfig.gown_vertices,):
        rows = bench_training(n, options.train_steps, options.timed_steps, options.repeats,
                              options.train_envs, options.train_envs_per_process)  # fmt: skip
        yield rows, shares(*rows[1:])


def bench_training(
    vertices: int = TrainConfig.gown_vertices,
    timesteps: int = TRAIN_STEPS,
    env_steps: int = 200,
    repeats: int = 3,
    envs: int = 0,
    envs_per_process: int = 1,
) -> list[dict]:
    """Time a short training run of the default recipe, its envs alone and the bare env step.

    Returns the env row of ``dressbench.bench.bench_env`` (``env_steps`` steps, best of
    ``repeats``), an ``envs`` row (``bench_training_envs``: the run's env processes stepped
    alone, ``env_steps`` steps each) and a ``train`` row: SB3's own environment steps per
    second of learning (at its last logged update), the wall seconds of the whole call, the env
    processes and the envs each steps. ``share_of_cores`` is a row's rate over (env processes x
    the single env step rate); the train row's ``share_of_envs``, its rate over the envs row's.
    """
    with tempfile.TemporaryDirectory(prefix="dressbench-train-bench-") as folder:
        config = bench_config(vertices, timesteps, envs, envs_per_process, Path(folder))
        single = bench_env(vertices, env_steps, "cpu", repeats)
        alone = bench_training_envs(config, env_steps, single["vertices"])
        rate, seconds = _train_rate(config)
    cores = config.processes * single["steps_per_second"]
    alone["share_of_cores"] = round(alone["steps_per_second"] / cores, 3)
    share = rate / cores
    learning = timing_row(single["vertices"], "train", timesteps, timesteps / rate)  # SB3's rate
    train = learning | {"seconds": round(seconds, 1), "envs": config.processes,
                        "envs_per_process": config.envs_per_process,
                        "share_of_cores": round(share, 3),
                        "share_of_envs": round(rate / alone["steps_per_second"], 3)}  # fmt: skip
    return [single, alone, train]


def shares(alone: dict, train: dict) -> list[str]:
    """What ``bench_training``'s rows say: the envs' and the training's shares of the cores."""
    cores = f"{train['envs']} cores x the env step"
    return [f"its envs alone: {alone['share_of_cores']:.0%} of {cores}",
            f"training: {train['share_of_cores']:.0%} of {cores} (aim: at least "
            f"{TARGET_SHARE:.0%}), {train['share_of_envs']:.0%} of its envs alone"]  # fmt: skip


def bench_training_envs(config: TrainConfig, steps: int, vertices: int, warmup: int = 5) -> dict:
    """Time the run's training envs stepped alone: ``steps`` steps of every env process at once
    (after ``warmup`` untimed ones), with actions drawn as the recipe's first policy draws
    them, N(0, action_std) clipped to [-1, 1]; near starts, resets and wrappers as in training.
    ``vertices`` (the gown's, as the env row counts them) labels the row."""
    from .run import training_envs  # stable-baselines3 loads here

    venv = training_envs(config)
    try:
        venv.seed(config.seed)
        venv.reset()
        rng = np.random.default_rng(config.seed)
        shape = (warmup + steps, venv.num_envs, *venv.action_space.shape)
        actions = np.clip(rng.normal(0.0, config.action_std, shape), -1.0, 1.0)
        failed = False
        for action in actions[:warmup]:
            venv.step(action)
        start = time.perf_counter()
        for action in actions[warmup:]:
            infos = venv.step(action)[3]
            failed |= any(info.get("sim_failure", False) for info in infos)
        seconds = time.perf_counter() - start
    finally:
        venv.close()
    total = steps * venv.num_envs
    return {**timing_row(vertices, "envs", total, seconds, failed), "envs": config.processes,
            "envs_per_process": config.envs_per_process}  # fmt: skip


def bench_config(
    vertices: int, timesteps: int, envs: int, envs_per_process: int, folder: Path
) -> TrainConfig:
    """The default recipe for ``timesteps`` steps, its run and policy under ``folder``; a run
    shorter than the recipe's batch updates once, on all its samples, so SB3 logs its rate."""
    recipe = TrainConfig.preset("default")
    return TrainConfig.preset(
        "default",
        timesteps=timesteps,
        gown_vertices=vertices,
        envs=envs,
        envs_per_process=envs_per_process,
        samples_per_update=min(recipe.samples_per_update, timesteps),
        out=str(folder / "runs"),
        policies=str(folder / "policies"),
        name=BENCH_RUN,
    )


def _train_rate(config: TrainConfig) -> tuple[float, float]:
    """Train ``config``: SB3's environment steps per second, and the wall seconds of the call."""
    from .run import train  # torch and stable-baselines3 load here
    from .summary import learning_table  # pandas loads here

    start = time.perf_counter()
    train(config, progress=False)
    seconds = time.perf_counter() - start
    try:
        table = learning_table(Path(config.out) / config.run_name)
    except FileNotFoundError:  # SB3 logs its rate after a whole rollout, and no rollout ended
        steps, envs = config.timesteps, config.n_envs
        raise ValueError(
            f"{steps} training steps end before the first update: give 64 per env ({envs}) at least"
        ) from None
    return float(table["time/fps"].iloc[-1]), seconds
