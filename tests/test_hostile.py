"""A results folder is untrusted input, a name means one policy, and one bad plugin never stops
a leaderboard.

The hostile plugins are a small package (tests/hostile_plugins/, its own pyproject.toml and
entry points) installed into a temporary folder on ``sys.path``; episodes are tiny (horizon 3,
a 300-vertex gown).
"""

import warnings
from pathlib import Path

import pytest

try:
    import tomllib
except ImportError:  # Python 3.10: pytest's own dependency
    import tomli as tomllib
from click.testing import CliRunner
from fakes import install

import dressbench
from dressbench import files
from dressbench.cli import main
from dressbench.evaluation.readme import write_results_readme

HOSTILE = Path(__file__).parent / "hostile_plugins"
TINY = {"horizon": 3, "gown_vertices": 300, "progress": False}
FROM = "from hostile-plugins 1.0"


@pytest.fixture
def hostile(site):
    """The hostile-plugins distribution, installed as pip would leave it (metadata, entry
    points, module) in a folder on ``sys.path``."""
    project = tomllib.loads((HOSTILE / "pyproject.toml").read_text())["project"]
    groups = {f"[{group}]": eps for group, eps in project["entry-points"].items()}
    install(site, project["name"], project["version"], groups,
            hostile_plugins=(HOSTILE / "hostile_plugins.py").read_text())  # fmt: skip
    return site


def _messages(caught) -> list[str]:
    return [str(w.message) for w in caught]


# --- one bad plugin never stops a leaderboard ------------------------------------------------


def test_a_plugin_raising_in_an_episode_flags_its_cell_and_the_leaderboard_goes_on(
    hostile, tmp_path
):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        board = dressbench.leaderboard(
            episodes=2, workers=1, out=tmp_path, robots=["fixed"],
            humans=["passive", "crashy", "quitter", "wrong_size"], **TINY,
        )  # fmt: skip
    assert list(board["human"]) == ["passive"]
    lines = _messages(caught)
    for name, reason in [
        ("crashy", "raised RuntimeError: boom"),
        ("quitter", "raised SystemExit: 3"),
        ("wrong_size", "raised ValueError: human action must have shape (11,), got (10,)"),
    ]:
        (line,) = [line for line in lines if f"x {name!r} left out" in line]
        assert f"human plugin {name!r} {FROM} {reason} in episode 0 (episode seed " in line, line
    meta = (tmp_path / "run_meta.json").read_text()
    assert "crashy" in meta and "flagged_cells" in meta


def test_an_episode_past_its_time_limit_flags_its_cell(hostile, tmp_path):
    with pytest.warns(UserWarning, match=r"'sleeper' left out: .* ran past its time limit of 2 s "
                                         r"\(--episode-timeout\) in episode 0"):  # fmt: skip
        board = dressbench.leaderboard(
            episodes=1, workers=1, out=tmp_path, robots=["fixed"], humans=["passive", "sleeper"],
            episode_timeout=2, **TINY,
        )  # fmt: skip
    assert list(board["human"]) == ["passive"]


def test_evaluate_of_a_failing_plugin_is_one_line_naming_it(hostile, tmp_path):
    result = CliRunner().invoke(main, ["evaluate", "--robot", "fixed", "--human", "quitter",
                                       "--episodes", "1", "--workers", "1", "--gown-vertices",
                                       "300", "--out", str(tmp_path)])  # fmt: skip
    assert result.exit_code == 1, result.output
    errors = [line for line in result.output.splitlines() if line.startswith("Error: ")]
    assert len(errors) == 1 and "Traceback" not in result.output, result.output
    assert f"human plugin 'quitter' {FROM} raised SystemExit: 3 in episode 0" in errors[0]


