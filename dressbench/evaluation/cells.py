"""Leaderboard cells: a robot strategy × a human model, with the env options they run under (the
capability profile among them)."""

from __future__ import annotations

import hashlib
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

from ..plugins import (
    TYPICAL_PROFILE,
    Plugin,
    human_plugin,
    human_plugins,
    human_providers,
    profile_plugin,
    robot_plugin,
    robot_plugins,
)
from ..plugins.contract import trains_generalists
from .identity import canonical, digest, plain

if TYPE_CHECKING:
    from ..config import EnvConfig
    from ..plugins import HumanPolicy


@dataclass(frozen=True)
class Cell:
    """A robot strategy and a human model, and the ``make_human_env`` options of their episodes.

    ``options`` always holds the human's own ablation and actuation, and its capability profile
    unless it runs under any: a policy is scored in the setting it was trained for. ``plugins``
    holds what the names stood for when the cell was made (``plugin_identities``), and
    ``records`` the plugins they were resolved to, so that workers make instances without
    looking them up again; a cell made by hand gets both from the registry on first use.
    """

    robot: str
    human: str
    options: Mapping[str, Any] = field(default_factory=dict, hash=False)
    plugins: Mapping[str, Any] | None = field(default=None, hash=False)
    records: tuple[Plugin, Plugin] | None = field(default=None, compare=False, repr=False)

    def resolved(self) -> tuple[Plugin, Plugin]:
        """The robot's and the human's plugin records: those the cell was made with, else the
        registry's."""
        return self.records or (robot_plugin(self.robot), human_plugin(self.human))

    @property
    def ablation(self) -> str:
        """The ablation the env runs with (the human's)."""
        return self.options["ablation"]

    @property
    def profile(self) -> str:
        """The capability profile the human's body has."""
        return self.columns["profile"]

    def config(self) -> EnvConfig:
        """The full env configuration, defaults resolved."""
        from ..config import EnvConfig  # here: importing it loads the physics

        return EnvConfig.build(**self.options)

    @cached_property
    def columns(self) -> dict[str, Any]:
        """The cell's identifying columns in the result tables (computed once)."""
        config = self.config()
        return {
            "robot": self.robot,
            "human": self.human,
            "ablation": config.ablation,
            "profile": config.profile,
            "horizon": config.horizon,
            "gown_vertices": config.gown_vertices,
            "device": config.device,
            "config_id": config_id(config),
        }

    @cached_property
    def identity(self) -> dict[str, Any]:
        """What the cell's rollouts belong to, as JSON values: the robot's and the human's
        identities (``plugin_identities``), the capability profile's (``profile_identity``) and
        the full env configuration (``config_fields``).

        A record is reused only by a cell of the same identity; its folder is named by its hash.
        """
        plugins = self.plugins
        if plugins is None:
            robot, human = self.resolved()
            plugins = plugin_identities(robot, human, human.factory())
        config = self.config()
        return plain({**plugins, **profile_identity(config.profile),
                      "config": config_fields(config)})  # fmt: skip

    @cached_property
    def key(self) -> str:
        """A short hash of ``identity``: the cell's rollout folder is named by it."""
        return digest(self.identity)


def config_fields(config: EnvConfig) -> dict[str, Any]:
    """Every field of an env configuration, nested dataclasses included, as JSON values; the
    profile only when it is not the typical body, whose episodes are those of every
    configuration made before profiles: their identities, caches and config ids stay valid."""
    fields = plain(asdict(config))
    if config.profile == TYPICAL_PROFILE:
        del fields["profile"]
    return fields


def config_id(config: EnvConfig) -> str:
    """A short stable name of a whole env configuration, so different settings never mix.

    ``cfg-`` + 10 hex digits of the SHA-1 of its fields as sorted JSON (``config_fields``).
    """
    return "cfg-" + hashlib.sha1(canonical(config_fields(config)).encode()).hexdigest()[:10]


def robot_identity(plugin: Plugin) -> dict[str, Any]:
    """What a robot strategy stands for: the entry point's name, distribution, version."""
    return {"name": plugin.name, "distribution": plugin.package, "version": plugin.version}


def human_identity(plugin: Plugin, policy: HumanPolicy) -> dict[str, Any]:
    """What a human stands for, given the instance ``policy`` its record made.

    A trained policy file is its checksum (the sha256 of its tensors, which ``load_policy``
    verified) and its observation normalisation, wherever the file lies; an entry point is its
    name, distribution and version, plus the checksum when it returns a trained policy.
    """
    from ..policy_file import TrainedPolicy  # light: NumPy and safetensors

    identity: dict[str, Any] = {"name": plugin.name}
    if plugin.from_policy_file:
        identity["source"] = "policy file"
    else:
        identity |= {"distribution": plugin.package, "version": plugin.version}
    if isinstance(policy, TrainedPolicy):
        identity |= {
            "checksum": policy.checksum,
            "obs_normalization": {"clip_obs": policy.clip_obs, "epsilon": policy.epsilon},
        }
    return identity


