"""Summaries of many episodes: bootstrap confidence intervals, the leaderboard and the curves."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from statistics import NormalDist
from typing import Any

import numpy as np
import pandas as pd

from .rollouts import EpisodeRecord
from .schema import CURVE_COLUMNS, KEY_COLUMNS, LEADERBOARD_COLUMNS, STAGE_COLUMNS

RESAMPLES = 10_000
CONFIDENCE = 0.95


def bootstrap_ci(
    values: Sequence[float] | np.ndarray,
    seed: int = 0,
    resamples: int = RESAMPLES,
    confidence: float = CONFIDENCE,
) -> tuple[float, float]:
    """The percentile bootstrap confidence interval of the mean, reproducible from ``seed``.

    Resample the values with replacement ``resamples`` times, take each resample's mean, and
    return the central ``confidence`` quantiles of those means. They are clipped to the data's
    range, where every resample mean lies, so constant data gives exactly (value, value).
    """
    x = np.asarray(values, dtype=float)
    if x.size == 0:
        return float("nan"), float("nan")
    rng = np.random.default_rng(seed)
    means = x[rng.integers(0, x.size, (resamples, x.size))].mean(axis=1)
    tail = 50.0 * (1.0 - confidence)
    low, high = np.clip(np.percentile(means, [tail, 100.0 - tail]), x.min(), x.max())
    return float(low), float(high)


def wilson_ci(successes: int, trials: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The Wilson score interval of a rate: unlike the bootstrap, it never claims certainty
    from finitely many trials (0 of 100 gives [0, 3.7%] at 95%, not [0, 0])."""
    if trials == 0:
        return float("nan"), float("nan")
    z = float(NormalDist().inv_cdf(0.5 + confidence / 2.0))
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = z * np.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / (1 + z * z / trials)
    return float(max(0.0, centre - half)), float(min(1.0, centre + half))


def leaderboard_table(episodes: pd.DataFrame, seed: int = 0) -> pd.DataFrame:
    """One row per cell of an episodes table: its ``episode_scores`` and simulation failures."""
    rows = []
    for key, group in episodes.groupby(KEY_COLUMNS, sort=False):
        row: dict[str, Any] = dict(zip(KEY_COLUMNS, key, strict=True))
        row |= episode_scores(group, seed)
        row["sim_failures"] = int(group["sim_failure"].sum())
        rows.append(row)
    return pd.DataFrame(rows, columns=LEADERBOARD_COLUMNS)


def episode_scores(group: pd.DataFrame, seed: int = 0) -> dict[str, Any]:
    """What a group of episodes scored: their count; mean, std and bootstrap CI of the final
    scores; each stage's rate with its Wilson interval."""
    row: dict[str, Any] = {"episodes": len(group)}
    for metric in ("final_arm_progress", "max_deformation"):
        values = group[metric].astype(float)
        low, high = bootstrap_ci(values, seed)
        row |= {
            f"{metric}_mean": values.mean(),
            f"{metric}_std": values.std(),  # sample std (ddof 1); NaN for one episode
            f"{metric}_ci_low": low,
            f"{metric}_ci_high": high,
        }
    for stage in STAGE_COLUMNS:
        reached = int(group[stage].astype(bool).sum())
        row[f"{stage}_rate"] = reached / len(group)
        row[f"{stage}_ci_low"], row[f"{stage}_ci_high"] = wilson_ci(reached, len(group))
    return row


def curve_table(cells: Iterable[tuple[Mapping[str, Any], Sequence[EpisodeRecord]]]) -> pd.DataFrame:
    """Per cell and policy step: mean and sample std (NaN for one episode) over its episodes."""
    parts = []
    for key, records in cells:
        progress = pd.DataFrame(np.stack([r.arm_progress for r in records]))
        deformation = pd.DataFrame(np.stack([r.max_deformation_curve for r in records]))
        part = pd.DataFrame(
            {
                "step": np.arange(1, progress.shape[1] + 1),
                "episodes": len(records),
                "arm_progress_mean": progress.mean().to_numpy(),
                "arm_progress_std": progress.std().to_numpy(),
                "max_deformation_mean": deformation.mean().to_numpy(),
                "max_deformation_std": deformation.std().to_numpy(),
            }
        )
        parts.append(part.assign(**{name: key[name] for name in KEY_COLUMNS}))
    if not parts:
        return pd.DataFrame(columns=CURVE_COLUMNS)
    return pd.concat(parts, ignore_index=True)[CURVE_COLUMNS]
