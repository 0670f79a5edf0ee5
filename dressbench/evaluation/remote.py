"""Rollouts as Ray tasks: the ``ray`` backend of ``evaluate`` and ``leaderboard``.

Each episode is one task; a worker process keeps its env for the next episode of the same cell,
as a local worker does. The records come back to the calling process, which saves them as the
local backend does, so the files are the same, bit for bit (docs/cluster.md).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

from ..cluster.session import ray_session
from ..cluster.tasks import run_remote
from ..cluster.worker import PolicyFolders, require_plugins
from .rollouts import EpisodeRecord
from .workers import Failure, Task, run_task

QUEUED_PER_CPU = 2  # tasks in flight per cluster CPU when no worker count is given


def ray_tasks(
    tasks: Sequence[Task],
    workers: int | None,
    address: str | None,
    skip: Callable[[Task], bool] = lambda task: False,
) -> Iterator[tuple[Task, EpisodeRecord | Failure]]:
    """Each task with its record or failure, as they finish, run on Ray at ``address`` (None: a
    local instance of ``workers`` CPUs), at most ``workers`` at once (None: two per cluster CPU,
    so a free CPU never waits for this process); a task ``skip`` says yes to when its turn
    comes is not run, and one whose worker died in every try is a ``Failure``. No tasks: Ray is
    not started."""
    if not tasks:
        return
    with ray_session(address, workers) as ray:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        limit = workers or QUEUED_PER_CPU * max(cpus, 1)
        yield from run_remote(
            rollout, (task for task in tasks if not skip(task)), PolicyFolders.of_driver(),
            limit=limit, describe=_describe, failed=lambda task, why: Failure(None, why),
        )  # fmt: skip


def rollout(task: Task, folders: PolicyFolders) -> EpisodeRecord | Failure:
    """One task on a Ray worker: the driver's policy folders, its cell's plugins checked on
    this node, then the episode (``workers.run_task``)."""
    folders.apply()
    require_plugins([task.cell.robot], [task.cell.human])
    return run_task(task)


def _describe(task: Task) -> str:
    """A task in a message."""
    return f"episode {task.episode} of {task.cell.robot!r} x {task.cell.human!r}"
