"""The paper's comparison: verdicts read off the intervals, and the files `reproduce` writes."""

import json
from fnmatch import fnmatch
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from dressbench import plugins
from dressbench.evaluation.readme import FILES, MARKER, README
from dressbench.evaluation.reproduction import (
    DOC_BEGIN,
    DOC_END,
    FAILS,
    HOLDS,
    PARTLY,
    ROLE_COLUMNS,
    ROLES,
    UNMEASURED,
    claims_table,
    doc_results,
    documented_results,
    paper_humans,
    reproduce,
    role_table,
    write_doc_results,
)
from dressbench.metrics import deformation_limit
from dressbench.training import TrainConfig, train

LIMIT = deformation_limit(1.0, 1.5)  # 2.02: where r_d reaches -0.1


def role(progress, deformation, success=0.0, episodes=100):
    """A role's pooled numbers with intervals of +-0.02 m, +-0.1 and +-10 points."""
    return {
        "episodes": episodes,
        "final_arm_progress_mean": progress,
        "final_arm_progress_ci_low": progress - 0.02,
        "final_arm_progress_ci_high": progress + 0.02,
        "max_deformation_mean": deformation,
        "max_deformation_ci_low": deformation - 0.1,
        "max_deformation_ci_high": deformation + 0.1,
        "success_rate": success,
        "success_ci_low": max(success - 0.1, 0.0),
        "success_ci_high": min(success + 0.1, 1.0),
    }


def roles_table(*numbers):
    rows = [{"role": r.name, "robot": r.robot, "ablation": r.ablation, **n}
            for r, n in zip(ROLES, numbers, strict=True)]  # fmt: skip
    return pd.DataFrame(rows).reindex(columns=ROLE_COLUMNS)


def verdicts(*numbers):
    return claims_table(roles_table(*numbers), LIMIT)["verdict"].tolist()


def test_the_papers_findings_hold_where_the_intervals_separate_as_claimed():
    paper_like = verdicts(
        role(0.50, 1.4, success=0.7),  # complete on fixed: dresses, gently
        role(0.40, 6.0),  # no_haptics: gets in, tears
        role(0.05, 1.3),  # no_task: hovers
        role(0.60, 1.5, success=0.8),  # front_linear
        role(0.62, 1.5, success=0.8),  # side_linear
    )
    assert paper_like == [HOLDS] * 5


def test_overlapping_intervals_or_the_wrong_direction_do_not_make_a_finding():
    found = verdicts(
        role(0.50, 1.95, success=0.7),  # its deformation CI reaches past the threshold
        role(0.40, 1.5),  # progress, but no tearing
        role(0.30, 1.3),  # enters
        role(0.53, 1.5, success=0.8),  # overlaps fixed: not higher
        role(0.30, 1.5),  # lower than fixed
    )
    assert found == [PARTLY, PARTLY, PARTLY, FAILS, PARTLY]


def test_a_claim_whose_policy_was_not_trained_is_not_measured():
    missing = role(float("nan"), float("nan"), episodes=0)
    found = verdicts(role(0.5, 1.4, 0.7), missing, role(0.05, 1.3), missing, missing)
    assert found == [HOLDS, UNMEASURED, HOLDS, UNMEASURED, UNMEASURED]


def test_a_verdict_resting_on_a_role_of_one_seed_says_so():
    table = roles_table(role(0.5, 1.4, 0.7), role(0.4, 6.0), role(0.05, 1.3), role(0.6, 1.5, 0.8),
                        role(0.62, 1.5, 0.8))  # fmt: skip
    table["humans"] = ["a-s0 a-s1 a-s2", "b-s0", "c-s0 c-s1", "d-s0 d-s1 d-s2", "e-s0 e-s1"]
    because = claims_table(table, LIMIT).set_index("claim")["because"]
    assert because[2].endswith("; one seed: the CI covers rollouts only (no_haptics on fixed)")
    assert "one seed" not in because[1] + because[3] + because[4] + because[5]


