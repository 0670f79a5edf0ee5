"""``dressbench score``: a strategy scored by the generalist seeds, as they are or fine-tuned."""

import json

import pandas as pd
import pytest
from click.testing import CliRunner

from dressbench.checks import MAX_EPISODES
from dressbench.cli import main
from dressbench.scoring import ScoreOptions, generalists, score, tuned_name
from dressbench.training import TrainConfig, train

TINY = {"gown_vertices": 300, "horizon": 24, "samples_per_update": 128, "envs": 1}
SMALL_EVAL = {"gown_vertices": 300, "horizon": 24}


@pytest.fixture
def two_generalists(tmp_path, policies_on_path):
    """Two seeds of a (barely) trained generalist, in this test's policies folder."""
    for seed in (0, 1):
        config = TrainConfig.preset("default", **TINY, robot="family", seed=seed, timesteps=8,
                                    name=f"generalist-s{seed}", out=str(tmp_path / "runs"),
                                    policies=str(tmp_path / "policies"))  # fmt: skip
        train(config, progress=False)
    return tmp_path


def test_score_without_fine_tuning_writes_the_strategys_row_from_every_generalist_seed(
    two_generalists,
):
    out = two_generalists / "score"
    result = CliRunner().invoke(main, ["score", "--robot", "fixed", "--minutes", "0",
                                       "--episodes", "2", "--gown-vertices", "300", "--horizon",
                                       "24", "--workers", "1", "--out", str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "fixed with generalist humans (2 seeds, 4 rollouts)" in result.output
    table = pd.read_csv(out / "strategies.csv")
    (row,) = table[table["robot"] == "fixed"].itertuples()
    assert (row.recipe, row.seeds, row.humans) == ("generalist", 2, "generalist-s0 generalist-s1")


def test_score_fine_tunes_each_seed_for_its_share_of_the_minutes_then_scores_them(
    two_generalists,
):
    options = ScoreOptions(minutes=0.1, episodes=2, out=str(two_generalists / "score"),
                           runs=str(two_generalists / "runs"),
                           policies=str(two_generalists / "policies"))  # fmt: skip
    rows = score("front_linear", options, workers=1, progress=False, **SMALL_EVAL)
    assert list(rows["recipe"]) == ["generalist-tuned"] and rows["seeds"][0] == 2
    for seed in (0, 1):
        run = two_generalists / "runs" / tuned_name("front_linear", seed)
        record = json.loads((run / "run.json").read_text())
        assert record["parent"]["name"] == f"generalist-s{seed}"
        assert record["config"]["hours"] == pytest.approx(0.05 / 60)
        learned = json.loads((run / "checkpoint.json").read_text())["training_seconds"]
        assert 0.05 * 60 <= learned < 0.05 * 60 + 15  # stopped where its share ran out


def test_score_under_a_profile_scores_the_generalists_with_that_body(two_generalists):
    out = two_generalists / "score"
    result = CliRunner().invoke(main, ["score", "--robot", "fixed", "--minutes", "0",
                                       "--profile", "weak_arm", "--episodes", "1",
                                       "--gown-vertices", "300", "--horizon", "24", "--workers",
                                       "1", "--out", str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    table = pd.read_csv(out / "strategies.csv")
    assert list(table.loc[table["robot"] == "fixed", "profile"]) == ["weak_arm"]


def test_a_tuned_human_is_named_for_its_strategy_seed_and_profile():
    assert tuned_name("arc", 2) == "arc-generalist-tuned-s2"
    assert tuned_name("arc", 2, "weak_arm") == "arc-generalist-tuned-weak_arm-s2"


def test_score_refuses_an_unknown_profile_in_one_line(two_generalists):
    result = CliRunner().invoke(main, ["score", "--robot", "fixed", "--profile", "nobody"])
    assert result.exit_code == 1, result.output
    assert result.output.startswith("Error: capability profile 'nobody' cannot be scored: ")


def test_without_a_generalist_score_says_how_to_train_one(tmp_path, policies_on_path):
    with pytest.raises(ValueError, match=r"^no generalist human is installed: train one"):
        generalists()
    result = CliRunner().invoke(main, ["score", "--robot", "fixed", "--minutes", "0"])
    assert result.exit_code == 1 and "no generalist human is installed" in result.output


def test_score_refuses_a_name_that_is_no_generalist(two_generalists):
    with pytest.raises(ValueError, match=r"^not a generalist human: scripted \(have "):
        generalists(["scripted"])


@pytest.mark.parametrize(
    ("option", "value"), [("episodes", 0), ("episodes", MAX_EPISODES + 1), ("minutes", -1.0)]
)
def test_score_options_refuse_what_the_command_line_refuses_before_any_fine_tuning(option, value):
    with pytest.raises(ValueError, match=option):
        ScoreOptions(**{option: value})
    result = CliRunner().invoke(main, ["score", "--robot", "fixed", f"--{option}", str(value)])
    assert result.exit_code != 0 and "Traceback" not in result.output
