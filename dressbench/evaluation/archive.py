"""Finished cells kept compactly, one file each, so that published results travel with the code.

The per-episode records under ``rollouts/`` make a running evaluation resumable but are a
machine's local cache (not committed). When every episode of a cell is done, its records are
also written to ``out/cells/<robot>__<human>-<key>-seed<s>.npz``: the cell's identity (as JSON)
once, every episode's curves and scores as arrays. A later evaluation, on any machine, reuses the
first n episodes of an archive of the same identity and base seed instead of running them again
(episode i's seed does not depend on how many episodes there are). Loaded with
``allow_pickle=False``: an archive holds arrays and strings, never code.
"""

from __future__ import annotations

import io
import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..files import write_bytes
from .cells import Cell
from .identity import canonical, same
from .rollouts import EpisodeRecord
from .store import notice, pair_name

CELLS = "cells"
# the scalar fields of an EpisodeRecord, each stored as one array, and the type it is read as
_SCALARS = {
    "episode_seed": int,
    "final_arm_progress": float,
    "max_deformation": float,
    "sim_failure": bool,
    "failure_reason": str,
    "episode_return": float,
    "steps": int,
}


def archive_path(out: Path, cell: Cell, seed: int) -> Path:
    """Where the archive of ``cell``'s episodes under base seed ``seed`` lives."""
    return out / CELLS / f"{pair_name(cell)}-{cell.key}-seed{seed}.npz"


def save_archive(out: Path, cell: Cell, seed: int, records: Sequence[EpisodeRecord]) -> None:
    """Write the records of episodes 0..n-1 of a cell, unless an archive holds more already."""
    path = archive_path(out, cell, seed)
    if len(load_archive(out, cell, seed, quiet=True)) >= len(records):
        return
    arrays = {
        "identity": np.array(canonical(cell.identity)),
        "seed": np.array(seed),
        "arm_progress": np.stack([r.arm_progress for r in records]),
        "max_deformation_curve": np.stack([r.max_deformation_curve for r in records]),
    }
    for name in _SCALARS:
        arrays[name] = np.array([getattr(r, name) for r in records])
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    write_bytes(path, buffer.getvalue())


def load_archive(out: Path, cell: Cell, seed: int, quiet: bool = False) -> list[EpisodeRecord]:
    """The archived episodes 0..n-1 of ``cell`` under ``seed`` ([] if none); an unreadable
    archive or one of another identity is ignored, with a one-line notice."""
    path = archive_path(out, cell, seed)
    if not path.exists():
        return []
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
        identity = json.loads(str(arrays["identity"]))
        problem = "" if same(identity, cell.identity) else "it belongs to another setup"
        if int(arrays["seed"]) != seed:
            problem = f"its base seed is {int(arrays['seed'])}"
    except (OSError, ValueError, KeyError) as exc:
        problem = f"unreadable ({type(exc).__name__})"
    if problem:
        if not quiet:
            notice(f"ignored {path}: {problem}; its episodes run again")
        return []
    return [_record(cell, arrays, i) for i in range(len(arrays["episode_seed"]))]


def _record(cell: Cell, arrays: dict[str, np.ndarray], i: int) -> EpisodeRecord:
    return EpisodeRecord(
        robot=cell.robot,
        human=cell.human,
        ablation=cell.ablation,
        arm_progress=arrays["arm_progress"][i].astype(float),
        max_deformation_curve=arrays["max_deformation_curve"][i].astype(float),
        **{name: kind(arrays[name][i]) for name, kind in _SCALARS.items()},
    )
