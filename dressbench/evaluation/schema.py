"""The column names of the result tables, in file order: one place for code, tests and docs."""

from __future__ import annotations

# What identifies a leaderboard cell: the pair and the env settings its episodes ran with.
CELL_COLUMNS = ["robot", "human", "ablation", "horizon", "gown_vertices", "device", "config_id"]
# A cell's episodes also share the evaluation's base seed.
KEY_COLUMNS = [*CELL_COLUMNS, "seed"]

EPISODE_COLUMNS = [
    *KEY_COLUMNS,
    "episode",
    "episode_seed",
    "final_arm_progress",
    "max_deformation",
    "hand_in",
    "success",
    "dressed",
    "sim_failure",
    "return",
    "steps",
]

CURVE_COLUMNS = [
    *KEY_COLUMNS,
    "step",
    "episodes",
    "arm_progress_mean",
    "arm_progress_std",
    "max_deformation_mean",
    "max_deformation_std",
]


def _summary(metric: str) -> list[str]:
    return [f"{metric}_{stat}" for stat in ("mean", "std", "ci_low", "ci_high")]


def _rate(stage: str) -> list[str]:
    return [f"{stage}_{stat}" for stat in ("rate", "ci_low", "ci_high")]


# The rates of the episodes columns that are stages of dressing, shallow to deep.
STAGE_COLUMNS = ["hand_in", "success", "dressed"]

LEADERBOARD_COLUMNS = [
    *KEY_COLUMNS,
    "episodes",
    *_summary("final_arm_progress"),
    *_summary("max_deformation"),
    *_rate("hand_in"),
    *_rate("success"),
    *_rate("dressed"),
    "sim_failures",
]
