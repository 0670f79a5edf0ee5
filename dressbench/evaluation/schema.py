"""The column names of the result tables, in file order: one place for code, tests and docs."""

from __future__ import annotations

# What identifies a leaderboard cell: the pair and the env settings its episodes ran with, the
# human's capability profile among them.
CELL_COLUMNS = ["robot", "human", "ablation", "profile", "horizon", "gown_vertices", "device",
                "config_id"]  # fmt: skip
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
# each stage's name in tables, captions and the report
STAGE_LABELS = {"hand_in": "hand in", "success": "past the elbow (success)", "dressed": "dressed"}

# What a group of episodes scored (``statistics.episode_scores``).
SCORE_COLUMNS = [
    "episodes",
    *_summary("final_arm_progress"),
    *_summary("max_deformation"),
    *_rate("hand_in"),
    *_rate("success"),
    *_rate("dressed"),
]

LEADERBOARD_COLUMNS = [*KEY_COLUMNS, *SCORE_COLUMNS, "sim_failures"]

# A family cell's episodes split by the member each faced (members.py): by which split (the
# member's kind, or the direction of its start) and into which member.
MEMBER_COLUMNS = [*CELL_COLUMNS, "split", "member", *SCORE_COLUMNS]

# What a row of the strategy table is: a robot strategy, the group of humans trained for it
# (groups.py: the recipe and ablation they were trained with), the env settings and base seed.
STRATEGY_KEY = ["robot", "recipe", *KEY_COLUMNS[2:]]
# The rows that compete for ranks and are compared pairwise: the same key but the robot.
COMPARED_COLUMNS = STRATEGY_KEY[1:]
# A strategy's scores: the means, then the stages' rates, each over seeds.
STRATEGY_MEANS = ["final_arm_progress", "max_deformation"]


def _over_seeds(name: str, centre: str) -> list[str]:
    return [f"{name}_{stat}" for stat in (centre, "ci_low", "ci_high", "seed_std")]


STRATEGY_COLUMNS = [
    *STRATEGY_KEY,
    "rank",
    "seeds",
    "training_seeds",
    "humans",
    "episodes",
    *(column for metric in STRATEGY_MEANS for column in _over_seeds(metric, "mean")),
    *(column for stage in STAGE_COLUMNS for column in _over_seeds(stage, "rate")),
    "note",
]

# One row per pair of compared strategies: P[a rollout of ``robot`` goes deeper than one of
# ``versus``], the pair ordered so that it is at least 1/2.
IMPROVEMENT_COLUMNS = [
    "robot",
    "versus",
    *COMPARED_COLUMNS,
    "probability",
    "ci_low",
    "ci_high",
    "separated",
]

# One row per fine-tuned human and setting where its parent played the same rollouts
# (finetuned.py): each score's mean for both, and the paired change with its interval.
FINETUNED_SCORES = ["final_arm_progress", "max_deformation", "success"]
FINETUNED_COLUMNS = [
    "robot",
    "human",
    "parent",
    "ablation",
    "profile",
    "config_id",
    "episodes",
    *(
        f"{score}{part}"
        for score in FINETUNED_SCORES
        for part in ("", "_parent", "_change", "_change_ci_low", "_change_ci_high")
    ),
    "deeper",
    "deeper_ci_low",
    "deeper_ci_high",
    "verdict",
]
