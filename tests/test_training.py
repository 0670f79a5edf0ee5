"""Training a human model: a tiny run end to end, kill and resume, and broken policy files."""

import json
import os
import re
import signal
import subprocess
import sys
import time
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from sb3_contrib import TRPO

from dressbench import plugins
from dressbench.cli import main
from dressbench.config import RewardConfig
from dressbench.evaluation import evaluate, leaderboard, leaderboard_cells, make_cell
from dressbench.factory import make_human_env
from dressbench.training import TrainConfig, load_policy, train
from dressbench.training.curriculum import CurriculumConfig
from dressbench.training.run import recorded_config
from dressbench.training.summary import (
    STEPS,
    comparison_figure,
    write_learning_comparison,
    write_learning_summary,
)
from dressbench.training.tear import TearConfig, TornGown
from dressbench.training.warmup import DeformationShare, WarmupConfig

TINY = {"gown_vertices": 600, "horizon": 32, "samples_per_update": 128, "envs": 1}


def tiny_config(tmp_path, **changes) -> TrainConfig:
    options = TINY | {"out": str(tmp_path / "runs"), "policies": str(tmp_path / "policies")}
    return TrainConfig(**(options | changes))


def test_timesteps_are_honoured_as_given_not_rounded_up_to_a_whole_update(tmp_path):
    path = train(tiny_config(tmp_path, timesteps=200, name="exact"), progress=False)
    assert json.loads(path.read_text())["steps"] == 200  # updates are of 128 samples
    short = train(tiny_config(tmp_path, timesteps=100, name="short"), progress=False)
    assert json.loads(short.read_text())["steps"] == 100  # less than one update: exported as is


def test_a_budget_of_hours_stops_the_run_where_it_runs_out_and_exports_it(tmp_path):
    config = tiny_config(tmp_path, timesteps=1_000_000, hours=3 / 3600, name="budget")
    path = train(config, progress=False)
    steps = json.loads(path.read_text())["steps"]
    result = json.loads((tmp_path / "runs" / "budget" / "run.json").read_text())["result"]
    assert 0 < steps < 1_000_000 and result["steps"] == steps
    assert result["training_seconds"] == pytest.approx(3, abs=0.5)  # stopped where it ran out
    again = train(config, progress=False)  # the budget is spent: nothing more to learn
    assert json.loads(again.read_text())["steps"] == steps
    more = train(replace(config, hours=6 / 3600), progress=False)  # a larger one goes on
    assert json.loads(more.read_text())["steps"] > steps


def test_run_json_records_steps_wall_time_and_speed(tmp_path):
    # SB3 logs its elapsed time in whole seconds: a run of 256 tiny steps can take less than one
    train(tiny_config(tmp_path, timesteps=1024, name="timed"), progress=False)
    result = json.loads((tmp_path / "runs" / "timed" / "run.json").read_text())["result"]
    assert result["steps"] == 1024 and result["training_seconds"] > 0
    assert result["env_steps_per_second"] == pytest.approx(1024 / result["training_seconds"], 0.01)
    files = write_learning_summary(tmp_path / "runs" / "timed", tmp_path / "summary")
    assert [f.name for f in files] == ["timed-progress.csv", "timed-learning.png", "timed-run.json"]
    assert json.loads(files[2].read_text())["result"] == result  # a summary carries its config


def test_a_comparison_draws_each_runs_learning_curve_on_shared_axes(tmp_path):
    progress = {}
    for label, rate in (("default recipe", 0.4), ("paper's preset", 0.1)):
        table = pd.DataFrame({STEPS: [4096, 8192, 12288],
                              "rollout/final_arm_progress": [0.0, rate / 2, rate]})  # fmt: skip
        progress[label] = tmp_path / f"{label}.csv"
        table.to_csv(progress[label], index=False)
    png = write_learning_comparison(progress, tmp_path / "figures" / "recipes.png", "fixed")
    assert png.read_bytes().startswith(b"\x89PNG")
    figure = comparison_figure({k: pd.read_csv(v) for k, v in progress.items()}, "fixed")
    arm = next(a for a in figure.axes if a.get_title() == "final arm progress")
    assert [line.get_label() for line in arm.lines] == list(progress)
    assert arm.get_legend() is not None  # the first panel the runs logged carries the legend
    assert [line.get_ydata()[-1] for line in arm.lines] == [0.4, 0.1]


