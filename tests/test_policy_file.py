"""Policy files: SB3 models export to safetensors + JSON and load back, without pickle, exactly."""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from sb3_contrib import TRPO
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

from dressbench.observation import scale_haptics
from dressbench.plugins.protocols import HumanPolicy
from dressbench.training import (
    PolicyFileError,
    TrainedPolicy,
    list_policies,
    load_policy,
    policy_paths,
    save_policy,
)

OBS_DIM = 163
METADATA = {
    "robot": "fixed",
    "ablation": "complete",
    "algorithm": "TRPO",
    "seed": 0,
    "steps": 128,
    "versions": {"dressbench": "0.1.0", "stable_baselines3": "2.9"},
    "git_commit": "0123abc",
    "config": {"gamma": 0.995, "net_arch": [64, 64]},
}


class NoiseEnv(gym.Env):
    """Seeded random observations of varied offset and scale, so normalisation matters."""

    def __init__(self) -> None:
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, (OBS_DIM,), np.float32)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (11,), np.float32)
        self._offset = np.linspace(-5.0, 5.0, OBS_DIM)
        self._scale = np.linspace(0.1, 20.0, OBS_DIM)
        self._t = 0

    def _obs(self) -> np.ndarray:
        noise = self.np_random.standard_normal(OBS_DIM)
        return (self._offset + self._scale * noise).astype(np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._t = 0
        return self._obs(), {}

    def step(self, action):
        self._t += 1
        reward = float(-np.sum(np.square(action)))
        return self._obs(), reward, False, self._t >= 32, {}


def _train(algorithm: type) -> tuple[object, VecNormalize]:
    """A tiny real model trained for two updates, and its VecNormalize."""
    venv = VecNormalize(DummyVecEnv([NoiseEnv]), gamma=0.995)
    venv.seed(0)
    model = algorithm(
        "MlpPolicy",
        venv,
        policy_kwargs=dict(net_arch=dict(pi=[64, 64], vf=[64, 64]), activation_fn=torch.nn.Tanh),
        n_steps=64,
        batch_size=64,
        seed=0,
        device="cpu",
    )
    model.learn(128)
    return model, venv


@pytest.fixture(scope="module")
def trpo() -> tuple[object, VecNormalize]:
    return _train(TRPO)


@pytest.fixture
def saved(trpo, tmp_path: Path) -> Path:
    """A saved TRPO policy pair; the path of its JSON."""
    model, venv = trpo
    return _save(tmp_path / "fixed_complete", model, venv)


def _save(stem: Path, model: object, venv: VecNormalize, **metadata: object) -> Path:
    meta = {**METADATA, **metadata}
    kwargs = dict(clip_obs=venv.clip_obs, epsilon=venv.epsilon)
    return save_policy(stem, model, venv.obs_rms, meta, **kwargs)[1]


def _observations(n: int = 8) -> np.ndarray:
    """Raw observations, some far outside the training range so clip_obs matters."""
    rng = np.random.default_rng(1)
    obs = rng.normal(0.0, 10.0, (n, OBS_DIM))
    obs[-1] *= 100.0
    return obs.astype(np.float32)


def _assert_matches_sb3(policy: TrainedPolicy, model: object, venv: VecNormalize) -> None:
    for obs in _observations():
        expected = model.predict(venv.normalize_obs(obs), deterministic=True)[0]
        np.testing.assert_allclose(policy.act(obs), expected, atol=1e-5, rtol=0)


def _rewrite_json(json_path: Path, edit) -> None:
    document = json.loads(json_path.read_text())
    edit(document)
    json_path.write_text(json.dumps(document))


def test_trpo_policy_acts_like_sb3(trpo, saved: Path) -> None:
    model, venv = trpo
    assert np.abs(venv.obs_rms.mean).max() > 0.5  # the stats are not the identity
    policy = load_policy(saved)
    assert isinstance(policy, HumanPolicy)
    assert policy.act(_observations()[0]).shape == (11,)
    _assert_matches_sb3(policy, model, venv)


def test_a_policy_that_read_log_forces_applies_the_log_scale_itself(trpo, tmp_path: Path) -> None:
    model, venv = trpo
    policy = load_policy(_save(tmp_path / "log", model, venv, haptics="log"))
    assert policy.haptics == "log"
    for obs in _observations():
        scaled = scale_haptics(obs, "complete", "log")
        expected = model.predict(venv.normalize_obs(scaled), deterministic=True)[0]
        np.testing.assert_allclose(policy.act(obs), expected, atol=1e-5, rtol=0)


def test_a_policy_file_without_a_haptic_scale_read_newtons(saved: Path) -> None:
    assert load_policy(saved).haptics == "newtons"  # files written before the log scale


def test_an_unknown_haptic_scale_fails_to_load(saved: Path) -> None:
    _rewrite_json(saved, lambda document: document.update(haptics="kg"))
    with pytest.raises(PolicyFileError, match="haptics must be 'newtons' or 'log'"):
        load_policy(saved)


def test_actions_are_clipped_like_sb3(trpo, tmp_path: Path) -> None:
    model, venv = trpo
    weight = model.policy.action_net.weight
    original = weight.detach().clone()
    with torch.no_grad():
        weight.mul_(100.0)  # so mean actions leave [-1, 1]
    try:
        policy = load_policy(_save(tmp_path / "loud", model, venv))
        actions = np.array([policy.act(obs) for obs in _observations()])
        assert np.abs(actions).max() == 1.0
        _assert_matches_sb3(policy, model, venv)
    finally:
        with torch.no_grad():
            weight.copy_(original)


def test_ppo_policy_acts_like_sb3(tmp_path: Path) -> None:
    model, venv = _train(PPO)
    policy = load_policy(_save(tmp_path / "ppo", model, venv, algorithm="PPO"))
    _assert_matches_sb3(policy, model, venv)


def test_metadata_round_trips(saved: Path) -> None:
    policy = load_policy(saved)
    assert policy.metadata == METADATA
    assert (policy.name, policy.robot, policy.ablation) == ("fixed_complete", "fixed", "complete")
    document = json.loads(saved.read_text())
    assert document["format"] == "dressbench-policy" and document["format_version"] == 1
    assert document["architecture"] == {
        "hidden_sizes": [64, 64],
        "activation": "tanh",
        "obs_dim": OBS_DIM,
        "act_dim": 11,
    }
    assert document["obs_normalization"] == {"clip_obs": 10.0, "epsilon": 1e-8}


def test_any_of_the_three_paths_loads(saved: Path) -> None:
    tensors_path, json_path = policy_paths(saved)
    for path in (json_path, tensors_path, json_path.with_suffix(""), str(json_path)):
        assert load_policy(path).name == "fixed_complete"


def test_act_checks_the_observation_length(saved: Path) -> None:
    policy = load_policy(saved)
    with pytest.raises(ValueError, match=r"\(163,\)"):
        policy.act(np.zeros(160))
    policy.reset(seed=3)  # deterministic: reset changes nothing
    obs = _observations()[0]
    np.testing.assert_array_equal(policy.act(obs), policy.act(obs))


NO_UNPICKLING = """
import sys

def refuse(event, args):
    if event == "pickle.find_class":  # every unpickling of a class or function raises it
        raise RuntimeError(f"unpickling was attempted: {args}")

sys.addaudithook(refuse)
"""


def _run_without_unpickling(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", NO_UNPICKLING + code], capture_output=True,
                          text=True, timeout=120)  # fmt: skip


def test_loading_and_acting_never_unpickle(saved: Path) -> None:
    code = f"""
import numpy as np
from dressbench.policy_file import load_policy
policy = load_policy({str(saved)!r})
print(policy.act(np.ones(policy.obs_dim)).shape)
"""
    result = _run_without_unpickling(code)
    assert result.returncode == 0 and "(11,)" in result.stdout, result.stderr


def test_the_unpickling_guard_catches_a_pickle(tmp_path: Path) -> None:
    """The guard above can fail: a pickled object (what SB3's .zip files hold) trips it."""
    path = tmp_path / "object.pkl"
    path.write_bytes(pickle.dumps(Path("x")))
    result = _run_without_unpickling(
        f"import pickle; pickle.loads(open({str(path)!r}, 'rb').read())"
    )
    assert result.returncode != 0 and "unpickling was attempted" in result.stderr


def test_loading_imports_neither_torch_nor_sb3(saved: Path) -> None:
    code = (
        "import sys\n"
        "from dressbench.training import load_policy\n"
        f"load_policy({str(saved)!r}).act([0.0] * {OBS_DIM})\n"
        "heavy = {'torch', 'stable_baselines3'} & set(sys.modules)\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


@pytest.mark.parametrize(
    ("damage", "file", "reason"),
    [
        ("truncate_tensors", "safetensors", "truncated"),
        ("flip_tensor_byte", "safetensors", "checksum"),
        ("delete_tensors", "safetensors", "missing .*goes with fixed_complete.json"),
        ("corrupt_json", "json", "not valid JSON"),
        ("delete_json", "json", "missing .*goes with fixed_complete.safetensors"),
        ("wrong_format", "json", "not a dressbench policy"),
        ("wrong_version", "json", "format_version 2 is not supported"),
        (
            "wrong_shape",
            "safetensors",
            r"tensor pi\.0\.weight has shape \(64, 163\).*needs \(32, 163\)",
        ),
        ("missing_field", "json", "ablation is missing"),
        ("bad_activation", "json", "activation must be 'tanh', found 'relu'"),
    ],
)
def test_damaged_files_raise_one_clear_line(saved: Path, damage: str, file: str, reason: str):
    tensors_path, json_path = policy_paths(saved)
    blob = tensors_path.read_bytes()
    damages = {
        "truncate_tensors": lambda: tensors_path.write_bytes(blob[:-10]),
        "flip_tensor_byte": lambda: tensors_path.write_bytes(blob[:-1] + bytes([blob[-1] ^ 1])),
        "delete_tensors": tensors_path.unlink,
        "corrupt_json": lambda: json_path.write_text('{"format": "dressbench-pol'),
        "delete_json": json_path.unlink,
        "wrong_format": lambda: _rewrite_json(json_path, lambda d: d.update(format="other")),
        "wrong_version": lambda: _rewrite_json(json_path, lambda d: d.update(format_version=2)),
        "wrong_shape": lambda: _rewrite_json(
            json_path, lambda d: d["architecture"].update(hidden_sizes=[32, 64])
        ),
        "missing_field": lambda: _rewrite_json(json_path, lambda d: d.pop("ablation")),
        "bad_activation": lambda: _rewrite_json(
            json_path, lambda d: d["architecture"].update(activation="relu")
        ),
    }
    damages[damage]()
    with pytest.raises(PolicyFileError, match=reason) as info:
        load_policy(saved)
    message = str(info.value)
    assert f"fixed_complete.{file}" in message
    assert "\n" not in message
    assert isinstance(info.value, ValueError)


def test_save_leaves_no_temp_files(saved: Path) -> None:
    assert sorted(p.name for p in saved.parent.iterdir()) == [
        "fixed_complete.json",
        "fixed_complete.safetensors",
    ]
    umask = os.umask(0)
    os.umask(umask)
    assert saved.stat().st_mode & 0o777 == 0o666 & ~umask  # the umask's, not mkstemp's 0600


def test_crash_between_the_two_writes_is_detected(trpo, saved: Path, monkeypatch) -> None:
    model, venv = trpo
    real_replace = os.replace

    def crash_on_json(src, dst):
        if str(dst).endswith(".json"):
            raise OSError("simulated crash")
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", crash_on_json)
    with torch.no_grad():
        model.policy.action_net.bias.add_(0.5)  # the new save has different tensors
    try:
        with pytest.raises(OSError, match="simulated crash"):
            _save(saved.with_suffix(""), model, venv)
    finally:
        with torch.no_grad():
            model.policy.action_net.bias.sub_(0.5)
    assert len(list(saved.parent.iterdir())) == 2  # the temp JSON was removed
    with pytest.raises(PolicyFileError, match="checksum does not match fixed_complete.json"):
        load_policy(saved)


def test_save_refuses_bad_metadata(trpo, tmp_path: Path) -> None:
    model, venv = trpo
    for metadata, reason in [
        ({"robot": "fixed"}, "ablation"),
        ({"ablation": "complete"}, "robot"),
        ({**METADATA, "format": "x"}, "format's keys"),
        ({**METADATA, "config": Path("x")}, "JSON"),
        ({**METADATA, "haptics": "kg"}, "haptics must be"),  # what loading would refuse
        ({**METADATA, "actuation": "wiggle"}, "actuation must be"),
        ({**METADATA, "profile": 3}, "profile must be"),
    ]:
        with pytest.raises(ValueError, match=reason):
            save_policy(tmp_path / "bad", model, venv.obs_rms, metadata)
    assert list(tmp_path.iterdir()) == []  # checked before anything is written


def test_list_policies_finds_policies_and_ignores_other_json(saved: Path, tmp_path: Path) -> None:
    (tmp_path / "leaderboard.json").write_text('{"rows": []}')
    (tmp_path / "notes.json").write_text("not json at all")
    broken = tmp_path / "broken.json"  # a policy JSON whose tensors are missing: still listed
    broken.write_text(json.dumps({"format": "dressbench-policy"}))
    assert list_policies(tmp_path) == [broken, saved]
    assert list_policies(tmp_path / "absent") == []
