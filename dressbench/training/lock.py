"""One process at a time per training run: ``run.lock`` in its folder, held while it trains.

The lock is an ``flock`` on the file, which the kernel releases when its holder dies however it
dies, so a lock left by a killed run is free again (and taken over); the file holds the pid of
the process that last took it, for the message of a run refused.
"""

from __future__ import annotations

import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

LOCK = "run.lock"


@contextmanager
def run_lock(folder: Path) -> Iterator[None]:
    """Hold the lock of the run in ``folder`` (an existing folder) for the block; a ValueError
    naming the run and the holder's pid when another process holds it."""
    fd = os.open(folder / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        _take(fd, folder)
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)


def check_unlocked(folder: Path) -> None:
    """Refuse (a ValueError naming the holder) a run whose lock another process holds; nothing
    is written."""
    try:
        fd = os.open(folder / LOCK, os.O_RDONLY)
    except FileNotFoundError:
        return
    try:
        _take(fd, folder)
    finally:
        os.close(fd)  # releases what _take took


def _take(fd: int, folder: Path) -> None:
    """Lock ``fd`` without waiting, or raise the ValueError of a run in use."""
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "unknown"
        raise ValueError(
            f"training run {folder.name!r} in {folder} is in use by process {holder}: wait for "
            f"it to end, or train under another name (--name)"
        ) from None
