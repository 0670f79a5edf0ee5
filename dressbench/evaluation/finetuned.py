"""A fine-tuned human against the human it started from, over the same seeded rollouts.

A human fine-tuned with ``--init`` (adapted to a capability profile, or a generalist tuned on a
strategy) answers one question: does it do better than its parent in the same place? Where an
evaluation scored both with the same strategy, profile and settings, every rollout seed was
played by each (``rollouts.episode_seed``: the same start, gown and involuntary motion), so the
two are compared rollout by rollout: the mean of the paired differences with a bootstrap
interval over the pairs, which the shared start makes tighter than two separate intervals.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import pandas as pd

from ..files import write_table
from .groups import TrainedHuman, episode_humans
from .schema import FINETUNED_COLUMNS, FINETUNED_SCORES
from .statistics import CONFIDENCE, RESAMPLES, bootstrap_ci

FINETUNED = "finetuned"  # finetuned.csv and finetuned.md, beside an evaluation's other tables
PAIRED_ON = ["robot", "profile", "config_id", "episode_seed"]  # one rollout seed in one setting
# what a change whose interval excludes 0 says, (up, down) per score, in the verdict
VERDICT_WORDS = {
    "final_arm_progress": ("deeper", "shallower"),
    "success": ("past the elbow more often", "past the elbow less often"),
    "max_deformation": ("deforms more", "deforms less"),
}


def finetuned_table(
    episodes: pd.DataFrame, humans: Mapping[str, TrainedHuman] | None = None, seed: int = 0
) -> pd.DataFrame:
    """One row per fine-tuned human and setting (robot, profile, env config) where its parent
    played the same rollout seeds: each score's mean for both, the mean paired change with its
    bootstrap interval, P[the human goes deeper than its parent on the same rollout] (ties
    half), and the verdict: each change whose interval excludes 0, in words (``VERDICT_WORDS``),
    or "not separated". ``humans`` default: ``episode_humans``."""
    if humans is None:
        humans = episode_humans(episodes)
    rows = []
    for name, human in humans.items():
        if human.parent is None or human.parent == name:
            continue
        pairs = pd.merge(
            episodes[episodes["human"] == name], episodes[episodes["human"] == human.parent],
            on=PAIRED_ON, suffixes=("", "_parent"),
        )  # fmt: skip
        for (robot, profile, config), paired in pairs.groupby(PAIRED_ON[:3], sort=True):
            rows.append({"robot": robot, "human": name, "parent": human.parent,
                         "ablation": paired["ablation"].iloc[0], "profile": profile,
                         "config_id": config, "episodes": len(paired),
                         **_paired_scores(paired, seed)})  # fmt: skip
    return pd.DataFrame(rows, columns=FINETUNED_COLUMNS)


def _paired_scores(paired: pd.DataFrame, seed: int) -> dict[str, object]:
    """Both humans' means, the paired changes with their intervals, and P(deeper), of the
    rollouts ``paired`` (the parent's columns suffixed ``_parent``)."""
    row: dict[str, object] = {}
    for score in FINETUNED_SCORES:
        mine, theirs = (paired[column].astype(float).to_numpy()
                        for column in (score, f"{score}_parent"))  # fmt: skip
        low, high = bootstrap_ci(mine - theirs, seed)
        row |= {score: mine.mean(), f"{score}_parent": theirs.mean(),
                f"{score}_change": (mine - theirs).mean(),
                f"{score}_change_ci_low": low, f"{score}_change_ci_high": high}  # fmt: skip
    progress = paired["final_arm_progress"].to_numpy(float)
    parent = paired["final_arm_progress_parent"].to_numpy(float)
    deeper = (progress > parent) + 0.5 * (progress == parent)
    row["deeper"] = deeper.mean()
    row["deeper_ci_low"], row["deeper_ci_high"] = bootstrap_ci(deeper, seed)
    separated = []
    for score, (up, down) in VERDICT_WORDS.items():
        if row[f"{score}_change_ci_low"] > 0:
            separated.append(up)
        elif row[f"{score}_change_ci_high"] < 0:
            separated.append(down)
    row["verdict"] = ", ".join(separated) or "not separated"
    return row


def finetuned_markdown(table: pd.DataFrame) -> str:
    """The table in Markdown, under its definition."""
    lines = [
        "# dressbench: fine-tuned humans against their parents",
        "",
        "Each human fine-tuned from another (`dressbench train --init`), against that parent, "
        "where both played the same seeded rollouts with the same strategy, capability profile "
        "and settings (the same start, gown and involuntary motion). Each score: the parent's "
        f"mean → the fine-tuned human's, then the mean change over the paired rollouts with its "
        f"{CONFIDENCE:.0%} percentile-bootstrap interval ({RESAMPLES:,} resamples of the pairs). "
        "P(deeper): the share of rollouts on which the fine-tuned human ends deeper, ties half. "
        "The verdict names each change whose interval excludes 0.",
        "",
        "| robot | profile | human | fine-tuned from | rollouts | final arm progress (m) "
        "| max deformation | past the elbow | P(deeper) | verdict |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---|",
    ]
    for r in table.itertuples():
        scores = [change_text(r, "final_arm_progress", "{:.3f}", "{:+.3f}"),
                  change_text(r, "max_deformation", "{:.2f}", "{:+.2f}"),
                  change_text(r, "success", "{:.0%}", "{:+.0%}")]  # fmt: skip
        lines.append(f"| {r.robot} | {r.profile} | {r.human} | {r.parent} | {r.episodes} "
                     f"| {' | '.join(scores)} | {r.deeper:.2f} [{r.deeper_ci_low:.2f}, "
                     f"{r.deeper_ci_high:.2f}] | {r.verdict} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def change_text(row: object, score: str, value: str, change: str) -> str:
    """``parent → human, change [low, high]`` of one score of a row (Markdown, report)."""
    parent, mine, delta, low, high = (getattr(row, f"{score}{part}") for part in
                                      ("_parent", "", "_change", "_change_ci_low",
                                       "_change_ci_high"))  # fmt: skip
    return (f"{value.format(parent)} → {value.format(mine)}, {change.format(delta)} "
            f"[{change.format(low)}, {change.format(high)}]")  # fmt: skip


def write_finetuned(
    out: Path,
    episodes: pd.DataFrame,
    seed: int = 0,
    humans: Mapping[str, TrainedHuman] | None = None,
) -> pd.DataFrame:
    """Write finetuned.csv/.md into ``out`` where the episodes hold a fine-tuned human and its
    parent on the same rollouts (and remove an earlier evaluation's otherwise); returns the
    table. ``humans`` default: ``episode_humans``."""
    table = finetuned_table(episodes, humans, seed)
    write_table(out, FINETUNED, table, finetuned_markdown)
    return table
