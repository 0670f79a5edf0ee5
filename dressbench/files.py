"""Atomic file writes: a temp file in the target's folder, flushed, then ``os.replace``; and a
JSON parse that refuses nesting too deep for the parser (``parse_json``).

A reader (or a resumed run) therefore sees either the previous file or the new one, never a
half-written one, even if the process dies mid-write. Files get the permissions of the umask
(``0o666 & ~umask``), as ``open`` would give them, not ``mkstemp``'s 0600.
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import asdict, is_dataclass
from io import BytesIO
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Callable

    import pandas as pd
    from matplotlib.figure import Figure

MAX_READ_BYTES = 64 << 20  # the most read of one results file (leaderboard, summary, plot)


def readable(path: str | os.PathLike, limit: int | None = None) -> bool:
    """Whether ``path`` is a regular file, not a link, of at most ``limit`` bytes (default
    ``MAX_READ_BYTES``): one that a reader of untrusted files may open (a link could reach
    anywhere, a device never end)."""
    path, limit = Path(path), MAX_READ_BYTES if limit is None else limit
    try:
        return not path.is_symlink() and path.is_file() and path.stat().st_size <= limit
    except OSError:
        return False


def read_untrusted(path: str | os.PathLike, what: str, limit: int | None = None) -> bytes:
    """The bytes of ``path``, ``what`` the caller expects it to be (for the message): a
    regular file, not a link, of at most ``limit`` bytes (default ``MAX_READ_BYTES``), read no
    further than that; else a one-line ValueError naming the file."""
    path, limit = Path(path), MAX_READ_BYTES if limit is None else limit
    if path.is_symlink() or not path.is_file():
        raise ValueError(f"{path}: not {what} (missing, a link or not a regular file)")
    try:
        with open(path, "rb") as file:
            data = file.read(limit + 1)
    except OSError as error:
        raise ValueError(f"{path}: cannot be read ({error.strerror})") from None
    if len(data) > limit:
        raise ValueError(f"{path}: more than {limit:,} bytes; not {what}")
    return data


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Replace ``path`` by ``data`` atomically; on error the old file stays, no temp remains."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = _create_temp(path)
    try:
        with os.fdopen(fd, "wb") as file:
            file.write(data)
            file.flush()
            os.fsync(file.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _create_temp(path: Path) -> tuple[int, Path]:
    """A new, empty temp file beside ``path``, open for writing, with mode ``0o666 & ~umask``.

    ``os.open`` with O_EXCL and 0o666 lets the kernel apply the umask (``mkstemp`` would force
    0600, and reading the umask means setting it, which races with other threads).
    """
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = path.with_name(f".{path.name}.{os.urandom(6).hex()}.tmp")
        try:
            return os.open(tmp, flags, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary file name beside {path}")


def write_text(path: str | os.PathLike, text: str) -> None:
    """Replace ``path`` by UTF-8 ``text`` atomically."""
    write_bytes(path, text.encode("utf-8"))


def write_csv(path: str | os.PathLike, table: pd.DataFrame) -> None:
    """Replace ``path`` by ``table`` as CSV (no index) atomically."""
    write_text(path, table.to_csv(index=False))


def write_table(
    out: str | os.PathLike, stem: str, table: pd.DataFrame, markdown: Callable[[pd.DataFrame], str]
) -> None:
    """Write ``stem``.csv and ``stem``.md (``markdown(table)``) into ``out``, or remove both
    where ``table`` is empty: an earlier evaluation's would show cells not scored now."""
    csv, text = Path(out) / f"{stem}.csv", Path(out) / f"{stem}.md"
    if table.empty:
        csv.unlink(missing_ok=True)
        text.unlink(missing_ok=True)
    else:
        write_csv(csv, table)
        write_text(text, markdown(table))


def write_json(path: str | os.PathLike, data: Any) -> None:
    """Replace ``path`` by ``data`` as indented JSON atomically (dataclasses as dicts)."""
    write_text(path, json.dumps(data, indent=2, default=jsonable) + "\n")


def write_png(path: str | os.PathLike, figure: Figure) -> None:
    """Render ``figure`` to PNG in memory and replace ``path`` by it atomically."""
    buffer = BytesIO()
    figure.savefig(buffer, format="png", dpi=120)
    write_bytes(path, buffer.getvalue())


def jsonable(value: Any) -> Any:
    """What JSON cannot encode natively: dataclasses as dicts, anything else by ``repr``."""
    if is_dataclass(value) and not isinstance(value, type):
        return asdict(value)
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return value.tolist()
    return repr(value)


def parse_json(text: str | bytes) -> Any:
    """``json.loads(text)``, but JSON nested deeper than the parser's recursion allows is a
    ValueError (not a RecursionError), so a caller refusing bad JSON refuses it too."""
    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("JSON nested too deeply") from None


def read_json(path: str | os.PathLike, what: str) -> Any:
    """The JSON document of ``path``, read as untrusted input (``read_untrusted``); a one-line
    ValueError naming the file where it is not JSON."""
    data = read_untrusted(path, what)
    try:
        return parse_json(data)
    except ValueError as error:  # JSONDecodeError, UnicodeDecodeError, too deep
        raise ValueError(f"{path}: not {what} (not JSON: {str(error).splitlines()[0]})") from None


def slug(name: str) -> str:
    """A plugin name made safe as a file name."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)
