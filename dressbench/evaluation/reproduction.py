"""The paper's comparison (Clegg et al., ICRA 2018, §V): its five policies, their claims, and a
verdict on each read off the confidence intervals; plus the cross-play of every complete human
against every built-in strategy.

``reproduce`` evaluates the cells, then writes beside the usual result files: ``roles.csv`` /
``roles.md`` (each of the paper's policies over its humans' seeds: two-level bootstrap
intervals and the spread across seeds), ``claims.csv`` / ``claims.md`` (each claim, its
verdict and why), ``cross_play.csv``, and the figures ``fig5_fixed_ablations.png``,
``fig6_final_scores.png``, ``fig7_linear_strategies.png`` and ``cross_play.png``.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..checks import EPISODES, REPRODUCTION
from ..config import RewardConfig
from ..files import write_csv, write_png, write_text
from ..plugins import TYPICAL_PROFILE, human_plugins, load_human
from ..plugins.robots import PAPER_STRATEGIES
from .bootstrap import two_level_draws
from .cells import checked_cell
from .docblock import DocBlock
from .groups import human_group
from .plots import cross_play_figure, role_bars_figure, role_curves_figure
from .rollouts import STAGE_DEPTHS, SUCCESS_DEPTH
from .statistics import RESAMPLES
from .strategies import ONE_SEED, over_seeds


@dataclass(frozen=True)
class Role:
    """One of the paper's five policies: a human of ``ablation`` trained for ``robot``."""

    robot: str
    ablation: str

    @property
    def name(self) -> str:
        return f"{self.ablation} on {self.robot}"


ROLES = (
    Role("fixed", "complete"),
    Role("fixed", "no_haptics"),
    Role("fixed", "no_task"),
    Role("front_linear", "complete"),
    Role("side_linear", "complete"),
)

ROLE_COLUMNS = [
    "role",
    "robot",
    "ablation",
    "humans",
    "episodes",
    "final_arm_progress_mean",
    "final_arm_progress_ci_low",
    "final_arm_progress_ci_high",
    "final_arm_progress_seed_std",
    "max_deformation_mean",
    "max_deformation_ci_low",
    "max_deformation_ci_high",
    "max_deformation_seed_std",
    "hand_in_rate",
    "hand_in_ci_low",
    "hand_in_ci_high",
    "success_rate",
    "success_ci_low",
    "success_ci_high",
]


def paper_humans(
    names: Iterable[str] | None = None, recipe: str | None = None
) -> dict[Role, list[str]]:
    """The humans that play each role: trained for its robot, with its ablation. ``names``
    chooses them (one that plays no role is a ValueError); by default, every usable human that
    is a seed of ``recipe`` (of any, when None) trained in the typical body, so that a role
    never mixes capability profiles (nor recipes, given one)."""
    found: dict[Role, list[str]] = {role: [] for role in ROLES}
    records = human_plugins()
    chosen = sorted(records) if names is None else list(names)
    for name in chosen:
        if names is None and records[name].status != "ok":
            continue
        policy = load_human(name)
        role = Role(str(getattr(policy, "robot", None)), policy.ablation)
        if role in found:
            if names is None and not _seed_of(name, policy, recipe):
                continue
            found[role].append(name)
        elif names is not None:
            raise ValueError(f"human {name!r} plays none of the paper's policies ({role.name})")
    return found


def _seed_of(name: str, policy: Any, recipe: str | None) -> bool:
    """Whether the human ``name`` is a seed of ``recipe`` (any, when None) in the typical body."""
    metadata = getattr(policy, "metadata", None)
    human = human_group(name, str(policy.robot), policy.ablation, metadata)
    return human is not None and human.profile == TYPICAL_PROFILE and recipe in (None, human.recipe)


def reproduction_cells(humans: Mapping[Role, Sequence[str]], **options: Any) -> list:
    """Each role's humans on their robot, then each complete human on the other strategies."""
    pairs = [(role.robot, human) for role, names in humans.items() for human in names]
    complete = [h for role, names in humans.items() if role.ablation == "complete" for h in names]
    pairs += [(robot, human) for human in complete for robot in PAPER_STRATEGIES]
    return [checked_cell(robot, human, **options) for robot, human in dict.fromkeys(pairs)]