@pytest.mark.parametrize(
    "coach",
    [CurriculumConfig(share=1.0, held_share=1.0, window=2, promote_at=0.0),  # after 2 episodes
     CurriculumConfig(share=1.0, held_share=1.0, judge="mean", trials=2, judge_every=128,
                      promote_at=0.0)],
    ids=["judged-on-training-episodes", "judged-on-trials-of-the-mean"],
)  # fmt: skip
def test_a_run_with_the_curriculum_widens_its_near_starts_and_keeps_the_level(tmp_path, coach):
    config = tiny_config(tmp_path, timesteps=256, name="coached", curriculum=coach)
    assert json.loads(train(config, progress=False).read_text())["steps"] == 256
    folder = tmp_path / "runs" / "coached"
    reach = json.loads((folder / "checkpoint.json").read_text())["curriculum_reach"]
    assert reach > coach.first_reach
    logged = pd.read_csv(folder / "logs" / "progress.csv")
    assert logged["curriculum/reach"].is_monotonic_increasing
    assert logged["curriculum/reach"].iloc[-1] == pytest.approx(reach)
    assert ("curriculum/trial_hand_in_rate" in logged) == (coach.judge == "mean")
    assert json.loads((folder / "run.json").read_text())["config"]["curriculum"] == asdict(coach)


def test_the_paper_recipe_trains_torques_and_its_policy_is_scored_with_torques(
    tmp_path, policies_on_path
):
    paper = TrainConfig.preset("paper")
    assert (paper.algo, paper.actuation, paper.samples_per_update) == ("trpo", "torque", 50_000)
    assert paper.curriculum is None and paper.warmup is None
    default = TrainConfig.preset()
    assert default.actuation == "delta" and default.curriculum == CurriculumConfig()
    assert (paper.haptics, TrainConfig.preset().haptics) == ("newtons", "log")
    assert paper.norm_epsilon == 1e-8  # SB3's VecNormalize default
    options = TINY | {"out": str(tmp_path / "runs"), "policies": str(tmp_path / "policies")}
    options |= {"timesteps": 128, "samples_per_update": 128}
    path = train(TrainConfig.preset("paper", **(options | {"name": "paperish"})), progress=False)
    assert json.loads(path.read_text())["actuation"] == "torque"
    assert json.loads(path.read_text())["haptics"] == "newtons"  # the paper's raw forces
    plugins.refresh()
    config = make_cell("fixed", "paperish", gown_vertices=600, horizon=8).config()
    assert config.scene.human.actuation == "torque"


def test_a_tiny_training_run_exports_a_policy_that_evaluate_can_name(tmp_path, policies_on_path):
    path = train(tiny_config(tmp_path, timesteps=256, name="tiny"), progress=False)
    meta = json.loads(path.read_text())
    assert meta["robot"] == "fixed" and meta["algorithm"] == "trpo" and meta["steps"] >= 256
    assert meta["seed"] == 0 and "versions" in meta and "git_commit" in meta
    assert meta["haptics"] == "log" and load_policy(path).haptics == "log"  # the default recipe
    assert meta["obs_normalization"]["epsilon"] == 0.1  # a floor under each feature's variance
    logs = tmp_path / "runs" / "tiny" / "logs"
    assert (logs / "progress.csv").exists()
    assert any(f.name.startswith("events.out.tfevents") for f in logs.iterdir())
    curves = pd.read_csv(tmp_path / "runs" / "tiny" / "tiny-progress.csv")  # learning summary
    assert curves["time/total_timesteps"].is_monotonic_increasing and len(curves) >= 2
    assert (tmp_path / "runs" / "tiny" / "tiny-learning.png").stat().st_size > 0

    plugins.refresh()
    assert plugins.human_plugins()["tiny"].ok
    table = evaluate("fixed", "tiny", episodes=2, workers=1, out=str(tmp_path / "results"),
                     gown_vertices=600, horizon=16)  # fmt: skip
    assert list(table["human"]) == ["tiny", "tiny"]
    assert np.isfinite(table["final_arm_progress"]).all()

    board = leaderboard(episodes=1, workers=1, out=str(tmp_path / "board"), gown_vertices=600,
                        horizon=8)  # fmt: skip
    cells = set(zip(board["robot"], board["human"], strict=True))
    assert ("fixed", "tiny") in cells and ("front_linear", "tiny") not in cells
    assert {("side_linear", "scripted"), ("fixed", "passive")} <= cells


