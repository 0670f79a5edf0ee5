"""``evaluate`` and ``leaderboard``: seeded, parallel, resumable evaluations written to a folder."""

from __future__ import annotations

import os
import time
import warnings
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, NamedTuple

import pandas as pd
from tqdm.auto import tqdm

from ..checks import (
    EPISODES,
    RESULTS,
    check_episode_timeout,
    check_episodes,
    check_folder,
    check_processes,
    check_seed,
)
from ..cluster import Backend
from ..files import write_csv
from ..provenance import git_commit, versions
from .archive import load_archive, save_archive
from .cells import (
    Cell,
    adapted_profiles,
    checked_cell,
    describe_plugin,
    leaderboard_cells,
    warn_losing_duplicates,
)
from .finetuned import write_finetuned
from .groups import episode_humans
from .members import write_members
from .ownership import check_owned, claim
from .remote import ray_tasks
from .report import stage_definitions, success_definition, write_summary
from .rollouts import SUCCESS_DEPTH, EpisodeRecord
from .schema import EPISODE_COLUMNS
from .statistics import CONFIDENCE, RESAMPLES, curve_table, leaderboard_table
from .store import cell_folder, load_record, report_earlier_rollouts, save_record
from .strategies import write_strategies
from .workers import Failure, Task, default_timeout, run_tasks


class Evaluated(NamedTuple):
    """What an evaluation wrote, as tables: its episodes (episodes.csv), its cells
    (leaderboard.csv) and its strategies (strategies.csv)."""

    episodes: pd.DataFrame
    leaderboard: pd.DataFrame
    strategies: pd.DataFrame


def evaluate(
    robot: str,
    human: str,
    episodes: int = EPISODES,
    seed: int = 0,
    workers: int | None = None,
    out: str | os.PathLike = RESULTS,
    *,
    success_depth: float = SUCCESS_DEPTH,
    progress: bool = True,
    backend: str = "local",
    address: str | None = None,
    episode_timeout: float | None = None,
    **options: Any,
) -> pd.DataFrame:
    """Score ``robot`` with ``human`` over seeded episodes; write the results to ``out``.

    Returns the episodes table (one row per rollout, as in episodes.csv). ``options`` go to
    ``make_human_env`` (horizon, gown_vertices, device, ...); the ablation is the human's.
    Episodes already in ``out`` of the same identity (the robot's and human's names, versions
    and, for a trained policy, checksum; the env settings; the seed) are not run again. Both
    plugins are first checked in a small env (``cells.plugin_problems``): a ValueError names
    the one that fails and why. ``backend`` "ray" runs the episodes as Ray tasks, on a local
    instance or, given an ``address``, a cluster (docs/cluster.md): the same files, the same
    numbers. An episode that fails (its plugin raises, runs past ``episode_timeout`` seconds,
    default ``workers.default_timeout``, or kills its worker) is a ValueError naming the
    plugin, its package and the episode's seed.
    """
    where = check_run(episodes, seed, workers, out, backend, address, episode_timeout)
    cell = checked_cell(robot, human, **options)
    return evaluate_cells(
        [cell], episodes, seed, workers, Path(out), success_depth, progress, "evaluate", options,
        backend=where, episode_timeout=episode_timeout,
    ).episodes  # fmt: skip


def leaderboard_results(
    episodes: int = EPISODES,
    seed: int = 0,
    workers: int | None = None,
    out: str | os.PathLike = RESULTS,
    humans: Iterable[str] | None = None,
    robots: Iterable[str] | None = None,
    *,
    success_depth: float = SUCCESS_DEPTH,
    progress: bool = True,
    backend: str = "local",
    address: str | None = None,
    episode_timeout: float | None = None,
    **options: Any,
) -> Evaluated:
    """Evaluate every robot strategy against the humans meant for it; write the combined files.

    The cells are every ok robot plugin × every ok human plugin trained for it or generic
    (``robot`` None, as the baselines passive, random and scripted); ``robots`` / ``humans``
    restrict the names; ``profile``, one capability profile or several, scores them under each
    (``profiles_cells``). Returns the three tables it writes (``Evaluated``). ``backend``,
    ``address`` and ``episode_timeout`` are those of ``evaluate``; a cell whose episode fails is
    left out with a warning naming the plugin, its package and the episode's seed (run_meta.json
    lists it), and the others are scored.
    """
    where = check_run(episodes, seed, workers, out, backend, address, episode_timeout)
    cells = profiles_cells(robots, humans, **options)
    if not cells:
        raise ValueError(
            "nothing to evaluate: no usable robot strategy with a usable human meant for it"
        )
    return evaluate_cells(
        cells, episodes, seed, workers, Path(out), success_depth, progress, "leaderboard", options,
        backend=where, episode_timeout=episode_timeout,
    )  # fmt: skip


