"""Where a result came from: the versions of what it depends on and the code's commit.

Both are read without importing anything: a results folder and a trained policy record them.
"""

from __future__ import annotations

import importlib.metadata
import platform
import subprocess
from pathlib import Path

# Distribution names of what results and trained humans depend on.
DISTRIBUTIONS = ("dressbench", "numpy", "pandas", "gymnasium", "warp-lang", "dartpy", "torch",
                 "stable-baselines3", "sb3-contrib")  # fmt: skip


def versions() -> dict[str, str | None]:
    """Python's and each dependency's version, None when it is not installed."""
    found: dict[str, str | None] = {"python": platform.python_version()}
    for name in DISTRIBUTIONS:
        try:
            found[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            found[name] = None
    return found


def git_commit() -> str | None:
    """The dressbench checkout's commit, with "-dirty" if tracked files changed; None outside a
    git checkout (an installed wheel) or without git."""
    root = Path(__file__).resolve().parent

    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=root, capture_output=True, text=True,
                              timeout=10, check=True).stdout.strip()  # fmt: skip

    try:
        commit = git("rev-parse", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return (commit + ("-dirty" if dirty else "")) or None