def profile_identity(name: str) -> dict[str, Any]:
    """What a capability profile adds to a cell's identity: nothing for the typical body (as
    ``config_fields``), else ``{"profile": ...}``, its entry point's name, distribution and
    version, so that a new version of the profile is not taken for the old one."""
    if name == TYPICAL_PROFILE:
        return {}
    plugin = profile_plugin(name)
    return {"profile": {"name": name, "distribution": plugin.package, "version": plugin.version}}


def plugin_identities(robot: Plugin, human: Plugin, policy: HumanPolicy) -> dict[str, Any]:
    """``{"robot": robot_identity(robot), "human": human_identity(human, policy)}``."""
    return {"robot": robot_identity(robot), "human": human_identity(human, policy)}


def make_cell(robot: str, human: str, policy: HumanPolicy | None = None, **options: Any) -> Cell:
    """A cell of the named plugins, resolved here once (``resolved_cell``)."""
    return resolved_cell((robot_plugin(robot), human_plugin(human)), policy, **options)


def resolved_cell(
    records: tuple[Plugin, Plugin], policy: HumanPolicy | None = None, **options: Any
) -> Cell:
    """A checked cell of resolved plugins: the options valid, and the env the one the human was
    made for (its ablation and actuation: ``factory.env_options``; another is a ValueError).

    Errors surface here, in the calling process, rather than inside a worker. The cell records
    the identities of the robot and of ``policy`` (the human, made if not given) and carries
    the records to the workers, which make their instances from them.
    """
    from ..factory import env_options

    robot, human = records
    policy = policy if policy is not None else human.factory()
    options = env_options(policy, **options)
    cell = Cell(robot.name, human.name, options, plugin_identities(robot, human, policy), records)
    cell.config()  # an unknown option raises TypeError now
    return cell


def leaderboard_cells(
    robots: Iterable[str] | None = None, humans: Iterable[str] | None = None, **options: Any
) -> list[Cell]:
    """Every ok robot strategy × every ok human meant for it (trained for it, or generic);
    a distribution of strategies (``contract.trains_generalists``) only when ``robots`` names it.

    A human is meant for a robot when its ``robot`` attribute names it; humans whose ``robot`` is
    None (the built-in baselines passive, random, reach, scripted) are generic and face every robot.
    ``robots`` / ``humans`` restrict the names. Each human runs under its own capability profile;
    one of profile None (the baselines) under ``options["profile"]`` (default: typical), and given
    that option only humans of that profile or of none are scored, and those ``humans`` names,
    under it. Broken plugins, and plugins that fail the preflight (``plugin_problems``: one
    reset and one act in a real env, a policy's metadata, its profile), are skipped with a
    warning naming each and its package; the others are scored. A profile asked for that
    cannot run is a ValueError.
    """
    from ..plugins.contract import declared_profile

    profile = options.get("profile", TYPICAL_PROFILE)
    _require_profile(profile)
    humans = None if humans is None else list(humans)
    robot_records, human_records = robot_plugins(), human_plugins()
    robot_names = _usable(robot_records, robots, "robot")
    if robots is None:  # a distribution of strategies is scored only when asked for by name
        robot_names = [n for n in robot_names if not trains_generalists(robot_records[n].factory)]
    policies, problems = _instances(human_records, _usable(human_records, humans, "human"))
    meant = {
        name: policy
        for name, policy in policies.items()
        if (not isinstance(getattr(policy, "robot", None), str) or policy.robot in robot_names)
        and (
            "profile" not in options
            or declared_profile(policy) in (None, profile)
            or (humans is not None and name in humans)
        )
    }  # humans for robots or profiles not asked for are neither checked nor scored
    good, meant, found = plugin_problems([robot_records[name] for name in robot_names], meant)
    for noun, name, problem in problems + found:
        records = robot_records if noun == "robot" else human_records
        warnings.warn(
            f"skipping {noun} plugin {name!r} from {records[name].source}: {problem}",
            stacklevel=2,
        )
    return [
        resolved_cell((robot, human_records[name]), policy, **options)
        for robot in good
        for name, policy in meant.items()
        if policy.robot in (None, robot.name)
    ]


