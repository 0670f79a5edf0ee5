"""The strategy table: each robot strategy scored over the humans trained for it, not one human.

A trained human is one draw of a training run, so a strategy's row pools the humans of one
group (``groups.py``: the robot, recipe and ablation they were trained with; they differ by
seed), each scored over its seeded rollouts. Every mean and rate is the mean of the seeds'
means, with a 95% interval from the two-level bootstrap (``bootstrap.py``) and the std of the
seeds' means (the spread a single human hides). Strategies compared with one another (the
same recipe, ablation, env settings and base seed) get a rank and pairwise probabilities of
improvement. ``strategy_table`` and ``improvement_table`` take an episodes table (as in
episodes.csv), for a notebook; ``write_strategies`` writes them beside the cell table. See
docs/evaluation.md, "A strategy's score".
"""

from __future__ import annotations

import zlib
from collections.abc import Iterator, Mapping, Sequence
from itertools import combinations
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..files import write_csv, write_png, write_text
from .bootstrap import Draws, improvement, observed, percentile_interval, two_level_draws
from .docblock import DocBlock
from .groups import TrainedHuman, episode_humans
from .plots import profiles_figure, strategies_figure
from .schema import (
    COMPARED_COLUMNS,
    IMPROVEMENT_COLUMNS,
    STAGE_COLUMNS,
    STAGE_LABELS,
    STRATEGY_COLUMNS,
    STRATEGY_KEY,
    STRATEGY_MEANS,
)
from .statistics import CONFIDENCE, RESAMPLES

PROFILES_FIGURE = "profiles.png"  # strategy x capability profile, when there are several
RANKED_BY = "final_arm_progress"  # the rank, and "deeper" in P(improvement)
ONE_SEED = "one seed: the CI covers rollouts only"
SCORES = [*STRATEGY_MEANS, *STAGE_COLUMNS]  # the episodes columns a strategy is scored on


def scored_episodes(
    episodes: pd.DataFrame, humans: Mapping[str, TrainedHuman] | None = None
) -> pd.DataFrame:
    """The episodes of trained humans on the strategy they were trained for (a generalist's on
    every strategy), with the ``recipe`` of their group and their ``training_seed``; ``humans``
    default: ``episode_humans``."""
    if humans is None:
        humans = episode_humans(episodes)
    known = episodes["human"].map(humans)
    meant = known.map(lambda h: getattr(h, "robot", ""))  # None: a generalist, meant for any
    mine = known.notna() & (meant.isna() | (meant == episodes["robot"]))
    return episodes[mine].assign(
        recipe=known[mine].map(lambda h: h.recipe),
        training_seed=known[mine].map(lambda h: h.seed),
    )


def seed_means(scored: pd.DataFrame) -> pd.DataFrame:
    """Each human's mean scores (rates as shares) over its episodes, by strategy and seed."""
    columns = [*STRATEGY_KEY, "training_seed", "human"]
    table = scored.astype({stage: float for stage in STAGE_COLUMNS}).groupby(columns)
    return table[SCORES].mean().join(table.size().rename("episodes")).reset_index()


def strategy_table(
    episodes: pd.DataFrame,
    humans: Mapping[str, TrainedHuman] | None = None,
    seed: int = 0,
    resamples: int = RESAMPLES,
) -> pd.DataFrame:
    """One row per strategy and group of humans: seeds, episodes, each score's mean over the
    seeds' means with its two-level bootstrap interval and the seeds' std, the rank, a note.

    ``humans`` maps human names to their group (default: ``trained_humans``); other humans
    (baselines) and humans on a strategy they were not trained for are left out. Reproducible
    from ``seed``: each row draws from its own generator, seeded by ``seed`` and its key.
    """
    rows = []
    for key, seeds in _strategies(scored_episodes(episodes, humans)):
        counts = [len(part) for part in seeds]
        draws = two_level_draws(counts, resamples, _generator(seed, key))
        row: dict[str, Any] = dict(zip(STRATEGY_KEY, key, strict=True)) | {
            "seeds": len(seeds),
            "training_seeds": " ".join(str(part["training_seed"].iloc[0]) for part in seeds),
            "humans": " ".join(str(part["human"].iloc[0]) for part in seeds),
            "episodes": sum(counts),
            "note": ONE_SEED if len(seeds) == 1 else "",
        }
        rows.append(row | over_seeds(seeds, draws))
    table = pd.DataFrame(rows, columns=STRATEGY_COLUMNS)
    table["rank"] = ranks(table)
    return table.sort_values([*COMPARED_COLUMNS, "rank", f"{RANKED_BY}_mean"],
                             ascending=[True] * len(COMPARED_COLUMNS) + [True, False],
                             ignore_index=True)  # fmt: skip


