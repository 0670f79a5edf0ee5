"""What a rollout record belongs to, as plain JSON: compared exactly, hashed into folder names.

An identity is a dict of JSON values (see ``Cell.identity``): the robot strategy's and the human
model's identities (names, distribution and version, a trained policy's checksum), the full env
configuration and, for one episode, the base seed and the episode index. Two identities are
the same when their canonical JSON texts are equal.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterator, Mapping
from typing import Any

from ..files import jsonable

SHOWN = 2  # differences named in a message


def canonical(data: Any) -> str:
    """The stable JSON text of ``data``: sorted keys, no spaces, tuples as lists, exact floats."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), default=jsonable)


def plain(data: Any) -> Any:
    """``data`` as JSON reads it back (tuples become lists, dataclasses dicts, ...)."""
    return json.loads(canonical(data))


def digest(data: Any, length: int = 12) -> str:
    """The first ``length`` hex digits of the SHA-256 of ``canonical(data)``."""
    return hashlib.sha256(canonical(data).encode()).hexdigest()[:length]


def same(a: Any, b: Any) -> bool:
    """Whether two identities are equal as JSON."""
    return canonical(a) == canonical(b)


def difference(found: Any, expected: Any, words: tuple[str, str] = ("is", "expected")) -> str:
    """Where ``found`` differs from ``expected``, for a one-line message ('' when equal).

    e.g. ``"human.checksum is 1f2e3d4c5b6a..., expected 9a8b7c6d5e4f..."`` (``words`` are "is"
    and "expected"); at most ``SHOWN`` differences are named, then how many more there are.
    """
    found, expected = plain(found), plain(expected)
    diffs = [
        f"{path or 'it'} {words[0]} {_short(a)}, {words[1]} {_short(b)}"
        for path, a, b in _walk(found, expected, "")
    ]
    more = f" (and {len(diffs) - SHOWN} more)" if len(diffs) > SHOWN else ""
    return "; ".join(diffs[:SHOWN]) + more


_ABSENT = object()


def _walk(a: Any, b: Any, path: str) -> Iterator[tuple[str, Any, Any]]:
    """The dotted paths where two JSON values differ, with both values (dicts compared by key)."""
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        for key in sorted(set(a) | set(b)):
            sub = f"{path}.{key}" if path else str(key)
            yield from _walk(a.get(key, _ABSENT), b.get(key, _ABSENT), sub)
    elif a is _ABSENT or b is _ABSENT or canonical(a) != canonical(b):
        yield path, a, b


def _short(value: Any, width: int = 40) -> str:
    """A value in a message: missing, a 12-digit prefix of a long hex digest, or a cut repr."""
    if value is _ABSENT:
        return "missing"
    if isinstance(value, str) and len(value) == 64 and all(c in "0123456789abcdef" for c in value):
        return value[:12] + "..."
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."
