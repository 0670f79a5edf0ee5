"""Running a function over many items as Ray tasks, results streamed back as they finish.

A task whose worker dies (killed, out of memory, its node lost) is run again, up to
``RETRIES`` times, by Ray; an exception the function raises is not retried and is raised here
as it would be locally. Each item's result arrives exactly once.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

from .backend import ClusterError, first_line

Item = TypeVar("Item")
Result = TypeVar("Result")

RETRIES = 3  # further tries of a task whose worker died (Ray's max_retries)


def run_remote(
    function: Callable[..., Result],
    items: Iterable[Item],
    *args: Any,
    limit: int,
    cpus: int = 1,
    describe: Callable[[Item], str] = str,
    failed: Callable[[Item, str], Result] | None = None,
) -> Iterator[tuple[Item, Result]]:
    """``(item, function(item, *args))`` for each item, in the order they finish, each run as a
    Ray task of ``cpus`` CPUs with at most ``limit`` in flight. Ray must be connected
    (``session.ray_session``). Stopping early cancels the tasks still running. Given
    ``failed``, a task that could not finish even after its retries gives
    ``(item, failed(item, why))`` and the others go on."""
    import ray

    remote = ray.remote(function).options(num_cpus=cpus, max_retries=RETRIES)
    shared = [ray.put(arg) for arg in args]  # sent to the object store once, not per task
    queue = iter(items)
    running: dict[Any, Item] = {}

    def submit() -> None:
        for item in queue:  # the next item, if any
            running[remote.remote(item, *shared)] = item
            return

    try:
        for _ in range(limit):
            submit()
        while running:
            (ref,), _ = ray.wait(list(running), num_returns=1)
            item = running.pop(ref)
            try:
                result = _result(ray, ref, describe(item))
            except ClusterError as error:
                if failed is None:
                    raise
                result = failed(item, f"could not finish ({error})")
            submit()
            yield item, result
    finally:
        for ref in running:
            ray.cancel(ref, force=True)


def _result(ray: Any, ref: Any, what: str) -> Any:
    """A finished task's value; the function's own exception re-raised as it was; a task that
    could not finish even after its retries a ClusterError naming it."""
    try:
        return ray.get(ref)
    except ray.exceptions.RayTaskError as error:
        if isinstance(error.cause, BaseException):
            raise error.cause from None
        raise ClusterError(f"{what} failed on Ray: {first_line(error)}") from None
    except ray.exceptions.RayError as error:
        raise ClusterError(
            f"{what} failed on Ray after {RETRIES + 1} tries: {first_line(error)}"
        ) from None