def test_a_dead_worker_is_replaced_its_task_retried_then_flagged(hostile, tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        board = dressbench.leaderboard(
            episodes=2, workers=2, out=tmp_path, robots=["fixed"],
            humans=["passive", "vanisher"], **TINY,
        )  # fmt: skip
    assert list(board["human"]) == ["passive"] and int(board["episodes"][0]) == 2
    (line,) = [line for line in _messages(caught) if "'vanisher' left out" in line]
    assert f"human plugin 'vanisher' {FROM}" in line
    assert "its worker died (exit code 7) in each of 3 tries in episode" in line


# --- a results folder is untrusted ------------------------------------------------------------


def _archived_cell(tmp_path):
    """A results folder holding one archived cell (fixed x passive, one tiny episode)."""
    from dressbench.evaluation import make_cell
    from dressbench.evaluation.archive import archive_path

    options = {"horizon": 3, "gown_vertices": 300}
    dressbench.evaluate("fixed", "passive", episodes=1, workers=1, out=tmp_path, **TINY)
    cell = make_cell("fixed", "passive", **options)
    return cell, archive_path(tmp_path, cell, 0)


def test_a_cell_archive_is_refused_before_decompressing_what_it_cannot_hold(tmp_path, capsys):
    import numpy as np

    from dressbench.evaluation import archive

    cell, path = _archived_cell(tmp_path)
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["arm_progress"] = np.zeros((1, 20_000_000))  # 160 MB that compress to ~150 kB
    np.savez_compressed(path, **arrays)
    assert path.stat().st_size < 1_000_000
    capsys.readouterr()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(archive.np, "load", lambda *a, **k: pytest.fail("decompressed"))
        assert archive.load_archive(tmp_path, cell, 0) == []
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"dressbench: ignored {path}: member arm_progress.npy is 160,000,128 "
                           "bytes uncompressed, more than the "), line  # fmt: skip
    assert line.endswith("its cell allows (3 steps, at most 17 episodes); its episodes run again")


def test_a_cell_archive_with_other_members_or_linked_is_refused(tmp_path, capsys):
    import zipfile

    from dressbench.evaluation import archive

    cell, path = _archived_cell(tmp_path)
    with zipfile.ZipFile(path, "a") as extra:
        extra.writestr("payload.npy", b"x")
    assert archive.load_archive(tmp_path, cell, 0) == []
    assert "not a cell archive (members payload.npy)" in capsys.readouterr().err
    target = tmp_path / "elsewhere.npz"
    path.rename(target)
    path.symlink_to(target)
    assert archive.load_archive(tmp_path, cell, 0) == []
    assert "not a regular file" in capsys.readouterr().err


def _results(tmp_path):
    """A results folder of one tiny cell (fixed x passive)."""
    out = tmp_path / "results"
    dressbench.evaluate("fixed", "passive", episodes=1, workers=1, out=out, **TINY)
    return out


def test_the_report_escapes_every_value_and_keeps_its_files_in_report(tmp_path):
    import pandas as pd

    from dressbench.evaluation.webpage import write_report

    out = _results(tmp_path)
    board = pd.read_csv(out / "leaderboard.csv")
    board["human"] = "<script>alert(1)</script>"
    board["config_id"] = "../../../escaped"
    board["episodes"] = '1"><script>alert(2)</script>'
    board.to_csv(out / "leaderboard.csv", index=False)
    page = write_report(out, videos=True, workers=1, progress=False).read_text()
    assert "<script>alert" not in page and "&lt;script&gt;alert(1)" in page
    written = {p for p in tmp_path.rglob("*") if p.is_file()}
    assert not [p for p in written if "escaped" in p.name and out / "report" not in p.parents]


def test_the_report_copies_no_linked_plot(tmp_path):
    from dressbench.evaluation.webpage import write_report

    out = _results(tmp_path)
    private = tmp_path / "private.png"
    private.write_bytes(b"secret")
    private.chmod(0o600)
    (out / "leaked.png").symlink_to(private)
    page = write_report(out, videos=False, progress=False).read_text()
    assert not (out / "report" / "images" / "leaked.png").exists() and "leaked" not in page
    assert (out / "report" / "images" / "final_scores.png").is_file()