def plugin_problems(
    robots: Iterable[Plugin], humans: Mapping[str, HumanPolicy]
) -> tuple[list[Plugin], dict[str, HumanPolicy], list[tuple[str, str, str]]]:
    """The preflight of an evaluation, in this process: which plugins can be run.

    Each robot strategy gets one reset and one act in a small real env
    (``preflight.robot_problem``); each human instance what it declares checked (ablation,
    robot, actuation, profile, ``obs_dim`` against the ablation's observation), one act on a
    real observation of its ablation (``preflight.human_problem``) and the check of the
    capability profile it declares (``preflight.profile_problem``). Returns the robots and
    humans that pass, and a ``(noun, name, why)`` for each that does not.
    """
    from ..plugins.contract import declared_profile, human_declaration_problem
    from ..preflight import Observations, human_problem, profile_problem, robot_problem

    problems: list[tuple[str, str, str]] = []
    good_robots = []
    for robot in robots:
        problem = robot_problem(robot)
        if problem:
            problems.append(("robot", robot.name, problem))
        else:
            good_robots.append(robot)
    good_humans: dict[str, HumanPolicy] = {}
    observations = Observations(good_robots[0]) if good_robots else None
    for name, policy in humans.items():
        problem = human_declaration_problem(policy)
        if problem is None and observations is not None:
            problem = human_problem(policy, observations(policy.ablation))
        profile = declared_profile(policy) if problem is None else None
        if profile is not None and (why := profile_problem(profile)):
            problem = f"its capability profile {profile!r} cannot run: {why}"
        if problem:
            problems.append(("human", name, problem))
        else:
            good_humans[name] = policy
    return good_robots, good_humans, problems


def checked_cell(robot: str, human: str, **options: Any) -> Cell:
    """The cell of one robot and one human, their plugins resolved once and through the
    preflight (``plugin_problems``); a ValueError naming the plugin, its package and why when
    one fails it."""
    records = robot_plugin(robot), human_plugin(human)  # unknown or broken: its PluginError
    policy = records[1].factory()
    _, _, problems = plugin_problems([records[0]], {human: policy})
    if problems:
        noun, name, problem = problems[0]
        record = records[0] if noun == "robot" else records[1]
        raise ValueError(
            f"{noun} plugin {name!r} from {record.source} cannot be evaluated: {problem}"
        )
    cell = resolved_cell(records, policy, **options)
    _require_profile(cell.profile)
    return cell


def _require_profile(name: str) -> None:
    """A ValueError in one line when the capability profile ``name`` cannot run
    (``preflight.profile_problem``)."""
    from ..preflight import profile_problem

    problem = profile_problem(name)
    if problem:
        raise ValueError(f"capability profile {name!r} cannot be evaluated: {problem}")


def adapted_profiles(names: Iterable[str]) -> dict[str, str]:
    """The profile each named human was adapted to, for those of one other than typical (a
    human that is unknown, broken or cannot be made is left to ``leaderboard_cells`` to report)."""
    from ..plugins.contract import declared_profile

    records = human_plugins()
    policies, _ = _instances(records, [n for n in names if n in records and records[n].ok])
    declared = {name: declared_profile(policy) for name, policy in policies.items()}
    return {name: profile for name, profile in declared.items()
            if isinstance(profile, str) and profile != TYPICAL_PROFILE}  # fmt: skip


def _instances(
    records: Mapping[str, Any], names: Iterable[str]
) -> tuple[dict[str, HumanPolicy], list[tuple[str, str, str]]]:
    """A fresh instance of each named human plugin, and a problem for each whose factory fails."""
    from ..plugins.registry import _one_line

    policies, problems = {}, []
    for name in names:
        try:
            policies[name] = records[name].factory()
        except Exception as exc:
            problems.append(("human", name, f"creating an instance failed: {_one_line(exc)}"))
    return policies, problems


def warn_losing_duplicates(cells: Iterable[Cell]) -> None:
    """One warning per human the cells run that other plugins or policy files also provide:
    which one runs, and which do not."""
    for name in dict.fromkeys(cell.human for cell in cells):
        providers = human_providers(name)
        if len(providers) < 2:
            continue
        winner, *losers = providers
        others = "; ".join(plugin.source for plugin in losers)
        lost = f"the one from {others}" if len(losers) == 1 else f"those from {others}"
        warnings.warn(
            f"human {name!r} has a losing duplicate: the one from {winner.source} runs, not "
            f"{lost} (rename it to run it)",
            stacklevel=3,
        )


def describe_plugin(noun: str, name: str) -> str:
    """``"NOUN plugin 'NAME' from ORIGIN"``: a plugin in a message."""
    records = robot_plugins() if noun == "robot" else human_plugins()
    return f"{noun} plugin {name!r} from {records[name].source}"


def _usable(plugins: Mapping[str, Any], wanted: Iterable[str] | None, noun: str) -> list[str]:
    """The sorted names of the ok plugins among ``wanted`` (all if None); warn about broken ones."""
    names = sorted(plugins) if wanted is None else list(dict.fromkeys(wanted))
    unknown = [name for name in names if name not in plugins]
    if unknown:
        raise ValueError(f"unknown {noun} plugin(s) {', '.join(unknown)}: have {sorted(plugins)}")
    for name in names:
        if not plugins[name].ok:
            plugin = plugins[name]
            warnings.warn(
                f"skipping broken {noun} plugin {name!r} from {plugin.source}: {plugin.error}",
                stacklevel=3,
            )
    return [name for name in names if plugins[name].ok]
