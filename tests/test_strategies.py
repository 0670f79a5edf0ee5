"""A strategy's score: humans grouped by training, two-level bootstrap, ranks, P(improvement)."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from dressbench.evaluation.bootstrap import (
    improvement,
    observed,
    percentile_interval,
    two_level_draws,
)
from dressbench.evaluation.groups import TrainedHuman, human_group, trained_humans
from dressbench.evaluation.schema import EPISODE_COLUMNS
from dressbench.evaluation.statistics import bootstrap_ci
from dressbench.evaluation.strategies import (
    ONE_SEED,
    STRATEGIES_BLOCK,
    improvement_table,
    strategy_rows_markdown,
    strategy_table,
    write_strategies,
)
from dressbench.plugins import human_plugins
from dressbench.policy_file import load_policy


def episodes(scores: dict[tuple[str, str], np.ndarray], ablation: str = "complete") -> pd.DataFrame:
    """An episodes table: each (robot, human) with its final arm progress values."""
    rows = [
        {"robot": robot, "human": human, "ablation": ablation, "profile": "typical",
         "horizon": 400,
         "gown_vertices": 2000, "device": "cpu", "config_id": f"cfg-{ablation}", "seed": 0,
         "episode": i, "episode_seed": i, "final_arm_progress": value,
         "max_deformation": 1.5 + value, "hand_in": value >= 0.18, "success": value >= 0.44,
         "dressed": value >= 0.6, "sim_failure": False, "return": 0.0, "steps": 400}
        for (robot, human), values in scores.items()
        for i, value in enumerate(values)
    ]  # fmt: skip
    return pd.DataFrame(rows, columns=EPISODE_COLUMNS)


def seeds_of(robot: str, means: list[float], spread: float = 0.05, n: int = 100, rng=None):
    """Humans ``robot-default-sK`` whose episodes centre on ``means``."""
    rng = rng or np.random.default_rng(0)
    return {(robot, f"{robot}-default-s{k}"): rng.normal(mean, spread, n)
            for k, mean in enumerate(means)}  # fmt: skip


# --- groups -------------------------------------------------------------------------------------


def test_a_policy_file_gives_its_group_and_seed():
    policy = load_policy(human_plugins()["fixed-no_haptics-default-s0"].value)
    assert human_group(policy.name, "fixed", "complete", policy.metadata) == TrainedHuman(
        "fixed", "default", "no_haptics", 0
    )


def test_the_older_recipe_is_a_group_of_its_own_though_its_config_says_default():
    metadata = {
        "robot": "fixed",
        "ablation": "complete",
        "seed": 2,
        "config": {"recipe": "default", "seed": 2},
    }  # as its policy file records
    human = human_group("fixed-complete-trpo-delta-curriculum-s2", "fixed", "complete", metadata)
    assert human == TrainedHuman("fixed", "trpo-delta-curriculum", "complete", 2)


def test_without_metadata_the_name_robot_ablation_recipe_seed_tells():
    assert human_group("fixed-no_haptics-default-s3", "fixed", "no_haptics") == TrainedHuman(
        "fixed", "default", "no_haptics", 3
    )
    assert human_group("fixed-complete-trpo-s0-timesteps1000", "fixed", "complete").recipe == (
        "trpo-timesteps1000"
    )
    assert human_group("passive", "fixed", "complete") is None  # a baseline: no seed


def test_a_name_without_a_seed_takes_the_metadata_seed_and_config_recipe():
    metadata = {"robot": "fixed", "ablation": "complete", "config": {"recipe": "paper", "seed": 4}}
    assert human_group("mine", "fixed", "complete", metadata) == TrainedHuman(
        "fixed", "paper", "complete", 4
    )
    assert human_group("any", "fixed", "complete", {"robot": None, "ablation": "complete"}) is None


def test_installed_policies_group_the_shipped_humans():
    found = trained_humans([("fixed-default-s0", "fixed", "complete"),
                            ("front_linear-default-s0", "front_linear", "complete"),
                            ("scripted", "fixed", "complete")])  # fmt: skip
    assert {name: human.group for name, human in found.items()} == {
        "fixed-default-s0": ("fixed", "default", "complete", "typical"),
        "front_linear-default-s0": ("front_linear", "default", "complete", "typical"),
    }


# --- the two-level bootstrap --------------------------------------------------------------------


def test_two_level_intervals_cover_the_true_mean_and_pooled_episodes_do_not():
    """4 seeds x 100 episodes: seed means ~ N(mu, 0.015), episodes ~ N(seed mean, 0.15)."""
    rng = np.random.default_rng(0)
    mu, draws, seeds, n = 0.4, 400, 4, 100
    two_level = pooled = 0
    for draw in range(draws):
        means = rng.normal(mu, 0.015, seeds)
        values = (means[:, None] + rng.normal(0.0, 0.15, (seeds, n))).ravel()
        low, high = percentile_interval(two_level_draws([n] * seeds, 1000, rng).means(values))
        two_level += low <= mu <= high
        low, high = bootstrap_ci(values, draw, resamples=1000)
        pooled += low <= mu <= high
    assert 0.90 <= two_level / draws <= 0.99
    assert pooled / draws < two_level / draws - 0.05


def test_every_seed_weighs_the_same_whatever_its_episodes():
    values = np.r_[np.zeros(100), np.ones(10)]
    assert observed([100, 10]).means(values) == pytest.approx([0.5])
    draws = two_level_draws([100, 10], 2000, np.random.default_rng(1))
    assert np.allclose(draws.weight.sum(axis=1), 1.0)
    assert draws.means(values).mean() == pytest.approx(0.5, abs=0.03)


def test_draws_are_reproducible_from_the_generator():
    a = two_level_draws([5, 7], 50, np.random.default_rng(3))
    b = two_level_draws([5, 7], 50, np.random.default_rng(3))
    assert np.array_equal(a.index, b.index) and np.array_equal(a.weight, b.weight)


def test_improvement_counts_ties_half():
    a, b = np.array([0.0, 1.0, 2.0]), np.array([1.0, 1.0])
    assert improvement(a, observed([3]), b, observed([2]))[0] == pytest.approx(0.5)
    x, y = np.array([0.0, 0.3]), np.array([0.0, 0.1, 0.2])
    expected = np.mean((x[:, None] > y) + 0.5 * (x[:, None] == y))
    assert improvement(x, observed([2]), y, observed([3]))[0] == pytest.approx(expected)


# --- the strategy table -------------------------------------------------------------------------


def test_a_strategy_row_pools_its_seeds_with_their_spread():
    scores = seeds_of("fixed", [0.30, 0.40, 0.50])
    table = strategy_table(episodes(scores), resamples=2000)
    (row,) = table.itertuples()
    assert (row.robot, row.recipe, row.seeds, row.episodes) == ("fixed", "default", 3, 300)
    assert row.training_seeds == "0 1 2" and row.note == ""
    seed_means = [values.mean() for values in scores.values()]
    assert row.final_arm_progress_mean == pytest.approx(np.mean(seed_means))
    assert row.final_arm_progress_seed_std == pytest.approx(np.std(seed_means, ddof=1))
    assert row.final_arm_progress_ci_low < 0.35 and row.final_arm_progress_ci_high > 0.45
    assert 0.0 <= row.success_ci_low <= row.success_rate <= row.success_ci_high <= 1.0


def test_a_group_with_one_seed_says_so():
    table = strategy_table(episodes(seeds_of("side_linear", [0.5])), resamples=500)
    (row,) = table.itertuples()
    assert row.seeds == 1 and row.note == ONE_SEED and np.isnan(row.final_arm_progress_seed_std)


def test_overlapping_strategies_share_a_rank_and_one_wholly_below_comes_after_them():
    scores = (seeds_of("a", [0.50, 0.52, 0.48]) | seeds_of("b", [0.49, 0.53, 0.47])
              | seeds_of("c", [0.10, 0.11, 0.12]))  # fmt: skip
    table = strategy_table(episodes(scores), resamples=2000)
    assert dict(zip(table["robot"], table["rank"], strict=True)) == {"a": 1, "b": 1, "c": 3}


def test_only_strategies_of_one_recipe_and_ablation_compete():
    table = strategy_table(
        pd.concat([episodes(seeds_of("a", [0.5])), episodes(seeds_of("b", [0.1]), "no_task")]),
        resamples=500,
    )
    assert list(table["rank"]) == [1, 1]
    assert improvement_table(episodes(seeds_of("a", [0.5])), resamples=500).empty


def test_a_human_on_a_strategy_it_was_not_trained_for_is_left_out():
    scores = seeds_of("fixed", [0.4]) | {("front_linear", "fixed-default-s0"): np.ones(100)}
    assert list(strategy_table(episodes(scores), resamples=500)["robot"]) == ["fixed"]


def test_a_generalists_seeds_score_every_strategy_as_a_group_of_their_own():
    humans = {f"generalist-s{k}": human_group(f"generalist-s{k}", "fixed", "complete",
                                              {"robot": None, "ablation": "complete", "seed": k})
              for k in range(3)}  # fmt: skip
    assert humans["generalist-s1"] == TrainedHuman(None, "generalist", "complete", 1)
    rng = np.random.default_rng(0)
    scores = {(robot, name): rng.normal(0.3, 0.05, 50)
              for robot in ("fixed", "front_linear") for name in humans}  # fmt: skip
    table = strategy_table(episodes(scores), humans, resamples=200)
    assert sorted(table["robot"]) == ["fixed", "front_linear"]
    assert set(table["recipe"]) == {"generalist"} and set(table["seeds"]) == {3}
    named = trained_humans([(name, robot, "complete") for robot, name in scores])
    assert named["generalist-s2"] == TrainedHuman(None, "generalist", "complete", 2)


def test_tables_are_reproducible_and_a_row_does_not_depend_on_the_others():
    one = episodes(seeds_of("a", [0.4, 0.5]))
    both = pd.concat([one, episodes(seeds_of("b", [0.2, 0.3], rng=np.random.default_rng(5)))])
    first = strategy_table(one, seed=7, resamples=500)
    pd.testing.assert_frame_equal(first, strategy_table(one, seed=7, resamples=500))
    alongside = strategy_table(both, seed=7, resamples=500)
    pd.testing.assert_frame_equal(
        alongside[alongside["robot"] == "a"].drop(columns="rank").reset_index(drop=True),
        first.drop(columns="rank"),
    )


# --- the probability of improvement -------------------------------------------------------------


def test_identical_strategies_improve_on_each_other_half_the_time():
    rng = np.random.default_rng(2)
    scores = seeds_of("a", [0.4] * 3, rng=rng) | seeds_of("b", [0.4] * 3, rng=rng)
    (pair,) = improvement_table(episodes(scores), resamples=2000).itertuples()
    assert pair.probability == pytest.approx(0.5, abs=0.05)
    assert pair.ci_low < 0.5 < pair.ci_high and not pair.separated


def test_a_clearly_better_strategy_goes_deeper_nearly_always():
    scores = seeds_of("worse", [0.30, 0.32, 0.28]) | seeds_of("better", [0.50, 0.52, 0.48])
    (pair,) = improvement_table(episodes(scores), resamples=2000).itertuples()
    assert (pair.robot, pair.versus) == ("better", "worse")
    assert pair.probability > 0.9 and pair.ci_low > 0.5 and pair.separated


# --- the files ----------------------------------------------------------------------------------


def test_the_files_are_written_beside_the_cell_table(tmp_path):
    scores = seeds_of("fixed", [0.3, 0.4, 0.35]) | seeds_of("front_linear", [0.5])
    write_strategies(tmp_path, episodes(scores))
    table = pd.read_csv(tmp_path / "strategies.csv")
    assert list(table["robot"]) == ["front_linear", "fixed"]
    markdown = (tmp_path / "strategies.md").read_text()
    assert "| fixed | default | complete | typical | 3 | 300 |" in markdown
    assert ONE_SEED in markdown
    improvements = (tmp_path / "improvement.md").read_text()
    assert "| front_linear | fixed | default | complete | typical |" in improvements
    assert len(pd.read_csv(tmp_path / "improvement.csv")) == 1
    assert (tmp_path / "strategies.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_strategies_under_several_profiles_get_a_figure_of_strategy_by_profile(tmp_path):
    scores = seeds_of("fixed", [0.3, 0.4]) | seeds_of("front_linear", [0.5, 0.45])
    typical = episodes(scores)
    weak = episodes({key: values - 0.2 for key, values in scores.items()}).assign(
        profile="weak_arm"
    )
    write_strategies(tmp_path, typical)
    assert not (tmp_path / "profiles.png").exists()
    table = write_strategies(tmp_path, pd.concat([typical, weak], ignore_index=True))
    assert sorted(zip(table["robot"], table["profile"], strict=True)) == [
        ("fixed", "typical"), ("fixed", "weak_arm"),
        ("front_linear", "typical"), ("front_linear", "weak_arm")]  # fmt: skip
    assert (tmp_path / "profiles.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    write_strategies(tmp_path, typical)
    assert not (tmp_path / "profiles.png").exists()  # no stale figure of profiles not scored


def test_without_trained_humans_the_table_says_so_and_no_figure_is_left(tmp_path):
    (tmp_path / "strategies.png").write_bytes(b"an earlier run's")
    write_strategies(tmp_path, episodes({("fixed", "passive"): np.zeros(3)}))
    assert "no trained human" in (tmp_path / "strategies.md").read_text()
    assert not (tmp_path / "strategies.png").exists()


def test_the_readme_states_the_committed_strategy_table():
    """README.md's strategies block is the table of results/strategies.md, as written."""
    root = Path(__file__).resolve().parents[1]
    committed = (root / "results" / "strategies.md").read_text()
    assert committed.endswith("\n\n" + STRATEGIES_BLOCK.read(root / "README.md"))


def test_a_docs_strategies_block_is_rewritten_and_the_rest_kept(tmp_path):
    doc = tmp_path / "README.md"
    doc.write_text(
        f"# Title\n\n{STRATEGIES_BLOCK.begin}\nold table\n{STRATEGIES_BLOCK.end}\n\nMore.\n"
    )
    table = write_strategies(tmp_path, episodes(seeds_of("fixed", [0.3, 0.4])))
    STRATEGIES_BLOCK.write(doc, strategy_rows_markdown(table))
    assert (tmp_path / "strategies.md").read_text().endswith(STRATEGIES_BLOCK.read(doc))
    assert "old table" not in doc.read_text() and doc.read_text().endswith("\n\nMore.\n")
    doc.write_text(f"{STRATEGIES_BLOCK.end}\n{STRATEGIES_BLOCK.begin}\n")  # out of order
    with pytest.raises(ValueError, match=r"README.md has no strategies block"):
        STRATEGIES_BLOCK.read(doc)
