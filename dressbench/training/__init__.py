"""Training human policies (``train``), and the policy files they ship as (``policy_file``).

Importing this package is light: the policy files need NumPy and safetensors only; torch and
stable-baselines3 load only when a model is exported or trained.
"""

from __future__ import annotations

from ..policy_file import PolicyFileError, TrainedPolicy, list_policies, load_policy, policy_paths
from .config import TrainConfig
from .export import save_policy

__all__ = [
    "PolicyFileError",
    "TrainedPolicy",
    "list_policies",
    "load_policy",
    "policy_paths",
    "save_policy",
    "TrainConfig",
    "train",
]


def __getattr__(name: str):
    """``train`` loads torch and stable-baselines3, so it is imported when first asked for."""
    if name == "train":
        from .run import train

        return train
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
