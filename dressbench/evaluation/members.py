"""Episodes against the family, split by the member each one faced: which kinds of strategy,
and which directions of approach, a human meant for any strategy handles worst.

An episode's member follows from its seed alone (``family.episode_members``), so the split
runs nothing again: it is read off the episodes table of any evaluation with ``--robot
family``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..files import write_table
from ..plugins.family import KINDS, Family, FamilyConfig, Member, cylindrical, episode_members
from .report import rate_text, summary_text
from .schema import CELL_COLUMNS, MEMBER_COLUMNS, STAGE_COLUMNS, STAGE_LABELS
from .statistics import CONFIDENCE, RESAMPLES, episode_scores

MEMBERS = "members"  # members.csv and members.md, beside an evaluation's other tables
# where a member's start lies about the right shoulder: the azimuth's upper bound (degrees,
# negative toward the human's right) and the name; fixed and front_linear start ahead,
# side_linear at the right side
APPROACHES = ((180.0, "ahead"), (-30.0, "front right"), (-60.0, "right side"),
              (-90.0, "behind right"))  # fmt: skip
SPLITS = {"kind": KINDS, "approach": tuple(name for _, name in APPROACHES)}


def approach(member: Member) -> str:
    """The direction a member's start lies in, seen from the right shoulder (``APPROACHES``)."""
    azimuth = np.degrees(cylindrical(member.start[:3])[1])
    return next(name for bound, name in reversed(APPROACHES) if azimuth <= bound)


def member_table(
    episodes: pd.DataFrame, configs: dict[str, FamilyConfig], seed: int = 0
) -> pd.DataFrame:
    """For each cell of a family strategy (``configs``: its robot names and distributions), a
    row per kind of member and a row per approach that its episodes faced, with what those
    episodes scored (``statistics.episode_scores``)."""
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
                                 "member": value, **episode_scores(group, seed)})  # fmt: skip
    return pd.DataFrame(rows, columns=MEMBER_COLUMNS)


def members_markdown(table: pd.DataFrame) -> str:
    """The member table in Markdown under a caption that defines every number in it."""
    stages = " | ".join(STAGE_LABELS[stage] for stage in STAGE_COLUMNS)
    lines = [
        "# dressbench: the family's episodes by member",
        "",
        "Each human's episodes against the family, split by the member of the family each "
        f"episode faced (known from its episode seed): by kind ({', '.join(KINDS)}) and by the "
        f"direction its start lies in from the right shoulder, by its azimuth from straight "
        f"ahead, negative toward the human's right ({_approaches_text()}; `fixed` and "
        "`front_linear` start ahead, `side_linear` at the right side). "
        f"Means ± sample std over the episodes, and in brackets the {CONFIDENCE:.0%} "
        f"percentile-bootstrap interval of the mean ({RESAMPLES:,} resamples); stage rates with "
        f"their {CONFIDENCE:.0%} Wilson interval.",
        "",
        f"| robot | human | profile | split | member | episodes | final arm progress (m) "
        f"| max deformation | {stages} |",
        "|---|---|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in table.itertuples():
        scores = [summary_text(r, "final_arm_progress", "{:.3f}"),
                  summary_text(r, "max_deformation", "{:.2f}"),
                  *(rate_text(r, stage) for stage in STAGE_COLUMNS)]  # fmt: skip
        lines.append(f"| {r.robot} | {r.human} | {r.profile} | {r.split} | {r.member} "
                     f"| {r.episodes} | {' | '.join(scores)} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def _approaches_text() -> str:
    """Each approach and its azimuths, as the caption gives them."""
    lowers = [bound for bound, _ in APPROACHES[1:]] + [None]
    return "; ".join(f"{name}: {_band(lower, upper)}"
                     for (upper, name), lower in zip(APPROACHES, lowers, strict=True))  # fmt: skip


def _band(lower: float | None, upper: float) -> str:
    if upper >= 180.0:
        return f"above {lower:g}°"
    return f"below {upper:g}°" if lower is None else f"{lower:g}° to {upper:g}°"


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
    write_table(out, MEMBERS, table, members_markdown)
    return table
