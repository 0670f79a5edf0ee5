"""Leaderboards and training sweeps on a Ray cluster (a local instance of 2 CPUs).

The ray backend must write what the local backend writes, bit for bit; a killed worker's episode
runs again, and counts once; a sweep trains its grid and scores it; a plugin missing on a worker,
an unreachable address or a missing Ray is one line.
"""

import importlib.metadata
import json
import logging
import os
import signal
import sys
import threading
import time
from pathlib import Path

import pandas as pd
import pytest
from click.testing import CliRunner
from fakes import HUMAN_MODULE, install

from dressbench import plugins
from dressbench.cli import main
from dressbench.evaluation import evaluate, leaderboard
from dressbench.sweep import Sweep, sweep

TINY = {"horizon": 10, "gown_vertices": 600, "progress": False}
TRAIN_TINY = {"gown_vertices": 600, "horizon": 32, "samples_per_update": 128, "envs": 1}
SUMMARY_FILES = ["episodes.csv", "curves.csv", "leaderboard.csv", "leaderboard.md"]


@pytest.fixture(scope="module")
def cluster():
    """A local Ray instance of 2 CPUs for this module's tests, shut down after them."""
    ray = pytest.importorskip("ray", reason="ray is not installed (pip install 'dressbench[ray]')")
    ray.init(num_cpus=2, include_dashboard=False, logging_level=logging.WARNING)
    yield ray
    ray.shutdown()


@pytest.fixture
def policies_here(tmp_path, monkeypatch):
    """Trained models go to, and are found in, this test's folder only."""
    monkeypatch.setenv("DRESSBENCH_POLICIES", str(tmp_path / "policies"))
    plugins.refresh()
    yield tmp_path / "policies"
    monkeypatch.delenv("DRESSBENCH_POLICIES")
    plugins.refresh()


def _files(folder: Path) -> dict[str, bytes]:
    """The summary files and every rollout record of a results folder."""
    records = sorted(folder.glob("rollouts/*/*.json"))
    return {name: (folder / name).read_bytes() for name in SUMMARY_FILES} | {
        str(path.relative_to(folder)): path.read_bytes() for path in records
    }


def test_a_leaderboard_on_ray_writes_the_local_backends_files_exactly(cluster, tmp_path):
    cells = {"robots": ["fixed", "front_linear"], "humans": ["passive", "random"]}
    leaderboard(episodes=3, workers=1, out=tmp_path / "local", **cells, **TINY)
    board = leaderboard(episodes=3, workers=2, out=tmp_path / "ray", backend="ray", **cells, **TINY)

    assert len(board) == 4
    assert _files(tmp_path / "ray") == _files(tmp_path / "local")
    meta = json.loads((tmp_path / "ray" / "run_meta.json").read_text())
    assert (meta["backend"], meta["address"], meta["episodes_run"]) == ("ray", None, 12)


def test_the_cli_runs_an_evaluation_on_ray_and_a_rerun_reuses_it(cluster, tmp_path):
    command = ["evaluate", "--robot", "fixed", "--human", "passive", "--episodes", "2",
               "--gown-vertices", "600", "--out", str(tmp_path), "--backend", "ray"]  # fmt: skip
    for _ in range(2):
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 0
    assert list(pd.read_csv(tmp_path / "episodes.csv")["episode"]) == [0, 1]


def _error_line(result) -> str:
    """The one error line of a refused command (after the progress bar, if it had started)."""
    assert result.exit_code == 1, result.output
    assert "Traceback" not in result.output, result.output
    errors = [line for line in result.output.splitlines() if line.startswith("Error: ")]
    assert len(errors) == 1, result.output
    return errors[0]


def _rollout_processes() -> list[int]:
    """Ray workers running a rollout now (Ray titles a busy worker ``ray::<task>``)."""
    found = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and (entry / "cmdline").read_bytes().startswith(
                b"ray::rollout"
            ):
                found.append(int(entry.name))
        except OSError:
            continue
    return found


