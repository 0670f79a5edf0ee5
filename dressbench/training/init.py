"""Starting a run from a trained human: its actor's weights, its action spread and its
observation normalisation. The critic starts afresh (a policy file keeps only the actor); the
normalisation keeps learning, weighted as though it had seen the parent's steps, so the inputs
the parent's actor knows do not jump at the first batch."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import torch

from ..plugins import human_plugin
from ..policy_file import TrainedPolicy, load_policy

if TYPE_CHECKING:
    from stable_baselines3.common.vec_env import VecNormalize

    from .config import TrainConfig


def parent_policy(config: TrainConfig) -> TrainedPolicy:
    """The trained human ``config.init`` names, checked to be one this run can start from
    (else a one-line ``ValueError``)."""
    plugin = human_plugin(config.init)
    if not plugin.from_policy_file:
        raise ValueError(f"cannot start from human {config.init!r}: it is a plugin from "
                         f"{plugin.source}, not a trained policy file")  # fmt: skip
    policy = load_policy(plugin.value)
    if problem := _mismatch(config, policy):
        raise ValueError(f"cannot start from human {config.init!r}: {problem}")
    return policy


def _mismatch(config: TrainConfig, policy: TrainedPolicy) -> str | None:
    """What in the parent's file differs from what the run trains with, or None."""
    wanted = {"ablation": config.ablation, "actuation": config.actuation,
              "haptics": config.haptics}  # fmt: skip
    found = {"ablation": policy.ablation, "actuation": policy.actuation,
             "haptics": policy.haptics}  # fmt: skip
    for key, value in wanted.items():
        if found[key] != value:
            return f"it was trained with {key} {found[key]!r}, this run trains with {value!r}"
    if not np.isclose(policy.epsilon, config.norm_epsilon):
        return (f"its observation normalisation has epsilon {policy.epsilon:g}, this run "
                f"{config.norm_epsilon:g}")  # fmt: skip
    steps = policy.metadata.get("steps")
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        return "its file does not record how many steps it learned ('steps')"
    return None


def start_from(model: Any, venv: VecNormalize, parent: TrainedPolicy) -> None:
    """Give a fresh SB3 actor-critic ``model`` the parent's actor and ``venv`` its observation
    normalisation; a ValueError if the networks' shapes differ."""
    policy = model.policy
    linears = [*policy.mlp_extractor.policy_net[0::2], policy.action_net]
    shapes = [tuple(layer.weight.shape) for layer in linears]
    found = [weight.shape for weight, _ in parent.layers]
    if shapes != found:
        raise ValueError(f"cannot start from human {parent.name!r}: its actor's layers are "
                         f"{found}, this run's {shapes}")  # fmt: skip
    with torch.no_grad():
        for layer, (weight, bias) in zip(linears, parent.layers, strict=True):
            layer.weight.copy_(torch.as_tensor(weight))
            layer.bias.copy_(torch.as_tensor(bias))
        policy.log_std.copy_(torch.as_tensor(parent.log_std))
    venv.obs_rms.mean = parent.obs_mean.copy()
    venv.obs_rms.var = parent.obs_var.copy()
    venv.obs_rms.count = float(parent.metadata["steps"])


def parent_record(parent: TrainedPolicy) -> dict[str, Any]:
    """What run.json and the exported file record of the parent: its name, the checksum of its
    weights, what it was trained for and how long."""
    metadata = parent.metadata
    return {"name": parent.name, "sha256": parent.checksum, "robot": metadata.get("robot"),
            "recipe": (metadata.get("config") or {}).get("recipe"),
            "steps": metadata.get("steps")}  # fmt: skip
