"""Making environments: the two-agent PettingZoo env and the human's gymnasium env, for a robot
strategy given by plugin name or as an instance. Nothing heavy loads until one is made."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .config import EnvConfig
    from .env import DressingEnv
    from .single_agent import HumanEnv


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

    name, origin = (robot, robot_origin(robot)) if isinstance(robot, str) else (None, None)
    return DressingEnv(_robot(robot), EnvConfig.build(config, **options), render_mode,
                       robot_name=name, robot_origin=origin)  # fmt: skip


def parallel_env(
    robot: str | Any = "fixed",
    *,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> DressingEnv:
    """PettingZoo's name for ``make_env``: the two-agent ``ParallelEnv`` (agents robot, human)."""
    return make_env(robot, render_mode=render_mode, config=config, **options)


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


def robot_origin(name: str) -> str | None:
    """The package (and version) that provides the robot plugin ``name``, for messages."""
    from .plugins import robot_plugins

    plugin = robot_plugins().get(name)
    return plugin.origin if plugin else None


def _robot(robot: str | Any) -> Any:
    if isinstance(robot, str):
        from .plugins import load_robot

        return load_robot(robot)
    return robot
