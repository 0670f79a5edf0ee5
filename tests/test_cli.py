"""The command line is a thin layer over the library."""

import json
from dataclasses import replace

import pandas as pd
import pytest
from click.testing import CliRunner

from dressbench.cli import main
from dressbench.config import EnvConfig
from dressbench.evaluation.readme import command_line
from dressbench.evaluation.runs import check_run
from dressbench.evaluation.strategies import STRATEGIES_BLOCK
from dressbench.scene.garment import GownConfig
from dressbench.scene.world import SceneConfig
from dressbench.sweep import Sweep
from dressbench.training.config import TRAINING_GOWN_VERTICES, TrainConfig


def test_bench_prints_one_json_object_per_measurement():
    result = CliRunner().invoke(
        main, ["bench", "--vertices", "600", "--steps", "5", "--repeats", "1", "--json"]
    )
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    assert [r["what"] for r in rows] == ["cloth", "scene", "env"]
    for row in rows:
        assert row["vertices"] > 400 and row["steps_per_second"] > 0
        assert not row["sim_failure"]


def test_plugins_lists_every_plugin_with_its_package_and_status():
    result = CliRunner().invoke(main, ["plugins"])
    assert result.exit_code == 0, result.output
    for name in ("fixed", "front_linear", "side_linear", "passive", "random", "reach", "scripted"):
        line = next(row for row in result.output.splitlines() if f" {name} " in row)
        assert "dressbench" in line and line.rstrip().endswith("ok")


def test_a_leaderboard_can_be_built_a_few_cells_at_a_time(tmp_path):
    tiny = ["--episodes", "1", "--workers", "1", "--gown-vertices", "600", "--horizon", "4"]
    out = ["--out", str(tmp_path)]
    first = ["evaluate", "leaderboard", *tiny, *out, "--robot", "fixed", "--human", "passive"]
    result = CliRunner().invoke(main, first)
    assert result.exit_code == 0, result.output
    board = pd.read_csv(tmp_path / "leaderboard.csv")
    assert list(zip(board["robot"], board["human"], strict=True)) == [("fixed", "passive")]

    more = ["evaluate", "leaderboard", *tiny, *out, "--robot", "fixed", "--human", "passive",
            "--human", "random"]  # fmt: skip
    result = CliRunner().invoke(main, more)
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 1  # reused one
    assert set(pd.read_csv(tmp_path / "leaderboard.csv")["human"]) == {"passive", "random"}


