"""The paper's figures: metric curves over an episode, and the final scores per cell.

Figures are built with ``matplotlib.figure.Figure`` (Agg when saved): no pyplot global state,
no display, safe in worker processes and notebooks alike.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ..plugins.protocols import ROBOT_DT, TYPICAL_PROFILE
from .rollouts import SUCCESS_DEPTH
from .schema import STRATEGY_KEY


def curves_figure(curves: pd.DataFrame, robot: str, success_depth: float = SUCCESS_DEPTH) -> Figure:
    """Mean ± std of arm progress and of max deformation over the steps, one line per human."""
    figure, (progress_axes, deformation_axes) = _curve_panels()
    for human, cell in curves[curves["robot"] == robot].groupby("human", sort=False):
        episodes = int(cell["episodes"].iloc[0])
        _plot_cell((progress_axes, deformation_axes), cell, f"{human} (n={episodes})")
    progress_axes.axhline(success_depth, color="0.4", linestyle="--", linewidth=1, label="success")
    progress_axes.legend(fontsize="small")
    figure.suptitle(f"robot strategy: {robot} (mean ± std over episodes)")
    return figure


def _curve_panels() -> tuple[Figure, tuple[Any, Any]]:
    """A figure with the arm progress and max deformation panels, titled and labelled."""
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    progress_axes, deformation_axes = figure.subplots(1, 2)
    progress_axes.set(title="arm progress", ylabel="depth into the sleeve (m)")
    deformation_axes.set(title="max deformation", ylabel="running max of triangle area ratio")
    for axes in (progress_axes, deformation_axes):
        axes.set_xlabel(f"policy step ({ROBOT_DT} s)")
        axes.grid(alpha=0.3)
    return figure, (progress_axes, deformation_axes)


def _plot_cell(panels: tuple[Any, Any], cell: pd.DataFrame, label: str) -> None:
    """One cell's mean curves, ± std shaded, into the progress and deformation panels."""
    for axes, metric in zip(panels, ("arm_progress", "max_deformation"), strict=True):
        mean, std = cell[f"{metric}_mean"], cell[f"{metric}_std"].fillna(0.0)
        (line,) = axes.plot(cell["step"], mean, label=label)
        axes.fill_between(cell["step"], mean - std, mean + std, color=line.get_color(), alpha=0.2)


def scores_figure(board: pd.DataFrame, success_depth: float = SUCCESS_DEPTH) -> Figure:
    """Bars of final arm progress and max deformation per cell, with std error bars."""
    figure = Figure(figsize=(max(6.0, 1.1 * len(board) + 3.0), 4.8), layout="constrained")
    progress_axes, deformation_axes = figure.subplots(1, 2)
    labels = [
        f"{robot} / {human}" for robot, human in zip(board["robot"], board["human"], strict=True)
    ]
    robots = list(dict.fromkeys(board["robot"]))
    colors = [f"C{robots.index(robot) % 10}" for robot in board["robot"]]
    positions = range(len(board))
    for axes, metric, title in (
        (progress_axes, "final_arm_progress", "final arm progress (m)"),
        (deformation_axes, "max_deformation", "max deformation (area ratio)"),
    ):
        axes.bar(
            positions,
            board[f"{metric}_mean"],
            yerr=board[f"{metric}_std"].fillna(0.0),
            color=colors,
            capsize=4,
        )
        axes.set_xticks(list(positions), labels, fontsize="small", rotation=45, ha="right")
        axes.set_title(title)
        axes.grid(axis="y", alpha=0.3)
    progress_axes.axhline(success_depth, color="0.4", linestyle="--", linewidth=1, label="success")
    progress_axes.legend(fontsize="small")
    figure.suptitle("final scores per leaderboard cell (mean ± std over episodes)")
    return figure


def role_curves_figure(
    curves: pd.DataFrame, lines: list[tuple[str, str]], limit: float, title: str
) -> Figure:
    """The paper's Figs. 5 and 7: arm progress and max deformation over the episode (mean ± std),
    one line per (robot, human), the deformation threshold drawn."""
    figure, (progress_axes, deformation_axes) = _curve_panels()
    for robot, human in lines:
        cell = curves[(curves["robot"] == robot) & (curves["human"] == human)]
        _plot_cell((progress_axes, deformation_axes), cell, f"{human} on {robot}")
    deformation_axes.axhline(limit, color="0.3", linestyle="--", linewidth=1, label="threshold")
    for axes in (progress_axes, deformation_axes):
        axes.legend(fontsize="small")
    figure.suptitle(f"{title} (mean ± std over episodes)")
    return figure


def role_bars_figure(roles: pd.DataFrame, limit: float) -> Figure:
    """The paper's Fig. 6: final arm progress and max deformation of each of its policies, bars
    at the mean over seeds with 95% interval whiskers, the deformation threshold drawn."""
    figure = Figure(figsize=(10, 4.4), layout="constrained")
    measured = roles[roles["episodes"] > 0]
    positions = list(range(len(measured)))
    for axes, metric, title in zip(
        figure.subplots(1, 2),
        ("final_arm_progress", "max_deformation"),
        ("final arm progress (m)", "max deformation (area ratio)"),
        strict=True,
    ):
        mean = measured[f"{metric}_mean"]
        whiskers = [mean - measured[f"{metric}_ci_low"], measured[f"{metric}_ci_high"] - mean]
        axes.bar(positions, mean, yerr=whiskers, capsize=4, color=[f"C{i}" for i in positions])
        axes.set_xticks(positions, measured["role"], fontsize="small", rotation=30, ha="right")
        axes.set_title(title)
        axes.grid(axis="y", alpha=0.3)
        if metric == "max_deformation":
            axes.axhline(limit, color="0.3", linestyle="--", linewidth=1, label="threshold")
            axes.legend(fontsize="small")
    figure.suptitle("the paper's policies: final scores (mean over seeds, two-level 95% CI)")
    return figure


