"""A sweep: a grid of training runs, each a normal run folder, then one leaderboard of their
policies. ``backend`` "local" trains them one after another in this process; "ray" trains them
as Ray tasks, as many at once as the cluster has CPUs for (docs/cluster.md).

It uses both training and evaluation, so it sits above them (docs/architecture.md).
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator, Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .checks import (
    EPISODES,
    RESULTS,
    check_episodes,
    check_folder,
    check_gown_vertices,
    check_seed,
)
from .cluster import Backend, ClusterError
from .config import EnvConfig
from .training.config import TrainConfig

if TYPE_CHECKING:
    import pandas as pd

NAMED_AXES = ("robot", "ablation", "profile", "algo", "seed")  # already in a run's default name
ENV_FIELDS = ("horizon",)  # the leaderboard's env too: one value per sweep


@dataclass(frozen=True)
class Sweep:
    """Every combination of ``grid`` (``TrainConfig`` field -> values) trained with ``train``
    (the other ``TrainConfig`` fields, the recipe among them), then evaluated over ``episodes``
    seeded rollouts each, into ``results``."""

    grid: Mapping[str, Sequence[Any]] = field(
        default_factory=lambda: {
            axis: [getattr(TrainConfig, axis)] for axis in ("robot", "ablation", "seed")
        }  # fmt: skip
    )
    train: Mapping[str, Any] = field(default_factory=dict)
    episodes: int = EPISODES
    seed: int = 0  # the evaluation's base seed (each run's own is a grid axis or in ``train``)
    results: str = RESULTS
    workers: int | None = None  # evaluation processes (local) or tasks at once (ray)
    eval_gown_vertices: int = EnvConfig.gown_vertices  # the leaderboard's gown, not training's

    def __post_init__(self) -> None:
        names = {f.name for f in fields(TrainConfig)}
        unknown = sorted((set(self.grid) | set(self.train)) - names)
        if unknown:
            raise ValueError(f"not TrainConfig fields: {', '.join(unknown)}")
        both = sorted(set(self.grid) & set(self.train))
        if both:
            raise ValueError(f"{', '.join(both)} given both as a grid axis and a fixed option")
        if "name" in self.grid or "name" in self.train:
            raise ValueError("a sweep names its runs itself (ROBOT-ABLATION-ALGO-sSEED...)")
        if empty := [axis for axis, values in self.grid.items() if not values]:
            raise ValueError(f"grid axis {empty[0]} has no values")
        if varied := [axis for axis in ENV_FIELDS if len(self.grid.get(axis, ())) > 1]:
            raise ValueError(f"{varied[0]} is the leaderboard's env too: give one value")
        check_episodes(self.episodes)
        check_gown_vertices(self.eval_gown_vertices, "eval_gown_vertices")
        check_seed(self.seed)
        check_folder(self.results, "results")

    def runs(self) -> list[TrainConfig]:
        """One configuration per combination, in grid order; ``envs`` defaults to 1 (a sweep's
        parallelism is its grid), ``out`` and ``policies`` are made absolute (a worker writes
        where this process reads)."""
        options = {"envs": 1, **self.train}
        options["envs"] = options["envs"] or os.cpu_count() or 1  # 0: every core, for each run
        for folder in ("out", "policies"):
            options[folder] = str(Path(options.get(folder, getattr(TrainConfig, folder))).resolve())
        recipe = options.pop("recipe", "default")
        configs = []
        for values in itertools.product(*self.grid.values()):
            combination = dict(zip(self.grid, values, strict=True))
            config = TrainConfig.preset(recipe, **options, **combination)
            suffix = "".join(f"-{k}{v}" for k, v in combination.items() if k not in NAMED_AXES)
            configs.append(replace(config, name=config.run_name + suffix))
        return configs

    def env_options(self) -> dict[str, Any]:
        """The env options the policies are scored with: the horizon they were trained with, on
        the evaluation's gown."""
        chosen = {axis: values[0] for axis, values in self.grid.items()} | dict(self.train)
        horizon = {axis: chosen.get(axis, getattr(TrainConfig, axis)) for axis in ENV_FIELDS}
        return horizon | {"gown_vertices": self.eval_gown_vertices}


