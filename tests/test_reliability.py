"""Issue 15: a bad plugin, policy, option or path ends in one clear line, before work starts.

Plugins are fake distributions in a fresh folder on ``sys.path`` (as in
tests/test_plugins_registry.py); episodes are tiny (horizon 3-5, a 300-vertex gown).
"""

import hashlib
import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import safetensors.numpy

from dressbench import plugins
from dressbench.evaluation import io as atomic
from dressbench.observation import ABLATIONS, observation_size
from dressbench.training import policy_file
from dressbench.training.policy_file import FORMAT, FORMAT_VERSION, PolicyFileError, load_policy


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
    document = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "architecture": {"hidden_sizes": [4], "activation": "tanh", "obs_dim": obs_dim,
                         "act_dim": 11},  # fmt: skip
        "obs_normalization": {"clip_obs": 10.0, "epsilon": 1e-8},
        "tensors": {"sha256": hashlib.sha256(blob).hexdigest(), "size": len(blob)},
        "robot": robot,
        "ablation": ablation,
    }
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
