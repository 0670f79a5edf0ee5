"""The on-disk record of every finished episode, which makes evaluations resumable.

Each episode is saved, as soon as it finishes, to its own JSON file under ``out/rollouts/``,
named by its cell's configuration, the pair, the base seed and the episode index. A task whose
file exists is done and is not run again.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

from .io import slug, write_json
from .rollouts import EpisodeRecord
from .workers import Task


def record_path(out: Path, task: Task) -> Path:
    """Where the record of ``task`` lives."""
    cell = task.cell
    pair = f"{slug(cell.robot)}__{slug(cell.human)}"
    name = f"seed{task.seed}-episode{task.episode:05d}.json"
    return out / "rollouts" / cell.columns["config_id"] / pair / name


def save_record(out: Path, task: Task, record: EpisodeRecord) -> None:
    """Save a finished episode atomically."""
    write_json(record_path(out, task), record.to_dict())


def load_record(out: Path, task: Task) -> EpisodeRecord | None:
    """The saved record of ``task`` judged with its success depth, or None if not yet run."""
    path = record_path(out, task)
    if not path.exists():
        return None
    record = EpisodeRecord.from_dict(json.loads(path.read_text()))
    return replace(record, success_depth=task.success_depth)
