"""Run episodes in this process or in worker processes, each keeping its env.

A plugin's failure is its task's, not the run's: any exception (``SystemExit`` included) or an
episode past its time limit comes back as a ``Failure``, and so does a task whose worker died
(``os._exit``, the OOM killer, a native crash) ``TRIES`` times; a dead worker is replaced. In
this process (one worker) exceptions and the time limit are caught too, but a plugin that ends
the process (``os._exit``, a crash) ends the run: use two workers or more to isolate those.
A worker ends itself within ``PARENT_POLL`` seconds of its parent's death (a killed
evaluation), rather than finish its episode first.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time
import traceback
from collections import Counter, deque
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from multiprocessing.connection import wait
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
    timeout: float | None = field(default=None, compare=False)  # s per episode; None: no limit

    @property
    def episode_seed(self) -> int:
        """The seed the env and the human are reset with."""
        return episode_seed(self.seed, self.episode)

    @property
    def identity(self) -> dict[str, Any]:
        """What the task's record belongs to: its cell's identity, the base seed and the index."""
        return {**self.cell.identity, "seed": self.seed, "episode": self.episode}


@dataclass(frozen=True)
class Failure:
    """Why a task has no record: ``plugin`` ("human", "robot" or None: unknown) and one line."""

    plugin: str | None
    reason: str


class EpisodeTimeout(BaseException):
    """An episode ran past its time limit (a BaseException: a plugin's ``except Exception``
    does not swallow it)."""


_runner: Runner | None = None  # this process's env: rebuilt only when the cell changes
PARENT_POLL = 0.5  # s between a worker's checks that its parent is alive
TRIES = 3  # runs of a task whose worker dies before it is flagged
SECONDS_PER_VERTEX_STEP = 1e-4  # an episode's default limit: ~20x a 2000-vertex step's 5 ms
MIN_TIMEOUT = 60.0  # s: the least default limit
_LATE = "ran past its time limit of {:g} s (--episode-timeout)"
GRACE = 30.0  # s past an episode's limit before its worker is killed (it ignored the alarm)


def run_task(task: Task) -> EpisodeRecord | Failure:
    """Run one task here, reusing this process's env when the previous task had the same cell;
    a failure of the episode (any exception, ``SystemExit``, its time limit) is returned."""
    global _runner
    try:
        if _runner is None or _runner.cell != task.cell:
            _runner = None  # free the old env before building the next
            _runner = Runner(task.cell)
        with time_limit(task.timeout):  # the episode's, not the env's building (Warp compiles)
            return _runner.run(task.episode_seed, task.success_depth)
    except EpisodeTimeout:
        failure = Failure(None, _LATE.format(task.timeout))
    except (Exception, SystemExit) as error:
        failure = Failure(_blame(error, _runner), f"raised {_one_line(error)}")
    _runner = None  # its env or policy may be left in any state
    return failure


def default_timeout(horizon: int, gown_vertices: int) -> float:
    """An episode's default time limit, scaled to its work: ``max(MIN_TIMEOUT, horizon x
    gown_vertices x SECONDS_PER_VERTEX_STEP)`` s (80 s for 400 steps of a 2000-vertex gown)."""
    return max(MIN_TIMEOUT, horizon * gown_vertices * SECONDS_PER_VERTEX_STEP)


@contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise ``EpisodeTimeout`` in the block after ``seconds`` (a SIGALRM timer; no limit
    for None, off the main thread or where there is no SIGALRM)."""
    usable = hasattr(signal, "SIGALRM") and threading.current_thread() is threading.main_thread()
    if seconds is None or not usable:
        yield
        return

    def expire(signum: int, frame: Any) -> None:
        raise EpisodeTimeout

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _blame(error: BaseException, runner: Runner | None) -> str | None:
    """Which plugin raised ``error``: the one whose class's file is the deepest in its
    traceback; "human" for an action the env refused as the human's; else None."""
    import inspect

    if runner is None:
        return None
    files = {}
    robot = getattr(getattr(runner.env, "env", None), "robot_strategy", None)
    for who, plugin in (("robot", robot), ("human", runner.policy)):
        try:
            files.setdefault(inspect.getfile(type(plugin)), who)
        except TypeError:  # a class without a file
            pass
    for frame, _ in reversed(list(traceback.walk_tb(error.__traceback__))):
        if frame.f_code.co_filename in files:
            return files[frame.f_code.co_filename]
    if isinstance(error, ValueError) and str(error).startswith("human action"):
        return "human"
    return None


