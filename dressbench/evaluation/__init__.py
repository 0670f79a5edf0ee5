"""Evaluation: seeded parallel rollouts, statistics, the leaderboard, and its plots.

``evaluate(robot, human)`` scores one pair; ``leaderboard()`` scores every robot strategy with
the humans meant for it. Both resume where an interrupted run stopped. See docs/evaluation.md.

Names load on first use, so that worker processes, which need only the rollouts, start without
importing pandas and matplotlib.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .cells import Cell, leaderboard_cells, make_cell
    from .report import success_definition
    from .rollouts import (
        SUCCESS_DEPTH,
        EpisodeRecord,
        Runner,
        episode_seed,
        is_success,
        run_episode,
    )
    from .runs import Evaluated, evaluate, leaderboard, leaderboard_results
    from .statistics import bootstrap_ci, curve_table, leaderboard_table
    from .strategies import improvement_table, strategy_table

_MODULES = {
    "Cell": "cells",
    "leaderboard_cells": "cells",
    "make_cell": "cells",
    "success_definition": "report",
    "SUCCESS_DEPTH": "rollouts",
    "EpisodeRecord": "rollouts",
    "Runner": "rollouts",
    "episode_seed": "rollouts",
    "is_success": "rollouts",
    "run_episode": "rollouts",
    "Evaluated": "runs",
    "evaluate": "runs",
    "leaderboard": "runs",
    "leaderboard_results": "runs",
    "bootstrap_ci": "statistics",
    "curve_table": "statistics",
    "leaderboard_table": "statistics",
    "improvement_table": "strategies",
    "strategy_table": "strategies",
}
__all__ = [
    "Cell",
    "EpisodeRecord",
    "Evaluated",
    "Runner",
    "SUCCESS_DEPTH",
    "bootstrap_ci",
    "curve_table",
    "episode_seed",
    "evaluate",
    "improvement_table",
    "is_success",
    "leaderboard",
    "leaderboard_cells",
    "leaderboard_results",
    "leaderboard_table",
    "make_cell",
    "run_episode",
    "strategy_table",
    "success_definition",
]


def __getattr__(name: str) -> Any:
    """Import a public name's module on first use (PEP 562)."""
    if name not in _MODULES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f".{_MODULES[name]}", __name__), name)
