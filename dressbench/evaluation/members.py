"""Episodes against the family, split by the member each one faced: which kinds of strategy,
and which directions of approach, a human meant for any strategy handles worst.

An episode's member follows from its seed alone (``family.episode_members``), so the split
runs nothing again: it is read off the episodes table of any evaluation with ``--robot
family``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..files import write_csv, write_text
from ..plugins.family import KINDS, Family, FamilyConfig, Member, cylindrical, episode_members
from .schema import CELL_COLUMNS, STAGE_COLUMNS, STAGE_LABELS
from .statistics import CONFIDENCE, bootstrap_ci, wilson_ci

MEMBERS = "members"  # members.csv and members.md, beside an evaluation's other tables
# where a member's start lies about the right shoulder: the azimuth's upper bound (degrees,
# negative toward the human's right) and the name; fixed and front_linear start ahead,
# side_linear at the right side
APPROACHES = ((180.0, "ahead"), (-30.0, "front right"), (-60.0, "right side"),
              (-90.0, "behind right"))  # fmt: skip
SPLITS = {"kind": KINDS, "approach": tuple(name for _, name in APPROACHES)}
SCORES = ["final_arm_progress", "max_deformation"]
MEMBER_COLUMNS = [
    *CELL_COLUMNS,
    "split",
    "member",
    "episodes",
    *(f"{score}_{stat}" for score in SCORES for stat in ("mean", "ci_low", "ci_high")),
    *(f"{stage}_{stat}" for stage in STAGE_COLUMNS for stat in ("rate", "ci_low", "ci_high")),
]


def approach(member: Member) -> str:
    """The direction a member's start lies in, seen from the right shoulder (``APPROACHES``)."""
    azimuth = np.degrees(cylindrical(member.start[:3])[1])
    return next(name for bound, name in reversed(APPROACHES) if azimuth <= bound)


def member_table(
    episodes: pd.DataFrame, configs: dict[str, FamilyConfig], seed: int = 0
) -> pd.DataFrame:
    """One row per cell of a family strategy (``configs``: its robot names and distributions),
    split by the kind of member and by its approach: the episodes, mean final arm progress and
    max deformation with their bootstrap CIs, and each stage's rate with its Wilson interval."""
    rows = []
    for key, cell in episodes[episodes["robot"].isin(configs)].groupby(CELL_COLUMNS, sort=False):
        seeds = [int(s) for s in cell["episode_seed"]]
        members = episode_members(seeds, configs[key[0]])
        split = cell.assign(kind=[m.kind for m in members], approach=[approach(m) for m in members])
        for by, order in SPLITS.items():
            for value in order:
                group = split[split[by] == value]
                if len(group):
                    rows.append({**dict(zip(CELL_COLUMNS, key, strict=True)), "split": by,
                                 "member": value, **_scores(group, seed)})  # fmt: skip
    return pd.DataFrame(rows, columns=MEMBER_COLUMNS)


def _scores(group: pd.DataFrame, seed: int) -> dict[str, Any]:
    row: dict[str, Any] = {"episodes": len(group)}
    for score in SCORES:
        values = group[score].astype(float)
        low, high = bootstrap_ci(values, seed)
        row |= {f"{score}_mean": values.mean(), f"{score}_ci_low": low, f"{score}_ci_high": high}
    for stage in STAGE_COLUMNS:
        reached = int(group[stage].astype(bool).sum())
        low, high = wilson_ci(reached, len(group))
        row |= {f"{stage}_rate": reached / len(group), f"{stage}_ci_low": low,
                f"{stage}_ci_high": high}  # fmt: skip
    return row


def members_markdown(table: pd.DataFrame) -> str:
    """The member table in Markdown under a caption that defines every number in it."""
    stages = " | ".join(STAGE_LABELS[stage] for stage in STAGE_COLUMNS)
    lines = [
        "# dressbench: the family's episodes by member",
        "",
        "Each human's episodes against the family, split by the member of the family each "
        "episode faced (known from its episode seed): by kind (still, straight, curve, "
        "reactive) and by the direction its start lies in from the right shoulder (ahead: "
        "azimuth above -30°, where `fixed` and `front_linear` start; front right: -60° to -30°; "
        "right side: -90° to -60°, where `side_linear` starts; behind right: below -90°). "
        f"Means with their {CONFIDENCE:.0%} percentile bootstrap interval over the episodes; "
        f"stage rates with their {CONFIDENCE:.0%} Wilson interval.",
        "",
        f"| robot | human | profile | split | member | episodes | final arm progress (m) "
        f"| max deformation | {stages} |",
        "|---|---|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in table.itertuples():
        scores = [_text(r, "final_arm_progress", "{:.3f}"), _text(r, "max_deformation", "{:.2f}"),
                  *(_text(r, stage, "{:.0%}", "rate") for stage in STAGE_COLUMNS)]  # fmt: skip
        lines.append(f"| {r.robot} | {r.human} | {r.profile} | {r.split} | {r.member} "
                     f"| {r.episodes} | {' | '.join(scores)} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def _text(row: Any, score: str, number: str, centre: str = "mean") -> str:
    value, low, high = (getattr(row, f"{score}_{s}") for s in (centre, "ci_low", "ci_high"))
    return f"{number.format(value)} [{number.format(low)}, {number.format(high)}]"


def family_configs(robots: list[str]) -> dict[str, FamilyConfig]:
    """Those of ``robots`` that are installed family strategies, and their distributions."""
    from ..plugins.registry import robot_plugins

    found = robot_plugins()
    return {
        name: factory.config
        for name in robots
        if name in found
        and isinstance(factory := found[name].factory, type)
        and issubclass(factory, Family)
    }


def write_members(out: Path, episodes: pd.DataFrame, seed: int = 0) -> pd.DataFrame:
    """Write members.csv/.md into ``out`` where the episodes hold a family strategy's cells
    (and remove an earlier evaluation's, which would show cells not scored here); returns the
    table."""
    table = member_table(episodes, family_configs(list(episodes["robot"].unique())), seed)
    csv, markdown = out / f"{MEMBERS}.csv", out / f"{MEMBERS}.md"
    if table.empty:
        csv.unlink(missing_ok=True)
        markdown.unlink(missing_ok=True)
    else:
        write_csv(csv, table)
        write_text(markdown, members_markdown(table))
    return table