def profiles_cells(
    robots: Iterable[str] | None, humans: Iterable[str] | None, **options: Any
) -> list[Cell]:
    """``leaderboard_cells`` under each capability profile of ``options["profile"]`` (one name
    or several; left out: each human under its own), in that order, each cell once.

    A named human adapted to a profile other than typical is scored under that profile alone
    when it is among those asked (one command then makes the grid of typical humans under every
    profile beside each adapted human under its own), and under those asked when it is not."""
    asked = options.pop("profile", None)
    if asked is None:
        return leaderboard_cells(robots, humans, **options)
    profiles = [asked] if isinstance(asked, str) else list(dict.fromkeys(asked))
    robots, humans = (None if names is None else list(names) for names in (robots, humans))
    adapted = {} if humans is None else adapted_profiles(humans)

    def named(profile: str) -> list[str] | None:
        """The named humans scored under ``profile``."""
        if humans is None:
            return None
        return [
            name
            for name in humans
            if adapted.get(name, profile) == profile or adapted[name] not in profiles
        ]

    found = [
        cell
        for profile in profiles
        for cell in leaderboard_cells(robots, named(profile), **options, profile=profile)
    ]
    return list(dict.fromkeys(found))


def leaderboard(*args: Any, **kwargs: Any) -> pd.DataFrame:
    """``leaderboard_results`` (the same arguments), returning its leaderboard table (as in
    leaderboard.csv): every robot strategy evaluated against the humans meant for it."""
    return leaderboard_results(*args, **kwargs).leaderboard


def check_run(
    episodes: int,
    seed: int,
    workers: int | None,
    out: str | os.PathLike,
    backend: str,
    address: str | None,
    episode_timeout: float | None = None,
) -> Backend:
    """Refuse, before anything runs, a count out of range, an ``out`` that is no folder or an
    unknown backend: episodes from 1 to ``MAX_EPISODES``, seed from 0 to ``MAX_SEED``, workers
    None (one per core) or from 1 to ``MAX_PROCESSES``, ``out`` a folder that exists or can be
    created and not a folder of someone else's files that the results would replace
    (``ownership.check_owned``), ``backend`` and ``address`` as ``Backend`` takes them,
    ``episode_timeout`` None or positive. Returns the backend."""
    check_episode_timeout(episode_timeout)
    check_episodes(episodes)
    check_seed(seed)
    if workers is not None:
        check_processes(workers)
    check_folder(out, "out")
    check_owned(out)
    return Backend(backend, address)