def sweep(
    config: Sweep,
    *,
    backend: str = "local",
    address: str | None = None,
    progress: bool = True,
) -> pd.DataFrame:
    """Train every run of ``config`` (each resumes from its checkpoint), then score each policy
    with the robot strategy it was trained for; returns the leaderboard table.

    Runs already finished only export again. The policies folder must be one where dressbench
    looks for trained humans (``./policies`` or a folder of ``DRESSBENCH_POLICIES``), so that
    the leaderboard, and every worker, finds them by name.
    """
    from .evaluation import leaderboard
    from .plugins import refresh

    where = Backend(backend, address)
    runs = config.runs()
    _check_runs(runs)
    with _connected(where):  # one Ray session for the trainings and their leaderboard
        policies = list(_train(runs, where, progress))
        refresh()  # the new policies are human plugins now
        return leaderboard(
            episodes=config.episodes,
            seed=config.seed,
            workers=config.workers,
            out=config.results,
            robots=list(dict.fromkeys(run.robot for run in runs)),
            humans=[policy.stem for policy in policies],
            progress=progress,
            backend=where.name,
            address=where.address,
            **config.env_options(),
        )


def _connected(where: Backend) -> AbstractContextManager[Any]:
    """A Ray session for the ray backend; nothing for the local one."""
    from .cluster.session import ray_session

    return ray_session(where.address) if where.is_ray else nullcontext()


def _check_runs(runs: Sequence[TrainConfig]) -> None:
    """Before any training: distinct names, each robot and capability profile checked once
    (``TrainConfig.check``), and a policies folder the registry looks in."""
    from .plugins.registry import policy_folders

    names = [run.run_name for run in runs]
    if len(set(names)) < len(names):
        raise ValueError(f"two runs of the grid share a name: {sorted(names)}")
    for run in {(run.robot, run.profile): run for run in runs}.values():
        run.check()
    searched = policy_folders()
    for folder in {Path(run.policies) for run in runs}:
        if folder.resolve() not in searched:
            raise ValueError(
                f"policies {str(folder)!r} is not where dressbench finds trained humans "
                "(./policies, or a folder of DRESSBENCH_POLICIES): the sweep could not score them"
            )


def _train(runs: Sequence[TrainConfig], where: Backend, progress: bool) -> Iterator[Path]:
    """Each run's policy JSON as it finishes: one after another here, or as Ray tasks (Ray
    connected)."""
    if not where.is_ray:
        from .training.run import train  # here: it loads torch and stable-baselines3

        for run in runs:
            yield train(run, progress=progress)
        return
    from tqdm.auto import tqdm

    from .cluster.tasks import run_remote

    cpus = max(run.n_envs for run in runs)  # each run reserves a CPU per env process
    with tqdm(total=len(runs), desc="sweep", unit="run", disable=not progress) as bar:
        # all submitted at once: Ray queues the runs its CPUs cannot take yet
        trained = run_remote(
            train_on_node, runs, limit=len(runs), cpus=cpus, describe=lambda r: f"run {r.run_name}"
        )
        for run, path in trained:
            yield _seen(run, Path(path))
            bar.update()


def train_on_node(config: TrainConfig) -> str:
    """One run on a Ray worker: its robot plugin checked on this node, then ``train``."""
    from .cluster.worker import require_plugins
    from .training.run import train

    require_plugins([config.robot])
    return str(train(config, progress=False))


def _seen(run: TrainConfig, path: Path) -> Path:
    """``path``, which a worker wrote, if this process sees it; else a ClusterError."""
    if not path.is_file():
        raise ClusterError(
            f"run {run.run_name} wrote its policy on another node ({path}): put out and "
            "policies on storage every node shares, at the same path"
        )
    return path
