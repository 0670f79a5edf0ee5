"""What a results folder records about how it was made: versions, code commit, settings."""

from __future__ import annotations

import importlib.metadata
import platform
import subprocess
from pathlib import Path

# Distribution names of what the results depend on (torch only matters for trained humans).
DISTRIBUTIONS = ("dressbench", "numpy", "pandas", "torch", "warp-lang", "dartpy")


def versions() -> dict[str, str | None]:
    """Python's and each dependency's version, None when not installed (nothing is imported)."""
    found: dict[str, str | None] = {"python": platform.python_version()}
    for name in DISTRIBUTIONS:
        try:
            found[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            found[name] = None
    return found


def git_commit() -> str | None:
    """The commit of the dressbench checkout, or None (not a git checkout, no git)."""
    try:
        result = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).resolve().parent,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return result.stdout.strip() or None