def reproduce(
    episodes: int = EPISODES,
    seed: int = 0,
    workers: int | None = None,
    out: str | os.PathLike = REPRODUCTION,
    humans: Mapping[Role, Sequence[str]] | None = None,
    *,
    progress: bool = True,
    backend: str = "local",
    address: str | None = None,
    **options: Any,
) -> pd.DataFrame:
    """Evaluate the paper's policies and the cross-play, write the comparison; returns the
    claims table. ``humans`` gives each role's humans (default: ``paper_humans()``); a role
    without one is reported as not measured."""
    from .runs import check_run, evaluate_cells

    where = check_run(episodes, seed, workers, out, backend, address)
    humans = {role: list(names) for role, names in (humans or paper_humans()).items() if names}
    if not humans:
        raise ValueError("no trained human for any of the paper's policies: train one first")
    cells = reproduction_cells(humans, **options)
    evaluated = evaluate_cells(
        cells,
        episodes,
        seed,
        workers,
        Path(out),
        SUCCESS_DEPTH,
        progress,
        "reproduce",
        options,
        backend=where,
    )
    return write_comparison(Path(out), evaluated.episodes, humans, seed)


def write_comparison(
    out: Path, episodes: pd.DataFrame, humans: Mapping[Role, Sequence[str]], seed: int = 0
) -> pd.DataFrame:
    """The comparison's tables and figures from an episodes table and curves.csv in ``out``."""
    limit = RewardConfig().limit
    roles = role_table(episodes, humans, seed)
    claims = claims_table(roles, limit)
    cross = cross_play_table(episodes, humans)
    curves = pd.read_csv(out / "curves.csv")
    write_csv(out / "roles.csv", roles)
    write_csv(out / "claims.csv", claims)
    write_text(out / "claims.md", claims_markdown(claims, limit))
    write_text(out / "roles.md", roles_markdown(roles))
    write_csv(out / "cross_play.csv", cross)
    fixed = [role for role in ROLES if role.robot == "fixed"]
    linear = [role for role in ROLES if role.robot != "fixed"]
    write_png(
        out / "fig5_fixed_ablations.png",
        role_curves_figure(curves, _lines(humans, fixed), limit, "fixed: the ablations"),
    )
    write_png(
        out / "fig7_linear_strategies.png",
        role_curves_figure(curves, _lines(humans, linear), limit, "linear strategies"),
    )
    write_png(out / "fig6_final_scores.png", role_bars_figure(roles, limit))
    write_png(out / "cross_play.png", cross_play_figure(cross))
    return claims


def _lines(humans: Mapping[Role, Sequence[str]], roles: Iterable[Role]) -> list[tuple[str, str]]:
    """(robot, human) of each curve a figure draws for ``roles``."""
    return [(role.robot, human) for role in roles for human in humans.get(role, ())]


def role_table(
    episodes: pd.DataFrame, humans: Mapping[Role, Sequence[str]], seed: int = 0
) -> pd.DataFrame:
    """Per role: its humans (one per training seed) on its robot, each score the mean of the
    seeds' means with its two-level bootstrap interval (``over_seeds``, as the strategy table)
    and the std of the seeds' means; a role without episodes has none."""
    rows = []
    for role in ROLES:
        names = list(humans.get(role, ()))
        mine = episodes[(episodes["robot"] == role.robot) & episodes["human"].isin(names)]
        seeds = [part for _, part in mine.groupby("human", sort=True)]
        row: dict[str, Any] = {
            "role": role.name,
            "robot": role.robot,
            "ablation": role.ablation,
            "humans": " ".join(names),
            "episodes": len(mine),
        }
        if seeds:
            rng = np.random.default_rng([seed, ROLES.index(role)])
            row |= over_seeds(seeds, two_level_draws([len(p) for p in seeds], RESAMPLES, rng))
        rows.append({column: row.get(column, np.nan) for column in ROLE_COLUMNS})
    return pd.DataFrame(rows, columns=ROLE_COLUMNS)