def test_training_resumes_after_a_kill_and_loses_at_most_one_checkpoint(tmp_path):
    config = tiny_config(tmp_path, timesteps=2048, checkpoint_every=128, name="killed")
    code = (
        "from dressbench.training import TrainConfig, train; import json, sys; "
        "train(TrainConfig.from_dict(json.loads(sys.argv[1])), progress=False)"
    )
    worker = subprocess.Popen([sys.executable, "-c", code, json.dumps(asdict(config))])
    marker = tmp_path / "runs" / "killed" / "checkpoint.json"
    deadline = time.time() + 300
    while not (marker.exists() and json.loads(marker.read_text())["timesteps"] >= 256):
        assert worker.poll() is None, "training ended before it could be killed"
        assert time.time() < deadline
        time.sleep(0.2)
    os.kill(worker.pid, signal.SIGKILL)
    worker.wait()
    saved = json.loads(marker.read_text())["timesteps"]
    assert saved < 2048

    path = train(config, progress=False)  # the same call again: it resumes
    assert json.loads(path.read_text())["steps"] >= 2048
    logs = tmp_path / "runs" / "killed" / "logs"
    progress = pd.read_csv(logs / "progress.csv")
    assert progress["time/total_timesteps"].min() > saved  # it went on from the checkpoint
    before = pd.read_csv(logs / "progress-history.csv")  # the killed session's log is kept
    assert 0 < before["time/total_timesteps"].max() <= saved


def test_a_malformed_policy_file_is_reported_by_name(tmp_path, policies_on_path):
    folder = tmp_path / "policies"  # made by the fixture
    (folder / "broken.safetensors").write_bytes(b"not tensors")
    (folder / "broken.json").write_text('{"format": "dressbench-policy", "format_version": 1')
    plugins.refresh()
    record = plugins.human_plugins()["broken"]
    assert not record.ok and "broken.json" in record.error
    with pytest.raises(plugins.BrokenPluginError, match="broken"):
        plugins.load_human("broken")
    with pytest.raises(ValueError, match="broken.json"):
        load_policy(folder / "broken.json")


@pytest.mark.slow
def test_the_default_recipe_trains_a_front_linear_human_that_beats_scripted(
    tmp_path, policies_on_path
):
    """Real learning (hours on 2 cores): ``dressbench train --robot front_linear`` with the
    default recipe, then 20 seeded episodes of it and of ``scripted`` on ``front_linear``.

    DRESSBENCH_LEARN_STEPS overrides the recipe's steps; DRESSBENCH_LEARN_RUNS names a runs folder
    to train in, so a run already there is resumed rather than started again.
    """
    recipe = TrainConfig.preset(robot="front_linear")
    steps = int(os.environ.get("DRESSBENCH_LEARN_STEPS", recipe.timesteps))
    runs = os.environ.get("DRESSBENCH_LEARN_RUNS", str(tmp_path / "runs"))
    config = TrainConfig.preset(robot="front_linear", timesteps=steps, out=runs,
                                policies=str(tmp_path / "policies"))  # fmt: skip
    train(config, progress=False)
    plugins.refresh()
    scores = {}
    for human in (config.run_name, "scripted"):
        table = evaluate("front_linear", human, episodes=20, seed=123, out=str(tmp_path / human))
        scores[human] = table["final_arm_progress"].mean()
    print(f"mean final arm progress after {steps} steps: {scores}")
    assert scores[config.run_name] > scores["scripted"] + 0.05


def test_the_deformation_warmup_grows_r_d_into_the_papers_reward():
    warmup = WarmupConfig(start=100, end=300)
    assert [warmup.share(s) for s in (0, 100, 200, 300, 10_000)] == [0.0, 0.0, 0.5, 1.0, 1.0]
    assert TrainConfig.preset("paper").warmup is None  # the paper's reward from the first step
    with pytest.raises(ValueError, match="start <= end"):
        WarmupConfig(start=2, end=1)


def test_a_warming_up_run_logs_the_share_of_r_d_it_trained_on(tmp_path):
    config = tiny_config(tmp_path, timesteps=384, name="warm", warmup=WarmupConfig(128, 256))
    train(config, progress=False)
    logged = pd.read_csv(tmp_path / "runs" / "warm" / "logs" / "progress.csv")
    assert logged["warmup/deformation_share"].tolist() == [0.0, 0.0, 1.0]  # at 0, 128, 256 steps


