"""Finished cells kept compactly, one file each, so that published results travel with the code.

The per-episode records under ``rollouts/`` make a running evaluation resumable but are a
machine's local cache (not committed). When every episode of a cell is done, its records are
also written to ``out/cells/<robot>__<human>-<key>-seed<s>.npz``: the cell's identity (as JSON)
once, every episode's curves and scores as arrays. A later evaluation, on any machine, reuses the
first n episodes of an archive of the same identity and base seed instead of running them again
(episode i's seed does not depend on how many episodes there are). Loaded with
``allow_pickle=False``: an archive holds arrays and strings, never code. It is untrusted (a results
folder travels between machines): before anything is decompressed, it must be a regular file
(no link) holding exactly the expected members, each no larger uncompressed than its cell's
horizon and the archive's episode count imply (``_size_problem``).
"""

from __future__ import annotations

import io
import stat
import zipfile
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..checks import MAX_EPISODES
from ..files import parse_json, write_bytes
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
_CURVES = ("arm_progress", "max_deformation_curve")
NPY_HEADER = 256  # bytes: at most an .npy member's header (numpy writes 128)
MAX_IDENTITY = 1 << 20  # bytes of the identity's string array (4 per character)
MAX_REASON = 1000  # characters of a failure reason


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
    archive, one of another identity or one whose scores contradict its curves
    (``EpisodeRecord.contradiction``) is ignored, with a one-line notice."""
    path = archive_path(out, cell, seed)
    if not path.exists():
        return []
    try:
        problem = _size_problem(path, cell.columns["horizon"])
        if not problem:
            with np.load(path, allow_pickle=False) as data:
                arrays = {name: data[name] for name in data.files}
            identity = parse_json(str(arrays["identity"]))
            problem = "" if same(identity, cell.identity) else "it belongs to another setup"
            if int(arrays["seed"]) != seed:
                problem = f"its base seed is {int(arrays['seed'])}"
        if not problem:
            records = [_record(cell, arrays, i) for i in range(len(arrays["episode_seed"]))]
            problem = next((f"episode {i}: {why}" for i, record in enumerate(records)
                            if (why := record.contradiction())), "")  # fmt: skip
    except (OSError, ValueError, KeyError, IndexError, zipfile.BadZipFile) as exc:
        problem = f"unreadable ({type(exc).__name__})"
    if problem:
        if not quiet:
            notice(f"ignored {path}: {problem}; its episodes run again")
        return []
    return records


def _size_problem(path: Path, horizon: int) -> str:
    """What makes the archive at ``path`` unsafe to decompress ('' if nothing): not a regular
    file, members other than the expected ones, or a member larger uncompressed than a cell of
    ``horizon`` steps allows for the episodes its ``episode_seed`` holds (zip headers, read
    before any member is inflated; a member cannot inflate past its declared size)."""
    mode = path.lstat().st_mode
    if not stat.S_ISREG(mode):
        return "not a regular file (a link or a device)"
    with zipfile.ZipFile(path) as archive:
        members = archive.infolist()
    sizes = {info.filename: info.file_size for info in members}
    expected = {f"{name}.npy" for name in ("identity", "seed", *_CURVES, *_SCALARS)}
    if set(sizes) != expected or len(sizes) != len(members):
        odd = sorted(set(sizes) ^ expected)[:3]
        return f"not a cell archive (members {', '.join(odd) or 'repeated'})"
    episodes = max(sizes["episode_seed.npy"] // 8, 1)  # at least the count it holds
    if episodes > MAX_EPISODES + NPY_HEADER // 8:
        return f"episode_seed.npy holds {sizes['episode_seed.npy']} bytes, more than a cell's"
    limits = {"identity": MAX_IDENTITY, "seed": 8, "failure_reason": 4 * MAX_REASON * episodes}
    limits |= {name: 8 * horizon * episodes for name in _CURVES}
    for name, size in sizes.items():
        limit = NPY_HEADER + limits.get(name[: -len(".npy")], 8 * episodes)
        if size > limit:
            return (
                f"member {name} is {size:,} bytes uncompressed, more than the {limit:,} its "
                f"cell allows ({horizon} steps, at most {episodes} episodes)"
            )
    return ""


def _record(cell: Cell, arrays: dict[str, np.ndarray], i: int) -> EpisodeRecord:
    return EpisodeRecord(
        robot=cell.robot,
        human=cell.human,
        ablation=cell.ablation,
        arm_progress=arrays["arm_progress"][i].astype(float),
        max_deformation_curve=arrays["max_deformation_curve"][i].astype(float),
        **{name: kind(arrays[name][i]) for name, kind in _SCALARS.items()},
    )
