"""The ecosystem's conventions: gymnasium registration, PettingZoo's ``parallel_env``, an
aligned plugin listing, and a clear error for a plugin name given to ``load_policy``."""

import subprocess
import sys

import gymnasium
import numpy as np
import pytest
from click.testing import CliRunner
from pettingzoo import ParallelEnv

import dressbench
from dressbench.cli import main
from dressbench.evaluation.listing import aligned
from dressbench.policy_file import PolicyFileError

TINY = {"horizon": 3, "gown_vertices": 300}


def test_importing_dressbench_registers_the_env_without_the_physics():
    code = (
        "import sys, gymnasium, dressbench; "
        "print(dressbench.ENV_ID in gymnasium.registry, "
        "sorted({'warp', 'dartpy', 'torch'} & set(sys.modules)))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "[]"]


def test_gymnasium_make_builds_the_human_env_for_a_robot():
    env = gymnasium.make("dressbench/Dressing-v0", robot="front_linear", **TINY)
    observation, _ = env.reset(seed=0)
    assert observation.shape == (163,) and env.unwrapped.env.robot_name == "front_linear"
    for _ in range(TINY["horizon"]):
        *_, terminated, truncated, _ = env.step(np.zeros(11, dtype=np.float32))
    assert truncated or terminated
    env.close()


def test_parallel_env_is_the_pettingzoo_env():
    env = dressbench.parallel_env("fixed", **TINY)
    assert isinstance(env, ParallelEnv) and env.possible_agents == ["robot", "human"]
    observations, _ = env.reset(seed=0)
    assert set(observations) == {"robot", "human"}
    env.close()


def test_plugin_listing_is_aligned_for_long_names():
    rows = [("group", "name", "status"), ("human", "a" * 40, "ok"), ("robot", "b", "BROKEN: x")]
    lines = aligned(rows)
    assert len({line.index(row[2]) for line, row in zip(lines, rows, strict=True)}) == 1
    result = CliRunner().invoke(main, ["plugins"])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    status = lines[0].index("status")
    assert all(line[status - 2 : status] == "  " for line in lines[1:])
    assert {line[status:].split()[0] for line in lines[1:]} <= {"ok", "BROKEN:", "FAILS"}


@pytest.mark.parametrize("name", ["scripted", "passive"])
def test_load_policy_of_a_plugin_name_says_it_is_a_plugin(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(PolicyFileError) as error:
        dressbench.load_policy(name)
    message = str(error.value)
    assert "human plugin name" in message and f"load_human({name!r})" in message
    assert len(message.splitlines()) == 1


def test_load_policy_of_a_missing_path_keeps_its_error(tmp_path):
    with pytest.raises(PolicyFileError, match="missing"):
        dressbench.load_policy(tmp_path / "nothing")
    with pytest.raises(PolicyFileError, match="missing"):
        dressbench.load_policy("no_such_policy_or_plugin")
