"""A bad plugin, policy, option or path ends in one clear line, before work starts.

Plugins are fake distributions in a fresh folder on ``sys.path`` (as in
tests/test_plugins_registry.py); episodes are tiny (horizon 3-5, a 300-vertex gown).
"""

import hashlib
import json
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import fakes
import numpy as np
import pytest
import safetensors.numpy
from click.testing import CliRunner
from fakes import install

import dressbench
from dressbench import files as atomic
from dressbench import plugins, policy_file
from dressbench.bench import bench_scene
from dressbench.cli import main
from dressbench.config import EnvConfig
from dressbench.observation import ABLATIONS, observation_size
from dressbench.policy_file import FORMAT, FORMAT_VERSION, PolicyFileError, load_policy
from dressbench.training import TrainConfig
from dressbench.training.run import TrainingRun
from dressbench.video import render_rollout


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_evaluation_files_follow_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        atomic.write_text(tmp_path / "leaderboard.md", "| a |\n")
    finally:
        os.umask(old)
    mode = stat.S_IMODE((tmp_path / "leaderboard.md").stat().st_mode)
    assert mode == 0o666 & ~umask
    assert [p.name for p in tmp_path.iterdir()] == ["leaderboard.md"]  # no temp left


# --- policy files: what is read is bounded -------------------------------------------------------


def write_policy(folder: Path, name: str, *, ablation="complete", obs_dim=None, robot="fixed"):
    """A tiny trained human (a policy file pair written as ``save_policy`` writes it) whose
    every action is 0.1; ``obs_dim`` defaults to the ablation's observation size."""
    obs_dim = obs_dim or observation_size("complete" if ablation not in ABLATIONS else ablation)
    tensors = {
        "pi.0.weight": np.zeros((4, obs_dim)),
        "pi.0.bias": np.zeros(4),
        "action.weight": np.zeros((11, 4)),
        "action.bias": np.full(11, 0.1),
        "log_std": np.zeros(11),
        "obs_mean": np.zeros(obs_dim),
        "obs_var": np.ones(obs_dim),
    }
    blob = safetensors.numpy.save(tensors)
    document: dict = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "architecture": {"hidden_sizes": [4], "activation": "tanh", "obs_dim": obs_dim},
        "obs_normalization": {"clip_obs": 10.0, "epsilon": 1e-8},
        "tensors": {"sha256": hashlib.sha256(blob).hexdigest(), "size": len(blob)},
        "robot": robot,
        "ablation": ablation,
    }
    document["architecture"]["act_dim"] = 11
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.safetensors").write_bytes(blob)
    (folder / f"{name}.json").write_text(json.dumps(document))
    return folder / f"{name}.json"


@pytest.fixture
def policies(tmp_path, monkeypatch):
    """A policies folder of this test's own, the only one the registry looks in."""
    folder = tmp_path / "policies"
    folder.mkdir()
    monkeypatch.setenv("DRESSBENCH_POLICIES", str(folder))
    plugins.refresh()
    yield folder
    monkeypatch.delenv("DRESSBENCH_POLICIES")
    plugins.refresh()


def test_a_policy_linked_to_an_endless_file_is_refused_without_reading_it(policies):
    write_policy(policies, "endless")
    (policies / "endless.safetensors").unlink()
    (policies / "endless.safetensors").symlink_to("/dev/zero")
    write_policy(policies, "fine")
    # under a 3 GB address-space limit, reading /dev/zero to the end fails with MemoryError
    code = (
        "import resource; resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))\n"
        "from dressbench.plugins import human_plugins\n"
        "found = human_plugins()\n"
        "print(found['endless'].status, found['endless'].error)\n"
        "print(found['fine'].status)\n"
    )
    env = {**os.environ, "DRESSBENCH_POLICIES": str(policies)}
    run = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, run.stderr[-2000:]
    endless, fine = run.stdout.splitlines()[-2:]
    assert endless.startswith("error creating an instance failed: PolicyFileError: "), endless
    assert "endless.safetensors: not a regular file (a character device)" in endless
    assert fine == "ok"


