"""Which folders an evaluation may write its results into: its own, or one that holds none of
the files it writes.

An evaluation marks its folder with ``MARKER``. A folder without the marker that already holds a
file an evaluation writes there (a user's README.md, say) is refused with one line naming the
file, before anything runs. A results folder written before folders were marked is taken as
dressbench's, and marked: its run_meta.json is one that an evaluation wrote, or (an evaluation
stopped before its summary) it holds the resume cache, ``rollouts/``.
"""

from __future__ import annotations

import fnmatch
import os
from pathlib import Path

from ..files import read_json, write_text
from .readme import FILES, MARKER, README
from .store import ROLLOUTS

_NOTE = ("dressbench writes this results folder (evaluate, leaderboard, reproduce) and replaces "
         "the files it writes here each time.\n")  # fmt: skip
_COMMANDS = ("evaluate", "leaderboard", "reproduce")  # run_meta.json's "command"
_WRITTEN = (README, *(name.replace("{robot}", "*") for name in FILES))  # names, as patterns


def check_owned(out: str | os.PathLike[str]) -> None:
    """Refuse ``out`` when it is not a results folder of dressbench's and already holds a file
    an evaluation writes there (a ValueError naming the files)."""
    folder = Path(out)
    if not folder.is_dir() or _owned(folder):
        return
    taken = [path.name for path in sorted(folder.iterdir()) if _ours(path)]
    if taken:
        them = "them" if len(taken) > 1 else "it"
        raise ValueError(
            f"out {str(folder)!r} holds {', '.join(taken)}, which dressbench did not write (the "
            f"folder has no {MARKER}): choose another folder (--out), or move {them}"
        )


def claim(out: Path) -> None:
    """Create ``out`` if need be and mark it as a results folder of dressbench's."""
    out.mkdir(parents=True, exist_ok=True)
    if not (out / MARKER).is_file():
        write_text(out / MARKER, _NOTE)


def _owned(folder: Path) -> bool:
    """Whether ``folder`` is marked, or holds the run_meta.json or resume cache of an
    evaluation."""
    return (
        (folder / MARKER).is_file()
        or (folder / ROLLOUTS).is_dir()
        or _written_by_an_evaluation(folder / "run_meta.json")
    )


def _written_by_an_evaluation(meta: Path) -> bool:
    """Whether ``meta`` is a regular file that reads as the run_meta.json of an evaluation."""
    try:
        data = read_json(meta, "a run's metadata")
    except ValueError:  # missing, a link, too large or not JSON: no evaluation's
        return False
    return (
        isinstance(data, dict)
        and data.get("command") in _COMMANDS
        and isinstance(data.get("versions"), dict)
        and "dressbench" in data["versions"]
    )


def _ours(path: Path) -> bool:
    """Whether an evaluation writes a file of ``path``'s name (a folder of that name is not
    overwritten: only files count)."""
    return not path.is_dir() and any(fnmatch.fnmatchcase(path.name, name) for name in _WRITTEN)
