"""A run's learning curves: its CSV logs over every session, as a table and a figure.

The figure (return, final arm progress and simulation failures against environment steps) is
what a reader of ``results/training/`` looks at first; the table is what it was drawn from.
"""

from __future__ import annotations

import io
import json
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..files import read_untrusted, write_csv, write_json, write_png

STEPS = "time/total_timesteps"
TIME = "time/time_elapsed"  # wall seconds of the session, as SB3 logs them
PANELS = (  # column of progress.csv, title, axis label
    ("rollout/ep_rew_mean", "episode return", "mean of the last 100 episodes"),
    ("rollout/final_arm_progress", "final arm progress", "m, mean of recent episodes"),
    ("rollout/max_deformation", "max deformation", "area ratio, mean of recent episodes"),
    ("rollout/sim_failure_rate", "simulation failures", "share of recent episodes"),
)
# a second curve drawn in a panel where the run logged it: (panel's column, column, its label)
OVERLAYS = (
    ("rollout/final_arm_progress", "rollout/rest_start_arm_progress", "episodes begun at rest"),
)


def learning_table(run_folder: str | Path, until: int | None = None) -> pd.DataFrame:
    """Every logged update of a run, earlier sessions (``progress-history.csv``) first.

    ``until`` drops updates logged after that many steps (past the checkpoint a model came from).
    """
    logs = Path(run_folder) / "logs"
    parts = [
        pd.read_csv(path)
        for path in (logs / "progress-history.csv", logs / "progress.csv")
        if path.exists() and path.stat().st_size > 0
    ]
    if not parts:
        raise FileNotFoundError(f"{logs}: no progress.csv, has this run trained yet?")
    table = pd.concat(parts, ignore_index=True).sort_values(STEPS, kind="stable")
    return table if until is None else table[table[STEPS] <= until]


def learning_seconds(table: pd.DataFrame) -> np.ndarray:
    """Wall time spent learning at each logged update, summed over sessions (SB3's
    time_elapsed restarts at a resume, so each session adds the last time of the one before)."""
    elapsed = table[TIME].to_numpy(dtype=float)
    restarts = np.flatnonzero(np.diff(elapsed) < 0)
    offsets = np.zeros_like(elapsed)
    for restart in restarts:
        offsets[restart + 1 :] += elapsed[restart]
    return elapsed + offsets


def training_seconds(table: pd.DataFrame) -> float:
    """Wall time spent learning over the whole run."""
    return float(learning_seconds(table)[-1])


def learning_figure(table: pd.DataFrame, title: str) -> Figure:
    """Return, final arm progress, max deformation and failure rate against environment steps."""
    figure, panels = _panels(title)
    for axes, column in panels:
        if _logged(table, column):
            axes.plot(table[STEPS], table[column], label="all episodes")
            for _, extra, label in (o for o in OVERLAYS if o[0] == column):
                if _logged(table, extra):
                    axes.plot(table[STEPS], table[extra], label=label)
                    axes.legend(fontsize=8)
        else:  # a run logged before this column existed
            axes.text(0.5, 0.5, "not logged in this run", ha="center", transform=axes.transAxes)
    return figure


def _logged(table: pd.DataFrame, column: str) -> bool:
    """Whether the run logged ``column`` (a run from before a column existed has none)."""
    return column in table and bool(table[column].notna().any())


def _panels(title: str) -> tuple[Figure, list]:
    """A figure of one titled axes per ``PANELS`` entry, and (axes, column) for each."""
    figure = Figure(figsize=(4.3 * len(PANELS), 3.8), layout="constrained")
    figure.suptitle(title)
    panels = []
    for axes, (column, name, unit) in zip(figure.subplots(1, len(PANELS)), PANELS, strict=True):
        axes.set(title=name, xlabel="environment steps", ylabel=unit)
        axes.grid(alpha=0.3)
        panels.append((axes, column))
    return figure, panels


def write_learning_summary(
    run_folder: str | Path, out: str | Path, until: int | None = None
) -> list[Path]:
    """Write the run's learning summary into ``out``: ``NAME-progress.csv``, ``NAME-learning.png``
    and ``NAME-run.json`` (its configuration and versions, with the steps and learning time
    read off the table if the run did not record them)."""
    run_folder, out = Path(run_folder), Path(out)
    out.mkdir(parents=True, exist_ok=True)
    table = learning_table(run_folder, until)
    run = json.loads((run_folder / "run.json").read_text())
    if "result" not in run:
        steps, seconds = int(table[STEPS].iloc[-1]), training_seconds(table)
        run["result"] = {"steps": steps, "training_seconds": round(seconds, 1),
                         "env_steps_per_second": round(steps / max(seconds, 1e-9), 1)}  # fmt: skip
    run_json = out / f"{run_folder.name}-run.json"
    write_json(run_json, run)
    return [*write_learning_table(table, run_folder.name, out), run_json]