def cross_play_table(episodes: pd.DataFrame, humans: Mapping[Role, Sequence[str]]) -> pd.DataFrame:
    """Mean final arm progress and max deformation of each complete human on each strategy."""
    complete = [h for role, names in humans.items() if role.ablation == "complete" for h in names]
    mine = episodes[episodes["human"].isin(complete) & episodes["robot"].isin(PAPER_STRATEGIES)]
    table = mine.groupby(["human", "robot"], sort=False)[["final_arm_progress", "max_deformation"]]
    return table.mean().reset_index()


@dataclass(frozen=True)
class _Claim:
    number: int
    statement: str
    roles: tuple[Role, ...]


CLAIMS = (
    _Claim(
        1,
        "the complete policy completes the fixed task reasonably with low deformation",
        (ROLES[0],),
    ),
    _Claim(2, "no_haptics makes progress but deforms the gown beyond the threshold", (ROLES[1],)),
    _Claim(
        3,
        "no_task keeps deformation low but hovers near the opening and fails to enter",
        (ROLES[2],),
    ),
    _Claim(
        4,
        "the linear strategies reach higher final progress than fixed (assistance helps)",
        (ROLES[0], ROLES[3], ROLES[4]),
    ),
    _Claim(
        5,
        "all haptic-aware policies keep deformation similarly low",
        (ROLES[0], ROLES[2], ROLES[3], ROLES[4]),
    ),
)

HOLDS, PARTLY, FAILS, UNMEASURED = "holds", "partly", "does not hold", "not measured"


def claims_table(roles: pd.DataFrame, limit: float) -> pd.DataFrame:
    """Each claim's verdict from the intervals (docs/reproduction.md gives the rules), with the
    tests it rests on in words."""
    by_role = {row.role: row for row in roles.itertuples()}
    rows = []
    for claim in CLAIMS:
        rows_of = [by_role[role.name] for role in claim.roles]
        if any(row.episodes == 0 for row in rows_of):
            verdict, because = (
                UNMEASURED,
                "no trained human for "
                + ", ".join(row.role for row in rows_of if row.episodes == 0),
            )
        else:
            verdict, because = _VERDICTS[claim.number](rows_of, limit)
            single = [row.role for row in rows_of if _seeds(row) == 1]
            if single:
                because += f"; {ONE_SEED} ({', '.join(single)})"
        rows.append(
            {
                "claim": claim.number,
                "statement": claim.statement,
                "verdict": verdict,
                "because": because,
            }
        )
    return pd.DataFrame(rows, columns=["claim", "statement", "verdict", "because"])


def _seeds(row: Any) -> int:
    """How many humans (training seeds) a roles-table row pools; 0 where it does not say."""
    return len(row.humans.split()) if isinstance(row.humans, str) else 0


def _verdict(tests: Sequence[tuple[bool, str]]) -> tuple[str, str]:
    """All tests pass: holds; some: partly; none: does not hold."""
    passed = sum(ok for ok, _ in tests)
    verdict = HOLDS if passed == len(tests) else PARTLY if passed else FAILS
    return verdict, "; ".join(f"{'yes' if ok else 'no'}: {text}" for ok, text in tests)


def _low_deformation(row: Any, limit: float) -> tuple[bool, str]:
    high = row.max_deformation_ci_high
    return high < limit, f"{row.role}: max deformation CI high {high:.3f} < {limit:.3f}"


def _completes(rows: Sequence[Any], limit: float) -> tuple[str, str]:
    (row,) = rows
    return _verdict(
        [
            (
                row.success_ci_low >= 0.5,
                f"past the elbow, CI low {row.success_ci_low:.0%} >= 50%",
            ),
            _low_deformation(row, limit),
        ]
    )


def _deforms(rows: Sequence[Any], limit: float) -> tuple[str, str]:
    (row,) = rows
    low, deform = row.final_arm_progress_ci_low, row.max_deformation_ci_low
    return _verdict(
        [
            (
                low > STAGE_DEPTHS["hand_in"],
                f"final arm progress CI low {low:.3f} m > "
                f"the hand's {STAGE_DEPTHS['hand_in']:.2f} m",
            ),
            (deform > limit, f"max deformation CI low {deform:.3f} > {limit:.3f}"),
        ]
    )


