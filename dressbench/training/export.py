"""Exporting a trained SB3 model as a policy file (the reading side: ``dressbench.policy_file``).

Only the actor is kept: its MLP weights, the Gaussian's ``log_std`` and the observation
normalisation, as safetensors, with the architecture and the training metadata in JSON.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import safetensors.numpy

from ..files import write_bytes
from ..policy_file import (
    ACTION_SIZE,
    ACTIVATION,
    FORMAT,
    FORMAT_VERSION,
    MAX_TENSORS_BYTES,
    RESERVED_KEYS,
    is_number,
    layer_names,
    metadata_problem,
    policy_paths,
)

if TYPE_CHECKING:
    from stable_baselines3.common.on_policy_algorithm import OnPolicyAlgorithm
    from stable_baselines3.common.policies import ActorCriticPolicy
    from stable_baselines3.common.running_mean_std import RunningMeanStd


def save_policy(
    path_stem: str | os.PathLike[str],
    model: OnPolicyAlgorithm,
    obs_rms: RunningMeanStd,
    metadata: dict[str, Any],
    *,
    clip_obs: float = 10.0,
    epsilon: float = 1e-8,
) -> tuple[Path, Path]:
    """Export what acting needs from a trained SB3 PPO/TRPO ``MlpPolicy`` as a policy file pair.

    ``obs_rms``, ``clip_obs`` and ``epsilon`` are those of the ``VecNormalize`` the model was
    trained in (the defaults are VecNormalize's). ``metadata`` must name ``robot`` (str or None)
    and ``ablation``; all of it is stored in the JSON. Each file is replaced atomically, tensors
    first, so an interrupted save leaves a pair whose checksum does not match.
    """
    tensors_path, json_path = policy_paths(path_stem)
    tensors, architecture = _export_actor(model.policy)
    tensors |= _export_normalization(obs_rms, architecture["obs_dim"], clip_obs, epsilon)
    _check_metadata(metadata)
    blob = safetensors.numpy.save(tensors)
    if len(blob) > MAX_TENSORS_BYTES:
        limit = MAX_TENSORS_BYTES // 2**20
        raise ValueError(f"cannot export: {len(blob)} bytes of tensors, more than {limit} MiB")
    document = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "architecture": architecture,
        "obs_normalization": {"clip_obs": float(clip_obs), "epsilon": float(epsilon)},
        "tensors": {"sha256": hashlib.sha256(blob).hexdigest(), "size": len(blob)},
        **metadata,
    }
    text = _to_json(document)
    json_path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes(tensors_path, blob)
    write_bytes(json_path, text.encode("utf-8"))
    return tensors_path, json_path


def _export_actor(policy: ActorCriticPolicy) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The actor's tensors and architecture, after checking the policy is one we can rebuild."""
    from gymnasium import spaces
    from stable_baselines3.common.distributions import DiagGaussianDistribution
    from stable_baselines3.common.policies import ActorCriticPolicy
    from stable_baselines3.common.torch_layers import FlattenExtractor
    from torch import nn

    if not isinstance(policy, ActorCriticPolicy):
        raise ValueError(f"cannot export {type(policy).__name__}: expected PPO/TRPO's MlpPolicy")
    if not isinstance(policy.action_dist, DiagGaussianDistribution):
        raise ValueError("cannot export: the policy must be a diagonal Gaussian (no gSDE)")
    obs_space, act_space = policy.observation_space, policy.action_space
    if not isinstance(obs_space, spaces.Box) or len(obs_space.shape) != 1:
        raise ValueError(f"cannot export: observations must be a 1-D Box, got {obs_space}")
    if not isinstance(policy.pi_features_extractor, FlattenExtractor):
        raise ValueError("cannot export: the features extractor must be the default Flatten")
    if not (
        isinstance(act_space, spaces.Box)
        and act_space.shape == (ACTION_SIZE,)
        and np.all(act_space.low == -1.0)
        and np.all(act_space.high == 1.0)
    ):
        raise ValueError(f"cannot export: actions must be Box(-1, 1, ({ACTION_SIZE},))")
    modules = list(policy.mlp_extractor.policy_net)
    if not (
        all(isinstance(m, nn.Linear) for m in modules[0::2])
        and all(isinstance(m, nn.Tanh) for m in modules[1::2])
        and len(modules) % 2 == 0
    ):
        raise ValueError("cannot export: the actor must be Linear layers each followed by Tanh")
    linears = [*modules[0::2], policy.action_net]
    tensors = {}
    for name, layer in zip(layer_names(len(linears) - 1), linears, strict=True):
        tensors[f"{name}.weight"] = _numpy(layer.weight)
        tensors[f"{name}.bias"] = _numpy(layer.bias)
    tensors["log_std"] = _numpy(policy.log_std)
    architecture = {
        "hidden_sizes": [layer.out_features for layer in modules[0::2]],
        "activation": ACTIVATION,
        "obs_dim": obs_space.shape[0],
        "act_dim": ACTION_SIZE,
    }
    return tensors, architecture


def _numpy(tensor: Any) -> np.ndarray:
    """A torch tensor as a contiguous NumPy array, as safetensors wants it."""
    return np.ascontiguousarray(tensor.detach().cpu().numpy())


def _export_normalization(
    obs_rms: RunningMeanStd, obs_dim: int, clip_obs: float, epsilon: float
) -> dict[str, np.ndarray]:
    """VecNormalize's running mean and variance of the observation, checked against the policy."""
    mean = np.ascontiguousarray(obs_rms.mean, dtype=np.float64)
    var = np.ascontiguousarray(obs_rms.var, dtype=np.float64)
    if mean.shape != (obs_dim,) or var.shape != (obs_dim,):
        raise ValueError(
            f"obs_rms has shapes {mean.shape} and {var.shape}, the policy observes ({obs_dim},)"
        )
    if not (is_number(clip_obs) and clip_obs > 0 and is_number(epsilon) and epsilon >= 0):
        raise ValueError(f"need clip_obs > 0 and epsilon >= 0, got {clip_obs!r} and {epsilon!r}")
    return {"obs_mean": mean, "obs_var": var}


def _check_metadata(metadata: dict[str, Any]) -> None:
    """Refuse metadata that would clash with the format or leave the protocol's fields unset."""
    clashes = [key for key in RESERVED_KEYS if key in metadata]
    if clashes:
        raise ValueError(f"metadata may not use the format's keys: {', '.join(clashes)}")
    if problem := metadata_problem(metadata):
        raise ValueError(f"metadata: {problem}")


def _to_json(document: dict[str, Any]) -> str:
    """Strict JSON text (no NaN), or a ValueError saying which metadata cannot be written."""
    try:
        return json.dumps(document, indent=2, allow_nan=False) + "\n"
    except (TypeError, ValueError) as exc:
        raise ValueError(f"metadata cannot be written as JSON: {exc}") from None