def test_a_policy_file_over_the_size_limit_is_refused_before_it_is_read(policies, monkeypatch):
    path = write_policy(policies, "huge")
    monkeypatch.setattr(policy_file, "MAX_TENSORS_BYTES", 1000)
    with pytest.raises(PolicyFileError, match=r"huge\.safetensors: \d+ bytes, more than"):
        load_policy(path)
    monkeypatch.setattr(policy_file, "MAX_JSON_BYTES", 100)
    with pytest.raises(PolicyFileError, match=r"huge\.json: \d+ bytes, more than"):
        load_policy(path)
    reads = []
    monkeypatch.setattr(Path, "read_bytes", lambda self: reads.append(self))
    assert policy_file.list_policies(policies) == [path]  # listed: its tensors sit beside it
    assert reads == []


# --- fake plugin distributions -------------------------------------------------------------------

ROBOTS = f"[{plugins.ROBOT_GROUP}]"  # entry_points.txt section headers
HUMANS = f"[{plugins.HUMAN_GROUP}]"

ROBOT_MODULE = """
import numpy as np

class Robot:
    api_version = 1
    pose = [0.55, -0.19, 0.45, 0.0, 0.0, 0.0, 1.0]
    action = [0.0, 0.0, 0.0]

    def reset(self, rng):
        return np.array(self.pose)

    def act(self, observation):
        return np.array(self.action)

class SixPose(Robot):
    pose = [0.55, -0.19, 0.45, 0.0, 0.0, 1.0]

class ZeroQuaternion(Robot):
    pose = [0.55, -0.19, 0.45, 0.0, 0.0, 0.0, 0.0]

class Outside(Robot):
    pose = [0.55, -0.19, 2.45, 0.0, 0.0, 0.0, 1.0]

class TwoAction(Robot):
    action = [0.0, 1.0]
"""

HUMAN_MODULE = (
    fakes.HUMAN_MODULE
    + """
class Ten(Human):
    def act(self, observation):
        return np.zeros(10)
"""
)

BAD_ROBOTS = {
    "six_pose": "acme_robots:SixPose",
    "zero_quat": "acme_robots:ZeroQuaternion",
    "outside": "acme_robots:Outside",
    "two_action": "acme_robots:TwoAction",
}


@pytest.fixture
def acme(site):
    """acme-robots 1.0: one good robot and the bad ones of BAD_ROBOTS; a good and a bad human."""
    robots = {"good_arm": "acme_robots:Robot", **BAD_ROBOTS}
    humans = {"good_person": "acme_humans:Human", "ten_person": "acme_humans:Ten"}
    install(site, "acme-robots", "1.0", {ROBOTS: robots, HUMANS: humans},
            acme_robots=ROBOT_MODULE, acme_humans=HUMAN_MODULE)  # fmt: skip
    return site


# --- what robot strategies return is checked -----------------------------------------------------


@pytest.mark.parametrize(
    ("name", "reason"),
    [
        ("six_pose", r"reset returned a pose of shape \(6,\), expected \(7,\)"),
        ("zero_quat", r"quaternion \(qx, qy, qz, qw\) = \[0.0, 0.0, 0.0, 0.0\] of norm 0, "
                      r"expected a unit quaternion"),
        ("outside", r"position \[0.55, -0.19, 2.45\], outside the workspace \(x in \[-0.3, 1.3\]"),
    ],
)  # fmt: skip
def test_a_bad_start_pose_is_an_error_naming_the_plugin_not_a_scored_failure(acme, name, reason):
    env = dressbench.make_env(name, gown_vertices=300, horizon=3)
    with pytest.raises(ValueError, match=reason) as caught:
        env.reset(seed=0)
    message = str(caught.value)
    assert message.startswith(f"robot strategy {name!r} from acme-robots 1.0: reset returned ")
    assert "\n" not in message


