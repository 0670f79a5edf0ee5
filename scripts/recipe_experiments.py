"""The learning curves behind the default training recipe (docs/training.md), side by side.

Reads the learning summaries in results/training/experiments/ and writes
results/training/experiments/recipe.png and a table of recent mean final arm progress at a few
step counts. Run: python scripts/recipe_experiments.py
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
from matplotlib.figure import Figure

FOLDER = Path(__file__).resolve().parents[1] / "results" / "training" / "experiments"
STEPS = "time/total_timesteps"
PROGRESS = "rollout/final_arm_progress"
RUNS = {  # learning summary stem: label
    "front_linear-complete-trpo-s0": "newtons, no floor (10-iteration cloth)",
    "front_linear-no_haptics-trpo-s0": "no_haptics ablation (10-iteration cloth)",
    "front_linear-complete-trpo-nofloor-s0": "log haptics, no floor",
    "front_linear-complete-trpo-floor-s0": "log haptics + variance floor",
    "side_linear-complete-trpo-nofloor-s0": "side_linear: log haptics, no floor",
    "side_linear-complete-trpo-floor-s0": "side_linear: log haptics + variance floor",
    "front_linear-complete-trpo-warmup-s0": "log haptics + floor + r_d warm-up (2026-12-01)",
    "side_linear-complete-trpo-warmup-s0": "side_linear: + r_d warm-up",
    "side_linear-complete-trpo-warmup-curriculum-s0": "side_linear: + r_d warm-up + curriculum",
    "side_linear-complete-trpo-delta-curriculum-s0": "side_linear: warm-up, delta, curriculum",
    "../fixed-complete-trpo-delta-curriculum-s0": "fixed: warm-up, delta, curriculum",
    "front_linear-complete-trpo-delta-curriculum-s0": "front_linear: default recipe of 2026-12-02",
    "front_linear-complete-trpo-delta-curriculum-tear3-s0": "front_linear: + tear limit 3 (600k)",
    "../front_linear-complete-trpo-delta-curriculum-tear202-s0": "front_linear: + tear limit 2.02",
    "side_linear-probe-std03-s0": "side_linear: + tear limit, action std 0.3 (probe, 2026-12-02)",
    "front_linear-candidate-std03-promote05-s0": "front_linear: std 0.3, 50% promotes (2026-12-02)",
    "side_linear-candidate-std03-promote05-s0": "side_linear: std 0.3, 50% promotes (2026-12-02)",
    "side_linear-share08-s0": "side_linear: default recipe, 80% near starts (2026-12-03)",
    "../front_linear-fine-gown-s0": "front_linear: the fine-gown recipe from scratch (2026-12-03)",
    "../side_linear-fine-gown-s0": "side_linear: the fine-gown recipe from scratch (2026-12-04)",
}
MARKS = (50_000, 100_000, 200_000, 300_000, 500_000, 750_000, 1_000_000)


def main() -> None:
    curves = {
        label: pd.read_csv(path)
        for stem, label in RUNS.items()
        if (path := FOLDER / f"{stem}-progress.csv").exists()
    }
    figure = Figure(figsize=(9, 4.5), layout="constrained")
    axes = figure.subplots()
    for label, table in curves.items():
        axes.plot(table[STEPS], table[PROGRESS], label=label)
    axes.set(xlabel="environment steps", ylabel="final arm progress (m), recent episodes",
             title="Which recipe gets the arm in")  # fmt: skip
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8)
    figure.savefig(FOLDER / "recipe.png", dpi=120)
    rows = []
    for label, table in curves.items():
        row = {"run": label, "steps": int(table[STEPS].max())}
        for mark in MARKS:
            near = table[(table[STEPS] > mark - 12_500) & (table[STEPS] <= mark + 12_500)]
            row[f"{mark // 1000}k"] = f"{near[PROGRESS].mean():.3f}" if len(near) else ""
        rows.append(row)
    table = pd.DataFrame(rows).fillna("")
    print("| " + " | ".join(table.columns) + " |")
    print("|" + "---|" * len(table.columns))
    for values in table.itertuples(index=False):
        print("| " + " | ".join(str(v) for v in values) + " |")


if __name__ == "__main__":
    main()
