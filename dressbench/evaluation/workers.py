"""Run episodes in this process or in a pool of worker processes, each keeping its env.

A worker ends itself within ``PARENT_POLL`` seconds of its parent's death (a killed
evaluation), rather than finish its episode and wait on the pool's pipe for a minute or more.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Any

from .cells import Cell
from .rollouts import SUCCESS_DEPTH, EpisodeRecord, Runner, episode_seed


@dataclass(frozen=True)
class Task:
    """Episode ``episode`` of ``cell`` in an evaluation seeded ``seed``."""

    cell: Cell
    seed: int
    episode: int
    success_depth: float = SUCCESS_DEPTH

    @property
    def episode_seed(self) -> int:
        """The seed the env and the human are reset with."""
        return episode_seed(self.seed, self.episode)

    @property
    def identity(self) -> dict[str, Any]:
        """What the task's record belongs to: its cell's identity, the base seed and the index."""
        return {**self.cell.identity, "seed": self.seed, "episode": self.episode}


_runner: Runner | None = None  # this process's env: rebuilt only when the cell changes
PARENT_POLL = 0.5  # s between a worker's checks that its parent is alive


def run_task(task: Task) -> EpisodeRecord:
    """Run one task here, reusing this process's env when the previous task had the same cell."""
    global _runner
    if _runner is None or _runner.cell != task.cell:
        _runner = None  # free the old env before building the next
        _runner = Runner(task.cell)
    return _runner.run(task.episode_seed, task.success_depth)


def exit_with_parent(parent: int) -> None:
    """Make this process exit as soon as process ``parent`` is gone (a pool's initializer).

    A daemon thread polls ``os.getppid()`` every ``PARENT_POLL`` s: when the parent dies the
    worker is re-parented, and it ends at once with ``os._exit`` (nothing of a killed run is
    left to save: finished episodes are already on disk).
    """

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL)
        os._exit(1)

    threading.Thread(target=watch, name="dressbench-exit-with-parent", daemon=True).start()


def run_tasks(tasks: Sequence[Task], workers: int) -> Iterator[tuple[Task, EpisodeRecord]]:
    """Each task with its record, as they finish: in this process for one worker, else in a
    "spawn" pool (fork is unsafe with Warp and DART threads); stopping early cancels the rest.
    No tasks: nothing is started, whatever ``workers``."""
    if not tasks:
        return
    if workers == 1:
        for task in tasks:
            yield task, run_task(task)
        return
    context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(
        min(workers, len(tasks)),
        mp_context=context,
        initializer=exit_with_parent,
        initargs=(os.getpid(),),
    )
    try:
        futures = {pool.submit(run_task, task): task for task in tasks}
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
