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
from dressbench.cli import main

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