@pytest.mark.parametrize(
    ("name", "content", "problem"),
    [
        ("run_meta.json", '{"seed": 0, "cells": [', "not valid JSON (JSONDecodeError: "),
        ("run_meta.json", "[" * 100_000 + "]" * 100_000, "not valid JSON (ValueError: JSON nested"),
        ("leaderboard.csv", "", "not a leaderboard table (EmptyDataError: "),
    ],
)
def test_a_broken_results_file_is_one_line_naming_it(tmp_path, name, content, problem):
    out = _results(tmp_path)
    (out / name).write_text(content)
    result = CliRunner().invoke(main, ["report", str(out), "--no-videos"])
    assert result.exit_code == 1 and "Traceback" not in result.output, result.output
    assert result.output.startswith(f"Error: {out / name}: {problem}"), result.output


def test_a_results_file_linked_elsewhere_or_too_large_is_refused_without_being_read(
    tmp_path, monkeypatch
):
    out = _results(tmp_path)
    (out / "strategies.csv").unlink()
    private = tmp_path / "private.csv"
    private.write_text("robot\nsecret\n")
    (out / "strategies.csv").symlink_to(private)
    result = CliRunner().invoke(main, ["report", str(out), "--no-videos"])
    assert result.output.startswith(
        f"Error: {out / 'strategies.csv'}: not a results file "
        f"(missing, a link or not a regular file)"
    ), result.output
    (out / "strategies.csv").unlink()
    (out / "strategies.csv").write_text("robot\n" + "fixed\n" * 100)
    monkeypatch.setattr(files, "MAX_READ_BYTES", 200)
    result = CliRunner().invoke(main, ["report", str(out), "--no-videos"])
    assert result.output.startswith(
        f"Error: {out / 'leaderboard.csv'}: more than 200 bytes; not a results file"
    ), result.output
    assert not files.readable(out / "leaderboard.csv") and files.readable(out / "README.md", 10**6)


def test_a_broken_run_record_beside_the_results_is_one_line_naming_it(tmp_path):
    out = _results(tmp_path)
    (out / "fixed-x-s0-run.json").write_text("{")
    with pytest.raises(ValueError, match=r"fixed-x-s0-run\.json: not a run's record \(not JSON"):
        write_results_readme(out)


def test_a_deeply_nested_json_among_the_policies_is_refused_and_the_others_load(
    tmp_path, monkeypatch
):
    from test_reliability import write_policy

    from dressbench import plugins

    folder = tmp_path / "policies"
    write_policy(folder, "fine")
    (folder / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    (folder / "deep.safetensors").write_bytes(b"")
    monkeypatch.setenv("DRESSBENCH_POLICIES", str(folder))
    plugins.refresh()
    try:
        result = CliRunner().invoke(main, ["plugins"])
    finally:
        plugins.refresh()
    assert result.exit_code == 0 and "RecursionError" not in result.output, result.output
    (deep,) = [line for line in result.output.splitlines() if " deep " in line]
    assert "deep.json: not valid JSON (JSON nested too deeply)" in deep
    (fine,) = [line for line in result.output.splitlines() if " fine " in line]
    assert fine.rstrip().endswith("ok")


def test_a_mistyped_policies_folder_is_named(tmp_path, monkeypatch):
    from dressbench import plugins

    monkeypatch.setenv("DRESSBENCH_POLICIES", str(tmp_path / "polcies"))
    plugins.refresh()
    try:
        with pytest.warns(UserWarning, match=r"DRESSBENCH_POLICIES names .*polcies, which is not"):
            plugins.human_plugins()
    finally:
        plugins.refresh()


# --- a name resolves to one policy ------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "provider"),
    [("crashy", f"human plugin 'crashy' {FROM}"), ("fixed-default-s0", "human plugin "
     "'fixed-default-s0' from policy file ")],
)  # fmt: skip
def test_train_refuses_a_name_another_plugin_or_a_shipped_policy_provides(
    hostile, tmp_path, name, provider
):
    runs, models = tmp_path / "runs", tmp_path / "policies"
    result = CliRunner().invoke(main, ["train", "--name", name, "--envs", "1", "--timesteps", "64",
                                       "--gown-vertices", "300", "--out", str(runs),
                                       "--policies", str(models)])  # fmt: skip
    assert result.exit_code == 1 and "Traceback" not in result.output, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith(f"Error: name {name!r} is taken: {provider}"), line
    assert line.endswith("train under another name (--name)"), line
    assert not runs.exists() and not models.exists()


