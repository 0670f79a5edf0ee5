"""Training human policies (``train``), and the policy files they ship as (``policy_file``).

Importing this package is light: the policy files need NumPy and safetensors only; torch and
stable-baselines3 load only when a model is exported or trained.
"""

from __future__ import annotations

from ..policy_file import PolicyFileError, TrainedPolicy, list_policies, load_policy, policy_paths
from .config import TrainConfig
from .export import save_policy

TRAIN_MODULES = {"torch": "torch", "stable_baselines3": "stable-baselines3",
                 "sb3_contrib": "sb3-contrib", "tensorboard": "tensorboard"}  # fmt: skip

__all__ = [
    "PolicyFileError",
    "require_train_extra",
    "TrainedPolicy",
    "list_policies",
    "load_policy",
    "policy_paths",
    "save_policy",
    "TrainConfig",
    "train",
    "train_config",
]


def require_train_extra() -> None:
    """Training's packages (the ``train`` extra) are installed, or a ValueError in one line
    saying what to do."""
    import importlib.util

    missing = [
        dist for module, dist in TRAIN_MODULES.items() if not importlib.util.find_spec(module)
    ]
    if missing:
        raise ValueError(f"training needs {', '.join(missing)}: pip install 'dressbench[train]' "
                         f"(evaluating and rendering trained humans does not)")  # fmt: skip


def __getattr__(name: str):
    """``train`` and ``train_config`` load torch and stable-baselines3, so they are imported
    when first asked for."""
    if name in ("train", "train_config"):
        from . import run

        return getattr(run, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
