"""The on-disk record of every finished episode, which makes evaluations resumable.

Each episode is saved, as soon as it finishes, to its own JSON file
``out/rollouts/<robot>__<human>-<key>/seed<s>-episode<i>.json``: ``key`` is a short hash of its
cell's identity (``Cell.identity``: the robot's and the human's identities, a trained policy's
checksum among them, and the full env configuration), and the file stores the episode's full
identity (the cell's, the base seed and the index) beside the record. A task whose file holds a
readable record of the same identity, whose final scores are its curves', is done and is not run
again. Any other file in its place (truncated, corrupt, of another identity, or contradicting
itself) is discarded with a one-line notice naming it, and the task runs again; its new record
replaces the file.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..files import parse_json, slug, write_text
from .cells import Cell
from .identity import difference, same
from .rollouts import EpisodeRecord
from .workers import Task

ROLLOUTS = "rollouts"
OLD_LAYOUT = "cfg-*"  # folders of records made before they carried an identity


def cell_folder(out: Path, cell: Cell) -> Path:
    """Where the records of ``cell`` live: readable names, then the hash of its identity."""
    return out / ROLLOUTS / f"{pair_name(cell)}-{cell.key}"


def record_path(out: Path, task: Task) -> Path:
    """Where the record of ``task`` lives."""
    return cell_folder(out, task.cell) / f"seed{task.seed}-episode{task.episode:05d}.json"


def save_record(out: Path, task: Task, record: EpisodeRecord) -> None:
    """Save a finished episode, with its identity, atomically, as one line of JSON (compact:
    the identity holds the whole env configuration)."""
    data = {"identity": task.identity, **record.to_dict()}
    write_text(record_path(out, task), json.dumps(data, separators=(",", ":")) + "\n")


def load_record(out: Path, task: Task) -> EpisodeRecord | None:
    """The saved record of ``task`` judged with its success depth, or None if it is to be run:
    not yet run, or its file discarded (with a notice) as unreadable or of another identity."""
    path = record_path(out, task)
    try:
        data = parse_json(path.read_bytes())
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:  # ValueError: JSONDecodeError, UnicodeDecodeError
        return _discard(path, f"unreadable ({_reason(exc)})")
    if not isinstance(data, dict):
        return _discard(path, f"not an episode record (a JSON {type(data).__name__})")
    if "identity" not in data:
        return _discard(path, "it carries no identity (an old-format record)")
    if not same(data["identity"], task.identity):
        return _discard(
            path, f"made by another setup: {difference(data['identity'], task.identity)}"
        )
    try:
        record = EpisodeRecord.from_dict(data)
    except (KeyError, TypeError, ValueError) as exc:
        return _discard(path, f"not an episode record ({_reason(exc)})")
    problem = _inconsistency(record, task)
    if problem:
        return _discard(path, f"its record disagrees with its identity ({problem})")
    problem = record.contradiction()
    if problem:
        return _discard(path, problem)
    return replace(record, success_depth=task.success_depth)


def report_earlier_rollouts(out: Path, fresh: Sequence[Cell]) -> None:
    """Say, one line each, why rollouts already in ``out`` are not reused for the ``fresh`` cells
    (those none of whose records were found): the same robot and human names under the same env
    configuration, but another robot or human (a replaced policy file, an upgraded plugin); and
    once, old-layout folders whose records carry no identity."""
    root = out / ROLLOUTS
    if not fresh or not root.is_dir():
        return
    for cell in fresh:
        for folder in sorted(root.glob(f"{pair_name(cell)}-*")):
            if folder != cell_folder(out, cell):
                change = _change(folder, cell)
                if change:
                    notice(
                        f"{cell.robot!r} x {cell.human!r} changed since the rollouts in {folder} "
                        f"({change}): they are not reused"
                    )
    old = [folder for folder in root.glob(OLD_LAYOUT) if folder.is_dir()]
    if old:
        notice(
            f"{len(old)} old-layout rollout folder(s) in {root} ({OLD_LAYOUT}) carry no identity "
            "and are not reused"
        )


def notice(message: str) -> None:
    """One line on stderr."""
    print(f"dressbench: {message}", file=sys.stderr, flush=True)


def pair_name(cell: Cell) -> str:
    """``robot__human``, made safe as a file name (names that differ may give the same pair)."""
    return f"{slug(cell.robot)}__{slug(cell.human)}"


def _discard(path: Path, why: str) -> None:
    """Say that the record at ``path`` is not reused and why; None, as for a missing record."""
    notice(f"discarded {path}: {why}; the episode runs again")
    return None


def _reason(exc: BaseException) -> str:
    """``'Type: first line'`` of an exception."""
    lines = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {lines[0]}" if lines else type(exc).__name__


def _inconsistency(record: EpisodeRecord, task: Task) -> str:
    """What in a record contradicts the task its identity names ('' if nothing)."""
    cell = task.cell
    if (record.robot, record.human) != (cell.robot, cell.human):
        return f"it names {record.robot!r} x {record.human!r}"
    if record.episode_seed != task.episode_seed:
        return f"episode_seed {record.episode_seed}, expected {task.episode_seed}"
    horizon = cell.columns["horizon"]
    if record.arm_progress.shape != (horizon,) or record.max_deformation_curve.shape != (horizon,):
        return f"curves of shape {record.arm_progress.shape}, expected ({horizon},)"
    return ""


def _change(folder: Path, cell: Cell) -> str:
    """How the robot and human of the records in ``folder`` differ from the cell's, when they
    have the cell's names and env configuration; '' otherwise (another pair, or unreadable)."""
    identity = _first_identity(folder)
    if not isinstance(identity, dict):
        return ""
    names = [_name(identity.get(who)) for who in ("robot", "human")]
    if names != [cell.robot, cell.human] or not same(
        identity.get("config"), cell.identity["config"]
    ):
        return ""
    found = {who: identity.get(who) for who in ("robot", "human")}
    expected = {who: cell.identity[who] for who in ("robot", "human")}
    return difference(found, expected, ("was", "now"))


def _name(plugin: Any) -> Any:
    """The name in a stored plugin identity, or None."""
    return plugin.get("name") if isinstance(plugin, dict) else None


def _first_identity(folder: Path) -> Any:
    """The stored identity of the first readable record in ``folder``, or None."""
    for path in sorted(folder.glob("seed*-episode*.json")):
        try:
            data = parse_json(path.read_bytes())
        except (OSError, ValueError):
            continue
        if isinstance(data, dict) and isinstance(data.get("identity"), dict):
            return data["identity"]
    return None
