"""Training throughput beside the bare env step (``dressbench bench --train``, docs/benchmark.md).

A short run of the default recipe trains in a temporary folder (its run folder and its policy
file are thrown away), and its environment steps per second are set against the cores' worth
of single-process env steps: issue 12's target is 85% of (cores x the single env step).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from ..bench import bench_env
from .config import TrainConfig
from .summary import learning_table

BENCH_RUN = "bench"  # the run's name inside the temporary folder
TRAIN_STEPS = 8192  # two of the default recipe's updates (4,096 samples each)


def bench_training(
    vertices: int = 2000,
    timesteps: int = TRAIN_STEPS,
    env_steps: int = 200,
    repeats: int = 3,
    envs: int = 0,
) -> list[dict]:
    """Time a short training run of the default recipe and the bare single env step.

    Returns the env row of ``dressbench.bench.bench_env`` (``env_steps`` steps, best of
    ``repeats``) and a ``train`` row: SB3's own environment steps per second of learning (at
    its last logged update), the wall seconds of the whole call, the env processes, and
    ``share_of_cores``, the training rate over (env processes x the single env step rate).
    """
    with tempfile.TemporaryDirectory(prefix="dressbench-train-bench-") as folder:
        config = bench_config(vertices, timesteps, envs, Path(folder))  # checked before work
        single = bench_env(vertices, env_steps, "cpu", repeats)
        rate, seconds = _train_rate(config)
    share = rate / (config.n_envs * single["steps_per_second"])
    train = {
        "vertices": single["vertices"],
        "what": "train",
        "steps": timesteps,
        "seconds": round(seconds, 1),
        "steps_per_second": round(rate, 1),
        "ms_per_step": round(1e3 / rate, 3),
        "sim_failure": False,
        "envs": config.n_envs,
        "share_of_cores": round(share, 3),
    }
    return [single, train]


def bench_config(vertices: int, timesteps: int, envs: int, folder: Path) -> TrainConfig:
    """The default recipe for ``timesteps`` steps, its run and policy under ``folder``; a run
    shorter than the recipe's batch updates once, on all its samples, so SB3 logs its rate."""
    recipe = TrainConfig.preset("default")
    return TrainConfig.preset(
        "default",
        timesteps=timesteps,
        gown_vertices=vertices,
        envs=envs,
        samples_per_update=min(recipe.samples_per_update, timesteps),
        out=str(folder / "runs"),
        policies=str(folder / "policies"),
        name=BENCH_RUN,
    )


def _train_rate(config: TrainConfig) -> tuple[float, float]:
    """Train ``config``: SB3's environment steps per second, and the wall seconds of the call."""
    from .run import train  # torch and stable-baselines3 load here

    start = time.perf_counter()
    train(config, progress=False)
    seconds = time.perf_counter() - start
    try:
        table = learning_table(Path(config.out) / config.run_name)
    except FileNotFoundError:  # SB3 logs its rate after a whole rollout, and no rollout ended
        steps, envs = config.timesteps, config.n_envs
        raise ValueError(
            f"{steps} training steps end before the first update: give 64 per env process "
            f"({envs}) at least"
        ) from None
    return float(table["time/fps"].iloc[-1]), seconds
