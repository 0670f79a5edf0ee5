"""A cached rollout is reused only for the policy, plugins, names and settings that made it."""

import hashlib
import importlib.metadata
import json
import shutil
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import safetensors.numpy

from dressbench import plugins
from dressbench.config import EnvConfig
from dressbench.evaluation import Runner, evaluate, leaderboard, make_cell
from dressbench.evaluation import workers as worker_module
from dressbench.observation import observation_size
from dressbench.policy_file import FORMAT, FORMAT_VERSION

TINY = {"horizon": 4, "gown_vertices": 300, "progress": False}  # an episode in ~0.05 s
RUN = {"robot": "fixed", "episodes": 2, "seed": 0, "workers": 1, **TINY}
SUMMARY_FILES = ["episodes.csv", "curves.csv", "leaderboard.csv", "leaderboard.md"]
DRESSBENCH = importlib.metadata.version("dressbench")


def write_policy(folder: Path, name: str, bias: float) -> str:
    """A tiny trained human (policy file pair NAME.safetensors + NAME.json, written the way
    ``save_policy`` writes them) whose every action component is ``bias``; its checksum."""
    obs_dim, hidden = observation_size("complete"), 4
    tensors = {
        "pi.0.weight": np.zeros((hidden, obs_dim)),
        "pi.0.bias": np.zeros(hidden),
        "action.weight": np.zeros((11, hidden)),
        "action.bias": np.full(11, bias),
        "log_std": np.zeros(11),
        "obs_mean": np.zeros(obs_dim),
        "obs_var": np.ones(obs_dim),
    }
    blob = safetensors.numpy.save(tensors)
    checksum = hashlib.sha256(blob).hexdigest()
    document = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "architecture": {
            "hidden_sizes": [hidden],
            "activation": "tanh",
            "obs_dim": obs_dim,
            "act_dim": 11,
        },
        "obs_normalization": {"clip_obs": 10.0, "epsilon": 1e-8},
        "tensors": {"sha256": checksum, "size": len(blob)},
        "robot": "fixed",
        "ablation": "complete",
    }
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.safetensors").write_bytes(blob)
    (folder / f"{name}.json").write_text(json.dumps(document))
    return checksum


@pytest.fixture
def policies(tmp_path, monkeypatch):
    """A policies folder of this test's own, the only one the registry looks in."""
    folder = tmp_path / "policies"
    monkeypatch.setenv("DRESSBENCH_POLICIES", str(folder))
    plugins.refresh()
    yield folder
    monkeypatch.delenv("DRESSBENCH_POLICIES")
    plugins.refresh()


def _meta(out: Path) -> dict:
    return json.loads((out / "run_meta.json").read_text())


def _files(out: Path) -> dict[str, bytes]:
    return {name: (out / name).read_bytes() for name in SUMMARY_FILES}


def _records(out: Path) -> list[Path]:
    return sorted((out / "rollouts").rglob("seed*-episode*.json"))


def test_humans_whose_names_slug_alike_do_not_share_records(tmp_path, policies):
    write_policy(policies, "pol x", 0.5)
    write_policy(policies, "pol_x", -0.5)
    plugins.refresh()
    shared = tmp_path / "shared"
    first = evaluate(human="pol x", out=shared, **RUN)
    second = evaluate(human="pol_x", out=shared, **RUN)
    assert _meta(shared)["episodes_run"] == 2  # not the records of 'pol x'
    assert list(second["human"]) == ["pol_x", "pol_x"]
    pd.testing.assert_frame_equal(second, evaluate(human="pol_x", out=tmp_path / "alone", **RUN))
    assert not np.allclose(first["return"], second["return"])
    assert len({path.parent for path in _records(shared)}) == 2


def test_a_record_carries_its_full_identity(tmp_path, policies):
    checksum = write_policy(policies, "pol x", 0.5)
    plugins.refresh()
    evaluate(human="pol x", out=tmp_path, **RUN)
    first = _records(tmp_path)[0]
    assert first.parent.name.startswith("fixed__pol_x-") and first.name == "seed0-episode00000.json"
    identity = json.loads(first.read_text())["identity"]
    config = asdict(EnvConfig.build(horizon=4, gown_vertices=300, ablation="complete"))
    del config["profile"]  # the typical body: as in every record made before profiles
    assert identity == {
        "robot": {"name": "fixed", "distribution": "dressbench", "version": DRESSBENCH},
        "human": {
            "name": "pol x",
            "source": "policy file",
            "checksum": checksum,
            "obs_normalization": {"clip_obs": 10.0, "epsilon": 1e-8},
        },
        "config": json.loads(json.dumps(config)),
        "seed": 0,
        "episode": 0,
    }
    meta = _meta(tmp_path)
    assert meta["plugins"] == [{"robot": identity["robot"], "human": identity["human"]}]
    assert meta["rollouts"] == [f"rollouts/{first.parent.name}"]


