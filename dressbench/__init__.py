"""dressbench: a benchmark suite for robot-assisted dressing (Clegg et al., ICRA 2018).

The public API. Importing the package is cheap: the physics (DART, Warp) and the plugins load
only when an environment is made.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .config import EnvConfig
    from .env import DressingEnv
    from .single_agent import HumanEnv

__version__ = "0.1.0"
__all__ = ["evaluate", "leaderboard", "load_policy", "make_env", "make_human_env", "train"]


def make_env(
    robot: str | Any = "fixed",
    *,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> DressingEnv:
    """The two-agent PettingZoo environment for a robot strategy (a plugin name or instance).

    ``options`` override fields of ``EnvConfig``: ablation, horizon, gown_vertices, device,
    reward, scene.
    """
    from .config import EnvConfig
    from .env import DressingEnv

    name = robot if isinstance(robot, str) else None
    return DressingEnv(
        _robot(robot), EnvConfig.build(config, **options), render_mode, robot_name=name
    )


def make_human_env(
    robot: str | Any = "fixed",
    *,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> HumanEnv:
    """A gymnasium env of the human alone, the robot driven by the named strategy."""
    from .single_agent import HumanEnv

    return HumanEnv(make_env(robot, render_mode=render_mode, config=config, **options))


def _robot(robot: str | Any) -> Any:
    if isinstance(robot, str):
        from .plugins import load_robot

        return load_robot(robot)
    return robot


def train(robot: str = "fixed", **options: Any):
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
    """A trained human model from its safetensors + JSON files, without unpickling."""
    from .training.policy_file import load_policy as load

    return load(path)