def evaluate_cells(
    cells: Sequence[Cell],
    episodes: int,
    seed: int,
    workers: int | None,
    out: Path,
    success_depth: float,
    progress: bool,
    command: str,
    options: dict[str, Any],
    *,
    backend: Backend,
    episode_timeout: float | None = None,
) -> Evaluated:
    """Run what is missing of ``episodes`` per cell on ``backend``, saving each as it finishes;
    then summarize the cells none of whose episodes failed (the failed ones: a warning each)."""
    started, clock = datetime.now(timezone.utc), time.perf_counter()
    warn_losing_duplicates(cells)
    claim(out)
    tasks = [
        Task(cell, seed, episode, success_depth, episode_timeout or _default_timeout(cell))
        for cell in cells
        for episode in range(episodes)
    ]
    archived = _archived(out, cells, seed, tasks)
    done = archived | {task: record for task in tasks if task not in archived
                       and (record := load_record(out, task)) is not None}  # fmt: skip
    pending = [task for task in tasks if task not in done]
    # cells whole in rollouts/ but not (wholly) archived: archived below; the running cells as
    # they finish
    unarchived = {t.cell for t in tasks if t not in archived} - {t.cell for t in pending}
    found = {task.cell for task in done}
    report_earlier_rollouts(out, [cell for cell in cells if cell not in found])
    flagged: dict[Cell, str] = {}  # a failed episode's line, per cell: its others are not run
    if backend.is_ray:  # None: as many at once as the cluster has CPUs for
        results = ray_tasks(pending, workers, backend.address, lambda t: t.cell in flagged)
    else:
        workers = workers or os.cpu_count() or 1
        results = run_tasks(pending, workers, lambda t: t.cell in flagged)
    left = Counter(task.cell for task in pending)  # episodes still to run, per cell
    with tqdm(
        total=len(tasks), initial=len(done), desc=command, unit="episode", disable=not progress
    ) as bar:
        try:
            for task, record in results:  # nothing pending: nothing starts
                if isinstance(record, Failure):
                    if task.cell not in flagged:  # its first failure; a cell's others are alike
                        flagged[task.cell] = _flag(task, record)
                        warnings.warn(flagged[task.cell], stacklevel=3)
                    bar.update()
                    continue
                save_record(out, task, record)  # each record at once: a stopped run resumes
                done[task] = record
                left[task.cell] -= 1
                if not left[task.cell]:  # the table once per finished cell, not per episode
                    write_csv(out / "episodes.csv", _episodes_table(tasks, done))
                    _archive(out, task.cell, seed, episodes, success_depth, done)
                bar.update()
        except BaseException:  # interrupted or failed: the table shows what finished
            write_csv(out / "episodes.csv", _episodes_table(tasks, done))
            raise
    elapsed = time.perf_counter() - clock
    if len(flagged) == len(cells):
        raise ValueError("; ".join(flagged.values()))
    cells = [cell for cell in cells if cell not in flagged]
    tasks = [task for task in tasks if task.cell not in flagged]
    for cell in cells:
        if cell in unarchived:
            _archive(out, cell, seed, episodes, success_depth, done)
    table = _episodes_table(tasks, done)
    write_csv(out / "episodes.csv", table)
    curves = curve_table(
        (
            {**cell.columns, "seed": seed},
            [done[Task(cell, seed, episode, success_depth)] for episode in range(episodes)],
        )
        for cell in cells
    )
    board = leaderboard_table(table, seed)
    meta = {
        "command": command,
        "started": started.isoformat(timespec="seconds"),
        "elapsed_seconds": round(elapsed, 3),
        "episodes_run": len(pending),
        "episodes_per_cell": episodes,
        "seed": seed,
        "episode_seeds": "numpy.random.SeedSequence(seed).spawn(n)[episode].generate_state(1)[0]",
        "workers": workers,
        "episode_timeout": episode_timeout or "default: max(60, horizon x gown_vertices x 1e-4) s",
        "flagged_cells": list(flagged.values()),
        "backend": backend.name,
        "address": backend.address,
        "options": options,
        "success": success_definition(success_depth),
        "success_depth": success_depth,
        "stages": stage_definitions(success_depth),
        "confidence_interval": f"means: {CONFIDENCE:.0%} percentile bootstrap of the mean, "
        f"{RESAMPLES} resamples, numpy default_rng(seed); stage rates: {CONFIDENCE:.0%} Wilson "
        f"score interval",
        "cells": [cell.columns for cell in cells],
        "plugins": [
            {"robot": cell.identity["robot"], "human": cell.identity["human"]} for cell in cells
        ],
        "rollouts": [cell_folder(out, cell).relative_to(out).as_posix() for cell in cells],
        "configs": {cell.columns["config_id"]: cell.config() for cell in cells},
        "versions": versions(),
        "git_commit": git_commit(),
    }
    humans = episode_humans(table)  # each policy file read once, for both tables of trained humans
    strategies = write_strategies(out, table, seed, humans)  # before the summary, which lists them
    write_members(out, table, seed)
    write_finetuned(out, table, seed, humans)
    write_summary(out, curves, board, meta, success_depth)
    return Evaluated(table, board, strategies)


def _default_timeout(cell: Cell) -> float:
    """The default time limit of ``cell``'s episodes (``workers.default_timeout``)."""
    return default_timeout(cell.columns["horizon"], cell.columns["gown_vertices"])


def _flag(task: Task, failure: Failure) -> str:
    """The one line saying which cell failed, whose fault, where it comes from, and when."""
    cell = task.cell
    if failure.plugin is None:
        who = f"{describe_plugin('robot', cell.robot)} with {describe_plugin('human', cell.human)}"
    else:
        who = describe_plugin(failure.plugin, getattr(cell, failure.plugin))
    return (
        f"cell {cell.robot!r} x {cell.human!r} left out: {who} {failure.reason} in episode "
        f"{task.episode} (episode seed {task.episode_seed})"
    )


def _archived(
    out: Path, cells: Sequence[Cell], seed: int, tasks: Sequence[Task]
) -> dict[Task, EpisodeRecord]:
    """The tasks whose episodes a cell archive holds (``archive.py``), judged at each task's
    success depth."""
    found = {cell: load_archive(out, cell, seed) for cell in cells}
    return {
        task: replace(found[task.cell][task.episode], success_depth=task.success_depth)
        for task in tasks
        if task.episode < len(found[task.cell])
        and found[task.cell][task.episode].episode_seed == task.episode_seed
    }


def _archive(
    out: Path,
    cell: Cell,
    seed: int,
    episodes: int,
    success_depth: float,
    done: dict[Task, EpisodeRecord],
) -> None:
    """Archive a cell whose episodes are all done."""
    records = [done.get(Task(cell, seed, episode, success_depth)) for episode in range(episodes)]
    if all(record is not None for record in records):
        save_archive(out, cell, seed, records)


def _episodes_table(tasks: Sequence[Task], done: dict[Task, EpisodeRecord]) -> pd.DataFrame:
    """The finished tasks' rows, in task order (cell, then episode) whatever order they ran in."""
    rows = [
        {**task.cell.columns, "seed": task.seed, "episode": task.episode, **done[task].scores()}
        for task in tasks
        if task in done
    ]
    return pd.DataFrame(rows, columns=EPISODE_COLUMNS)
