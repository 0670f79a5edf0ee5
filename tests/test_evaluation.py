"""Evaluation: seeded, parallel, resumable rollouts; statistics; result files written atomically."""

import json
import os
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import dressbench
from dressbench import files as atomic
from dressbench.cli import main
from dressbench.evaluation import (
    SUCCESS_DEPTH,
    Runner,
    bootstrap_ci,
    episode_seed,
    evaluate,
    leaderboard,
    leaderboard_cells,
    make_cell,
    run_episode,
    success_definition,
)
from dressbench.evaluation import workers as worker_module
from dressbench.evaluation.readme import results_readme
from dressbench.evaluation.report import stage_definitions
from dressbench.evaluation.rollouts import STAGE_DEPTHS
from dressbench.evaluation.schema import CURVE_COLUMNS, EPISODE_COLUMNS, LEADERBOARD_COLUMNS
from dressbench.evaluation.statistics import wilson_ci
from dressbench.plugins import Plugin
from dressbench.plugins import registry as plugin_registry

TINY = {"horizon": 10, "gown_vertices": 600, "progress": False}  # fast tests
SUMMARY_FILES = ["episodes.csv", "curves.csv", "leaderboard.csv", "leaderboard.md"]
ROBOTS = ["fixed", "front_linear", "side_linear"]
BASELINES = ["passive", "random", "reach", "scripted"]
INTS = ["horizon", "gown_vertices", "seed", "episode", "episode_seed", "steps"]
FLOATS = ["final_arm_progress", "max_deformation", "return"]


def _files(folder: Path) -> dict[str, bytes]:
    """The summary files' contents, to compare two results folders."""
    return {name: (folder / name).read_bytes() for name in SUMMARY_FILES}