def test_the_command_a_results_readme_gives_remakes_its_tables_from_the_cache(tmp_path):
    """A results folder's README names the command that made it; run as written, it is valid
    (each option it names exists) and re-makes the tables without simulating anything."""
    from dressbench.evaluation import evaluate

    evaluate("fixed", "passive", episodes=1, workers=1, out=tmp_path, progress=False,
             horizon=4, gown_vertices=300)  # fmt: skip
    line = command_line(json.loads((tmp_path / "run_meta.json").read_text()))
    assert "--horizon 4" in line and "--gown-vertices 300" in line
    words = line.split()[1:]  # without "dressbench"
    result = CliRunner().invoke(main, [*words, "--workers", "1", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 0


def test_a_leaderboard_under_several_profiles_scores_each_and_its_readme_names_each(tmp_path):
    tiny = ["--episodes", "1", "--workers", "1", "--horizon", "4", "--gown-vertices", "300"]
    asked = [
        "--robot",
        "fixed",
        "--human",
        "passive",
        "--profile",
        "typical",
        "--profile",
        "tremor",
    ]
    result = CliRunner().invoke(
        main, ["evaluate", "leaderboard", *tiny, *asked, "--out", str(tmp_path)]
    )
    assert result.exit_code == 0, result.output
    meta = json.loads((tmp_path / "run_meta.json").read_text())
    assert [cell["profile"] for cell in meta["cells"]] == ["typical", "tremor"]
    assert list(pd.read_csv(tmp_path / "leaderboard.csv")["profile"]) == ["typical", "tremor"]
    assert "| fixed | passive | complete | tremor |" in (tmp_path / "README.md").read_text()
    line = command_line(meta)
    assert "--profile typical --profile tremor" in line
    words = line.split()[1:]  # as written, it re-makes the tables from the cache
    result = CliRunner().invoke(main, [*words, "--workers", "1", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "run_meta.json").read_text())["episodes_run"] == 0


def test_an_unknown_strategy_is_a_one_line_error_not_a_traceback():
    for command in (["evaluate", "--robot", "fixd", "--human", "passive"],
                    ["evaluate", "leaderboard", "--robot", "fixd"]):  # fmt: skip
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 1
        assert result.output.startswith("Error: unknown robot") and "fixd" in result.output
        assert len(result.output.strip().splitlines()) == 1


def test_reproduce_refuses_a_human_that_plays_none_of_the_papers_policies_in_one_line(tmp_path):
    result = CliRunner().invoke(
        main, ["evaluate", "reproduce", "--human", "scripted", "--out", str(tmp_path)]
    )
    assert result.exit_code != 0
    assert "'scripted' plays none of the paper's policies" in result.output
    assert "Traceback" not in result.output and not list(tmp_path.iterdir())


def test_leaderboard_writes_its_strategy_table_into_a_docs_block(tmp_path):
    doc = tmp_path / "README.md"
    doc.write_text(f"# Results\n{STRATEGIES_BLOCK.begin}\nold\n{STRATEGIES_BLOCK.end}\nKept.\n")
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["evaluate", "leaderboard", "--robot", "fixed", "--human",
                                       "passive", "--episodes", "1", "--horizon", "4",
                                       "--gown-vertices", "300", "--workers", "1", "--out",
                                       str(out), "--doc", str(doc)])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert (out / "strategies.md").read_text().endswith(STRATEGIES_BLOCK.read(doc))
    assert "no trained human" in STRATEGIES_BLOCK.read(doc) and doc.read_text().endswith("Kept.\n")


@pytest.mark.parametrize(
    ("command", "block"), [("leaderboard", "strategies"), ("reproduce", "results")]
)
def test_a_doc_without_its_block_is_refused_before_anything_is_evaluated(command, block, tmp_path):
    doc = tmp_path / "notes.md"
    doc.write_text("# Notes\n\nno block here\n")
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["evaluate", command, "--doc", str(doc), "--out", str(out)])
    assert result.exit_code == 1 and f"has no {block} block" in result.output
    assert len(result.output.strip().splitlines()) == 1 and not out.exists()


@pytest.mark.parametrize("seconds", ["0", "-1", "nan", "inf"])
def test_an_episode_time_limit_that_is_no_positive_number_is_refused_as_python_refuses_it(
    seconds, tmp_path
):
    out = tmp_path / "out"
    given = ["--robot", "fixed", "--human", "passive", "--episode-timeout", seconds]
    result = CliRunner().invoke(main, ["evaluate", *given, "--out", str(out)])
    assert result.exit_code == 2 and "must be a positive number of seconds" in result.output
    with pytest.raises(ValueError, match="episode_timeout must be a positive number of seconds"):
        check_run(1, 0, None, out, "local", None, episode_timeout=float(seconds))
    assert not out.exists()


def _default(command: list[str], name: str):
    """The default the command line shows for ``name`` in ``command`` (e.g. ["train"])."""
    group = main
    for word in command:
        group = group.commands[word]
    return next(p.default for p in group.params if p.name == name)