def test_the_deformation_share_scales_only_the_deformation_term():
    rewards = {}
    for share in (0.0, 0.5, 1.0):
        env = DeformationShare(make_human_env("fixed", gown_vertices=600, horizon=8), share)
        env.reset(seed=3)
        _, rewards[share], _, _, info = env.step(np.zeros(env.action_space.shape))
        env.close()
    deformation = info["reward_terms"]["deformation"]
    assert deformation < 0.0  # the hanging gown's triangles are a little stretched
    assert rewards[1.0] == pytest.approx(sum(info["reward_terms"].values()))  # the paper's reward
    assert rewards[1.0] - rewards[0.0] == pytest.approx(deformation)
    assert rewards[0.5] - rewards[0.0] == pytest.approx(deformation / 2)


def test_a_torn_gown_ends_a_training_episode_once_the_deformation_term_has_its_full_weight():
    env = DeformationShare(make_human_env("fixed", gown_vertices=600, horizon=8), 0.0)
    torn = TornGown(env, TearConfig(ratio=1.01))  # the hanging gown is a little above 1.01
    torn.reset(seed=3)
    _, _, terminated, _, info = torn.step(np.zeros(torn.action_space.shape))
    assert info["max_deformation"] > 1.01 and not terminated and info["torn"] == 0.0  # warming up
    env.set_share(0.5)
    _, _, terminated, _, info = torn.step(np.zeros(torn.action_space.shape))
    assert not terminated and info["torn"] == 0.0  # still warming up
    env.set_share(1.0)
    _, _, terminated, _, info = torn.step(np.zeros(torn.action_space.shape))
    assert terminated and info["torn"] == 1.0
    torn.close()
    with pytest.raises(ValueError, match="above 1"):
        TearConfig(ratio=0.9)


def test_a_run_with_a_tear_limit_logs_how_many_episodes_tore(tmp_path):
    config = tiny_config(tmp_path, timesteps=256, name="tear", warmup=None,
                         tear=TearConfig(ratio=1.01))  # fmt: skip
    train(config, progress=False)
    logged = pd.read_csv(tmp_path / "runs" / "tear" / "logs" / "progress.csv")
    assert logged["rollout/torn_rate"].iloc[-1] == 1.0  # every episode ends at its first step
    assert logged["rollout/ep_len_mean"].iloc[-1] == 1.0


def test_the_default_recipe_ends_episodes_at_the_deformation_threshold_and_paper_never():
    assert TrainConfig().tear == TearConfig(ratio=RewardConfig().limit)
    assert RewardConfig().limit == pytest.approx(2.02, abs=0.005)
    assert TrainConfig.preset("paper").tear is None