def over_seeds(seeds: Sequence[pd.DataFrame], draws: Draws) -> dict[str, float]:
    """Each score of ``SCORES`` over seeds (one episodes frame each): the mean of the seeds'
    means (``_mean``, a stage's ``_rate``), the interval of the ``draws`` (``_ci_low``,
    ``_ci_high``) and the std of the seeds' means (``_seed_std``; NaN for one seed)."""
    found = {}
    for score in SCORES:
        values = np.concatenate([part[score].to_numpy(dtype=float) for part in seeds])
        means = np.array([part[score].to_numpy(dtype=float).mean() for part in seeds])
        centre = "rate" if score in STAGE_COLUMNS else "mean"
        low, high = percentile_interval(draws.means(values), CONFIDENCE)
        found |= {
            f"{score}_{centre}": means.mean(),
            f"{score}_ci_low": low,
            f"{score}_ci_high": high,
            f"{score}_seed_std": means.std(ddof=1) if len(means) > 1 else np.nan,
        }
    return found


def ranks(table: pd.DataFrame) -> pd.Series:
    """Each row's rank among the rows it is compared with (``COMPARED_COLUMNS`` equal):
    1 + the number of them whose final-progress interval lies wholly above its own (their low
    end above its high end). Rows whose intervals overlap share a place; a row below two
    overlapping leaders is third."""
    low = table[f"{RANKED_BY}_ci_low"].to_numpy()
    high = table[f"{RANKED_BY}_ci_high"].to_numpy()
    rank = np.ones(len(table), dtype=int)
    for rows in table.groupby(COMPARED_COLUMNS, sort=False).indices.values():
        rank[rows] = 1 + (low[rows][None, :] > high[rows][:, None]).sum(axis=1)
    return pd.Series(rank, index=table.index)


def improvement_table(
    episodes: pd.DataFrame,
    humans: Mapping[str, TrainedHuman] | None = None,
    seed: int = 0,
    resamples: int = RESAMPLES,
) -> pd.DataFrame:
    """One row per pair of compared strategies: the probability that a rollout of one goes
    deeper (final arm progress) than a rollout of the other, ties counting half, averaged over
    their seeds' pairs, with its two-level bootstrap interval (the draws of ``strategy_table``);
    each pair ordered so that the probability is at least 1/2, ``separated`` when the interval
    excludes 1/2."""
    found = {key: seeds for key, seeds in _strategies(scored_episodes(episodes, humans))}
    rows = []
    for (a, a_seeds), (b, b_seeds) in combinations(found.items(), 2):
        if a[1:] != b[1:]:  # not compared: another recipe, ablation or setting
            continue
        values = [np.concatenate([part[RANKED_BY].to_numpy(float) for part in seeds])
                  for seeds in (a_seeds, b_seeds)]  # fmt: skip
        counts = [[len(part) for part in seeds] for seeds in (a_seeds, b_seeds)]
        estimate = improvement(values[0], observed(counts[0]), values[1], observed(counts[1]))[0]
        draws = [two_level_draws(n, resamples, _generator(seed, key))
                 for n, key in zip(counts, (a, b), strict=True)]  # fmt: skip
        low, high = percentile_interval(improvement(values[0], draws[0], values[1], draws[1]))
        if estimate < 0.5:
            (a, b), (estimate, low, high) = (b, a), (1.0 - estimate, 1.0 - high, 1.0 - low)
        compared = dict(zip(COMPARED_COLUMNS, a[1:], strict=True))
        rows.append({"robot": a[0], "versus": b[0], **compared, "probability": estimate,
                     "ci_low": low, "ci_high": high, "separated": low > 0.5})  # fmt: skip
    return pd.DataFrame(rows, columns=IMPROVEMENT_COLUMNS)


def _strategies(scored: pd.DataFrame) -> Iterator[tuple[tuple[Any, ...], list[pd.DataFrame]]]:
    """Each strategy's key and its humans' episodes, one frame per human, by training seed."""
    for key, group in scored.groupby(STRATEGY_KEY, sort=True):
        ordered = group.sort_values(["training_seed", "human"], kind="stable")
        yield key, [part for _, part in ordered.groupby(["training_seed", "human"], sort=True)]


def _generator(seed: int, key: tuple[Any, ...]) -> np.random.Generator:
    """A strategy's own generator: the same draws whichever other strategies are in a table."""
    return np.random.default_rng([seed, zlib.crc32("/".join(map(str, key)).encode())])


STRATEGY_CAPTION = (
    f"Each row is a robot strategy with a group of humans trained for it (the same recipe and "
    f"ablation, one human per training seed), each scored over its seeded rollouts. A score is "
    f"the mean of the seeds' means ± the std of the seeds' means, and in brackets its "
    f"{CONFIDENCE:.0%} interval from a two-level bootstrap ({RESAMPLES:,} resamples of the "
    f"seeds, then of the episodes within each). The rank orders the strategies compared (same "
    f"recipe, ablation, capability profile and settings) by final arm progress: 1 + the number "
    f"whose interval lies wholly above the row's, so strategies whose intervals overlap share a "
    f"place."
)