def test_the_defaults_the_command_line_shows_are_the_configs():
    gown = GownConfig.target_vertices
    assert TrainConfig.gown_vertices == TRAINING_GOWN_VERTICES < gown  # training's coarser gown
    assert TrainConfig.preset("fine-gown").gown_vertices == gown == EnvConfig.gown_vertices
    for command in (["train"], ["sweep"]):  # the recipe's gown, which the help lists
        assert _default(command, "gown_vertices") is None
    assert _default(["sweep"], "eval_gown_vertices") == Sweep.eval_gown_vertices == gown
    assert _default(["sweep"], "horizon") == TrainConfig.horizon == EnvConfig.horizon
    for command in (["evaluate"], ["evaluate", "leaderboard"], ["render"]):
        assert _default(command, "gown_vertices") == EnvConfig.gown_vertices
    assert _default(["evaluate", "reproduce"], "horizon") == EnvConfig.horizon
    assert _default(["bench"], "device") == SceneConfig.device
    for name in ("robot", "algo", "ablation", "seed", "out", "policies", "recipe"):
        assert _default(["train"], name) == getattr(TrainConfig, name), name


def test_train_builds_the_config_the_library_builds_from_the_same_options(tmp_path, monkeypatch):
    from dressbench.training import run

    built = []
    monkeypatch.setattr(run, "train", lambda config: built.append(config) or tmp_path / "p.json")
    flags = ["--robot", "front_linear", "--seed", "3", "--no-curriculum", "--tear-limit", "3",
             "--out", str(tmp_path), "--timesteps", "100"]  # fmt: skip
    result = CliRunner().invoke(main, ["train", *flags])
    assert result.exit_code == 0, result.output
    library = run.train_config(robot="front_linear", seed=3, curriculum=False, tear_limit=3.0,
                               out=str(tmp_path), timesteps=100, resume=True)  # fmt: skip
    assert built == [library] and library.curriculum is None and library.tear.ratio == 3.0


def test_a_scene_setting_the_resolution_or_device_unlike_the_env_options_is_refused():
    """The env's ``gown_vertices`` and ``device`` are the one owner: they set the scene's, and a
    scene given with other values of its own is refused in one line, never overwritten."""
    scene = SceneConfig(gown=GownConfig(target_vertices=1000))
    with pytest.raises(ValueError) as error:
        EnvConfig(scene=scene)
    assert "gown_vertices" in str(error.value) and len(str(error.value).splitlines()) == 1
    with pytest.raises(ValueError, match="device"):
        EnvConfig(scene=replace(SceneConfig(), device="cuda"))
    assert EnvConfig(gown_vertices=1000, scene=scene).scene_config() == scene
    assert EnvConfig(gown_vertices=600).scene_config().gown.target_vertices == 600


def test_train_takes_the_recipes_gown_and_a_given_one_over_it(tmp_path, monkeypatch):
    from dressbench.training import run

    built = []
    monkeypatch.setattr(run, "train", lambda config: built.append(config) or tmp_path / "p.json")
    for flags in (["--recipe", "fine-gown"], ["--recipe", "fine-gown", "--gown-vertices", "600"],
                  []):  # fmt: skip
        result = CliRunner().invoke(main, ["train", "--out", str(tmp_path), "--fresh", *flags])
        assert result.exit_code == 0, result.output
    assert [config.gown_vertices for config in built] == [2000, 600, TRAINING_GOWN_VERTICES]
    assert [config.recipe for config in built] == ["fine-gown", "fine-gown", "default"]


def test_the_learning_curves_command_draws_summaries_and_refuses_a_file_that_is_not_one(tmp_path):
    summary = tmp_path / "fixed-default-s0-progress.csv"
    summary.write_text("time/total_timesteps,time/time_elapsed,rollout/rest_start_arm_progress\n"
                       "4096,20,0.0\n8192,40,0.1\n")  # fmt: skip
    out = tmp_path / "curves.png"
    result = CliRunner().invoke(main, ["curves", str(summary), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert out.read_bytes().startswith(b"\x89PNG") and "1 runs" in result.output
    for text in ("not,a,summary\n1,2,3\n", "\x00\xff" * 10):
        bad = tmp_path / "bad-progress.csv"
        bad.write_text(text, encoding="latin-1")
        result = CliRunner().invoke(main, ["curves", str(bad), "--out", str(out)])
        assert result.exit_code == 1 and str(bad) in result.output
        assert len(result.output.strip().splitlines()) == 1, result.output
