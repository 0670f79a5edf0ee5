"""A results folder's README.md, written from what the folder holds: how its tables were made
(the command, rebuilt from run_meta.json, and the commit), what each file is, and the learning
summaries and other evaluations below it. Nothing in it is typed by hand, so it cannot drift
from the files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..files import read_json, write_text
from ..plugins.protocols import TYPICAL_PROFILE

README = "README.md"
MARKER = ".dressbench-results"  # marks a folder as dressbench's results folder (ownership.py)
_META = "an evaluation's run_meta.json"
_WRITTEN = ("Written by dressbench from the files in this folder (`dressbench.evaluation.readme`) "
            "each time an evaluation writes to it.")  # fmt: skip

# what each file an evaluation writes is; a name with {robot} is one file per robot strategy
FILES = {
    "leaderboard.md": "the leaderboard table, with every number defined in its caption",
    "leaderboard.csv": "the same table, every column (means, std, 95% intervals, stage rates)",
    "strategies.md": "the strategy table: each robot strategy over the humans trained for it "
    "(seeds, then rollouts), 95% two-level bootstrap intervals, ranks",
    "strategies.csv": "the same table, every column (the seeds' std among them)",
    "improvement.md": "P[a rollout of one strategy goes deeper than one of another], per pair",
    "improvement.csv": "the same, every column",
    "strategies.png": "each strategy's scores with their intervals, and each seed's mean",
    "profiles.png": "each strategy under each capability profile, with intervals (written "
    "where the strategy table holds more than one profile)",
    "members.md": "the episodes against the family, split by the member each faced: its kind "
    "and the direction of its start (written where a family strategy was scored)",
    "members.csv": "the same, every column",
    "finetuned.md": "each fine-tuned human against the human it started from, rollout by "
    "rollout: the paired change in each score with its interval (written where both were "
    "scored on the same rollouts)",
    "finetuned.csv": "the same, every column",
    "episodes.csv": "one row per rollout: its seed, final arm progress, max deformation, stages",
    "curves.csv": "mean and std of arm progress and deformation at every policy step, per cell",
    "run_meta.json": "how the tables were made: seeds, settings, plugin versions, commit",
    "final_scores.png": "bars of final arm progress and max deformation per cell",
    "curves_{robot}.png": "arm progress and max deformation over the episode, one robot strategy",
    "roles.csv": "the paper's comparison: each of its policies (robot, ablation) over the humans "
    "that play it, with intervals over their seeds (`dressbench evaluate reproduce`)",
    "roles.md": "the same, as a table",
    "claims.csv": "each of the paper's claims, with its verdict and the numbers it rests on",
    "claims.md": "the same, as a table",
    "cross_play.csv": "each trained human on every strategy, the one it was trained for or not",
    "cross_play.png": "the cross-play as a picture",
    "fig5_fixed_ablations.png": "the paper's figure 5 redrawn: fixed, the ablations",
    "fig6_final_scores.png": "the paper's figure 6 redrawn: final scores per policy",
    "fig7_linear_strategies.png": "the paper's figure 7 redrawn: the linear strategies",
    "report": "a web page of the leaderboard with one rollout video per cell (`dressbench report`)",
    "cells": "one compact archive per finished cell (its identity, every episode's curves and "
    "scores): committed, so an evaluation on another machine reuses the cells instead of "
    "running them again",
    "rollouts": "the resume cache, one record per rollout (not committed: `.gitignore`)",
    MARKER: "marks the folder as dressbench's: an evaluation replaces its files only in a folder "
    "so marked, or in one that holds none of them",
}


def results_readme(folder: str | Path) -> str:
    """The README of ``folder`` (a results folder with a ``run_meta.json``, or a folder of
    learning summaries and results folders)."""
    folder = Path(folder)
    lines = [f"# {folder.name}", "", _WRITTEN, ""]
    meta_path = folder / "run_meta.json"
    if meta_path.exists():
        lines += _evaluation(read_json(meta_path, _META), folder)
    summaries = sorted(folder.rglob("*-run.json"))
    if summaries:
        lines += ["## Learning summaries", "",
                  "Each training run's `NAME-progress.csv` (every logged update), "
                  "`NAME-learning.png` and `NAME-run.json` (its configuration and versions):", "",
                  "| run | robot | ablation | algorithm | recipe | steps | hours | dressbench |",
                  "|---|---|---|---|---|---:|---:|---|"]  # fmt: skip
        lines += [_summary_row(path, folder) for path in summaries]
        lines.append("")
    unfinished = sorted(p.parent for p in folder.rglob("checkpoint.json"))
    if unfinished:
        lines += ["## Unfinished training runs", "",
                  "Checkpoints to continue on any machine: copy the folder into `runs/` and run "
                  "`dressbench train` with the options its `run.json` records (for the default "
                  "recipe, the command below). A part the command line cannot state (a "
                  "curriculum's share, say) is resumed exactly as recorded from Python: "
                  "`train(TrainConfig.from_dict(json.loads(Path('runs/NAME/run.json')"
                  ".read_text())['config']))` (`from dressbench.training import TrainConfig, "
                  "train`).", ""]  # fmt: skip
        lines += [_checkpoint_line(run, folder) for run in unfinished]
        lines.append("")
    nested = sorted(p.parent for p in folder.glob("*/**/run_meta.json"))
    if nested:
        lines += ["## Other evaluations below this folder", ""]
        for sub in nested:
            meta = read_json(sub / "run_meta.json", _META)
            lines.append(f"* `{sub.relative_to(folder).as_posix()}/`: {_cells(meta)}, "
                         f"`{command_line(meta)}` at {_commit(meta)}")  # fmt: skip
        lines.append("")
    return "\n".join(lines)


def write_results_readme(folder: str | Path) -> Path:
    """Write ``folder/README.md`` from its contents; returns its path."""
    path = Path(folder) / README
    write_text(path, results_readme(folder))
    return path


def command_line(meta: dict[str, Any]) -> str:
    """The ``dressbench evaluate`` command that makes (or, from its cache, re-makes) the tables
    of ``meta``: the same cells, episodes, seed and env settings."""
    cells = meta["cells"]
    words = ["dressbench", "evaluate"]
    if meta["command"] in ("leaderboard", "reproduce"):
        words.append(meta["command"])
    words += ["--episodes", str(meta["episodes_per_cell"]), "--seed", str(meta["seed"])]
    for option, value in meta.get("options", {}).items():
        for one in value if isinstance(value, (list, tuple)) else [value]:  # repeatable: each
            words += [f"--{option.replace('_', '-')}", str(one)]
    for role in ("robot", "human") if meta["command"] != "reproduce" else ("human",):
        for name in dict.fromkeys(cell[role] for cell in cells):
            words += [f"--{role}", name]
    return " ".join(words)


def _evaluation(meta: dict[str, Any], folder: Path) -> list[str]:
    versions = meta.get("versions", {})
    lines = [
        "## How the tables were made", "",
        f"`{command_line(meta)}`", "",
        f"at {_commit(meta)}, dressbench {versions.get('dressbench', '?')}: {_cells(meta)} "
        f"(base seed {meta['seed']}; finished cells in `cells/` and rollouts in `rollouts/` "
        f"are reused, so this run simulated {meta['episodes_run']} of them in "
        f"{meta['elapsed_seconds'] / 60:.0f} min on {meta['workers']} {meta['backend']} "
        f"workers, started {meta['started']}).", "",
        "| robot | human | ablation | profile | the human is |", "|---|---|---|---|---|",
    ]  # fmt: skip
    for cell, plugin in zip(meta["cells"], meta["plugins"], strict=True):
        profile = cell.get("profile", TYPICAL_PROFILE)  # a table made before profiles: typical
        lines.append(f"| {cell['robot']} | {cell['human']} | {cell['ablation']} | {profile} "
                     f"| {_source(plugin['human'])} |")  # fmt: skip
    lines += ["", "## Files", ""]
    robots = list(dict.fromkeys(cell["robot"] for cell in meta["cells"]))
    for name, what in FILES.items():
        names = [name.format(robot=robot) for robot in robots] if "{robot}" in name else [name]
        present = [n for n in names if (folder / n).exists()]
        if present:
            lines.append(f"* {', '.join(f'`{n}`' for n in present)}: {what}")
    return lines + [""]


def _source(human: dict[str, Any]) -> str:
    if human.get("source") == "policy file":
        return f"a trained policy file, sha256 {human['checksum'][:12]}…"
    return f"a plugin of {human.get('distribution', '?')} {human.get('version', '?')}"


def _cells(meta: dict[str, Any]) -> str:
    return f"{len(meta['cells'])} cells × {meta['episodes_per_cell']} seeded rollouts"


def _commit(meta: dict[str, Any]) -> str:
    return f"commit {meta['git_commit']}" if meta.get("git_commit") else "an unknown commit"


def _summary_row(path: Path, folder: Path) -> str:
    run = read_json(path, "a run's record")
    config, result = run["config"], run.get("result", {})
    hours = f"{result['training_seconds'] / 3600:.1f}" if "training_seconds" in result else "?"
    name = path.relative_to(folder).as_posix().removesuffix("-run.json")
    steps = f"{result['steps']:,}" if "steps" in result else "?"
    return (f"| `{name}` | {config['robot']} | {config['ablation']} | {config['algo']} "
            f"| {config.get('recipe', '?')} | {steps} | {hours} "
            f"| {run['versions'].get('dressbench', '?')} |")  # fmt: skip


def _checkpoint_line(run: Path, folder: Path) -> str:
    config = read_json(run / "run.json", "a run's record")["config"]
    steps = read_json(run / "checkpoint.json", "a checkpoint's marker")["timesteps"]
    return (f"* `{run.relative_to(folder).as_posix()}/`: {steps:,} of {config['timesteps']:,} "
            f"steps, `{_continue_command(config, run.name)}`")  # fmt: skip


def _continue_command(config: dict[str, Any], name: str) -> str:
    """The train command that resumes a run as it was configured. Options left out continue as
    run.json records them, but a record older than a setting (a run from before the tear limit)
    would continue with today's default for it, so each setting that shaped the run is stated."""
    recipe = config.get("recipe", "default")
    flags = [f"--robot {config['robot']}", f"--ablation {config['ablation']}"]
    if recipe != "default":
        flags.append(f"--recipe {recipe}")
    if config.get("algo", "trpo") != "trpo":
        flags.append(f"--algo {config['algo']}")
    if config.get("profile", TYPICAL_PROFILE) != TYPICAL_PROFILE:
        flags.append(f"--profile {config['profile']}")
    if config.get("init"):
        flags.append(f"--init {config['init']}")
    flags += [f"--seed {config.get('seed', 0)}", f"--timesteps {config['timesteps']}"]
    if recipe == "default":
        off = [part for part in ("curriculum", "warmup") if part in config and config[part] is None]
        flags += [f"--no-{part}" for part in off]
    if config.get("action_std", 1.0) != 1.0:
        flags.append(f"--action-std {config['action_std']!r}")
    tear = config.get("tear")  # a run from before the tear limit had none
    flags.append(f"--tear-limit {tear['ratio']!r}" if tear else "--no-tear-limit")
    return f"dressbench train {' '.join(flags)} --name {name}"
