"""The two-level bootstrap: resample training seeds, then episodes within each resampled seed.

A strategy's score varies with the trained human (a training seed) as well as with the
rollout; resampling the pooled episodes alone sees only the second and claims too much. Each
resample here draws as many seeds as there are, with replacement, and for each drawn seed as
many of its episodes as it has, with replacement; every seed weighs the same whatever its
episode count. Everything is vectorized over the resamples and reproducible from a NumPy
generator.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .statistics import CONFIDENCE


@dataclass(frozen=True)
class Draws:
    """Which episodes each resample takes (``index`` into the seeds' episodes laid end to end)
    and the weight of each (1 / (seeds x that seed's episodes); 0 pads a short seed): rows are
    resamples, and each row's weights sum to 1."""

    index: np.ndarray  # (resamples, seeds x most episodes), int
    weight: np.ndarray  # the same shape, float

    def means(self, values: np.ndarray) -> np.ndarray:
        """Each resample's mean of seed means of ``values`` (the episodes laid end to end)."""
        return (np.asarray(values, dtype=float)[self.index] * self.weight).sum(axis=1)


def two_level_draws(counts: Sequence[int], resamples: int, rng: np.random.Generator) -> Draws:
    """``resamples`` two-level resamples of seeds with ``counts`` episodes each."""
    counts = np.asarray(counts, dtype=np.int64)
    seeds, longest = counts.size, int(counts.max())
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    chosen = rng.integers(0, seeds, (resamples, seeds))
    sizes = counts[chosen][..., None]  # (resamples, seeds, 1): each drawn seed's episode count
    episodes = rng.integers(0, sizes, (resamples, seeds, longest))
    kept = np.arange(longest) < sizes  # a seed with fewer episodes draws only as many
    index = np.where(kept, starts[chosen][..., None] + episodes, 0)
    weight = kept / (seeds * sizes)
    return Draws(index.reshape(resamples, -1), weight.reshape(resamples, -1))


def observed(counts: Sequence[int]) -> Draws:
    """The data itself as one draw: every episode once, each seed weighing the same."""
    counts = np.asarray(counts, dtype=np.int64)
    weight = np.repeat(1.0 / (counts.size * counts), counts)
    return Draws(np.arange(counts.sum())[None, :], weight[None, :])


def percentile_interval(
    estimates: np.ndarray, confidence: float = CONFIDENCE
) -> tuple[float, float]:
    """The central ``confidence`` interval of bootstrap estimates."""
    tail = 50.0 * (1.0 - confidence)
    low, high = np.percentile(estimates, [tail, 100.0 - tail])
    return float(low), float(high)


def improvement(a: np.ndarray, a_draws: Draws, b: np.ndarray, b_draws: Draws) -> np.ndarray:
    """P[a draw of ``a`` exceeds one of ``b``], ties counting half, per resample (row).

    ``a`` and ``b`` are the two samples' episodes laid end to end; each row of the draws weighs
    its episodes (summing to 1), so a row's probability is the weighted share of (a, b) pairs
    where a's value is the larger. Computed for all rows at once: the values become integer
    ranks shared by both samples, each row's are shifted into a range of its own, and one
    sorted search counts, for every draw of ``a``, the weight of ``b`` below and equal to it.
    """
    values, codes = np.unique(np.concatenate([a, b]), return_inverse=True)
    a_codes, b_codes = codes[: len(a)][a_draws.index], codes[len(a) :][b_draws.index]
    rows, width = b_codes.shape
    shift = np.arange(rows)[:, None] * values.size
    b_keys = (b_codes + shift).ravel()
    order = np.argsort(b_keys, kind="stable")
    keys = b_keys[order]
    total = np.concatenate([[0.0], np.cumsum(b_draws.weight.ravel()[order])])
    queries = (a_codes + shift).ravel()
    below = np.searchsorted(keys, queries, "left")
    above = np.searchsorted(keys, queries, "right")
    before_row = np.repeat(total[np.arange(rows) * width], a_codes.shape[1])
    share = total[below] - before_row + (total[above] - total[below]) / 2.0
    return (share.reshape(a_codes.shape) * a_draws.weight).sum(axis=1)