def cross_play_figure(cross: pd.DataFrame) -> Figure:
    """A heat map of each complete human's mean final arm progress on each robot strategy."""
    grid = cross.pivot(index="human", columns="robot", values="final_arm_progress")
    labels = 0.08 * max(len(str(name)) for name in grid.index)  # inches the humans' names take
    figure = Figure(figsize=(2.0 + labels + 1.6 * grid.shape[1], 2.0 + 0.6 * grid.shape[0]),
                    layout="constrained")  # fmt: skip
    axes = figure.subplots()
    image = axes.imshow(grid.to_numpy(), cmap="viridis", vmin=0.0, aspect="auto")
    axes.set_xticks(range(grid.shape[1]), grid.columns, rotation=30, ha="right")
    axes.set_yticks(range(grid.shape[0]), grid.index)
    for (row, column), value in np.ndenumerate(grid.to_numpy()):
        axes.text(column, row, f"{value:.2f}", ha="center", va="center", color="w")
    axes.set(xlabel="robot strategy evaluated with", ylabel="human (trained for its strategy)")
    figure.colorbar(image, ax=axes, label="mean final arm progress (m)")
    figure.suptitle("cross-play: each human on each strategy")
    return figure


def strategies_figure(table: pd.DataFrame, seeds: pd.DataFrame) -> Figure:
    """Each strategy row's final arm progress and max deformation: the mean over seeds with its
    95% interval (two-level bootstrap), and each seed's mean as a dot beside it."""
    figure = Figure(figsize=(max(7.0, 1.4 * len(table) + 4.0), 5.6), layout="constrained")
    labels = [f"{r.robot} ({r.recipe}, {r.ablation}, {r.profile}; "
              f"{r.seeds} seed{'s' * (r.seeds > 1)})" for r in table.itertuples()]  # fmt: skip
    positions = np.arange(len(table))
    rows = seeds.merge(table[STRATEGY_KEY].assign(position=positions), on=STRATEGY_KEY)
    for axes, metric, title in zip(
        figure.subplots(1, 2),
        ("final_arm_progress", "max_deformation"),
        ("final arm progress (m)", "max deformation (area ratio)"),
        strict=True,
    ):
        mean = table[f"{metric}_mean"].to_numpy()
        whiskers = [mean - table[f"{metric}_ci_low"], table[f"{metric}_ci_high"] - mean]
        axes.errorbar(positions, mean, yerr=whiskers, fmt="s", color="C0", capsize=5,
                      label="mean over seeds, 95% CI")  # fmt: skip
        axes.scatter(rows["position"] + 0.18, rows[metric], s=18, color="C1", zorder=3,
                     label="a seed's mean")  # fmt: skip
        axes.set_xticks(positions, labels, fontsize="small", rotation=30, ha="right")
        axes.set_xlim(-0.6, len(table) - 0.4)
        axes.set_title(title)
        axes.grid(axis="y", alpha=0.3)
    axes.legend(fontsize="small")
    figure.suptitle("strategies: scores over the humans trained for them (seeds, then rollouts)")
    return figure


def profiles_figure(table: pd.DataFrame) -> Figure:
    """Each strategy (along x) under each capability profile: one marker per group of humans
    (profile, recipe, ablation) with its mean over seeds and 95% interval, for final arm
    progress and max deformation: which strategy holds up for whom. A colour is a profile and a
    marker a kind of human (filled: the first recipe and ablation, e.g. the typical humans; open:
    the others, e.g. humans adapted to the profile), so each adapted human stands beside the
    typical one in the same body."""
    figure = Figure(figsize=(max(7.0, 2.0 * table["robot"].nunique() + 4.0), 5.6),
                    layout="constrained")  # fmt: skip
    robots = sorted(table["robot"].unique())
    groups = sorted(table.groupby(["profile", "recipe", "ablation"]),
                    key=lambda group: (group[0][0] != TYPICAL_PROFILE, group[0]))  # fmt: skip
    profiles = list(dict.fromkeys(profile for (profile, _, _), _ in groups))
    kinds = list(dict.fromkeys((recipe, ablation) for (_, recipe, ablation), _ in groups))
    width = 0.8 / len(groups)
    for axes, metric, title in zip(
        figure.subplots(1, 2),
        ("final_arm_progress", "max_deformation"),
        ("final arm progress (m)", "max deformation (area ratio)"),
        strict=True,
    ):
        for k, ((profile, recipe, ablation), rows) in enumerate(groups):
            x = np.array([robots.index(r) for r in rows["robot"]]) + (k + 0.5) * width - 0.4
            mean = rows[f"{metric}_mean"].to_numpy()
            whiskers = [mean - rows[f"{metric}_ci_low"], rows[f"{metric}_ci_high"] - mean]
            kind = kinds.index((recipe, ablation))
            color = f"C{profiles.index(profile) % 10}"
            axes.errorbar(x, mean, yerr=whiskers, fmt="osD^v<>"[kind % 7], capsize=4, color=color,
                          markerfacecolor=color if kind == 0 else "white",
                          label=f"{profile} ({recipe}, {ablation})")  # fmt: skip
        axes.set_xticks(np.arange(len(robots)), robots)
        axes.set_xlim(-0.6, len(robots) - 0.4)
        axes.set_title(title)
        axes.grid(axis="y", alpha=0.3)
    figure.legend(*axes.get_legend_handles_labels(), loc="outside lower center", fontsize="small",
                  ncols=min(len(groups), 4), title="profile (recipe, ablation)")  # fmt: skip
    figure.suptitle("strategies under each capability profile: mean over seeds, 95% CI")
    return figure
