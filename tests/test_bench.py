"""`dressbench bench --compare pybullet` and `--train`: the gown exported to OBJ is the
same garment, both rates and their ratio are printed, and a training run leaves nothing behind.
No timing is asserted: these machines' speed varies by 2x."""

import json
import sys
from dataclasses import asdict

import numpy as np
import pytest
from click.testing import CliRunner

from dressbench.bench import BenchOptions, bench_lines, table_header, table_line, timing_row
from dressbench.cli import main
from dressbench.scene.garment import GownConfig, make_gown, write_obj
from dressbench.training import TrainConfig
from dressbench.training.bench import bench_config

TINY = ["-v", "300", "--steps", "5", "--repeats", "1"]


def read_obj(path) -> tuple[np.ndarray, np.ndarray]:
    """The vertices and (0-based) triangles of an OBJ file of ``v`` and ``f`` lines."""
    lines = [line.split() for line in path.read_text().splitlines()]
    vertices = np.array([line[1:] for line in lines if line[0] == "v"], dtype=float)
    faces = np.array([line[1:] for line in lines if line[0] == "f"], dtype=int) - 1
    return vertices, faces


def json_rows(output: str) -> list[dict]:
    return [json.loads(line) for line in output.splitlines() if line.startswith("{")]


def test_the_obj_export_round_trips_the_gowns_vertices_and_triangles(tmp_path):
    gown = make_gown(GownConfig(target_vertices=600))
    path = write_obj(gown, tmp_path / "gown.obj")
    vertices, faces = read_obj(path)
    assert len(vertices) == gown.num_vertices and len(faces) == gown.num_triangles
    np.testing.assert_array_equal(faces, gown.triangles)
    np.testing.assert_allclose(vertices, gown.positions, atol=1e-6)


def test_the_obj_export_writes_the_positions_it_is_given(tmp_path):
    gown = make_gown(GownConfig(target_vertices=300))
    moved = gown.positions + [0.1, -0.2, 0.5]
    vertices, _ = read_obj(write_obj(gown, tmp_path / "held.obj", moved))
    np.testing.assert_allclose(vertices, moved, atol=1e-6)
    with pytest.raises(ValueError, match="positions must have shape"):
        write_obj(gown, tmp_path / "bad.obj", moved[:-1])


def test_compare_pybullet_prints_both_rates_and_their_ratio():
    pytest.importorskip("pybullet")
    result = CliRunner().invoke(main, ["bench", "--compare", "pybullet", *TINY])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert any(line.split()[1:2] == ["pybullet"] for line in lines[1:])
    assert any(line.split()[1:2] == ["env"] for line in lines[1:])
    assert "dressbench / PyBullet, simulated seconds per wall second:" in lines[-1]
    assert lines[-1].endswith("x")


def test_compare_pybullet_in_json_simulates_the_same_gown_for_the_same_time():
    pytest.importorskip("pybullet")
    result = CliRunner().invoke(main, ["bench", "--compare", "pybullet", *TINY, "--json"])
    assert result.exit_code == 0, result.output
    theirs, ours = json_rows(result.output)
    assert (theirs["what"], ours["what"]) == ("pybullet", "env") and theirs["self_collision"]
    assert theirs["vertices"] == ours["vertices"] == make_gown(GownConfig(300)).num_vertices
    assert not theirs["sim_failure"] and not ours["sim_failure"]
    assert theirs["sim_seconds_per_second"] > 0 and ours["sim_seconds_per_second"] > 0
    ratio = ours["sim_seconds_per_second"] / theirs["sim_seconds_per_second"]
    assert ours["times_pybullet"] == pytest.approx(ratio, rel=0.01)
    assert theirs["steps"] * 0.1 == pytest.approx(ours["steps"] * 0.04, abs=0.1)  # 5 x 0.04 s


def test_compare_pybullet_can_turn_pybullets_self_collision_off():
    pytest.importorskip("pybullet")
    args = ["bench", "--compare", "pybullet", "--no-pybullet-self-collision", *TINY, "--json"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    theirs, ours = json_rows(result.output)
    assert theirs["self_collision"] is False and ours["times_pybullet"] > 0


def test_compare_pybullet_without_pybullet_is_one_line_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pybullet", None)  # import pybullet now fails
    result = CliRunner().invoke(main, ["bench", "--compare", "pybullet", *TINY])
    assert result.exit_code != 0
    errors = [line for line in result.output.splitlines() if line.strip()]
    assert len(errors) == 1 and "pip install 'dressbench[compare]'" in errors[0]


def test_the_training_bench_runs_the_default_recipe_updating_at_least_once(tmp_path):
    config = bench_config(300, 1000, 0, 1, tmp_path)
    assert config.samples_per_update == 1000  # shorter than the recipe's batch: one update
    changed = {"timesteps", "gown_vertices", "samples_per_update", "out", "policies", "name"}
    recipe, bench = asdict(TrainConfig.preset("default")), asdict(config)
    assert {key: bench[key] for key in recipe if key not in changed} == {
        key: value for key, value in recipe.items() if key not in changed
    }
    longer = bench_config(300, 10_000, 0, 1, tmp_path)
    assert longer.samples_per_update == recipe["samples_per_update"]
    assert config.out.startswith(str(tmp_path)) and config.policies.startswith(str(tmp_path))


def test_train_reports_env_steps_per_second_and_leaves_no_runs_or_policies(tmp_path, monkeypatch):
    pytest.importorskip("stable_baselines3")
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(
        main, ["bench", "--train", "--train-steps", "128", "--train-envs", "1", *TINY, "--json"]
    )
    assert result.exit_code == 0, result.output
    single, alone, train = json_rows(result.output)
    assert (single["what"], alone["what"], train["what"]) == ("env", "envs", "train")
    assert all(row["steps_per_second"] > 0 for row in (single, alone, train))
    assert alone["envs"] == train["envs"] == 1 and alone["steps"] == 5  # --steps, per env process
    assert train["share_of_envs"] == pytest.approx(
        train["steps_per_second"] / alone["steps_per_second"], abs=0.01
    )
    assert not (tmp_path / "policies").exists() and not (tmp_path / "runs").exists()
    assert list(tmp_path.iterdir()) == []


def test_bench_options_refuse_what_the_command_line_refuses_and_train_as_training_does():
    bad = {"steps": 0, "vertices": (300, 3), "train_envs": -1, "compare": "mujoco"}
    for name, value in bad.items():
        with pytest.raises(ValueError, match=name):
            BenchOptions(**{name: value})
    options = BenchOptions()
    assert options.train_envs == TrainConfig.envs
    assert options.train_envs_per_process == TrainConfig.envs_per_process


def test_bench_lines_are_a_table_with_its_lines_or_one_json_object_per_row():
    row = timing_row(300, "env", 5, 0.5)
    groups = [([row], ["what the row says"])]
    table = [table_header(), table_line(row), "what the row says"]
    assert list(bench_lines(BenchOptions(), groups)) == table
    assert list(bench_lines(BenchOptions(json=True), groups)) == [json.dumps(row)]