def _policies_on_path(monkeypatch, folder: Path) -> None:
    """Make ``folder`` the only place the registry finds trained models."""
    from dressbench import plugins

    monkeypatch.setenv("DRESSBENCH_POLICIES", str(folder))
    plugins.refresh()


def test_a_rerun_may_replace_its_own_policy_but_not_one_elsewhere(tmp_path, monkeypatch):
    from test_reliability import write_policy

    from dressbench import plugins
    from dressbench.training import TrainConfig

    mine = tmp_path / "policies"
    write_policy(mine, "mine")
    _policies_on_path(monkeypatch, mine)
    options = {"name": "mine", "gown_vertices": 300, "horizon": 3, "out": str(tmp_path / "runs")}
    try:
        TrainConfig(policies=str(mine), **options).check()  # its own earlier policy: a re-run
        with pytest.raises(ValueError, match=r"^name 'mine' is taken: human plugin 'mine' from "
                                             r"policy file .*mine\.json"):  # fmt: skip
            TrainConfig(policies=str(tmp_path / "elsewhere"), **options).check()
    finally:
        plugins.refresh()


def test_an_evaluation_names_the_losing_duplicate_of_its_human(tmp_path, monkeypatch):
    from test_reliability import write_policy

    from dressbench import plugins

    folder = tmp_path / "policies"
    write_policy(folder, "passive")
    _policies_on_path(monkeypatch, folder)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            dressbench.evaluate("fixed", "passive", episodes=1, workers=1,
                                out=tmp_path / "results", **TINY)  # fmt: skip
    finally:
        plugins.refresh()
    (line,) = [line for line in _messages(caught) if "duplicate" in line]
    assert line == (f"human 'passive' has a losing duplicate: the one from dressbench "
                    f"{dressbench.__version__} runs, not the one from policy file "
                    f"{(folder / 'passive.json').resolve()} (rename it to run it)")  # fmt: skip


# --- --out writes only files it owns ----------------------------------------------------------


def test_out_refuses_a_folder_holding_a_readme_it_did_not_write(tmp_path):
    folder = tmp_path / "notes"
    folder.mkdir()
    (folder / "README.md").write_text("my notes\n")
    result = CliRunner().invoke(main, ["evaluate", "--robot", "fixed", "--human", "passive",
                                       "--episodes", "1", "--workers", "1", "--gown-vertices",
                                       "300", "--out", str(folder)])  # fmt: skip
    assert result.exit_code == 1 and "Traceback" not in result.output, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith(f"Error: out {str(folder)!r} holds README.md, which dressbench did not "
                           "write"), line  # fmt: skip
    assert [p.name for p in folder.iterdir()] == ["README.md"]
    assert (folder / "README.md").read_text() == "my notes\n"


def test_out_takes_its_own_results_folders_those_written_before_the_marker_too(tmp_path):
    from dressbench.evaluation.ownership import MARKER

    out = _results(tmp_path)
    assert (out / MARKER).is_file()
    for written_before_the_marker in ([], ["run_meta.json", "README.md"]):  # whole, stopped
        for name in [MARKER, *written_before_the_marker]:
            (out / name).unlink()
        dressbench.evaluate("fixed", "passive", episodes=1, workers=1, out=out, **TINY)
        assert (out / MARKER).is_file()


# --- two trainings of one run do not interleave -----------------------------------------------


