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
__all__ = ["make_env", "make_human_env"]


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

    return DressingEnv(_robot(robot), EnvConfig.build(config, **options), render_mode)


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
