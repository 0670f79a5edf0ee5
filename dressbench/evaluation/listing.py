"""The plugin listing of ``dressbench plugins``: every robot strategy, human policy and capability
profile plugin, its package, version and status, as aligned lines."""

from __future__ import annotations

from typing import Any

from ..plugins import HUMAN_GROUP, PROFILE_GROUP, ROBOT_GROUP, all_plugins, human_plugins
from .cells import _instances, plugin_problems

HEADER = ("group", "name", "package", "version", "status")
GROUPS = {ROBOT_GROUP: "robot", HUMAN_GROUP: "human", PROFILE_GROUP: "profile"}  # as listed


def plugin_rows(check: bool = False) -> list[tuple[str, ...]]:
    """``HEADER`` and one row per plugin. "ok": it imports and has the protocol's methods and
    attributes; with ``check``, an ok plugin that fails the preflight of evaluations is
    "FAILS CHECK: why" instead."""
    plugins = all_plugins()
    failed = _preflight(plugins) if check else {}
    rows = [HEADER]
    for p in plugins:
        group = GROUPS[p.group]
        status = "ok" if p.ok else f"BROKEN: {p.error}"
        if p.ok and (group, p.name) in failed:
            status = f"FAILS CHECK: {failed[group, p.name]}"
        rows.append((group, p.name, p.package, p.version, status))
    return rows


def aligned(rows: list[tuple[str, ...]]) -> list[str]:
    """Rows as lines of columns padded to their widest cell (the last column is not padded),
    so long names never push a row out of line."""
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    padded = ([cell.ljust(w) for cell, w in zip(row[:-1], widths, strict=True)] for row in rows)
    return ["  ".join([*cells, row[-1]]).rstrip() for cells, row in zip(padded, rows, strict=True)]


def _preflight(plugins: list[Any]) -> dict[tuple[str, str], str]:
    """Why each ok plugin among ``plugins`` fails the preflight of evaluations, by (group, name)."""
    from ..preflight import profile_problem

    robots = [p for p in plugins if p.ok and p.group == ROBOT_GROUP]
    humans = [p.name for p in plugins if p.ok and p.group == HUMAN_GROUP]
    policies, problems = _instances(human_plugins(), humans)
    problems += plugin_problems(robots, policies)[2]
    found = {(noun, name): why for noun, name, why in problems}
    for p in plugins:
        if p.ok and p.group == PROFILE_GROUP and (why := profile_problem(p.name)):
            found["profile", p.name] = why
    return found