def test_a_roles_interval_spans_what_its_seeds_give_not_only_their_rollouts():
    rng = np.random.default_rng(0)
    progress = {"fixed-default-s0": 0.2, "fixed-default-s1": 0.4, "fixed-default-s2": 0.3}
    episodes = pd.DataFrame(
        [{"robot": "fixed", "human": human, "final_arm_progress": value, "max_deformation": 1.5,
          "hand_in": True, "success": value > 0.3, "dressed": False}
         for human, mean in progress.items() for value in rng.normal(mean, 0.05, 100)]
    )  # fmt: skip
    roles = role_table(episodes, {ROLES[0]: list(progress)})
    row = roles.iloc[0]
    assert row["episodes"] == 300 and row["final_arm_progress_seed_std"] == pytest.approx(0.1, 0.1)
    assert row["final_arm_progress_ci_low"] < 0.23 and row["final_arm_progress_ci_high"] > 0.37
    assert roles.iloc[1:]["episodes"].eq(0).all() and roles.iloc[1:]["success_rate"].isna().all()


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """Tiny real policies for three of the paper's roles, and one trained in another body, found
    through DRESSBENCH_POLICIES."""
    folder = tmp_path_factory.mktemp("reproduction")
    where = {"out": str(folder / "runs"), "policies": str(folder / "policies")}
    tiny = {"gown_vertices": 600, "horizon": 16, "samples_per_update": 128, "envs": 1,
            "timesteps": 64, **where}  # fmt: skip
    for robot, ablation, profile in (
        ("fixed", "complete", "typical"),
        ("fixed", "no_haptics", "typical"),
        ("front_linear", "complete", "typical"),
        ("fixed", "complete", "tremor"),
    ):
        train(TrainConfig(robot=robot, ablation=ablation, profile=profile, **tiny), progress=False)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("DRESSBENCH_POLICIES", str(folder / "policies"))
        plugins.refresh()
        yield folder
    plugins.refresh()


@pytest.fixture(scope="module")
def compared(trained):
    """The comparison of the tiny policies, 2 episodes a cell: its folder and claims."""
    out = trained / "results"
    claims = reproduce(episodes=2, workers=1, out=out, humans=paper_humans(), horizon=6,
                       gown_vertices=600, progress=False)  # fmt: skip
    return out, claims


def test_the_trained_humans_play_the_roles_of_their_robot_and_ablation(trained):
    humans = paper_humans()
    assert humans[ROLES[0]] == ["fixed-complete-trpo-s0"]
    assert humans[ROLES[1]] == ["fixed-no_haptics-trpo-s0"] and humans[ROLES[2]] == []


def test_a_role_takes_the_seeds_of_one_recipe_in_the_typical_body_unless_humans_are_named(trained):
    assert paper_humans(recipe="trpo")[ROLES[0]] == ["fixed-complete-trpo-s0"]
    assert not any(paper_humans(recipe="default").values())
    named = paper_humans(["fixed-complete-tremor-trpo-s0"])
    assert named[ROLES[0]] == ["fixed-complete-tremor-trpo-s0"]


def test_reproduce_scores_each_role_and_the_cross_play_and_writes_the_figures(compared):
    out, claims = compared
    assert claims.loc[claims["claim"] == 3, "verdict"].item() == UNMEASURED  # no no_task human
    cross = pd.read_csv(out / "cross_play.csv")
    assert sorted(zip(cross["human"], cross["robot"], strict=True)) == sorted(
        (human, robot)
        for human in ("fixed-complete-trpo-s0", "front_linear-complete-trpo-s0")
        for robot in ("fixed", "front_linear", "side_linear")
    )
    roles = pd.read_csv(out / "roles.csv")
    assert roles.loc[0, "episodes"] == 2 and roles.loc[2, "episodes"] == 0
    for figure in ("fig5_fixed_ablations", "fig6_final_scores", "fig7_linear_strategies",
                   "cross_play"):  # fmt: skip
        assert (out / f"{figure}.png").read_bytes()[:4] == b"\x89PNG"
    assert "| 3 |" in (out / "claims.md").read_text()
    assert json.loads((out / "run_meta.json").read_text())["command"] == "reproduce"
    assert "dressbench evaluate reproduce --episodes 2" in (out / "README.md").read_text()
    assert "| no_task on fixed | none trained | 0 |" in (out / "roles.md").read_text()
    known = {README, MARKER, *(name.replace("{robot}", "*") for name in FILES)}
    unknown = [p.name for p in out.iterdir() if not any(fnmatch(p.name, k) for k in known)]
    assert not unknown  # every file it writes is one the ownership check guards


def test_a_docs_results_block_is_rewritten_from_the_csvs_and_the_rest_kept(compared, tmp_path):
    out, _ = compared
    doc = tmp_path / "reproduction.md"
    doc.write_text(f"# Title\n\n{DOC_BEGIN}\nold numbers\n{DOC_END}\n\nWhere we differ.\n")
    write_doc_results(doc, out)
    assert documented_results(doc) == doc_results(out)
    assert "old numbers" not in doc.read_text() and doc.read_text().endswith("Where we differ.\n")
    assert "| 1 | the complete policy completes" in documented_results(doc)


def test_a_human_that_plays_none_of_the_papers_policies_is_refused_by_name(trained):
    with pytest.raises(ValueError, match="'scripted' plays none of the paper's policies"):
        paper_humans(["scripted"])


def test_docs_reproduction_states_the_numbers_of_the_committed_comparison():
    """docs/reproduction.md's results block is what results/reproduction's CSVs say."""
    root = Path(__file__).resolve().parents[1]
    assert documented_results(root / "docs" / "reproduction.md") == doc_results(
        root / "results" / "reproduction"
    )
