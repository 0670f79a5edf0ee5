"""The summary files of a results folder: curves, leaderboard (CSV and Markdown), meta, plots."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pandas as pd

from .io import slug, write_csv, write_json, write_png, write_text
from .plots import curves_figure, scores_figure
from .rollouts import SUCCESS_DEPTH
from .statistics import CONFIDENCE, RESAMPLES


def success_definition(depth: float = SUCCESS_DEPTH) -> str:
    """The success rule in words, as the docs, the Markdown table and run_meta.json state it."""
    return (
        f"an episode succeeds when the arm is through the sleeve opening past the elbow at its "
        f"end: final arm progress >= {depth:.2f} m (default: hand 0.18 m + forearm 0.26 m), "
        f"with no simulation failure"
    )


def markdown_leaderboard(board: pd.DataFrame, success_depth: float = SUCCESS_DEPTH) -> str:
    """The leaderboard as a Markdown table under a caption that defines every number in it."""
    settings = board[["horizon", "gown_vertices", "device", "seed"]].drop_duplicates()
    described = "; ".join(
        f"horizon {r.horizon} steps, {r.gown_vertices}-vertex gown, device {r.device}, "
        f"base seed {r.seed}"
        for r in settings.itertuples()
    )
    lines = [
        "# dressbench leaderboard",
        "",
        f"Settings: {described}.",
        "",
        f"**Success**: {success_definition(success_depth)}.",
        "",
        f"Each cell is a robot strategy x a human model over seeded rollouts: mean ± sample std, "
        f"and in brackets the {CONFIDENCE:.0%} percentile-bootstrap confidence interval of the "
        f"mean ({RESAMPLES:,} resamples). Arm progress is the arm's depth in the sleeve (m); "
        f"max deformation is the largest triangle area ratio (stretched / rest) of the episode.",
        "",
        "| robot | human | ablation | episodes | final arm progress (m) "
        "| max deformation | success rate | sim failures |",
        "|---|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in board.itertuples():
        progress = _summary(r, "final_arm_progress", "{:.3f}")
        deformation = _summary(r, "max_deformation", "{:.2f}")
        success = f"{r.success_rate:.0%} [{r.success_ci_low:.0%}, {r.success_ci_high:.0%}]"
        lines.append(
            f"| {r.robot} | {r.human} | {r.ablation} | {r.episodes} | {progress} "
            f"| {deformation} | {success} | {r.sim_failures} |"
        )
    return "\n".join(lines) + "\n"


def _summary(row: Any, metric: str, number: str) -> str:
    """``mean ± std [low, high]`` of one metric of a leaderboard row."""
    mean, std, low, high = (
        getattr(row, f"{metric}_{s}") for s in ("mean", "std", "ci_low", "ci_high")
    )
    spread = "" if pd.isna(std) else f" ± {number.format(std)}"
    return f"{number.format(mean)}{spread} [{number.format(low)}, {number.format(high)}]"


def write_summary(
    out: Path,
    curves: pd.DataFrame,
    board: pd.DataFrame,
    meta: dict[str, Any],
    success_depth: float = SUCCESS_DEPTH,
) -> None:
    """Write curves.csv, leaderboard.csv/.md, run_meta.json and the PNG plots, each atomically."""
    write_csv(out / "curves.csv", curves)
    write_csv(out / "leaderboard.csv", board)
    write_text(out / "leaderboard.md", markdown_leaderboard(board, success_depth))
    write_json(out / "run_meta.json", meta)
    for robot in dict.fromkeys(board["robot"]):
        write_png(out / f"curves_{slug(robot)}.png", curves_figure(curves, robot, success_depth))
    write_png(out / "final_scores.png", scores_figure(board, success_depth))
