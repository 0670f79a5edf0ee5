"""A human runs with what it was made for, everywhere: its evaluation, its video and
``dressbench render`` show one episode, and another ablation or actuation is refused in one line."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from dressbench.cli import main
from dressbench.evaluation.cells import make_cell
from dressbench.evaluation.rollouts import run_episode
from dressbench.factory import make_human_env
from dressbench.plugins import load_human
from dressbench.scene.world import SceneConfig

ROBOT, HUMAN = "front_linear", "front_linear-default-s0"  # a shipped human of delta actuation
SEED = 3757552657
SMALL = {"gown_vertices": 300, "horizon": 40}


@pytest.fixture(scope="module")
def scored():
    """The evaluation's episode of SEED."""
    return run_episode(ROBOT, HUMAN, SEED, **SMALL)


def test_the_shipped_human_declares_delta_and_every_env_for_it_is_delta():
    assert load_human(HUMAN).actuation == "delta"
    assert make_human_env(ROBOT, human=HUMAN, **SMALL).env.config.scene.human.actuation == "delta"
    assert make_cell(ROBOT, HUMAN, **SMALL).config().scene.human.actuation == "delta"
    assert make_human_env(ROBOT, human="random", **SMALL).env.config.scene.human.actuation == "pd"


def test_under_pd_the_same_seed_is_another_episode(scored):
    """What a video under PD targets showed: not the scored episode, so the agreements below
    are not a coincidence of a still arm."""
    policy = load_human(HUMAN)
    env = make_human_env(ROBOT, ablation="complete", actuation="pd", **SMALL)  # no human given
    observation, info = env.reset(seed=SEED)
    done = False
    while not done:
        observation, _, terminated, truncated, info = env.step(policy.act(observation))
        done = terminated or truncated
    assert info["max_deformation"] != scored.max_deformation


def test_the_video_ends_where_the_evaluation_scored_the_same_seed(scored, tmp_path):
    pytest.importorskip("imageio")
    from dressbench.video import render_rollout

    video = render_rollout(ROBOT, HUMAN, tmp_path / "clip.gif", seed=SEED, every=20, **SMALL)
    assert video.steps == scored.steps == SMALL["horizon"]
    assert video.arm_progress == scored.final_arm_progress
    assert video.max_deformation == scored.max_deformation


def test_dressbench_render_ends_where_the_evaluation_scored_the_same_seed(scored, tmp_path):
    pytest.importorskip("imageio")
    out = tmp_path / "clip.gif"
    size = ["--gown-vertices", str(SMALL["gown_vertices"]), "--horizon", str(SMALL["horizon"])]
    command = ["render", "--robot", ROBOT, "--human", HUMAN, "--seed", str(SEED), "--out", str(out)]
    result = CliRunner().invoke(main, command + size)
    assert result.exit_code == 0, result.output
    expected = (
        f"arm progress {100 * scored.final_arm_progress:.1f} cm, max deformation "
        f"{scored.max_deformation:.2f} after {scored.steps} steps"
    )
    assert result.output.strip() == f"video written to {out}: {expected}"


def _one_line_error(call) -> str:
    with pytest.raises(ValueError) as caught:
        call()
    message = str(caught.value)
    assert "\n" not in message
    return message


@pytest.mark.parametrize(
    "stated",
    [{"actuation": "pd"}, {"actuation": "torque"}, {"scene": SceneConfig()}],
)
def test_running_a_human_under_another_actuation_is_one_line_naming_both(stated):
    message = _one_line_error(lambda: make_human_env(ROBOT, human=HUMAN, **SMALL, **stated))
    other = stated.get("actuation", "pd")
    assert message == (
        f"human {HUMAN!r} acts by 'delta' actuation; it cannot run under {other!r} actuation"
    )


def test_a_human_that_does_not_declare_an_actuation_acts_by_pd():
    class Undeclared:
        api_version = 1
        robot = None
        ablation = "complete"

    env = make_human_env("fixed", human=Undeclared(), **SMALL)
    assert env.env.config.scene.human.actuation == "pd"
    message = _one_line_error(
        lambda: make_human_env("fixed", human=Undeclared(), actuation="delta", **SMALL)
    )
    assert "acts by 'pd' actuation; it cannot run under 'delta' actuation" in message


def test_another_ablation_is_refused_in_one_line_naming_both():
    message = _one_line_error(lambda: make_cell(ROBOT, HUMAN, ablation="no_task", **SMALL))
    assert message == (
        f"human {HUMAN!r} declares ablation 'complete'; it cannot run with ablation 'no_task'"
    )