def test_a_training_run_is_locked_while_it_trains_and_a_dead_holder_is_taken_over(tmp_path):
    import os
    import subprocess
    import sys

    from dressbench.training import TrainConfig
    from dressbench.training.run import TrainingRun

    where = {"out": str(tmp_path / "runs"), "policies": str(tmp_path / "policies")}
    config = TrainConfig(name="busy", envs=1, timesteps=64, gown_vertices=300, horizon=3, **where)
    run = TrainingRun(config)
    run._run = lambda progress: config.check()  # inside: another call finds the run in use
    with pytest.raises(ValueError, match=rf"^training run 'busy' in {run.folder} is in use by "
                                         rf"process {os.getpid()}: "):  # fmt: skip
        run.run(progress=False)
    run.folder.mkdir(parents=True)
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\n"
                               "from pathlib import Path\n"
                               "from dressbench.training.lock import run_lock\n"
                               "with run_lock(Path(sys.argv[1])):\n"
                               "    print('held', flush=True)\n"
                               "    time.sleep(120)\n", str(run.folder)],
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(ValueError, match=rf"in use by process {holder.pid}: "):
            config.check()
    finally:
        holder.kill()
        holder.wait()
    config.check()  # its holder died: the lock is free again
    from dressbench.training.lock import run_lock

    with run_lock(run.folder):
        assert str(os.getpid()) in (run.folder / "run.lock").read_text()


# --- a cached record agrees with itself -------------------------------------------------------


@pytest.mark.parametrize(
    ("score", "curve", "what"),
    [("final_arm_progress", "arm_progress", "the last value"),
     ("max_deformation", "max_deformation_curve", "the largest value")],
)  # fmt: skip
def test_a_record_whose_score_contradicts_its_curve_runs_again(tmp_path, capsys, score, curve,
                                                                what):  # fmt: skip
    import json
    import shutil

    out = _results(tmp_path)
    shutil.rmtree(out / "cells")  # else the cell's archive would serve the episode
    (path,) = (out / "rollouts").rglob("*.json")
    data = json.loads(path.read_text())
    right = data[score]
    data[score] = right + 0.25
    path.write_text(json.dumps(data))
    capsys.readouterr()
    table = dressbench.evaluate("fixed", "passive", episodes=1, workers=1, out=out, **TINY)
    assert table[score].iloc[0] == right
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == (f"dressbench: discarded {path}: its {score} {right + 0.25!r} is not {what} "
                    f"of its {curve} curve ({right!r}); the episode runs again")  # fmt: skip


def test_a_cell_archive_whose_score_contradicts_its_curve_runs_again(tmp_path, capsys):
    import numpy as np

    from dressbench.evaluation import archive

    cell, path = _archived_cell(tmp_path)
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["final_arm_progress"] = arrays["final_arm_progress"] + 0.25
    np.savez_compressed(path, **arrays)
    capsys.readouterr()
    assert archive.load_archive(tmp_path, cell, 0) == []
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"dressbench: ignored {path}: episode 0: its final_arm_progress "), line


# --- a robot that makes results unrepeatable is named -----------------------------------------


def test_a_robot_drawing_from_the_global_random_state_is_named(hostile):
    from dressbench.plugins import robot_plugin
    from dressbench.preflight import robot_problem

    with pytest.warns(UserWarning) as caught:
        assert robot_problem(robot_plugin("gambler")) is None
    (line,) = _messages(caught)
    assert line == (f"robot plugin 'gambler' {FROM} draws from NumPy's global random state "
                    "(np.random) in reset: its episodes cannot be repeated; draw from the "
                    "generator reset gets")  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert robot_problem(robot_plugin("fixed")) is None


# --- the docs say what one worker does not isolate --------------------------------------------


def test_the_docs_say_what_one_worker_does_not_isolate():
    docs = (Path(__file__).resolve().parents[1] / "docs" / "evaluation.md").read_text()
    assert "`--workers 1`" in docs and "`os._exit`" in docs and "`--workers 2`" in docs