# --- files --------------------------------------------------------------------------------------


def strategies_markdown(table: pd.DataFrame) -> str:
    """The strategy table in Markdown under a caption that defines every number in it."""
    return f"# dressbench strategies\n\n{STRATEGY_CAPTION}\n\n{strategy_rows_markdown(table)}"


def strategy_rows_markdown(table: pd.DataFrame) -> str:
    """The strategy table's Markdown table alone (strategies.md's, and a doc's strategies
    block: ``STRATEGIES_BLOCK``)."""
    lines = [
        "| rank | robot | recipe | ablation | profile | seeds | episodes "
        f"| final arm progress (m) | max deformation "
        f"| {' | '.join(STAGE_LABELS[s] for s in STAGE_COLUMNS)} | note |",
        "|---:|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in table.itertuples():
        scores = [score_text(r, "final_arm_progress", "mean", "{:.3f}"),
                  score_text(r, "max_deformation", "mean", "{:.2f}"),
                  *(score_text(r, stage, "rate", "{:.0%}") for stage in STAGE_COLUMNS)]  # fmt: skip
        lines.append(f"| {r.rank} | {r.robot} | {r.recipe} | {r.ablation} | {r.profile} "
                     f"| {r.seeds} | {r.episodes} | {' | '.join(scores)} | {r.note} |")  # fmt: skip
    if table.empty:
        lines.append("| | no trained human in these results | | | | | | | | | | | |")
    return "\n".join(lines) + "\n"


# A doc's copy of the strategy table (the README's), which `evaluate leaderboard --doc` rewrites
STRATEGIES_BLOCK = DocBlock(
    "strategies",
    "<!-- begin strategies: written by `dressbench evaluate leaderboard --doc` -->",
    "<!-- end strategies -->",
)


def improvement_markdown(table: pd.DataFrame) -> str:
    """The pairwise probabilities of improvement in Markdown, under their definition."""
    lines = [
        "# dressbench: probability of improvement",
        "",
        f"P[a rollout of the first strategy goes deeper than one of the second] (final arm "
        f"progress; ties count half), averaged over the pairs of their seeds, with its "
        f"{CONFIDENCE:.0%} two-level bootstrap interval. Separated: the interval excludes 1/2.",
        "",
        "| robot | versus | recipe | ablation | profile | P(deeper) | separated |",
        "|---|---|---|---|---|---:|---|",
    ]
    lines += [f"| {r.robot} | {r.versus} | {r.recipe} | {r.ablation} | {r.profile} "
              f"| {r.probability:.2f} "
              f"[{r.ci_low:.2f}, {r.ci_high:.2f}] | {'yes' if r.separated else 'no'} |"
              for r in table.itertuples()]  # fmt: skip
    return "\n".join(lines) + "\n"


def score_text(row: Any, score: str, centre: str, number: str) -> str:
    """``centre ± seeds' std [low, high]`` of one score of a strategy row (Markdown, report)."""
    value, std, low, high = (getattr(row, f"{score}_{s}")
                             for s in (centre, "seed_std", "ci_low", "ci_high"))  # fmt: skip
    spread = "" if pd.isna(std) else f" ± {number.format(std)}"
    return f"{number.format(value)}{spread} [{number.format(low)}, {number.format(high)}]"


def write_strategies(
    out: Path,
    episodes: pd.DataFrame,
    seed: int = 0,
    humans: Mapping[str, TrainedHuman] | None = None,
) -> pd.DataFrame:
    """Write strategies.csv/.md, improvement.csv/.md and strategies.png (none without a trained
    human), and profiles.png where the table holds more than one capability profile, into
    ``out``; returns the strategy table. ``humans`` default: ``episode_humans``."""
    if humans is None:
        humans = episode_humans(episodes)  # each policy file read once
    table = strategy_table(episodes, humans, seed)
    pairs = improvement_table(episodes, humans, seed)
    write_csv(out / "strategies.csv", table)
    write_text(out / "strategies.md", strategies_markdown(table))
    write_csv(out / "improvement.csv", pairs)
    write_text(out / "improvement.md", improvement_markdown(pairs))
    figure = out / "strategies.png"
    if table.empty:
        figure.unlink(missing_ok=True)  # an earlier run's would show strategies not scored here
    else:
        write_png(figure, strategies_figure(table, seed_means(scored_episodes(episodes, humans))))
    by_profile = out / PROFILES_FIGURE
    if table["profile"].nunique() > 1:
        write_png(by_profile, profiles_figure(table))
    else:
        by_profile.unlink(missing_ok=True)
    return table
