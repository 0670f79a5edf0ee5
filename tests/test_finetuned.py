"""A fine-tuned human against its parent: paired over the same seeded rollouts."""

import numpy as np
import pandas as pd
import pytest
from test_strategies import episodes

from dressbench.evaluation.finetuned import finetuned_table, write_finetuned
from dressbench.evaluation.groups import TrainedHuman, human_group, trained_humans

PARENT = TrainedHuman("fixed", "default", "complete", 0)
CHILD = TrainedHuman("fixed", "tuned", "complete", 0, "limited_shoulder", "fixed-default-s0")
HUMANS = {"fixed-default-s0": PARENT, "fixed-limited_shoulder-tuned-s0": CHILD}


def played(change: np.ndarray, profile: str = "limited_shoulder") -> pd.DataFrame:
    """The parent and the child on the same 100 rollout seeds; the child's progress moved by
    ``change`` on each (the rollouts' own spread far wider than the change)."""
    base = np.random.default_rng(0).uniform(0.1, 0.6, 100)
    table = episodes({("fixed", "fixed-default-s0"): base,
                      ("fixed", "fixed-limited_shoulder-tuned-s0"): base + change})  # fmt: skip
    return table.assign(profile=profile)


def test_a_small_change_on_every_rollout_is_separated_though_the_rollouts_spread_widely():
    row = finetuned_table(played(np.full(100, 0.02)), HUMANS).iloc[0]
    assert (row.human, row.parent, row.profile, row.episodes) == (
        "fixed-limited_shoulder-tuned-s0", "fixed-default-s0", "limited_shoulder", 100
    )  # fmt: skip
    assert row.final_arm_progress_change == pytest.approx(0.02)
    assert row.final_arm_progress_change_ci_low == pytest.approx(0.02)  # every pair moved 0.02
    assert row.final_arm_progress - row.final_arm_progress_parent == pytest.approx(0.02)
    assert row.deeper == 1.0
    # some rollouts cross the 0.44 m elbow; the helper's deformation is 1.5 + progress
    assert row.verdict == "deeper, past the elbow more often, deforms more"


def test_changes_that_go_both_ways_are_not_separated():
    change = np.random.default_rng(1).normal(0.0, 0.1, 100)
    row = finetuned_table(played(change - change.mean()), HUMANS).iloc[0]
    assert row.final_arm_progress_change_ci_low < 0 < row.final_arm_progress_change_ci_high
    assert row.verdict == "not separated"
    worse = finetuned_table(played(np.full(100, -0.05)), HUMANS).iloc[0]
    assert worse.verdict == "shallower, past the elbow less often, deforms less"


def test_only_rollouts_both_played_in_one_setting_are_paired():
    both = played(np.full(100, 0.02))
    elsewhere = both[both["human"] == "fixed-default-s0"].assign(profile="typical")
    child = both[both["human"] != "fixed-default-s0"]
    assert finetuned_table(pd.concat([child, elsewhere]), HUMANS).empty  # another body
    assert finetuned_table(both, {"fixed-default-s0": PARENT}).empty  # nothing fine-tuned
    half = pd.concat([both[both["human"] == "fixed-default-s0"].iloc[:50], child])
    assert finetuned_table(half, HUMANS).iloc[0].episodes == 50


def test_the_parent_is_read_from_the_policy_file_and_a_malformed_one_is_none():
    metadata = {"robot": "fixed", "ablation": "complete", "seed": 0, "profile": "tremor",
                "parent": {"name": "fixed-default-s0", "sha256": "00"}}  # fmt: skip
    assert human_group("fixed-tremor-tuned-s0", "fixed", "complete", metadata).parent == (
        "fixed-default-s0"
    )
    for hostile in (["fixed-default-s0"], {"name": 3}, "fixed-default-s0", None):
        assert (
            human_group("x-s0", "fixed", "complete", metadata | {"parent": hostile}).parent is None
        )
    shipped = trained_humans([("front_linear-tremor-tuned-s0", "front_linear", "complete")])
    assert shipped["front_linear-tremor-tuned-s0"].parent == "front_linear-default-s0"


def test_the_files_are_written_with_the_pairs_and_removed_without_them(tmp_path):
    write_finetuned(tmp_path, played(np.full(100, 0.02)).replace(
        {"fixed-limited_shoulder-tuned-s0": "front_linear-tremor-tuned-s0",
         "fixed-default-s0": "front_linear-default-s0"}).assign(robot="front_linear"))  # fmt: skip
    text = (tmp_path / "finetuned.md").read_text()
    assert "| front_linear | limited_shoulder | front_linear-tremor-tuned-s0 |" in text
    assert (
        "+0.020 [+0.020, +0.020]" in text
        and "| deeper, past the elbow more often, deforms more |" in text
    )
    write_finetuned(tmp_path, played(np.zeros(100)).assign(human="front_linear-default-s0"))
    assert not (tmp_path / "finetuned.md").exists() and not (tmp_path / "finetuned.csv").exists()