def _hovers(rows: Sequence[Any], limit: float) -> tuple[str, str]:
    (row,) = rows
    high = row.final_arm_progress_ci_high
    return _verdict(
        [
            _low_deformation(row, limit),
            (
                high < STAGE_DEPTHS["hand_in"],
                f"final arm progress CI high {high:.3f} m < "
                f"the hand's {STAGE_DEPTHS['hand_in']:.2f} m",
            ),
        ]
    )


def _assistance_helps(rows: Sequence[Any], limit: float) -> tuple[str, str]:
    fixed, *linear = rows
    return _verdict(
        [
            (
                row.final_arm_progress_ci_low > fixed.final_arm_progress_ci_high,
                f"{row.role} CI low {row.final_arm_progress_ci_low:.3f} m > {fixed.role} "
                f"CI high {fixed.final_arm_progress_ci_high:.3f} m",
            )
            for row in linear
        ]
    )


def _all_low(rows: Sequence[Any], limit: float) -> tuple[str, str]:
    return _verdict([_low_deformation(row, limit) for row in rows])


_VERDICTS = {1: _completes, 2: _deforms, 3: _hovers, 4: _assistance_helps, 5: _all_low}


def claims_markdown(claims: pd.DataFrame, limit: float) -> str:
    """The claims table in Markdown, under a caption naming the threshold the verdicts use."""
    lines = [
        f"Verdicts from 95% intervals; the deformation threshold is the area ratio at which "
        f"r_d reaches -0.1 ({limit:.2f} with dressbench's calibration).",
        "",
        "| claim | statement | verdict | because |",
        "|---:|---|---|---|",
    ]
    lines += [
        f"| {r.claim} | {r.statement} | {r.verdict} | {r.because} |" for r in claims.itertuples()
    ]
    return "\n".join(lines) + "\n"


def roles_markdown(roles: pd.DataFrame) -> str:
    """The roles table in Markdown: each policy's means over seeds with 95% intervals, the spread of
    its seeds' means where it has several, and its stage rates."""
    lines = [
        "| policy | humans | episodes | final arm progress (m) | max deformation "
        "| hand in | past the elbow |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for row in roles.itertuples():
        if not row.episodes:
            lines.append(f"| {row.role} | none trained | 0 | | | | |")
            continue
        cells = [
            _mean_cell(row, "final_arm_progress", ".3f"),
            _mean_cell(row, "max_deformation", ".2f"),
            _rate_cell(row, "hand_in"),
            _rate_cell(row, "success"),
        ]
        lines.append(f"| {row.role} | {row.humans} | {row.episodes} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _mean_cell(row: Any, metric: str, spec: str) -> str:
    mean, low, high = (getattr(row, f"{metric}_{part}") for part in ("mean", "ci_low", "ci_high"))
    text = f"{mean:{spec}} [{low:{spec}}, {high:{spec}}]"
    spread = getattr(row, f"{metric}_seed_std")
    return text if pd.isna(spread) else f"{text}, seeds' std {spread:{spec}}"


def _rate_cell(row: Any, stage: str) -> str:
    rate, low, high = (getattr(row, f"{stage}_{part}") for part in ("rate", "ci_low", "ci_high"))
    return f"{rate:.0%} [{low:.0%}, {high:.0%}]"


DOC_BEGIN = "<!-- begin results: written by `dressbench evaluate reproduce --doc` -->"
DOC_END = "<!-- end results -->"
RESULTS_BLOCK = DocBlock("results", DOC_BEGIN, DOC_END)


def doc_results(out: str | os.PathLike) -> str:
    """What docs/reproduction.md states of a comparison: its roles and claims tables, read from
    the CSVs in ``out``."""
    out = Path(out)
    limit = RewardConfig().limit
    roles = pd.read_csv(out / "roles.csv", keep_default_na=False, na_values=[""])
    claims = pd.read_csv(out / "claims.csv")
    return roles_markdown(roles) + "\n" + claims_markdown(claims, limit)


def documented_results(doc: str | os.PathLike) -> str:
    """The results block of a doc: the text between its markers (ValueError without them)."""
    return RESULTS_BLOCK.read(doc)


def write_doc_results(doc: str | os.PathLike, out: str | os.PathLike) -> None:
    """Rewrite a doc's results block from the comparison in ``out``."""
    RESULTS_BLOCK.write(doc, doc_results(out))