def test_a_start_pose_within_the_tolerance_of_a_unit_quaternion_is_accepted(acme):
    env = dressbench.make_env("good_arm", gown_vertices=300, horizon=3)
    env.robot_strategy.pose = [0.55, -0.19, 0.45, 0.0, 0.0, 0.0, 1.0005]
    observations, _ = env.reset(seed=0)
    assert np.isfinite(observations["human"]).all()


def test_a_robot_action_of_the_wrong_shape_names_the_plugin(acme):
    env = dressbench.make_human_env("two_action", gown_vertices=300, horizon=3)
    env.reset(seed=0)
    reason = r"'two_action' from acme-robots 1.0: act returned an action of shape \(2,\), expected"
    with pytest.raises(ValueError, match=f"^robot strategy {reason}"):
        env.step(np.zeros(11))


def test_make_env_without_a_robot_fails_at_construction():
    with pytest.raises(TypeError, match="must be a robot strategy: a plugin name such as 'fixed'"):
        dressbench.make_env(None)


# --- plugins and policies are checked before a leaderboard starts --------------------------------

TINY = {"horizon": 3, "gown_vertices": 300, "progress": False}
SKIPPED = {
    "six_pose": "robot plugin 'six_pose' from acme-robots 1.0: reset returned a pose of shape (6,)",
    "zero_quat": "robot plugin 'zero_quat' from acme-robots 1.0: reset returned the quaternion",
    "outside": "robot plugin 'outside' from acme-robots 1.0: reset returned the position",
    "two_action": "robot plugin 'two_action' from acme-robots 1.0: act returned an action of "
    "shape (2,)",
    "ten_person": "human plugin 'ten_person' from acme-robots 1.0: act returned an action of "
    "shape (10,), expected (11,)",
    "sideways": "human plugin 'sideways' from policy file {policies}/sideways.json: it declares "
    "ablation 'sideways'; expected one of complete, no_haptics, no_task",
    "misfit": "human plugin 'misfit' from policy file {policies}/misfit.json: its obs_dim is 163, "
    "but ablation 'no_task' observes 160 numbers",
}


@pytest.fixture
def mixed(acme, policies):
    """The acme plugins, and three policy files for good_arm: one good, two with bad metadata."""
    write_policy(policies, "trained", robot="good_arm")
    write_policy(policies, "sideways", ablation="sideways", robot="good_arm")
    write_policy(policies, "misfit", ablation="no_task", obs_dim=163, robot="good_arm")
    return policies


def test_a_leaderboard_skips_plugins_that_fail_their_check_and_scores_the_rest(
    mixed, tmp_path, recwarn
):
    humans = ["passive", "good_person", "ten_person", "trained", "sideways", "misfit"]
    board = dressbench.leaderboard(
        episodes=1, workers=1, out=tmp_path / "out", robots=["good_arm", *BAD_ROBOTS],
        humans=humans, **TINY,
    )  # fmt: skip
    pairs = set(zip(board["robot"], board["human"], strict=True))
    assert pairs == {("good_arm", "passive"), ("good_arm", "good_person"), ("good_arm", "trained")}
    lines = [str(w.message) for w in recwarn.list]
    for name, expected in SKIPPED.items():
        (line,) = [line for line in lines if f" plugin {name!r} " in line]
        assert line.startswith("skipping " + expected.format(policies=mixed)), line


def test_the_cli_names_each_skipped_plugin_on_one_line(mixed, tmp_path):
    command = ["evaluate", "leaderboard", "--episodes", "1", "--workers", "1", "--horizon", "3",
               "--gown-vertices", "300", "--out", str(tmp_path / "out"), "--robot", "good_arm",
               "--robot", "six_pose", "--human", "passive", "--human", "misfit"]  # fmt: skip
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 0, result.output
    warnings = [line for line in result.stderr.splitlines() if line.startswith("Warning: ")]
    assert warnings == [
        "Warning: skipping " + SKIPPED[name].format(policies=mixed) + text
        for name, text in [
            ("six_pose", ", expected (7,): (x, y, z, qx, qy, qz, qw) in the human frame"),
            ("misfit", " (the file's ablation does not match the network)"),
        ]
    ]