@pytest.mark.skipif(not Path("/proc/self/cmdline").exists(), reason="reads /proc")
def test_killing_a_worker_mid_evaluation_still_runs_every_episode_once(cluster, tmp_path):
    run = {"robot": "fixed", "human": "random", "episodes": 10, "horizon": 40,
           "gown_vertices": 600, "progress": False}  # fmt: skip
    out = tmp_path / "ray"
    killed: list[int] = []

    def kill_a_busy_worker_after_the_first_record() -> None:
        deadline = time.monotonic() + 120
        while not killed and time.monotonic() < deadline:
            busy = _rollout_processes()
            if busy and list(out.glob("rollouts/*/*.json")):
                os.kill(busy[0], signal.SIGKILL)
                killed.append(busy[0])
            time.sleep(0.02)

    killer = threading.Thread(target=kill_a_busy_worker_after_the_first_record, daemon=True)
    killer.start()
    table = evaluate(workers=2, out=out, backend="ray", **run)
    killer.join()

    assert killed, "no worker was caught running a rollout"
    assert list(table["episode"]) == list(range(10))  # each once, none lost
    assert len(list(out.glob("rollouts/*/*.json"))) == 10
    evaluate(workers=1, out=tmp_path / "local", **run)
    assert _files(out) == _files(tmp_path / "local")


def test_a_sweep_on_ray_trains_its_grid_and_scores_it_in_one_leaderboard(
    cluster, tmp_path, policies_here
):
    timesteps = 2048  # 16 updates of 128 samples
    train = TRAIN_TINY | {"timesteps": timesteps, "out": str(tmp_path / "runs"),
                          "policies": str(policies_here)}  # fmt: skip
    grid = {"robot": ["fixed"], "seed": [0, 1]}
    config = Sweep(grid, train | {"gown_vertices": 400}, episodes=2,
                   results=str(tmp_path / "results"), eval_gown_vertices=600)  # fmt: skip
    board = sweep(config, backend="ray", progress=False)

    names = ["fixed-complete-trpo-s0", "fixed-complete-trpo-s1"]
    assert sorted(path.stem for path in policies_here.glob("*.safetensors")) == names
    for name in names:
        run = json.loads((tmp_path / "runs" / name / "run.json").read_text())
        assert run["result"]["steps"] == timesteps and run["config"]["seed"] == int(name[-1])
    assert sorted(board["human"]) == names and set(board["robot"]) == {"fixed"}
    assert (board["episodes"] == 2).all() and (board["horizon"] == 32).all()
    assert (board["gown_vertices"] == 600).all()  # scored on the evaluation's gown, not training's
    assert len(pd.read_csv(tmp_path / "results" / "episodes.csv")) == 4


def test_a_sweeps_grid_is_every_combination_each_named_as_train_names_it(tmp_path):
    grid = {"robot": ["fixed", "front_linear"], "seed": [0, 1], "gamma": [0.99]}
    runs = Sweep(grid, {"timesteps": 64, "out": str(tmp_path)}).runs()
    assert [run.run_name for run in runs] == [
        f"{robot}-complete-trpo-s{seed}-gamma0.99"
        for robot in ("fixed", "front_linear")
        for seed in (0, 1)
    ]
    assert {(run.timesteps, run.envs, run.out) for run in runs} == {(64, 1, str(tmp_path))}
    profiled = Sweep({"robot": ["fixed"], "profile": ["typical", "weak_arm"]}).runs()
    assert [run.run_name for run in profiled] == ["fixed-complete-trpo-s0",
                                                  "fixed-complete-weak_arm-trpo-s0"]  # fmt: skip
    for bad, message in [
        ({"grid": {"colour": ["red"]}}, "not TrainConfig fields: colour"),
        ({"grid": {"seed": []}}, "grid axis seed has no values"),
        ({"grid": {"horizon": [8, 16]}}, "horizon is the leaderboard's env too"),
        ({"train": {"name": "mine"}}, "a sweep names its runs itself"),
    ]:
        with pytest.raises(ValueError, match=message):
            Sweep(**bad)


def test_a_sweep_on_the_local_backend_trains_one_run_after_another_and_resumes(
    tmp_path, policies_here
):
    command = ["sweep", "--robot", "fixed", "--seed", "0", "--seed", "1", "--timesteps", "128",
               "--gown-vertices", "600", "--horizon", "8", "--samples-per-update", "128",
               "--episodes", "1", "--workers", "1", "--out", str(tmp_path / "runs"),
               "--policies", str(policies_here),
               "--results", str(tmp_path / "results")]  # fmt: skip
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 0, result.output
    first = _checkpoints(tmp_path / "runs")
    assert len(first) == 2

    result = CliRunner().invoke(main, command)  # finished runs are not trained again
    assert result.exit_code == 0, result.output
    assert _checkpoints(tmp_path / "runs") == first
    board = pd.read_csv(tmp_path / "results" / "leaderboard.csv")
    assert sorted(board["human"]) == ["fixed-complete-trpo-s0", "fixed-complete-trpo-s1"]


