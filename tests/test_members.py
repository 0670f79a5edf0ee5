"""A human's episodes against the family, split by the member each faced: the kind of
strategy and the direction of its start, read off the episodes table without running again."""

import numpy as np
import pandas as pd
import pytest

from dressbench.evaluation import evaluate
from dressbench.evaluation.members import (
    MEMBER_COLUMNS,
    SPLITS,
    approach,
    family_configs,
    member_table,
)
from dressbench.evaluation.schema import EPISODE_COLUMNS
from dressbench.plugins.family import KINDS, Family, Member, episode_members
from dressbench.plugins.robots import FixedGown, FrontLinear, SideLinear

TINY = {"horizon": 3, "gown_vertices": 300, "progress": False}


def synthetic_episodes(seeds: list[int]) -> pd.DataFrame:
    """An episodes table of one family cell whose progress is 0.1 x the kind's index: each
    kind's mean is known exactly."""
    kinds = [member.kind for member in episode_members(seeds)]
    rows = [{"robot": "family", "human": "generalist-s0", "ablation": "complete",
             "profile": "typical", "horizon": 400, "gown_vertices": 2000, "device": "cpu",
             "config_id": "cfg", "seed": 0, "episode": i, "episode_seed": seed,
             "final_arm_progress": 0.1 * KINDS.index(kind), "max_deformation": 1.5,
             "hand_in": kind != "still", "success": False, "dressed": False,
             "sim_failure": False, "return": 0.0, "steps": 400}
            for i, (seed, kind) in enumerate(zip(seeds, kinds, strict=True))]  # fmt: skip
    return pd.DataFrame(rows, columns=EPISODE_COLUMNS)


def test_each_episode_is_counted_under_the_member_its_seed_drew():
    seeds = list(range(1000, 1200))
    table = member_table(synthetic_episodes(seeds), {"family": Family.config})
    assert list(table.columns) == MEMBER_COLUMNS
    by_kind = table[table["split"] == "kind"].set_index("member")
    drawn = pd.Series([m.kind for m in episode_members(seeds)]).value_counts()
    assert by_kind["episodes"].to_dict() == drawn.to_dict()
    for kind in by_kind.index:
        assert by_kind.loc[kind, "final_arm_progress_mean"] == pytest.approx(
            0.1 * KINDS.index(kind)
        )
    assert by_kind.loc["still", "hand_in_rate"] == 0.0 and by_kind.loc["curve", "hand_in_rate"] == 1
    by_approach = table[table["split"] == "approach"]
    assert by_approach["episodes"].sum() == len(seeds)
    assert list(by_approach["member"]) == [
        a for a in SPLITS["approach"] if a in set(by_approach["member"])
    ]


def test_the_built_in_strategies_start_ahead_or_at_the_right_side():
    def start(strategy) -> Member:
        return Member("still", strategy.reset(np.random.default_rng(0)), None)

    assert approach(start(FixedGown())) == approach(start(FrontLinear())) == "ahead"
    assert approach(start(SideLinear())) == "right side"


def test_only_family_strategies_are_split():
    assert set(family_configs(["family", "fixed", "no_such_robot"])) == {"family"}
    episodes = synthetic_episodes([1, 2, 3]).assign(robot="fixed")
    assert member_table(episodes, family_configs(["fixed"])).empty


def test_an_evaluation_against_the_family_writes_its_members_and_another_removes_them(tmp_path):
    episodes = evaluate("family", "passive", episodes=4, workers=1, out=tmp_path, **TINY)
    table = pd.read_csv(tmp_path / "members.csv")
    assert table.groupby("split")["episodes"].sum().to_dict() == {"approach": 4, "kind": 4}
    kinds = [m.kind for m in episode_members([int(s) for s in episodes["episode_seed"]])]
    assert set(table.loc[table["split"] == "kind", "member"]) == set(kinds)
    assert "members.md" in (tmp_path / "README.md").read_text()
    assert "| family | passive | typical | kind |" in (tmp_path / "members.md").read_text()
    evaluate("fixed", "passive", episodes=2, workers=1, out=tmp_path, **TINY)
    assert not (tmp_path / "members.csv").exists() and not (tmp_path / "members.md").exists()
