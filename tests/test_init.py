"""Starting a run from a trained human (``--init``); the generalists the ``family`` trains."""

import json

import numpy as np
import pytest
from click.testing import CliRunner

from dressbench.cli import main
from dressbench.evaluation import leaderboard_cells
from dressbench.plugins import PluginError
from dressbench.policy_file import load_policy
from dressbench.training import TrainConfig, train

TINY = {"gown_vertices": 300, "horizon": 32, "samples_per_update": 128, "envs": 1}


def tiny(tmp_path, **changes) -> TrainConfig:
    folders = {"out": str(tmp_path / "runs"), "policies": str(tmp_path / "policies")}
    return TrainConfig.preset("default", **(TINY | folders | changes))


@pytest.fixture
def parent(tmp_path, policies_on_path):
    """A trained human to start from: 256 steps against ``fixed``."""
    return load_policy(train(tiny(tmp_path, timesteps=256, name="parent"), progress=False))


def test_a_run_started_from_a_human_begins_with_its_actor_and_normalisation(tmp_path, parent):
    """Fewer steps than one update: the exported child is its parent, but for the
    normalisation's running statistics, which weigh the parent's steps against its own."""
    child = train(tiny(tmp_path, robot="front_linear", init="parent", timesteps=32,
                       name="child"), progress=False)  # fmt: skip
    tuned = load_policy(child)
    for (w, b), (w0, b0) in zip(tuned.layers, parent.layers, strict=True):
        assert np.array_equal(w, w0) and np.array_equal(b, b0)
    assert np.array_equal(tuned.log_std, parent.log_std)
    assert np.allclose(tuned.obs_mean, parent.obs_mean, atol=0.5 * np.sqrt(parent.obs_var).max())
    shift = np.abs(tuned.obs_mean - parent.obs_mean).max()
    assert shift < np.abs(parent.obs_mean).max()  # weighed, not replaced by 32 new steps
    record = json.loads((tmp_path / "runs" / "child" / "run.json").read_text())
    assert record["parent"] == {"name": "parent", "sha256": parent.checksum, "robot": "fixed",
                                "recipe": "default", "steps": 256}  # fmt: skip
    assert tuned.metadata["parent"] == record["parent"]
    assert record["config"]["curriculum"] is None and record["config"]["warmup"] is None


def test_a_human_that_cannot_be_started_from_is_refused_in_one_line(tmp_path, parent):
    with pytest.raises(ValueError, match=r"^cannot start from human 'parent': it was trained "
                       r"with ablation 'complete', this run trains with 'no_task'$"):  # fmt: skip
        train(tiny(tmp_path, ablation="no_task", init="parent", timesteps=8), progress=False)
    with pytest.raises(ValueError, match=r"^cannot start from human 'scripted': it is a plugin"):
        train(tiny(tmp_path, init="scripted", timesteps=8, name="x"), progress=False)
    with pytest.raises(PluginError, match="nobody"):
        train(tiny(tmp_path, init="nobody", timesteps=8, name="y"), progress=False)
    assert not (tmp_path / "runs" / "x").exists()  # a refused run leaves no folder


def test_the_command_line_starts_a_run_from_a_human_and_asks_for_the_curriculum_back(
    tmp_path, parent
):
    runs, policies = str(tmp_path / "runs"), str(tmp_path / "policies")
    result = CliRunner().invoke(main, ["train", "--robot", "side_linear", "--init", "parent",
                                       "--curriculum", "--timesteps", "8", "--envs", "1",
                                       "--gown-vertices", "300", "--name", "tuned", "--out",
                                       runs, "--policies", policies])  # fmt: skip
    assert result.exit_code == 0, result.output
    record = json.loads((tmp_path / "runs" / "tuned" / "run.json").read_text())
    assert record["parent"]["name"] == "parent" and record["config"]["init"] == "parent"
    assert record["config"]["curriculum"] is not None and record["config"]["warmup"] is None


def test_a_human_trained_against_the_family_is_meant_for_any_strategy(tmp_path, policies_on_path):
    path = train(tiny(tmp_path, robot="family", timesteps=8, name="generalist-s0"),
                 progress=False)  # fmt: skip
    human = load_policy(path)
    assert human.robot is None and human.metadata["config"]["robot"] == "family"
    cells = leaderboard_cells(humans=["generalist-s0"], gown_vertices=300)
    assert {cell.robot for cell in cells} >= {"fixed", "front_linear", "side_linear"}
    assert "family" not in {cell.robot for cell in cells}