def _checkpoints(runs: Path) -> dict[str, int]:
    """Each run's checkpoint and when it was last written."""
    return {str(path.relative_to(runs)): path.stat().st_mtime_ns for path in runs.glob("*/*.zip")}


def _installed(distribution: str) -> bool:
    try:
        importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return False
    return True


@pytest.mark.skipif(not _installed("dressbench-arc"), reason="plugins/dressbench-arc not installed")
def test_a_third_party_plugin_installed_on_every_node_runs_on_ray_unchanged(cluster, tmp_path):
    run = {"robot": "arc", "human": "follow_task", "episodes": 2, **TINY}
    on_ray = evaluate(workers=2, out=tmp_path / "ray", backend="ray", **run)
    pd.testing.assert_frame_equal(on_ray, evaluate(workers=1, out=tmp_path / "local", **run))


def test_a_plugin_missing_on_a_worker_is_one_line_naming_it_and_the_node(cluster, site, tmp_path):
    install(
        site,
        "ghost",
        "1.0",
        {f"[{plugins.HUMAN_GROUP}]": {"ghost": "ghost_human:Human"}},
        ghost_human=HUMAN_MODULE,
    )  # fmt: skip  (on this process's sys.path only)
    # the cell is flagged, as for any plugin that fails on a node; with no other cell, the run
    # ends in that one line
    with pytest.raises(ValueError, match="human plugin 'ghost' is not installed on Ray node"):
        evaluate("fixed", "ghost", episodes=1, out=tmp_path, backend="ray", **TINY)

    command = ["evaluate", "--robot", "fixed", "--human", "ghost", "--episodes", "1",
               "--gown-vertices", "600", "--out", str(tmp_path), "--backend", "ray"]  # fmt: skip
    error = _error_line(CliRunner().invoke(main, command))
    assert error.startswith("Error: cell 'fixed' x 'ghost' left out: ")
    assert "human plugin 'ghost' is not installed on Ray node " in error


def test_a_bad_backend_or_address_is_one_line_before_anything_runs(tmp_path):
    evaluate_on = ["evaluate", "--robot", "fixed", "--human", "passive", "--out", str(tmp_path)]
    result = CliRunner().invoke(main, [*evaluate_on, "--backend", "spark"])
    assert result.exit_code == 2 and "'spark' is not one of 'local', 'ray'" in result.output

    for backend, address, message in [
        ("spark", None, "backend must be one of local, ray, got 'spark'"),
        ("local", "auto", "an address is for the ray backend, not 'local'"),
        ("ray", "http://head", "address must be auto, HOST:PORT or ray://HOST:PORT"),
    ]:
        with pytest.raises(ValueError, match=message):
            evaluate("fixed", "passive", out=tmp_path, backend=backend, address=address)
        where = ["--backend", backend] + (["--address", address] if address else [])
        result = CliRunner().invoke(
            main, ["evaluate", "leaderboard", "--out", str(tmp_path), *where]
        )
        assert result.exit_code in (1, 2) and "Traceback" not in result.output
    assert list(tmp_path.iterdir()) == []


def test_an_unreachable_cluster_is_one_line_within_seconds(tmp_path, monkeypatch):
    ray = pytest.importorskip("ray", reason="ray is not installed (pip install 'dressbench[ray]')")
    monkeypatch.setattr(ray, "is_initialized", lambda: False)  # as in a fresh process
    command = ["evaluate", "--robot", "fixed", "--human", "passive", "--episodes", "1",
               "--gown-vertices", "600", "--out", str(tmp_path), "--backend", "ray",
               "--address", "127.0.0.1:1"]  # fmt: skip
    started = time.monotonic()
    error = _error_line(CliRunner().invoke(main, command))
    assert time.monotonic() - started < 60
    assert error.startswith("Error: cannot reach a Ray cluster at 127.0.0.1:1: ")


def test_without_ray_the_ray_backend_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray raises ImportError
    command = ["evaluate", "--robot", "fixed", "--human", "passive", "--episodes", "1",
               "--gown-vertices", "600", "--out", str(tmp_path), "--backend", "ray"]  # fmt: skip
    error = _error_line(CliRunner().invoke(main, command))
    assert (
        error == "Error: the ray backend needs Ray: pip install 'dressbench[ray]' (on every node)"
    )
