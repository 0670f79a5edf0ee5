"""The summary files of a results folder: curves, leaderboard (CSV and Markdown), meta, plots."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pandas as pd

from ..files import slug, write_csv, write_json, write_png, write_text
from ..scene.body import FOREARM_LENGTH, HAND_LENGTH
from .plots import curves_figure, scores_figure
from .readme import write_results_readme
from .rollouts import STAGE_DEPTHS, SUCCESS_DEPTH
from .schema import STAGE_COLUMNS, STAGE_LABELS
from .statistics import CONFIDENCE, RESAMPLES


def success_definition(depth: float = SUCCESS_DEPTH) -> str:
    """The success rule in words, as the docs, the Markdown table and run_meta.json state it."""
    return (
        f"an episode succeeds when the arm is through the sleeve opening past the elbow at its "
        f"end: final arm progress >= {depth:.2f} m (default: hand {HAND_LENGTH:.2f} m + forearm "
        f"{FOREARM_LENGTH:.2f} m), with no simulation failure"
    )


def stage_definitions(depth: float = SUCCESS_DEPTH) -> dict[str, str]:
    """The three stages of dressing each rate counts, in words (docs, tables, run_meta.json)."""
    return {
        "hand_in": f"the wrist through the sleeve opening at the episode's end: final arm "
        f"progress >= {STAGE_DEPTHS['hand_in']:.2f} m (the hand), no simulation failure",
        "success": success_definition(depth),
        "dressed": f"the opening at the middle of the upper arm at the end: final arm progress "
        f">= {STAGE_DEPTHS['dressed']:.2f} m (hand, forearm and half the upper arm), no "
        f"simulation failure",
    }


def settings_text(board: pd.DataFrame) -> str:
    """The env settings and base seeds of a leaderboard's cells in words (the table's caption,
    the report page)."""
    settings = board[["horizon", "gown_vertices", "device", "seed"]].drop_duplicates()
    return "; ".join(
        f"horizon {r.horizon} steps, {r.gown_vertices}-vertex gown, device {r.device}, "
        f"base seed {r.seed}"
        for r in settings.itertuples()
    )


def markdown_leaderboard(board: pd.DataFrame, success_depth: float = SUCCESS_DEPTH) -> str:
    """The leaderboard as a Markdown table under a caption that defines every number in it."""
    stages = stage_definitions(success_depth)
    lines = [
        "# dressbench leaderboard",
        "",
        f"Settings: {settings_text(board)}.",
        "",
        *(f"**{STAGE_LABELS[stage].capitalize()}**: {text}." for stage, text in stages.items()),
        "",
        f"Each cell is a robot strategy x a human model over seeded rollouts: mean ± sample std, "
        f"and in brackets the {CONFIDENCE:.0%} percentile-bootstrap confidence interval of the "
        f"mean ({RESAMPLES:,} resamples); rates carry their {CONFIDENCE:.0%} Wilson interval. "
        f"Arm progress is the arm's depth in the sleeve (m); max deformation is the largest "
        f"triangle area ratio (stretched / rest) of the episode.",
        "",
        "| robot | human | ablation | profile | episodes | final arm progress (m) "
        f"| max deformation | {' | '.join(STAGE_LABELS[s] for s in STAGE_COLUMNS)} "
        "| sim failures |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in board.itertuples():
        progress = summary_text(r, "final_arm_progress", "{:.3f}")
        deformation = summary_text(r, "max_deformation", "{:.2f}")
        rates = " | ".join(rate_text(r, stage) for stage in stages)
        lines.append(
            f"| {r.robot} | {r.human} | {r.ablation} | {r.profile} | {r.episodes} | {progress} "
            f"| {deformation} | {rates} | {r.sim_failures} |"
        )
    return "\n".join(lines) + "\n"


def rate_text(row: Any, stage: str) -> str:
    """``rate [low, high]`` of one stage of a leaderboard (or member) row."""
    rate, low, high = (getattr(row, f"{stage}_{s}") for s in ("rate", "ci_low", "ci_high"))
    return f"{rate:.0%} [{low:.0%}, {high:.0%}]"


def summary_text(row: Any, metric: str, number: str) -> str:
    """``mean ± std [low, high]`` of one metric of a leaderboard (or member) row."""
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
    """Write curves.csv, leaderboard.csv/.md, run_meta.json, the PNG plots and README.md, each
    atomically."""
    write_csv(out / "curves.csv", curves)
    write_csv(out / "leaderboard.csv", board)
    write_text(out / "leaderboard.md", markdown_leaderboard(board, success_depth))
    write_json(out / "run_meta.json", meta)
    for robot in dict.fromkeys(board["robot"]):
        write_png(out / f"curves_{slug(robot)}.png", curves_figure(curves, robot, success_depth))
    write_png(out / "final_scores.png", scores_figure(board, success_depth))
    write_results_readme(out)
