"""Making environments: the two-agent PettingZoo env and the human's gymnasium env, for a robot
strategy (a plugin name, its record or an instance), the capability profile the options name and,
given one, the human that will act in it. Nothing heavy loads until one is made."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .config import EnvConfig
    from .env import DressingEnv
    from .plugins import HumanPolicy, Plugin
    from .single_agent import HumanEnv

DEFAULT_ROBOT = "fixed"  # the strategy an env, a training or a plugin check gets when none is named


def make_env(
    robot: str | Plugin | Any = DEFAULT_ROBOT,
    *,
    human: str | HumanPolicy | None = None,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> DressingEnv:
    """The two-agent PettingZoo environment for a robot strategy and, given ``human`` (a human
    plugin's name or a policy), the setting that human was made for (``env_options``).

    ``options`` override fields of ``EnvConfig``: ablation, profile, horizon, gown_vertices,
    device, reward, scene; ``actuation`` says how the human's actions drive its joints. The
    profile's plugin is loaded here and gives the env the human's body.
    """
    from .config import EnvConfig
    from .env import DressingEnv
    from .plugins import profile_plugin

    strategy, name, origin = _robot(robot)
    config = EnvConfig.build(config, **env_options(human, config, **options))
    profile = profile_plugin(config.profile)
    return DressingEnv(strategy, config, render_mode, robot_name=name, robot_origin=origin,
                       profile=profile.factory(), profile_origin=profile.origin)  # fmt: skip


def parallel_env(
    robot: str | Plugin | Any = DEFAULT_ROBOT,
    *,
    human: str | HumanPolicy | None = None,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> DressingEnv:
    """PettingZoo's name for ``make_env``: the two-agent ``ParallelEnv`` (agents robot, human)."""
    return make_env(robot, human=human, render_mode=render_mode, config=config, **options)


def make_human_env(
    robot: str | Plugin | Any = DEFAULT_ROBOT,
    *,
    human: str | HumanPolicy | None = None,
    render_mode: str | None = None,
    config: EnvConfig | None = None,
    **options: Any,
) -> HumanEnv:
    """A gymnasium env of the human alone, the robot driven by its strategy; given ``human``, the
    env that human was made for (``env_options``), for any caller that runs a human."""
    from .single_agent import HumanEnv

    env = make_env(robot, human=human, render_mode=render_mode, config=config, **options)
    return HumanEnv(env)


def env_options(
    human: str | HumanPolicy | None = None, config: EnvConfig | None = None, **options: Any
) -> dict[str, Any]:
    """The ``EnvConfig`` options of an env: ``options`` with ``actuation`` (how the human's
    actions drive its joints) put into the scene, and given ``human`` (a name or a policy) its
    own ablation and actuation, and its capability profile unless the caller states one (a
    human runs under the body it was trained for unless asked to run under another). An
    ablation or actuation the caller states (in ``options``, its ``scene`` or ``config``) other
    than the human's is a one-line ValueError naming both."""
    from .plugins.contract import declared_actuation, declared_profile, pairing_problem
    from .scene.world import actuated_scene

    actuation = options.pop("actuation", None)
    scene = options.get("scene", config.scene if config else None)
    if human is not None:
        name = human if isinstance(human, str) else None
        policy = _human(human)
        stated = actuation or (scene.human.actuation if scene is not None else None)
        ablation = options.get("ablation", config.ablation if config else None)
        profile = options.get("profile", config.profile if config else None)
        problem = pairing_problem(policy, ablation, stated, name)
        if problem:
            raise ValueError(problem)
        options["ablation"], actuation = policy.ablation, declared_actuation(policy)
        if profile is None and declared_profile(policy) is not None:
            options["profile"] = declared_profile(policy)
    if actuation is not None:
        options["scene"] = actuated_scene(actuation, scene)
    return options


def _human(human: str | HumanPolicy) -> HumanPolicy:
    """The policy of a human given by plugin name or as a policy."""
    if isinstance(human, str):
        from .plugins import load_human

        return load_human(human)
    return human


def _robot(robot: str | Plugin | Any) -> tuple[Any, str | None, str | None]:
    """A robot strategy's instance and, when it is a plugin, its name and origin (messages)."""
    from .plugins import Plugin, robot_plugin

    plugin = robot_plugin(robot) if isinstance(robot, str) else robot
    if isinstance(plugin, Plugin):
        return plugin.factory(), plugin.name, plugin.origin
    return robot, None, None