def test_a_run_starts_its_policy_at_the_action_std_it_is_given(tmp_path):
    train(tiny_config(tmp_path, timesteps=8, name="narrow", action_std=0.4), progress=False)
    model = TRPO.load(tmp_path / "runs" / "narrow" / "checkpoint.zip", device="cpu")
    assert np.exp(model.policy.log_std.detach().numpy()) == pytest.approx(0.4)
    with pytest.raises(ValueError, match="action_std"):
        TrainConfig(action_std=0.0)


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"algo": "sac"}, "unknown algo 'sac': choose one of trpo, ppo"),
        ({"haptics": "kg"}, "unknown haptics 'kg'"),
        ({"ablation": "no_eyes"}, "unknown ablation 'no_eyes'"),
        ({"timesteps": 0}, "timesteps must be at least 1"),
        ({"horizon": 0}, "horizon must be from 1"),
        ({"name": "../escape"}, "name must be a plain file name"),
        ({"init": "a/b"}, "init must be a plain file name"),
        ({"action_std": 0.0}, "action_std must be a positive number, got 0.0"),
        ({"hours": float("inf")}, "hours must be a positive number, got inf"),
    ],
)
def test_a_train_config_refuses_in_python_what_the_command_line_refuses(bad, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        TrainConfig(**bad)
    assert TrainConfig(init=None).init is None  # an optional option left out


@pytest.mark.parametrize(
    ("command", "option", "value", "message"),
    [
        ("train", "--action-std", "0", "must be a positive number, got 0.0"),
        ("train", "--hours", "-1", "must be a positive number, got -1.0"),
        ("sweep", "--hours", "nan", "must be a positive number, got nan"),
        ("sweep", "--samples-per-update", "0", "must be at least 1"),
    ],
)
def test_the_command_line_refuses_a_training_setting_with_the_fields_own_check(
    command, option, value, message
):
    result = CliRunner().invoke(main, [command, "--robot", "fixed", option, value])
    assert result.exit_code == 2 and message in result.output, result.output


def test_a_no_haptics_run_records_no_tear_limit_since_its_reward_has_no_r_d():
    assert TrainConfig(ablation="no_haptics").record()["tear"] is None
    assert TrainConfig(ablation="no_task").record()["tear"] == asdict(TearConfig())


@pytest.mark.parametrize(
    ("flags", "expected"),
    [
        ([], {"warmup": asdict(WarmupConfig()), "tear": asdict(TearConfig())}),
        (["--no-warmup", "--no-curriculum", "--no-tear-limit"],
         {"warmup": None, "curriculum": None, "tear": None}),
        (["--tear-limit", "3"], {"tear": {"ratio": 3.0}}),
        (["--action-std", "0.4"], {"action_std": 0.4}),
        (["--envs-per-process", "2"], {"envs": 1, "envs_per_process": 2}),
    ],
)  # fmt: skip
def test_train_options_turn_the_recipes_parts_off_or_change_them(tmp_path, flags, expected):
    where = ["--out", str(tmp_path / "runs"), "--policies", str(tmp_path / "policies")]
    tiny = ["--gown-vertices", "600", "--envs", "1", "--timesteps", "8"]
    result = CliRunner().invoke(main, ["train", "--robot", "fixed", "--name", "flags", *where,
                                       *tiny, *flags])  # fmt: skip
    assert result.exit_code == 0, result.output
    config = json.loads((tmp_path / "runs" / "flags" / "run.json").read_text())["config"]
    assert {key: config[key] for key in expected} == expected


def test_a_config_comes_back_whole_from_its_run_json_fields():
    config = TrainConfig(robot="side_linear", curriculum=CurriculumConfig(share=0.3),
                         tear=TearConfig(2.5))  # fmt: skip
    assert TrainConfig.from_dict(json.loads(json.dumps(asdict(config)))) == config
    assert TrainConfig.from_dict(asdict(TrainConfig.preset("paper"))).warmup is None


def test_a_run_json_of_settings_this_dressbench_does_not_know_is_refused_in_one_line(tmp_path):
    folder = tmp_path / "runs" / "future"
    folder.mkdir(parents=True)
    record = TrainConfig(name="future").record() | {"wings": 2}
    (folder / "run.json").write_text(json.dumps({"config": record}))
    with pytest.raises(ValueError, match=r"run\.json: settings .* does not know: wings"):
        recorded_config(folder)


def test_a_run_folder_moved_to_another_place_resumes_there(tmp_path):
    first = tiny_config(tmp_path, timesteps=256, name="moved", out=str(tmp_path / "here"))
    train(first, progress=False)
    folder = tmp_path / "elsewhere" / "moved"
    (tmp_path / "here" / "moved").rename(folder.parent.mkdir() or folder)
    for name in ("run.json", "checkpoint.json"):
        assert str(tmp_path) not in (folder / name).read_text()  # no absolute path inside
    path = train(replace(first, timesteps=512, out=str(folder.parent)), progress=False)
    assert json.loads(path.read_text())["steps"] == 512
    steps = pd.read_csv(folder / "logs" / "progress-history.csv")["time/total_timesteps"]
    assert steps.max() == 256  # the first session's log was kept, its steps not trained again


def test_a_checkpoint_resumes_only_with_the_settings_it_was_trained_on(tmp_path):
    first = tiny_config(
        tmp_path, timesteps=128, name="kept", curriculum=CurriculumConfig(share=0.5)
    )
    train(first, progress=False)
    with pytest.raises(ValueError, match=r"curriculum\.share 0\.5 \(now 0\.8\)") as refused:
        train(replace(first, timesteps=256, curriculum=CurriculumConfig()), progress=False)
    assert "\n" not in str(refused.value)
    folder = tmp_path / "runs" / "kept"
    assert json.loads((folder / "checkpoint.json").read_text())["timesteps"] == 128  # untouched
    resumed = replace(recorded_config(folder), timesteps=256, policies=first.policies)
    path = train(resumed, progress=False)
    assert json.loads(path.read_text())["config"]["curriculum"]["share"] == 0.5


def test_train_resumes_a_run_as_recorded_with_only_the_options_given_changed(tmp_path):
    where = ["--out", str(tmp_path / "runs"), "--policies", str(tmp_path / "policies")]
    tiny = ["--gown-vertices", "600", "--envs", "1", "--action-std", "0.4", "--no-warmup"]
    first = ["train", "--robot", "side_linear", "--name", "again", *where, *tiny]
    assert CliRunner().invoke(main, [*first, "--timesteps", "8"]).exit_code == 0
    again = ["train", "--name", "again", *where, "--timesteps", "16"]  # the rest left out
    result = CliRunner().invoke(main, again)
    assert result.exit_code == 0, result.output
    run = json.loads((tmp_path / "runs" / "again" / "run.json").read_text())
    assert run["result"]["steps"] == 16
    assert {key: run["config"][key] for key in ("robot", "action_std", "warmup")} == {
        "robot": "side_linear", "action_std": 0.4, "warmup": None}  # fmt: skip
    changed = CliRunner().invoke(main, [*again, "--action-std", "0.5"])
    assert changed.exit_code != 0
    assert "action_std 0.4 (now 0.5)" in changed.output


def test_a_run_resumed_with_more_env_processes_keeps_the_size_of_its_updates(tmp_path):
    first = tiny_config(tmp_path, timesteps=256, name="grown")  # one env: 128 steps an update
    train(first, progress=False)
    path = train(replace(first, timesteps=768, envs=2), progress=False)  # 64 steps from each env
    assert json.loads(path.read_text())["steps"] == 768
    logged = pd.read_csv(tmp_path / "runs" / "grown" / "logs" / "progress.csv")
    assert logged["time/total_timesteps"].tolist() == [384, 512, 640, 768]


def test_a_stopped_training_saves_its_checkpoint_where_it_stopped_and_says_so(tmp_path):
    """`kill` (SIGTERM) or Ctrl-C: the checkpoint is saved at that step, one line says how to
    go on, and nothing trained is lost."""
    where = ["--out", str(tmp_path / "runs"), "--policies", str(tmp_path / "policies")]
    tiny = ["--gown-vertices", "600", "--envs", "1"]
    command = [str(Path(sys.executable).parent / "dressbench"), "train", "--robot", "fixed",
               "--timesteps", "100000", "--name", "stopped", *where, *tiny]  # fmt: skip
    worker = subprocess.Popen(command, stderr=subprocess.PIPE, text=True)
    log = tmp_path / "runs" / "stopped" / "logs" / "progress.csv"
    deadline = time.time() + 300
    while not (log.exists() and log.stat().st_size > 0):  # a first update has been made
        assert worker.poll() is None and time.time() < deadline
        time.sleep(0.2)
    worker.send_signal(signal.SIGTERM)
    _, errors = worker.communicate(timeout=120)
    assert worker.returncode == 130
    saved = json.loads((tmp_path / "runs" / "stopped" / "checkpoint.json").read_text())
    assert 4096 <= saved["timesteps"] < 20_000  # past the first update, before a periodic save
    assert f"training stopped at {saved['timesteps']:,} steps" in errors
    assert "Traceback" not in errors


def test_a_human_trained_in_a_profile_runs_under_it_unless_asked_otherwise(
    tmp_path, policies_on_path
):
    path = train(tiny_config(tmp_path, timesteps=64, name="trembler", profile="tremor"),
                 progress=False)  # fmt: skip
    assert json.loads(path.read_text())["profile"] == "tremor"
    run = json.loads((tmp_path / "runs" / "trembler" / "run.json").read_text())
    assert run["config"]["profile"] == "tremor"
    plugins.refresh()
    assert make_cell("fixed", "trembler", gown_vertices=600, horizon=8).config().profile == "tremor"
    asked = make_cell("fixed", "trembler", profile="typical", gown_vertices=600, horizon=8)
    assert asked.config().profile == "typical"
    cells = leaderboard_cells(["fixed"], ["trembler"], profile="weak_arm", gown_vertices=600,
                              horizon=8)  # fmt: skip
    assert [cell.config().profile for cell in cells] == ["weak_arm"]  # named: run under it


def test_a_human_trained_to_move_its_targets_is_scored_moving_them(tmp_path, policies_on_path):
    path = train(tiny_config(tmp_path, timesteps=64, name="mover", actuation="delta"),
                 progress=False)  # fmt: skip
    assert json.loads(path.read_text())["actuation"] == "delta"
    plugins.refresh()
    config = make_cell("fixed", "mover", gown_vertices=600, horizon=8).config()
    assert config.scene.human.actuation == "delta"
