"""Checks of what a user asks for, shared by the API and the command line, run before any work.

Each check raises ``ValueError`` with one line that says what is allowed; the command line
turns it into a ``click.BadParameter`` naming the option. Importing this module is cheap.

The caps bound what one call may allocate: every episode of an evaluation is a task held in
memory, and a gown's memory grows with its vertices (about 9 kB each).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from math import inf
from pathlib import Path

EPISODES = 100  # rollouts per cell (and per seed) of an evaluation unless told otherwise
RESULTS = "results"  # the folder an evaluation writes unless told otherwise
REPRODUCTION = f"{RESULTS}/reproduction"  # and the paper's comparison
MAX_EPISODES = 100_000  # per cell of an evaluation
MIN_GOWN_VERTICES = 100  # GownConfig's own lower bound
MAX_GOWN_VERTICES = 20_000  # 10x the default; ~180 MB of cloth state
MAX_HORIZON = 100_000  # policy steps per episode (67 simulated minutes)
MAX_PROCESSES = 256  # worker or env processes
MAX_SEED = 2**32 - 1  # what numpy.random.seed (used by stable-baselines3) accepts


def check_int(
    value: object,
    name: str = "",
    minimum: int | None = None,
    maximum: int | None = None,
    why_maximum: str = "",
) -> int:
    """``value`` if it is an integer in ``[minimum, maximum]``; else a ValueError saying so.

    ``name`` starts the message (the API's argument; the CLI leaves it out and names the
    option); ``why_maximum`` says what the cap protects.
    """
    lead = f"{name} " if name else ""
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{lead}must be an integer, got {value!r}")
    if minimum is not None and value < minimum:
        allowed = f"from {minimum} to {maximum}" if maximum is not None else f"at least {minimum}"
        raise ValueError(f"{lead}must be {allowed}, got {value}")
    if maximum is not None and value > maximum:
        reason = f" ({why_maximum})" if why_maximum else ""
        raise ValueError(f"{lead}must be at most {maximum}{reason}, got {value}")
    return value


def check_episodes(episodes: object, name: str = "episodes") -> int:
    """At least 1 and at most ``MAX_EPISODES``."""
    return check_int(episodes, name, 1, MAX_EPISODES, "a cap on the tasks held in memory")


def check_gown_vertices(vertices: object, name: str = "gown_vertices") -> int:
    """From ``MIN_GOWN_VERTICES`` to ``MAX_GOWN_VERTICES``."""
    why = "a cap on the cloth's memory, about 9 kB a vertex"
    return check_int(vertices, name, MIN_GOWN_VERTICES, MAX_GOWN_VERTICES, why)


def check_horizon(horizon: object, name: str = "horizon") -> int:
    """From 1 to ``MAX_HORIZON`` policy steps."""
    return check_int(horizon, name, 1, MAX_HORIZON, "a cap on the per-step curves in memory")


def check_seed(seed: object, name: str = "seed") -> int:
    """From 0 to ``MAX_SEED``."""
    return check_int(seed, name, 0, MAX_SEED)


def check_processes(count: object, name: str = "workers", zero: str = "") -> int:
    """A number of processes, from 1 to ``MAX_PROCESSES`` (each holds its own env); 0 too when
    ``zero`` says what 0 means (e.g. "one per core")."""
    check_int(count, name)
    assert isinstance(count, int)
    if not (0 if zero else 1) <= count <= MAX_PROCESSES:
        lead = f"{name} " if name else ""
        allowed = f"from 1 to {MAX_PROCESSES}"
        allowed = f"0 ({zero}) or {allowed}" if zero else allowed
        raise ValueError(f"{lead}must be {allowed} (each process holds its own env), got {count}")
    return count


def check_positive(value: object, name: str = "", unit: str = "number") -> float:
    """``value`` as a float if it is a positive, finite number (``unit`` says of what in the
    message); else a ValueError saying so."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < inf:
        lead = f"{name} " if name else ""
        raise ValueError(f"{lead}must be a positive {unit}, got {value!r}")
    return float(value)


def check_episode_timeout(seconds: object, name: str = "episode_timeout") -> float | None:
    """None (the default limit) or a positive, finite number of seconds."""
    return None if seconds is None else check_positive(seconds, name, "number of seconds")


def check_folder(path: str | os.PathLike[str], name: str = "out") -> Path:
    """A folder that exists or can be created (nothing is created): not empty, not a file, and
    its nearest existing ancestor a writable folder."""
    text = os.fspath(path)
    lead = f"{name} " if name else ""
    if not text.strip():
        raise ValueError(f"{lead}must name a folder, got {text!r}")
    folder = Path(text)
    if folder.exists():
        if not folder.is_dir():
            raise ValueError(f"{lead}{str(folder)!r} is a file, not a folder")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise ValueError(f"{lead}{str(folder)!r} is a folder this user cannot write to")
        return folder
    ancestor = folder.absolute().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise ValueError(f"{lead}{str(folder)!r} cannot be created: {str(ancestor)!r} is a file")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise ValueError(
            f"{lead}{str(folder)!r} cannot be created: {str(ancestor)!r} is not writable"
        )
    return folder


def check_output_file(
    path: str | os.PathLike[str], suffixes: Sequence[str], name: str = "path"
) -> Path:
    """A file to be written: a name with one of ``suffixes``, not a folder, in a folder that
    exists and is writable (it is not created: a typo in a folder name fails here)."""
    text = os.fspath(path)
    lead = f"{name} " if name else ""
    if not text.strip():
        raise ValueError(f"{lead}must name a file, got {text!r}")
    file = Path(text)
    if file.suffix.lower() not in suffixes:
        raise ValueError(f"{lead}{file.name!r} must end in {' or '.join(suffixes)}")
    if file.is_dir():
        raise ValueError(f"{lead}{text!r} is a folder, not a file")
    folder = file.absolute().parent
    if not folder.is_dir():
        what = "is a file" if folder.exists() else "does not exist"
        raise ValueError(f"{lead}{text!r} cannot be written: the folder {str(folder)!r} {what}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{lead}{text!r} cannot be written: {str(folder)!r} is not writable")
    return file


def check_name(value: str, name: str = "name") -> str:
    """A run or policy name: '' (the default) or one file name, no folders in it."""
    if value and (value in (".", "..") or "/" in value or "\\" in value):
        lead = f"{name} " if name else ""
        raise ValueError(f"{lead}must be a plain file name, without folders, got {value!r}")
    return value


def check_device(device: str, name: str = "device") -> str:
    """A Warp device this machine has: ``cpu``, or ``cuda`` / ``cuda:N`` with a CUDA driver."""
    import re

    import warp as wp

    from .scene.cloth import init_warp

    lead = f"{name} " if name else ""
    init_warp()
    have = [str(d) for d in wp.get_devices()]
    if device != "cpu" and re.fullmatch(r"cuda(:\d+)?", device or "") is None:
        raise ValueError(f"{lead}must be 'cpu', 'cuda' or 'cuda:N', got {device!r}")
    cuda = device.startswith("cuda")
    if (cuda and not wp.is_cuda_available()) or (":" in device and device not in have):
        raise ValueError(
            f"{lead}{device!r} is not a Warp device of this machine: it has {', '.join(have)}"
        )
    return device
