"""dressbench: a benchmark suite for robot-assisted dressing (Clegg et al., ICRA 2018).

The public API. Importing the package is cheap: the physics (DART, Warp) and the plugins load
only when an environment is made. It registers the human's gymnasium env as
``dressbench/Dressing-v0`` (an entry point string: nothing heavy is imported), so
``gymnasium.make("dressbench/Dressing-v0", robot="front_linear")`` works after
``import dressbench``.
"""

from __future__ import annotations

from typing import Any

from .factory import DEFAULT_ROBOT, make_env, make_human_env, parallel_env

__version__ = "0.3.0"
__all__ = [
    "ENV_ID",
    "evaluate",
    "leaderboard",
    "load_policy",
    "make_env",
    "make_human_env",
    "parallel_env",
    "train",
]

ENV_ID = "dressbench/Dressing-v0"  # gymnasium.make(ENV_ID, robot=..., **EnvConfig options)


def train(robot: str = DEFAULT_ROBOT, **options: Any):
    """Train a human model for a robot strategy; ``options`` are ``TrainConfig`` fields."""
    from .training import train as train_policy

    return train_policy(robot=robot, **options)


def evaluate(robot: str, human: str, **options: Any):
    """Score a robot strategy with a human over seeded rollouts (see dressbench.evaluation)."""
    from .evaluation import evaluate as run_evaluation

    return run_evaluation(robot, human, **options)


def leaderboard(**options: Any):
    """Every robot strategy against the humans meant for it (see dressbench.evaluation)."""
    from .evaluation import leaderboard as run_leaderboard

    return run_leaderboard(**options)


def load_policy(path: str):
    """A trained human model from its safetensors + JSON files, without unpickling.

    ``path`` is a file of the pair or its stem. Given the name of a human plugin instead (e.g.
    ``"scripted"``, or a shipped policy's name), the error says so and what to call.
    """
    from .policy_file import PolicyFileError
    from .policy_file import load_policy as load

    try:
        return load(path)
    except PolicyFileError as error:
        hint = _plugin_name_hint(path)
        if hint is None:
            raise
        raise PolicyFileError(hint) from error


def _plugin_name_hint(path: Any) -> str | None:
    """One line for a missing policy file whose ``path`` is a human plugin's name, or None."""
    import os
    from pathlib import Path

    name = os.fspath(path)
    if os.sep in name or "/" in name or Path(name).suffix in (".json", ".safetensors"):
        return None
    if Path(name + ".json").exists() or Path(name + ".safetensors").exists():
        return None  # a pair in the working directory, broken: its own error says why
    from .plugins import human_plugins

    plugin = human_plugins().get(name)
    if plugin is None:
        return None
    where = f" (its file: {plugin.value})" if plugin.from_policy_file else ""
    return (
        f"{name!r} is a human plugin name, not a policy file path{where}: use "
        f"dressbench.plugins.load_human({name!r}), or give load_policy the path of a .json"
    )


def _register_gymnasium() -> None:
    """Register ``ENV_ID`` with gymnasium by its entry point string (no physics is imported)."""
    try:
        import gymnasium
    except ImportError:  # pragma: no cover - gymnasium is a dependency
        return
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="dressbench.factory:make_human_env")


_register_gymnasium()