def write_learning_table(table: pd.DataFrame, name: str, out: Path) -> list[Path]:
    """``table`` as ``NAME-progress.csv`` and its figure as ``NAME-learning.png`` in ``out``."""
    csv_path = out / f"{name}-progress.csv"
    png_path = out / f"{name}-learning.png"
    write_csv(csv_path, table)
    write_png(png_path, learning_figure(table, f"training run {name}"))
    return [csv_path, png_path]


def comparison_figure(tables: Mapping[str, pd.DataFrame], title: str) -> Figure:
    """The panels of ``learning_figure`` with one curve per run (``tables``: label -> table), so
    that runs of different recipes or seeds read against one another."""
    figure, panels = _panels(title)
    for axes, column in panels:
        for label, table in tables.items():
            if _logged(table, column):
                axes.plot(table[STEPS], table[column], label=label)
    drawn = [axes for axes, _ in panels if axes.lines]
    if drawn:  # one legend, on the first panel any run logged
        drawn[0].legend(fontsize=8)
    return figure


def write_learning_comparison(
    progress: Mapping[str, str | Path], out: str | Path, title: str
) -> Path:
    """Draw the learning summaries' tables (``progress``: label -> ``NAME-progress.csv``) on
    shared axes into the PNG ``out``."""
    tables = {label: read_learning_summary(path, (STEPS,)) for label, path in progress.items()}
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_png(out, comparison_figure(tables, title))
    return out


# What a recipe is judged by, against learning time: the shares and depth of the episodes begun
# at rest (what an evaluation plays) and the gown's deformation
TIME_PANELS = (
    ("rollout/rest_start_hand_in_rate", "hand in, episodes begun at rest", "share of the last 20"),
    ("rollout/rest_start_past_elbow_rate", "past the elbow, begun at rest", "share of the last 20"),
    ("rollout/rest_start_arm_progress", "final arm progress, begun at rest", "m, last 20 episodes"),
    ("rollout/max_deformation", "max deformation", "area ratio, recent episodes"),
)


def time_figure(tables: Mapping[str, pd.DataFrame], title: str, smooth: int = 5) -> Figure:
    """One curve per run (``tables``: label -> learning table) against hours of learning (minutes
    where every run learned for an hour or less, as a fine-tuning does), the axis a recipe's cost
    is counted on; each curve a rolling mean of ``smooth`` updates. A run
    keeps its colour in every panel; the legend, under the panels, names the panels a run did
    not log (an older run lacks the rates of episodes begun at rest)."""
    figure = Figure(figsize=(4.3 * len(TIME_PANELS), 4.6), layout="constrained")
    figure.suptitle(title)
    colours = {label: f"C{i % 10}" for i, label in enumerate(tables)}
    missing: dict[str, list[str]] = {label: [] for label in tables}
    longest = max((learning_seconds(table).max() for table in tables.values()), default=0.0)
    seconds, time_unit = (60.0, "minutes") if longest <= 3600.0 else (3600.0, "hours")
    for axes, (column, name, unit) in zip(figure.subplots(1, len(TIME_PANELS)), TIME_PANELS,
                                          strict=True):  # fmt: skip
        axes.set(title=name, xlabel=f"{time_unit} of learning", ylabel=unit)
        axes.grid(alpha=0.3)
        for label, table in tables.items():
            if not _logged(table, column):
                missing[label].append(name.split(",")[0])
                continue
            values = table[column].astype(float).rolling(smooth, min_periods=1).mean()
            axes.plot(learning_seconds(table) / seconds, values, color=colours[label], label=label)
    handles = [
        Line2D([], [], color=colours[label],
               label=label + (f" (not logged: {', '.join(missing[label])})" if missing[label]
                              else ""))
        for label in tables
    ]  # fmt: skip
    if handles:
        figure.legend(handles=handles, loc="outside lower center", ncols=min(3, len(handles)),
                      fontsize=8)  # fmt: skip
    return figure


def read_learning_summary(
    path: str | Path, columns: tuple[str, ...] = (STEPS, TIME)
) -> pd.DataFrame:
    """A learning summary's table (``NAME-progress.csv``), read as untrusted input: a regular
    file of bounded size whose ``columns`` (default: steps and learning times) are numbers;
    else one ValueError naming the file."""
    path = Path(path)
    data = read_untrusted(path, "a learning summary file (NAME-progress.csv)")
    try:
        table = pd.read_csv(io.BytesIO(data))
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as error:
        raise ValueError(f"{path}: not a CSV table ({error})") from None
    for column in columns:
        values = pd.to_numeric(table.get(column), errors="coerce") if column in table else None
        if values is None or values.isna().any() or values.empty:
            raise ValueError(f"{path}: no numeric {column} column: is it a NAME-progress.csv?")
    return table


def write_time_comparison(progress: Mapping[str, str | Path], out: str | Path, title: str) -> Path:
    """Draw the learning summaries' tables (``progress``: label -> ``NAME-progress.csv``)
    against learning time (``time_figure``) into the PNG ``out``."""
    tables = {label: read_learning_summary(path) for label, path in progress.items()}
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_png(out, time_figure(tables, title))
    return out