def test_a_policy_file_replaced_under_its_name_is_run_again(tmp_path, policies, capsys):
    write_policy(policies, "pol x", 0.5)
    plugins.refresh()
    out = tmp_path / "results"
    before = evaluate(human="pol x", out=out, **RUN)
    checksum = write_policy(policies, "pol x", -0.5)  # more training, exported under its name
    capsys.readouterr()
    after = evaluate(human="pol x", out=out, **RUN)
    assert _meta(out)["episodes_run"] == 2
    notes = capsys.readouterr().err.splitlines()
    assert len(notes) == 1
    assert "'fixed' x 'pol x' changed" in notes[0] and "human.checksum was " in notes[0]
    assert "not reused" in notes[0]
    assert not np.allclose(before["return"], after["return"])
    pd.testing.assert_frame_equal(after, evaluate(human="pol x", out=tmp_path / "fresh", **RUN))
    assert {
        json.loads(path.read_text())["identity"]["human"]["checksum"] for path in _records(out)
    } >= {checksum}
    assert _meta(out)["plugins"][0]["human"]["checksum"] == checksum


def test_a_policy_replaced_while_its_cell_is_running_is_refused(policies):
    write_policy(policies, "pol x", 0.5)
    plugins.refresh()
    cell = make_cell("fixed", "pol x", horizon=4, gown_vertices=300)
    write_policy(policies, "pol x", -0.5)
    with pytest.raises(RuntimeError, match=r"'pol x' changed since the evaluation started"):
        Runner(cell)


def test_nothing_left_to_run_with_two_workers_just_writes_the_summary(tmp_path, monkeypatch):
    run = {**RUN, "human": "passive"}
    evaluate(out=tmp_path, **run)
    files = _files(tmp_path)
    evaluate(out=tmp_path, **{**run, "workers": 2})  # e.g. after a kill before the summary
    assert _meta(tmp_path)["episodes_run"] == 0 and _files(tmp_path) == files

    def no_pool(*args, **kwargs):
        raise AssertionError("a pool was started with nothing to run")

    monkeypatch.setattr(worker_module, "_Pool", no_pool)
    # a leaderboard built a cell at a time: this cell is done already
    board = leaderboard(out=tmp_path, robots=["fixed"], humans=["passive"], episodes=2, workers=2,
                        **TINY)  # fmt: skip
    assert len(board) == 1 and _meta(tmp_path)["episodes_run"] == 0


@pytest.fixture(scope="module")
def finished(tmp_path_factory) -> Path:
    """A results folder of two finished episodes of fixed x passive, its rollout records only
    (without the cell's archive, which would be reused before them)."""
    out = tmp_path_factory.mktemp("finished")
    evaluate(human="passive", out=out, **RUN)
    shutil.rmtree(out / "cells")
    return out


def _truncate(path: Path) -> None:
    text = path.read_text()
    path.write_text(text[: len(text) // 2])


def _edit(change):
    def edit(path: Path) -> None:
        data = json.loads(path.read_text())
        change(data)
        path.write_text(json.dumps(data))

    return edit


@pytest.mark.parametrize(
    ("damage", "why"),
    [
        (_truncate, "unreadable (JSONDecodeError"),
        (lambda path: path.write_text(""), "unreadable (JSONDecodeError"),
        (lambda path: path.write_bytes(b"\xff\xfe{"), "unreadable ("),
        (lambda path: path.write_text("[1, 2]"), "not an episode record (a JSON list)"),
        (_edit(lambda data: data.pop("identity")), "no identity (an old-format record)"),
        (
            _edit(lambda data: data["identity"]["robot"].update(version="0.0.1")),
            "made by another setup: robot.version is '0.0.1', expected",
        ),
        (
            _edit(lambda data: data["identity"].update(episode=7)),
            "made by another setup: episode is 7, expected 1",
        ),
        (_edit(lambda data: data.pop("arm_progress")), "not an episode record (KeyError"),
        (_edit(lambda data: data.update(episode_seed=3)), "disagrees with its identity"),
        (_edit(lambda data: data.update(arm_progress=[0.0])), "disagrees with its identity"),
    ],
    ids=[
        "truncated",
        "empty",
        "not-utf8",
        "not-an-object",
        "old-format",
        "other-plugin-version",
        "other-episode",
        "field-missing",
        "other-episode-seed",
        "short-curve",
    ],
)
def test_a_broken_record_is_discarded_with_a_notice_naming_it_and_run_again(
    finished, tmp_path, capsys, damage, why
):
    out = tmp_path / "results"
    shutil.copytree(finished, out)
    damaged = _records(out)[1]  # episode 1
    damage(damaged)
    capsys.readouterr()
    evaluate(human="passive", out=out, **RUN)
    notes = capsys.readouterr().err.splitlines()
    assert len(notes) == 1, notes
    assert f"discarded {damaged}: " in notes[0] and why in notes[0]
    assert _meta(out)["episodes_run"] == 1
    assert _files(out) == _files(finished)
    assert damaged.read_bytes() == _records(finished)[1].read_bytes()  # replaced by the rerun


def test_old_layout_folders_are_named_once_and_not_reused(finished, tmp_path, capsys):
    out = tmp_path / "results"
    shutil.copytree(finished, out)
    shutil.rmtree(_records(out)[0].parent)
    old = out / "rollouts" / "cfg-0123456789" / "fixed__passive"
    for path in _records(finished):
        record = json.loads(path.read_text())
        del record["identity"]
        old.mkdir(parents=True, exist_ok=True)
        (old / path.name).write_text(json.dumps(record))
    capsys.readouterr()
    evaluate(human="passive", out=out, **RUN)
    notes = capsys.readouterr().err.splitlines()
    assert notes == [
        f"dressbench: 1 old-layout rollout folder(s) in {out / 'rollouts'} (cfg-*) carry no "
        "identity and are not reused"
    ]
    assert _meta(out)["episodes_run"] == 2
