"""Scoring a robot strategy the same afternoon: fine-tune each generalist seed on it within a time
budget, evaluate every tuned seed, and write the strategy's row of the strategy table and its
cells. ``score`` is what ``dressbench score`` runs; docs/plugins.md walks an author through it."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .checks import EPISODES, check_episodes, check_folder, check_positive
from .config import EnvConfig, check_options, option, option_like
from .plugins.protocols import TYPICAL_PROFILE

if TYPE_CHECKING:
    import pandas as pd

GENERALIST = "generalist"  # the recipe of the generalists' group: humans generalist-sSEED
TUNED = f"{GENERALIST}-tuned"  # a strategy's humans fine-tuned from them: ROBOT-TUNED-sSEED


def _check_minutes(value: float, name: str = "minutes") -> float:
    """0 (no fine-tuning) or a positive, finite number of minutes."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0:
        return 0.0
    return check_positive(value, name, "number of minutes (or 0)")


@dataclass(frozen=True)
class ScoreOptions:
    """What ``dressbench score`` fine-tunes and evaluates (the command's options)."""

    minutes: float = option(30.0, "Minutes of fine-tuning in all, shared among the generalist "
                            "seeds (0: score them as they are).", _check_minutes)  # fmt: skip
    episodes: int = option(EPISODES, "Rollouts per seed.", check_episodes)
    profile: str = option_like(EnvConfig, "profile", EnvConfig.profile,
                               "The capability profile the strategy is scored for: the "
                               "generalists are fine-tuned and evaluated under it.")  # fmt: skip
    out: str = option("results/score", "Folder of the score's files (cells and strategy row).",
                      check_folder)  # fmt: skip
    runs: str = option("runs", "Folder of the fine-tuning runs.", check_folder)
    policies: str = option("policies", "Where the tuned humans go (a folder dressbench finds "
                           "humans in).", check_folder)  # fmt: skip

    def __post_init__(self) -> None:
        """Refuse what the command line refuses, before any fine-tuning (a ValueError)."""
        check_options(self)


def generalists(names: list[str] | None = None) -> dict[str, int]:
    """The installed generalist seeds (``GENERALIST`` group, trained for any strategy) by name,
    with their training seed; ``names`` restricts them (each must be one)."""
    from .evaluation.groups import trained_humans
    from .plugins import human_plugins

    found = {name: human for name, human in trained_humans(
        (name, None, "complete") for name, plugin in human_plugins().items()
        if plugin.ok and plugin.from_policy_file).items()
        if human.robot is None and human.recipe == GENERALIST}  # fmt: skip
    if names:
        if unknown := [name for name in names if name not in found]:
            raise ValueError(f"not a generalist human: {', '.join(unknown)} (have "
                             f"{', '.join(sorted(found)) or 'none'})")  # fmt: skip
        found = {name: found[name] for name in names}
    if not found:
        raise ValueError(f"no generalist human is installed: train one against the family "
                         f"(dressbench train --robot family --name {GENERALIST}-s0; "
                         f"docs/training.md)")  # fmt: skip
    return {name: human.seed for name, human in sorted(found.items())}


def score(
    robot: str,
    options: ScoreOptions | None = None,
    *,
    humans: list[str] | None = None,
    workers: int | None = None,
    seed: int = 0,
    progress: bool = True,
    **env_options: Any,
) -> pd.DataFrame:
    """Fine-tune each generalist seed (``humans``: these; default every installed one) on
    ``robot`` for an equal share of ``options.minutes``, one after another on all cores, then
    evaluate each tuned seed (each generalist as it is, for 0 minutes), all under
    ``options.profile``; return ``robot``'s rows of the strategy table, also written to
    ``options.out``. A fine-tuning run resumes where an
    interrupted one stopped; finished rollouts are reused. ``env_options`` go to the
    evaluation's env (gown_vertices, horizon, ...); fine-tuning plays the same horizon on the
    recipe's training gown. The tuned humans go to ``options.policies``, which must be a folder
    dressbench finds humans in."""
    from .evaluation import leaderboard_results
    from .plugins import robot_plugin
    from .plugins.registry import policy_folders
    from .preflight import profile_problem

    options = options or ScoreOptions()
    robot_plugin(robot)  # an unknown strategy or profile: one line, before anything runs
    if problem := profile_problem(options.profile):
        raise ValueError(f"capability profile {options.profile!r} cannot be scored: {problem}")
    seeds = generalists(humans)
    if options.minutes > 0.0 and Path(options.policies).resolve() not in [
        folder.resolve() for folder in policy_folders()
    ]:
        raise ValueError(f"dressbench does not look for humans in {options.policies} (see "
                         f"DRESSBENCH_POLICIES): the tuned humans could not be scored")  # fmt: skip
    started = time.monotonic()
    scored = list(seeds)
    if options.minutes > 0.0:
        minutes = options.minutes / len(seeds)
        horizon = env_options.get("horizon")
        scored = [_fine_tune(robot, name, seeds[name], minutes, options, progress, horizon)
                  for name in seeds]  # fmt: skip
    table = leaderboard_results(options.episodes, seed, workers, options.out, humans=scored,
                                robots=[robot], progress=progress, profile=options.profile,
                                **env_options).strategies  # fmt: skip
    rows = table[table["robot"] == robot].reset_index(drop=True)
    rows.attrs["seconds"] = time.monotonic() - started
    return rows


def tuned_name(robot: str, seed: int, profile: str = TYPICAL_PROFILE) -> str:
    """The name of ``robot``'s human fine-tuned from the generalist of ``seed`` (for a capability
    profile not typical, its name too)."""
    profiled = "" if profile == TYPICAL_PROFILE else f"-{profile}"
    return f"{robot}-{TUNED}{profiled}-s{seed}"


def _fine_tune(robot: str, parent: str, seed: int, minutes: float, options: ScoreOptions,
               progress: bool, horizon: int | None) -> str:  # fmt: skip
    """Fine-tune ``parent`` on ``robot`` for ``minutes`` of learning; the tuned human's name."""
    from .training import train, train_config

    name = tuned_name(robot, seed, options.profile)
    config = train_config(resume=True, robot=robot, init=parent, seed=seed, hours=minutes / 60.0,
                          name=name, out=options.runs, policies=options.policies,
                          horizon=horizon, profile=options.profile)  # fmt: skip
    train(config, progress=progress)
    return name