def test_plugins_lists_them_as_ok_and_with_check_says_which_fail_and_why(mixed):
    listed = CliRunner().invoke(main, ["plugins"])
    assert listed.exit_code == 0, listed.output
    checked = CliRunner().invoke(main, ["plugins", "--check"])
    assert checked.exit_code == 0, checked.output

    def status(output: str, name: str) -> str:
        (row,) = [row for row in output.splitlines() if row.split()[1:2] == [name]]
        return row.split(maxsplit=4)[4] if "policy file" not in row else row.split(" file ")[-1]

    for name in [*BAD_ROBOTS, "ten_person", "sideways", "misfit"]:
        assert status(listed.output, name).strip() == "ok"  # it imports: that is all
        expected = SKIPPED[name].format(policies=mixed).split(": ", 1)[1]
        assert status(checked.output, name).strip().startswith(f"FAILS CHECK: {expected}")
    for name in ["good_arm", "good_person", "trained", "passive", "fixed"]:
        assert status(checked.output, name).strip() == "ok"


def test_evaluate_refuses_a_plugin_that_fails_its_check_naming_it(mixed, tmp_path):
    with pytest.raises(
        ValueError,
        match=r"^human plugin 'misfit' from policy file .*misfit\.json "
        "cannot be evaluated: its obs_dim is 163",
    ):
        dressbench.evaluate("good_arm", "misfit", episodes=1, workers=1, out=tmp_path, **TINY)
    with pytest.raises(
        ValueError,
        match="^robot plugin 'zero_quat' from acme-robots 1.0 cannot "
        "be evaluated: reset returned the quaternion",
    ):
        dressbench.evaluate("zero_quat", "passive", episodes=1, workers=1, out=tmp_path, **TINY)
    assert not (tmp_path / "rollouts").exists()


# --- killing an evaluation ends its workers ------------------------------------------------------

SLEEPY_MODULE = (
    HUMAN_MODULE
    + """
import multiprocessing, os, pathlib, time

class Sleepy(Human):
    def act(self, observation):
        if multiprocessing.parent_process() is not None:  # in a pool's worker, not the preflight
            pathlib.Path(os.environ["SLEEPY_MARKS"], str(os.getpid())).touch()
            time.sleep(120)
        return np.zeros(11)
"""
)


