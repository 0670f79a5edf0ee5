"""Learning curves against learning time: what a recipe costs is read in hours, not steps."""

import numpy as np
import pandas as pd
import pytest

from dressbench.training import TrainConfig, train
from dressbench.training.summary import (
    TIME_PANELS,
    learning_seconds,
    learning_table,
    time_figure,
    training_seconds,
    write_time_comparison,
)

STEPS = "time/total_timesteps"


def test_learning_time_adds_each_resumed_session_to_the_ones_before():
    table = pd.DataFrame({STEPS: [1, 2, 3, 4, 5], "time/time_elapsed": [10, 20, 5, 15, 30]})
    assert learning_seconds(table).tolist() == [10, 20, 25, 35, 50]
    assert training_seconds(table) == 50


def test_the_time_figure_draws_every_run_against_hours_and_names_runs_that_did_not_log(tmp_path):
    fast = pd.DataFrame({STEPS: [1, 2, 3], "time/time_elapsed": [900, 1800, 3600],
                         "rollout/rest_start_hand_in_rate": [0.0, 0.5, 0.9],
                         "rollout/rest_start_arm_progress": [0.0, 0.2, 0.4]})  # fmt: skip
    old = pd.DataFrame({STEPS: [1, 2], "time/time_elapsed": [3600, 7200],
                        "rollout/rest_start_arm_progress": [0.1, 0.3]})  # fmt: skip
    figure = time_figure({"coarse gown": fast, "today's default": old}, "fixed", smooth=1)
    panels = {axes.get_title(): axes for axes in figure.axes}
    assert set(panels) == {name for _, name, _ in TIME_PANELS}
    hand_in = panels["hand in, episodes begun at rest"]
    assert [line.get_label() for line in hand_in.lines] == ["coarse gown"]
    assert hand_in.lines[0].get_xdata().tolist() == [0.25, 0.5, 1.0]  # hours, not steps
    assert hand_in.get_xlabel() == "hours of learning"
    progress = panels["final arm progress, begun at rest"]
    assert [line.get_ydata()[-1] for line in progress.lines] == [0.4, 0.3]
    colour = {line.get_label(): line.get_color() for line in progress.lines}
    assert hand_in.lines[0].get_color() == colour["coarse gown"]  # a run's colour in every panel
    (legend,) = figure.legends
    assert [text.get_text() for text in legend.get_texts()] == [
        "coarse gown (not logged: past the elbow, max deformation)",
        "today's default (not logged: hand in, past the elbow, max deformation)",
    ]
    paths = {}
    for label, table in (("a", fast), ("b", old)):
        paths[label] = tmp_path / f"{label}.csv"
        table.to_csv(paths[label], index=False)
    png = write_time_comparison(paths, tmp_path / "levers" / "fixed.png", "fixed")
    assert png.read_bytes().startswith(b"\x89PNG")


def test_runs_of_an_hour_or_less_are_drawn_against_minutes():
    tuned = pd.DataFrame({STEPS: [1, 2, 3], "time/time_elapsed": [120, 300, 600],
                          "rollout/rest_start_hand_in_rate": [0.1, 0.2, 0.3]})  # fmt: skip
    axes = time_figure({"fine-tuned": tuned}, "fixed", smooth=1).axes[0]
    assert axes.get_xlabel() == "minutes of learning"
    assert axes.lines[0].get_xdata().tolist() == [2.0, 5.0, 10.0]


@pytest.mark.filterwarnings("ignore")
def test_training_logs_the_hand_in_and_past_the_elbow_shares_of_episodes_begun_at_rest(tmp_path):
    config = TrainConfig(gown_vertices=600, horizon=32, samples_per_update=128, envs=1,
                         timesteps=512, out=str(tmp_path / "runs"),
                         policies=str(tmp_path / "policies"), name="shares")  # fmt: skip
    train(config, progress=False)
    table = learning_table(tmp_path / "runs" / "shares")
    progress = table["rollout/rest_start_arm_progress"].dropna()
    assert len(progress) > 0
    for stage in ("hand_in", "past_elbow"):
        rates = table[f"rollout/rest_start_{stage}_rate"].dropna().to_numpy()
        assert len(rates) == len(progress) and np.all((0 <= rates) & (rates <= 1))
    # a rate is a share of the same episodes the mean progress is taken over: no rate without
    # progress that deep somewhere among them
    deep = table["rollout/rest_start_hand_in_rate"] > 0
    assert not deep.any() or (table.loc[deep, "rollout/rest_start_arm_progress"] > 0).all()