def test_end_to_end_in_a_worker_pool_writes_every_file_with_its_schema(tmp_path):
    table = evaluate("fixed", "passive", episodes=3, workers=2, out=tmp_path, **TINY)

    episodes = pd.read_csv(tmp_path / "episodes.csv")
    assert list(episodes.columns) == EPISODE_COLUMNS and len(episodes) == 3
    assert list(episodes["episode"]) == [0, 1, 2]
    assert all(pd.api.types.is_integer_dtype(episodes[c]) for c in INTS)
    assert all(pd.api.types.is_float_dtype(episodes[c]) for c in FLOATS)
    booleans = ("hand_in", "success", "dressed", "sim_failure")
    assert all(pd.api.types.is_bool_dtype(episodes[c]) for c in booleans)
    assert all(pd.api.types.is_string_dtype(episodes[c]) for c in ("robot", "human", "config_id"))
    assert (episodes["horizon"] == 10).all() and (episodes["gown_vertices"] == 600).all()
    assert (episodes["steps"] == 10).all() and (episodes["max_deformation"] >= 1.0).all()
    pd.testing.assert_frame_equal(table, episodes, check_dtype=False)

    board = pd.read_csv(tmp_path / "leaderboard.csv")
    assert list(board.columns) == LEADERBOARD_COLUMNS and len(board) == 1
    assert board.loc[0, "episodes"] == 3 and board.loc[0, "human"] == "passive"
    for metric in ("final_arm_progress", "max_deformation"):
        low, mean, high = board.loc[0, [f"{metric}_{s}" for s in ("ci_low", "mean", "ci_high")]]
        assert low <= mean <= high

    curves = pd.read_csv(tmp_path / "curves.csv")
    assert list(curves.columns) == CURVE_COLUMNS and list(curves["step"]) == list(range(1, 11))

    for stage in ("hand_in", "success", "dressed"):  # 0 of 3: Wilson, not the bootstrap's [0, 0]
        assert board.loc[0, [f"{stage}_rate", f"{stage}_ci_low"]].tolist() == [0.0, 0.0]
        assert board.loc[0, f"{stage}_ci_high"] == pytest.approx(wilson_ci(0, 3)[1])
    markdown = (tmp_path / "leaderboard.md").read_text()
    assert all(text in markdown for text in stage_definitions().values())
    meta = json.loads((tmp_path / "run_meta.json").read_text())
    assert meta["versions"]["numpy"] == np.__version__ and "git_commit" in meta
    assert meta["options"] == {"horizon": 10, "gown_vertices": 600}
    assert meta["success_depth"] == SUCCESS_DEPTH
    for png in ("curves_fixed.png", "final_scores.png"):
        assert (tmp_path / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    # the pool's workers ran the episodes in some order; one process gives the same numbers
    serial = evaluate("fixed", "passive", episodes=3, workers=1, out=tmp_path / "serial", **TINY)
    pd.testing.assert_frame_equal(table, serial)


def test_same_seed_same_numbers_other_seed_other_numbers(tmp_path):
    run = {"robot": "fixed", "human": "random", "episodes": 2, "workers": 1, **TINY}
    first = evaluate(seed=3, out=tmp_path / "a", **run)
    again = evaluate(seed=3, out=tmp_path / "b", **run)
    other = evaluate(seed=4, out=tmp_path / "c", **run)
    assert (tmp_path / "a" / "episodes.csv").read_bytes() == (
        tmp_path / "b" / "episodes.csv"
    ).read_bytes()
    pd.testing.assert_frame_equal(first, again)
    assert list(first["episode_seed"]) == [episode_seed(3, 0), episode_seed(3, 1)]
    assert not np.isin(other["episode_seed"], first["episode_seed"]).any()
    assert not np.allclose(other["return"], first["return"])


def test_episode_seeds_are_the_seed_sequence_children():
    children = np.random.SeedSequence(7).spawn(5)
    assert [episode_seed(7, i) for i in range(5)] == [
        int(child.generate_state(1)[0]) for child in children
    ]


def test_an_interrupted_evaluation_resumes_where_it_stopped(tmp_path, monkeypatch):
    run = {"robot": "fixed", "human": "random", "episodes": 4, "seed": 1, "workers": 1, **TINY}
    evaluate(out=tmp_path / "whole", **run)

    calls = []
    real = worker_module.run_task

    def interrupted(task):
        if len(calls) == 2:
            raise KeyboardInterrupt  # Ctrl-C during the third episode
        calls.append(task.episode)
        return real(task)

    monkeypatch.setattr(worker_module, "run_task", interrupted)
    with pytest.raises(KeyboardInterrupt):
        evaluate(out=tmp_path / "resumed", **run)
    kept = pd.read_csv(tmp_path / "resumed" / "episodes.csv")
    assert list(kept["episode"]) == [0, 1]

    calls.clear()
    monkeypatch.setattr(worker_module, "run_task", lambda task: calls.append(task) or real(task))
    evaluate(out=tmp_path / "resumed", **run)
    assert sorted(task.episode for task in calls) == [2, 3]
    assert _files(tmp_path / "resumed") == _files(tmp_path / "whole")

    calls.clear()
    evaluate(out=tmp_path / "resumed", **run)  # all done: nothing runs
    assert calls == []


def test_every_result_file_is_written_by_replacing_a_temp_file(tmp_path, monkeypatch):
    replaced = []
    real_replace = os.replace

    def spy(source, target):
        replaced.append(Path(target))
        real_replace(source, target)

    monkeypatch.setattr(os, "replace", spy)
    evaluate("fixed", "passive", episodes=2, workers=1, out=tmp_path, **TINY)
    written = {path for path in tmp_path.rglob("*") if path.is_file()}
    assert written and written <= set(replaced)
    assert not [path for path in written if path.name.endswith(".tmp")]


@pytest.mark.parametrize("crash_in", ["fsync", "replace"])
def test_a_crash_mid_write_leaves_the_previous_file_and_no_temp(tmp_path, monkeypatch, crash_in):
    target = tmp_path / "leaderboard.md"
    atomic.write_text(target, "old\n")

    def crash(*args):
        raise OSError("disk gone")

    monkeypatch.setattr(os, crash_in, crash)
    with pytest.raises(OSError, match="disk gone"):
        atomic.write_text(target, "new and longer\n" * 1000)
    assert target.read_text() == "old\n"
    assert [path.name for path in tmp_path.iterdir()] == ["leaderboard.md"]


def test_bootstrap_ci_is_seeded_and_brackets_the_mean():
    values = np.random.default_rng(0).normal(1.0, 0.5, 50)
    low, high = bootstrap_ci(values, seed=5)
    assert (low, high) == bootstrap_ci(values, seed=5)
    assert (low, high) != bootstrap_ci(values, seed=6)
    assert low < values.mean() < high
    assert high - low == pytest.approx(2 * 1.96 * values.std() / np.sqrt(50), rel=0.2)


def test_a_rate_carries_a_wilson_interval_that_never_claims_certainty():
    assert wilson_ci(0, 100) == pytest.approx((0.0, 0.037), abs=5e-4)
    assert wilson_ci(100, 100) == pytest.approx((0.963, 1.0), abs=5e-4)
    low, high = wilson_ci(50, 100)
    assert low < 0.5 < high and high - 0.5 == pytest.approx(0.5 - low)
    assert all(np.isnan(wilson_ci(0, 0)))


def test_the_stages_of_dressing_are_the_hand_the_elbow_and_half_the_upper_arm():
    assert STAGE_DEPTHS == {
        "hand_in": pytest.approx(0.18),
        "past_elbow": pytest.approx(0.44),
        "dressed": pytest.approx(0.44 + 0.15),
    }
    assert SUCCESS_DEPTH == STAGE_DEPTHS["past_elbow"]
    record = run_episode("fixed", "passive", seed=0, horizon=5, gown_vertices=600)
    deep = replace(record, final_arm_progress=0.5)
    assert deep.reached("hand_in") and deep.success and not deep.reached("dressed")
    assert not replace(deep, sim_failure=True).reached("hand_in")


def test_bootstrap_ci_of_constant_data_is_the_value():
    assert bootstrap_ci([0.1] * 30) == (0.1, 0.1)
    assert bootstrap_ci([2.5]) == (2.5, 2.5)
    assert all(np.isnan(bootstrap_ci([])))


def test_success_is_past_the_elbow_without_a_sim_failure():
    record = run_episode("fixed", "passive", seed=0, horizon=5, gown_vertices=600)
    assert record.arm_progress.shape == record.max_deformation_curve.shape == (5,)
    assert record.success is (record.final_arm_progress >= SUCCESS_DEPTH)
    assert SUCCESS_DEPTH == pytest.approx(0.18 + 0.26)
    assert "0.44 m" in success_definition() and "0.30 m" in success_definition(0.3)


class _FailingEnv:
    """A human env whose simulation fails at the third step (its info then says progress 0)."""

    def reset(self, seed=None):
        self.t = 0
        return np.zeros(3), {"arm_progress": 0.0, "max_deformation": 1.0}

    def step(self, action):
        self.t += 1
        failed = self.t == 3
        progress = 0.0 if failed else 0.4 + 0.1 * self.t
        info = {"arm_progress": progress, "max_deformation": 1.0 + self.t, "sim_failure": failed}
        return np.zeros(3), -1.0, failed, False, info


def test_a_sim_failure_ends_the_episode_and_pads_the_curves(monkeypatch):
    monkeypatch.setattr(
        dressbench.factory, "make_human_env", lambda robot, **options: _FailingEnv()
    )
    record = Runner(make_cell("fixed", "passive", horizon=6)).run(seed=0)
    assert record.sim_failure and record.steps == 3 and record.episode_return == -3.0
    np.testing.assert_allclose(record.arm_progress, [0.5, 0.6, 0.6, 0.6, 0.6, 0.6])
    np.testing.assert_allclose(record.max_deformation_curve, [2, 3, 3, 3, 3, 3])
    assert record.final_arm_progress == pytest.approx(0.6) and record.max_deformation == 3.0
    assert not record.success  # deep enough, but the simulation failed


def test_the_ablation_is_the_humans(tmp_path):
    with pytest.raises(ValueError, match="declares ablation 'complete'"):
        evaluate("fixed", "passive", episodes=1, out=tmp_path, ablation="no_task", **TINY)
    with pytest.raises(TypeError, match="unknown option"):
        evaluate("fixed", "passive", episodes=1, out=tmp_path, colour="red", **TINY)


class _Trained:
    """A stand-in for a trained human plugin."""

    api_version = 1
    ablation = "no_task"

    def __init__(self, robot):
        self.robot = robot

    def reset(self, seed=None):
        pass

    def act(self, observation):
        return np.zeros(11)


def test_leaderboard_pairs_each_robot_with_its_trained_and_the_generic_humans(monkeypatch):
    def fake(name, group, robot=None, error=None):
        factory = None if error else (lambda: _Trained(robot))
        status = "error" if error else "ok"
        return Plugin(name, group, "mine", "1", "m:C", status, error, factory)

    real_robots, real_humans = plugin_registry.robot_plugins(), plugin_registry.human_plugins()
    robots = {name: real_robots[name] for name in ROBOTS}
    robots["broken_arm"] = fake("broken_arm", "dressbench.robots", error="ImportError: no")
    humans = {name: real_humans[name] for name in BASELINES}
    humans["for_fixed"] = fake("for_fixed", "dressbench.humans", robot="fixed")
    humans["for_side"] = fake("for_side", "dressbench.humans", robot="side_linear")
    monkeypatch.setattr("dressbench.evaluation.cells.robot_plugins", lambda: robots)
    monkeypatch.setattr("dressbench.evaluation.cells.human_plugins", lambda: humans)

    with pytest.warns(UserWarning, match="broken robot plugin 'broken_arm' from mine 1"):
        cells = leaderboard_cells(horizon=10, gown_vertices=600)
    pairs = {(cell.robot, cell.human) for cell in cells}
    trained = {("fixed", "for_fixed"), ("side_linear", "for_side")}
    assert pairs == {(robot, human) for robot in ROBOTS for human in BASELINES} | trained
    assert {c.ablation for c in cells if c.human == "for_fixed"} == {"no_task"}
    only = leaderboard_cells(robots=["fixed"], humans=["for_side", "passive"], horizon=10)
    assert [(c.robot, c.human) for c in only] == [("fixed", "passive")]


def test_leaderboard_writes_one_row_per_cell(tmp_path):
    board = leaderboard(
        episodes=2, workers=1, out=tmp_path, robots=["fixed"], humans=["passive", "random"], **TINY
    )
    assert list(board[["robot", "human"]].itertuples(index=False, name=None)) == [
        ("fixed", "passive"),
        ("fixed", "random"),
    ]
    assert len(pd.read_csv(tmp_path / "episodes.csv")) == 4
    assert len(pd.read_csv(tmp_path / "curves.csv")) == 2 * 10
    board_text = (tmp_path / "leaderboard.md").read_text()
    assert "| fixed | random | complete | typical | 2 |" in board_text
    assert (tmp_path / "curves_fixed.png").stat().st_size > 0


def test_the_readme_of_a_results_folder_says_how_to_remake_it_and_lists_what_is_there(tmp_path):
    leaderboard(episodes=2, workers=1, out=tmp_path, robots=["fixed"], humans=["passive"], **TINY)
    readme = (tmp_path / "README.md").read_text()
    listed = re.findall(r"^\* (.+?): ", readme, flags=re.MULTILINE)
    named = [name.strip("`") for entry in listed for name in entry.split(", ")]
    assert sorted(named) == sorted(p.name for p in tmp_path.iterdir() if p.name != "README.md")
    meta = json.loads((tmp_path / "run_meta.json").read_text())
    assert meta["git_commit"] is None or meta["git_commit"] in readme

    command = re.search(r"`(dressbench evaluate leaderboard .+?)`", readme).group(1)
    before = (tmp_path / "leaderboard.csv").read_bytes()
    result = CliRunner().invoke(main, [*command.split()[1:], "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "leaderboard.csv").read_bytes() == before  # the same table, from the cache
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 0


def test_the_readme_lists_an_unfinished_training_run_with_how_to_continue_it(tmp_path):
    run = tmp_path / "training" / "runs" / "fixed-no_task-trpo-s0"
    run.mkdir(parents=True)
    config = {"robot": "fixed", "ablation": "no_task", "timesteps": 1_000_000}
    (run / "run.json").write_text(json.dumps({"config": config, "versions": {}}))
    (run / "checkpoint.json").write_text(json.dumps({"timesteps": 178_631, "seed": 0}))
    seeded = tmp_path / "training" / "runs" / "fixed-complete-trpo-s2"
    seeded.mkdir()
    config = {"robot": "fixed", "ablation": "complete", "timesteps": 761_802, "seed": 2,
              "recipe": "default", "warmup": None, "tear": {"ratio": 2.02},
              "action_std": 0.4}  # fmt: skip
    (seeded / "run.json").write_text(json.dumps({"config": config, "versions": {}}))
    (seeded / "checkpoint.json").write_text(json.dumps({"timesteps": 326_284, "seed": 2}))
    readme = results_readme(tmp_path)
    assert (
        "* `training/runs/fixed-no_task-trpo-s0/`: 178,631 of 1,000,000 steps, `dressbench "
        "train --robot fixed --ablation no_task --seed 0 --timesteps 1000000 --no-tear-limit "
        "--name fixed-no_task-trpo-s0`"
    ) in readme  # a run from before the tear limit is continued without one
    assert (
        "* `training/runs/fixed-complete-trpo-s2/`: 326,284 of 761,802 steps, `dressbench train "
        "--robot fixed --ablation complete --seed 2 --timesteps 761802 --no-warmup --action-std "
        "0.4 --tear-limit 2.02 --name fixed-complete-trpo-s2`"
    ) in readme


def test_a_finished_cell_is_archived_and_reused_on_a_machine_without_the_rollout_cache(tmp_path):
    first = evaluate("fixed", "random", episodes=3, workers=1, out=tmp_path / "a", **TINY)
    archives = list((tmp_path / "a" / "cells").glob("fixed__random-*-seed0.npz"))
    assert len(archives) == 1
    (tmp_path / "b" / "cells").mkdir(parents=True)  # only the committed archive travels
    archives[0].rename(tmp_path / "b" / "cells" / archives[0].name)

    again = evaluate("fixed", "random", episodes=3, workers=1, out=tmp_path / "b", **TINY)
    assert json.loads((tmp_path / "b" / "run_meta.json").read_text())["episodes_run"] == 0
    pd.testing.assert_frame_equal(first, again)
    assert _files(tmp_path / "a") == _files(tmp_path / "b")  # curves too: exact to the bit

    fewer = evaluate("fixed", "random", episodes=2, workers=1, out=tmp_path / "b", **TINY)
    pd.testing.assert_frame_equal(fewer, first.head(2))
    evaluate("fixed", "random", episodes=4, workers=1, out=tmp_path / "b", **TINY)
    assert json.loads((tmp_path / "b" / "run_meta.json").read_text())["episodes_run"] == 1


def test_an_unreadable_archive_is_ignored_with_a_notice_and_its_episodes_run(tmp_path, capsys):
    evaluate("fixed", "passive", episodes=2, workers=1, out=tmp_path, **TINY)
    (archive,) = (tmp_path / "cells").iterdir()
    archive.write_bytes(b"not an archive")
    for record in (tmp_path / "rollouts").rglob("*.json"):
        record.unlink()
    evaluate("fixed", "passive", episodes=2, workers=1, out=tmp_path, **TINY)
    assert f"ignored {archive}: unreadable" in capsys.readouterr().err
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 2
    assert archive.read_bytes()[:2] == b"PK"  # written anew, as a zip of arrays