def _alive(pid: int) -> bool:
    """Whether a process runs (a zombie, dead but not yet reaped, does not count)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, ProcessLookupError):
        return False


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")
def test_killing_an_evaluation_ends_its_workers_within_seconds(site, tmp_path):
    install(site, "sleepy", "1.0", {HUMANS: {"sleepy": "sleepy_human:Sleepy"}},
            sleepy_human=SLEEPY_MODULE)  # fmt: skip
    marks = tmp_path / "marks"
    marks.mkdir()
    code = (
        "import dressbench\n"
        f"dressbench.evaluate('fixed', 'sleepy', episodes=4, workers=2, out={str(tmp_path)!r}, "
        "horizon=3, gown_vertices=300, progress=False)\n"
    )
    env = {**os.environ, "PYTHONPATH": str(site), "SLEEPY_MARKS": str(marks)}
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    main_process = subprocess.Popen([sys.executable, "-c", code], env=env, **quiet)
    workers: list[int] = []
    try:
        deadline = time.monotonic() + 240
        while len(workers) < 2 and time.monotonic() < deadline:
            assert main_process.poll() is None, "the evaluation ended before its workers acted"
            workers = [int(p.name) for p in marks.iterdir()]
            time.sleep(0.2)
        assert len(workers) == 2, "the workers did not start"
        main_process.kill()  # SIGKILL: no cleanup runs in the main process
        main_process.wait()
        deadline = time.monotonic() + 15
        while any(map(_alive, workers)) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert not [pid for pid in workers if _alive(pid)], "workers outlived their parent"
    finally:
        if main_process.poll() is None:
            main_process.kill()
            main_process.wait()
        for pid in workers:
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)


# --- every option is checked before work starts, in one line naming it ---------------------------

EVALUATE = ["evaluate", "--robot", "fixed", "--human", "passive"]
LEADERBOARD = ["evaluate", "leaderboard", "--robot", "fixed", "--human", "passive"]


def _one_error_line(result, option: str) -> str:
    """The error of a refused command line: exit status 2 (a usage error), one line naming the
    option, no traceback."""
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    errors = [line for line in result.output.splitlines() if line.startswith("Error: ")]
    assert len(errors) == 1 and "Traceback" not in result.output, result.output
    assert errors[0].startswith(f"Error: Invalid value for '{option}'"), errors[0]
    return errors[0]


def _cuda_available() -> bool:
    import warp as wp

    from dressbench.scene import cloth  # noqa: F401 - Warp's kernel cache

    wp.init()
    return wp.is_cuda_available()


@pytest.mark.parametrize(
    ("args", "option", "allowed"),
    [
        (["train", "--envs", "-1"], "--envs", "must be 0 (one per core) or from 1 to 256"),
        (["train", "--seed", "-5"], "--seed", "must be from 0 to 4294967295, got -5"),
        (["train", "--timesteps", "0"], "--timesteps", "must be at least 1, got 0"),
        (["train", "--name", "../elsewhere"], "--name", "must be a plain file name"),
        (["bench", "--steps", "0"], "--steps", "must be at least 1, got 0"),
        (["bench", "--repeats", "0"], "--repeats", "must be at least 1, got 0"),
        (["bench", "--vertices", "50"], "--vertices", "must be from 100 to 20000, got 50"),
        ([*EVALUATE, "--workers", "-1"], "--workers", "must be 0 (one per core) or from 1 to"),
        ([*EVALUATE, "--seed", "-5"], "--seed", "must be from 0 to 4294967295, got -5"),
        ([*EVALUATE, "--episodes", "0"], "--episodes", "must be from 1 to 100000, got 0"),
        ([*LEADERBOARD, "--episodes", "0"], "--episodes", "must be from 1 to 100000, got 0"),
        ([*LEADERBOARD, "--workers", "-1"], "--workers", "must be 0 (one per core) or from 1"),
        ([*LEADERBOARD, "--horizon", "0"], "--horizon", "must be from 1 to 100000, got 0"),
        (["render", "--seed", "-1"], "--seed", "must be from 0 to 4294967295, got -1"),
        (["calibrate", "--episodes", "0"], "--episodes", "must be from 1 to 100000, got 0"),
    ],
)
def test_a_bad_option_is_one_line_naming_it_and_what_is_allowed(
    tmp_path, monkeypatch, args, option, allowed
):
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, args)
    assert allowed in _one_error_line(result, option)
    assert list(tmp_path.iterdir()) == []  # nothing was started, nothing written


@pytest.mark.skipif(_cuda_available(), reason="this machine has a GPU")
def test_bench_on_a_missing_gpu_is_one_line():
    result = CliRunner().invoke(main, ["bench", "--device", "cuda", "--vertices", "300"])
    assert "'cuda' is not a Warp device of this machine: it has cpu" in _one_error_line(
        result, "--device"
    )


@pytest.mark.parametrize(
    ("args", "option", "cap"),
    [
        ([*EVALUATE, "--episodes", "1000000000"], "--episodes", "must be at most 100000 (a cap"),
        ([*LEADERBOARD, "--gown-vertices", "1000000"], "--gown-vertices", "must be at most 20000"),
        (["train", "--gown-vertices", "1000000"], "--gown-vertices", "must be at most 20000"),
    ],
)
def test_enormous_runs_are_refused_up_front_saying_the_cap(tmp_path, args, option, cap):
    # in a process of at most 3 GB: without the caps, these grew to 4.9 and 9 GB
    code = (
        "import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))\n"
        "from dressbench.cli import main\n"
        "main(sys.argv[1:])\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, *args], cwd=tmp_path, capture_output=True, text=True,
        timeout=120,
    )  # fmt: skip
    assert run.returncode == 2, run.stderr[-2000:]
    (line,) = [line for line in run.stderr.splitlines() if line.startswith("Error: ")]
    assert line.startswith(f"Error: Invalid value for '{option}': {cap}"), line
    assert list(tmp_path.iterdir()) == []


def test_enormous_values_are_refused_by_the_api_too(tmp_path):
    with pytest.raises(ValueError, match="gown_vertices must be at most 20000"):
        EnvConfig(gown_vertices=1_000_000)
    with pytest.raises(ValueError, match="horizon must be from 1 to 100000, got 0"):
        EnvConfig(horizon=0)
    with pytest.raises(ValueError, match="workers must be from 1 to 256"):
        dressbench.evaluate("fixed", "passive", episodes=1, workers=-1, out=tmp_path, **TINY)
    with pytest.raises(ValueError, match="seed must be from 0 to"):
        dressbench.leaderboard(episodes=1, seed=-5, out=tmp_path, **TINY)
    with pytest.raises(ValueError, match="envs must be 0 \\(one per core\\) or from 1 to 256"):
        TrainConfig(envs=-1)
    with pytest.raises(ValueError, match="steps must be at least 1, got 0"):
        bench_scene(300, 0)
    assert list(tmp_path.iterdir()) == []


# --- every path problem is one line ---------------------------------------------------------------


@pytest.mark.parametrize("command", ["evaluate", "leaderboard", "train"])
@pytest.mark.parametrize(
    ("out", "problem"),
    [
        ("a_file", "'a_file' is a file, not a folder"),
        ("a_file/results", "'a_file/results' cannot be created: '{here}/a_file' is a file"),
        ("", "must name a folder, got ''"),
    ],
)
def test_an_out_folder_that_cannot_be_one_is_one_line(tmp_path, monkeypatch, command, out, problem):
    args = {"evaluate": EVALUATE, "leaderboard": LEADERBOARD, "train": ["train"]}[command]
    tiny = ["--episodes", "1", "--workers", "1", "--gown-vertices", "300"]
    tiny = {"evaluate": tiny, "leaderboard": [*tiny, "--horizon", "3"], "train": []}[command]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("not a folder\n")
    result = CliRunner().invoke(main, [*args, *tiny, "--out", out])
    line = _one_error_line(result, "--out")
    assert line.endswith(problem.format(here=tmp_path)), line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]


def test_render_into_a_missing_folder_fails_before_rendering(tmp_path, monkeypatch):
    def no_rendering(*args, **kwargs):
        raise AssertionError("rendering started")

    monkeypatch.setattr("dressbench.render.Renderer", no_rendering)
    monkeypatch.setattr("dressbench.factory.make_human_env", no_rendering)
    target = tmp_path / "missing" / "clip.gif"
    result = CliRunner().invoke(main, ["render", "--out", str(target), "--gown-vertices", "300"])
    line = _one_error_line(result, "--out")
    assert line.endswith(f"cannot be written: the folder '{tmp_path / 'missing'}' does not exist")
    (tmp_path / "folder.gif").mkdir()
    for path, problem in [
        (tmp_path / "clip.avi", "'clip.avi' must end in .gif or .mp4"),
        (tmp_path / "folder.gif", "is a folder, not a file"),
    ]:
        with pytest.raises(ValueError, match=problem):
            render_rollout("fixed", "passive", path, gown_vertices=300)


# --- a failed train leaves no run folder ----------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--robot", "fixd"], "Error: unknown robot 'fixd': did you mean 'fixed'?"),
        (["--robot", "six_pose"], "Error: robot plugin 'six_pose' from acme-robots 1.0 cannot be "
                                  "trained for: reset returned a pose of shape (6,)"),
    ],
)  # fmt: skip
def test_a_failed_train_leaves_no_run_folder(acme, tmp_path, args, message):
    runs, models = tmp_path / "runs", tmp_path / "policies"
    command = ["train", *args, "--envs", "1", "--timesteps", "64", "--gown-vertices", "300",
               "--out", str(runs), "--policies", str(models)]  # fmt: skip
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 1 and result.output.startswith(message), result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not runs.exists() and not models.exists()


def test_a_train_that_fails_before_its_first_checkpoint_removes_its_new_folder(tmp_path):
    config = TrainConfig(robot="fixed", timesteps=64, envs=1, gown_vertices=300, horizon=4,
                         out=str(tmp_path / "runs"), policies=str(tmp_path / "policies"),
                         name="doomed")  # fmt: skip
    run = TrainingRun(config)
    run._envs = lambda: (_ for _ in ()).throw(RuntimeError("no envs today"))
    with pytest.raises(RuntimeError, match="no envs today"):
        run.run(progress=False)
    assert list((tmp_path / "runs").iterdir()) == []


# --- the docs answer what a third-party author needed --------------------------------------------

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_start_poses_are_absolute_in_the_human_frame_as_the_docs_say(acme):
    env = dressbench.make_env("good_arm", gown_vertices=300, horizon=3)
    observations, _ = env.reset(seed=0)
    pose = np.array(env.robot_strategy.pose)
    np.testing.assert_array_equal(env.scene.gripper_pose, pose)  # not offset by the shoulder
    np.testing.assert_allclose(observations["robot"][:3], pose[:3], atol=1e-6)
    robots = (DOCS / "robots.md").read_text()
    assert "returns an **absolute** pose" in robots and "Poses are relative" not in robots


def test_the_documented_order_of_the_human_actions_is_the_bodys():
    from dressbench.scene.human import Human

    human = Human()
    skeleton = human.skeleton
    actuated = [skeleton.getDof(int(i)).getName() for i in human.actuated_index]
    text = " ".join((DOCS / "plugins.md").read_text().split())
    listed = text.split("one per actuated degree of freedom, in this order: ")[1].split(" (")[0]
    assert [name.strip("`,") for name in listed.split()] == actuated


def test_the_public_names_the_docs_list_exist():
    from dressbench import env
    from dressbench.plugins import contract, protocols, robots

    for module, names in [
        (protocols, ["ROBOT_MAX_SPEED", "ROBOT_DT", "OBS_TIME"]),
        (robots, ["RIGHT_SHOULDER", "FRONT", "sample_box", "yaw_quaternion", "LINEAR_DURATION",
                  "ROBOT_MAX_SPEED", "ROBOT_DT", "OBS_TIME"]),
        (env, ["ROBOT_OBS_SIZE"]),
        (contract, ["WORKSPACE", "QUATERNION_TOLERANCE", "start_pose_problem"]),
    ]:  # fmt: skip
        for name in names:
            assert hasattr(module, name), f"{module.__name__}.{name}"
    text = " ".join((DOCS / "plugins.md").read_text().split())
    for needed in ["`RIGHT_SHOULDER`", "`ROBOT_DT`", "`OBS_TIME`", "`yaw_quaternion(direction)`",
                   "dressbench.testing", "`check_robot_plugin`", "## Results are cached",
                   "imports and has the protocol's names, not that it runs",
                   "Entries outside [−1, 1] are clipped"]:  # fmt: skip
        assert needed in text, needed