def _one_line(error: BaseException) -> str:
    """``'Type: first line'`` of an exception."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return f"{type(error).__name__}: {lines[0]}" if lines else type(error).__name__


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


def run_tasks(
    tasks: Sequence[Task], workers: int, skip: Callable[[Task], bool] = lambda task: False
) -> Iterator[tuple[Task, EpisodeRecord | Failure]]:
    """Each task with its record or failure, as they finish: in this process for one worker,
    else in "spawn" worker processes (fork is unsafe with Warp and DART threads), a dead one
    replaced; a task ``skip`` says yes to when its turn comes is not run; stopping early ends
    the workers. No tasks: nothing is started."""
    if not tasks:
        return
    if workers == 1:
        for task in tasks:
            if not skip(task):
                yield task, run_task(task)
        return
    yield from _Pool(min(workers, len(tasks))).run(tasks, skip)


class _Worker:
    """A worker process serving tasks over a pipe, one at a time."""

    def __init__(self, context: Any) -> None:
        self.connection, child = context.Pipe()
        self.process = context.Process(
            target=_serve, args=(child, os.getpid()), name="dressbench-worker"
        )
        self.process.start()
        child.close()
        self.task: Task | None = None
        self.since = 0.0

    def give(self, task: Task) -> None:
        """Start ``task`` in this worker."""
        self.task, self.since = task, time.monotonic()
        self.connection.send(task)

    def overdue(self) -> bool:
        """Whether its task ran past its limit and the grace after it."""
        limit = self.task.timeout if self.task else None
        return limit is not None and time.monotonic() - self.since > limit + GRACE

    def end(self) -> None:
        """Stop the process now (what it was running is lost)."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.connection.close()


def _serve(connection: Any, parent: int) -> None:
    """A worker's loop: run each task received, send back its result."""
    exit_with_parent(parent)
    while True:
        try:
            task = connection.recv()
        except EOFError:
            return
        connection.send(run_task(task))


class _Pool:
    """``size`` worker processes: a dead one is replaced and its task run again, up to
    ``TRIES`` runs; one stuck past its task's limit is killed and its task flagged."""

    def __init__(self, size: int) -> None:
        self.size = size
        self.context = multiprocessing.get_context("spawn")

    def run(
        self, tasks: Sequence[Task], skip: Callable[[Task], bool]
    ) -> Iterator[tuple[Task, EpisodeRecord | Failure]]:
        """Each task with its record or failure, as they finish (but those ``skip`` says yes
        to when their turn comes)."""
        queue, runs = deque(tasks), Counter[Task]()
        workers = [_Worker(self.context) for _ in range(self.size)]
        try:
            while queue or any(worker.task for worker in workers):
                for worker in workers:
                    while worker.task is None and queue:
                        task = queue.popleft()
                        if not skip(task):
                            runs[task] += 1
                            worker.give(task)
                busy = [worker for worker in workers if worker.task]
                if not busy:
                    return
                wait([w.connection for w in busy] + [w.process.sentinel for w in busy], PARENT_POLL)
                for index, worker in enumerate(workers):
                    task = worker.task
                    if task is None:
                        continue
                    try:
                        result = worker.connection.recv() if worker.connection.poll() else None
                    except (EOFError, OSError):  # it died while sending
                        result = None
                    if result is not None:
                        worker.task = None
                        yield task, result
                        continue
                    died = not worker.process.is_alive()
                    if not died and not worker.overdue():
                        continue
                    code = worker.process.exitcode
                    worker.end()
                    workers[index] = _Worker(self.context)
                    if not died:
                        yield task, Failure(None, _LATE.format(task.timeout))
                    elif runs[task] < TRIES:
                        queue.appendleft(task)
                    else:
                        why = f"its worker died (exit code {code}) in each of {TRIES} tries"
                        yield task, Failure(None, why)
        finally:
            for worker in workers:
                worker.end()
