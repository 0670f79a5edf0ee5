"""Leaderboard cells: a robot strategy × a human model, with the env options they run under."""

from __future__ import annotations

import hashlib
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

from ..plugins import human_plugins, load_human, load_robot, robot_plugins
from .identity import canonical, digest, plain

if TYPE_CHECKING:
    from ..config import EnvConfig
    from ..plugins import HumanPolicy


@dataclass(frozen=True)
class Cell:
    """A robot strategy and a human model, and the ``make_human_env`` options of their episodes.

    ``options`` always holds the human's own ``ablation``: a policy is scored in the setting it
    was trained for. ``plugins`` holds what the names stood for when the cell was made
    (``plugin_identities``); a cell made by hand gets it from the registry on first use.
    """

    robot: str
    human: str
    options: Mapping[str, Any] = field(default_factory=dict, hash=False)
    plugins: Mapping[str, Any] | None = field(default=None, hash=False)

    @property
    def ablation(self) -> str:
        """The ablation the env runs with (the human's)."""
        return self.options["ablation"]

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
            "horizon": config.horizon,
            "gown_vertices": config.gown_vertices,
            "device": config.device,
            "config_id": config_id(config),
        }

    @cached_property
    def identity(self) -> dict[str, Any]:
        """What the cell's rollouts belong to, as JSON values: the robot's and the human's
        identities (``plugin_identities``) and the full env configuration (``config_fields``).

        A record is reused only by a cell of the same identity; its folder is named by its hash.
        """
        plugins = self.plugins
        if plugins is None:
            plugins = plugin_identities(self.robot, self.human)
        return plain({**plugins, "config": config_fields(self.config())})

    @cached_property
    def key(self) -> str:
        """A short hash of ``identity``: the cell's rollout folder is named by it."""
        return digest(self.identity)


def config_fields(config: EnvConfig) -> dict[str, Any]:
    """Every field of an env configuration, nested dataclasses included, as JSON values."""
    return plain(asdict(config))


def config_id(config: EnvConfig) -> str:
    """A short stable name of a whole env configuration, so different settings never mix.

    ``cfg-`` + 10 hex digits of the SHA-1 of its fields as sorted JSON (``config_fields``).
    """
    return "cfg-" + hashlib.sha1(canonical(config_fields(config)).encode()).hexdigest()[:10]


def robot_identity(name: str) -> dict[str, Any]:
    """What a robot strategy name stands for: the entry point's name, distribution, version."""
    plugin = robot_plugins()[name]
    return {"name": name, "distribution": plugin.package, "version": plugin.version}


def human_identity(name: str, policy: HumanPolicy) -> dict[str, Any]:
    """What a human name stands for, given the instance ``policy`` it was loaded as.

    A trained policy file is its checksum (the sha256 of its tensors, which ``load_policy``
    verified) and its observation normalisation, wherever the file lies; an entry point is its
    name, distribution and version, plus the checksum when it returns a trained policy.
    """
    from ..policy_file import TrainedPolicy  # light: NumPy and safetensors

    plugin = human_plugins()[name]
    identity: dict[str, Any] = {"name": name}
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


def plugin_identities(
    robot: str, human: str, policy: HumanPolicy | None = None
) -> dict[str, dict[str, Any]]:
    """``{"robot": robot_identity(robot), "human": human_identity(human, policy)}``; the human
    is loaded when ``policy`` is None."""
    policy = policy if policy is not None else load_human(human)
    return {"robot": robot_identity(robot), "human": human_identity(human, policy)}


def make_cell(robot: str, human: str, policy: HumanPolicy | None = None, **options: Any) -> Cell:
    """A checked cell: both plugins exist, the options are valid, and the ablation is the human's.

    Errors surface here, in the calling process, rather than inside a worker. The cell records
    the identities of the robot and of ``policy`` (the human, loaded if not given).
    """
    load_robot(robot)
    policy = policy if policy is not None else load_human(human)
    if options.get("ablation", policy.ablation) != policy.ablation:
        raise ValueError(
            f"human {human!r} declares ablation {policy.ablation!r}; it is evaluated with it, "
            f"not with ablation={options['ablation']!r}"
        )
    plugins = plugin_identities(robot, human, policy)
    options = {**options, "ablation": policy.ablation}
    actuation = getattr(policy, "actuation", "pd")  # a policy of the paper's torques is
    if actuation != "pd":  # scored with torques
        from ..scene.world import actuated_scene  # here: importing it loads the physics

        options["scene"] = actuated_scene(actuation, options.get("scene"))
    cell = Cell(robot, human, options, plugins)
    cell.config()  # an unknown option raises TypeError now
    return cell


def leaderboard_cells(
    robots: Iterable[str] | None = None, humans: Iterable[str] | None = None, **options: Any
) -> list[Cell]:
    """Every ok robot strategy × every ok human meant for it (trained for it, or generic).

    A human is meant for a robot when its ``robot`` attribute names it; humans whose ``robot`` is
    None (the built-in baselines passive, random, reach, scripted) are generic and face every robot.
    ``robots`` / ``humans`` restrict the names. Broken plugins, and plugins that fail the
    preflight (``plugin_problems``: one reset and one act in a real env, a policy's metadata),
    are skipped with a warning naming each and its package; the others are scored.
    """
    robot_records, human_records = robot_plugins(), human_plugins()
    robot_names = _usable(robot_records, robots, "robot")
    policies, problems = _instances(human_records, _usable(human_records, humans, "human"))
    meant = {
        name: policy
        for name, policy in policies.items()
        if not isinstance(getattr(policy, "robot", None), str) or policy.robot in robot_names
    }  # humans for robots not asked for are neither checked nor scored
    robot_names, meant, found = plugin_problems(robot_names, meant)
    for noun, name, problem in problems + found:
        records = robot_records if noun == "robot" else human_records
        warnings.warn(
            f"skipping {noun} plugin {name!r} from {_origin(records[name])}: {problem}",
            stacklevel=2,
        )
    return [
        make_cell(robot, name, policy, **options)
        for robot in robot_names
        for name, policy in meant.items()
        if policy.robot in (None, robot)
    ]


def plugin_problems(
    robots: Iterable[str], humans: Mapping[str, HumanPolicy]
) -> tuple[list[str], dict[str, HumanPolicy], list[tuple[str, str, str]]]:
    """The preflight of an evaluation, in this process: which plugins can be run.

    Each robot strategy gets one reset and one act in a small real env
    (``preflight.robot_problem``); each human instance its metadata checked (ablation, robot,
    ``obs_dim`` against the ablation's observation) and one act on a real observation of its
    ablation (``preflight.human_problem``). Returns the robots and humans that pass, and a
    ``(noun, name, why)`` for each that does not.
    """
    from ..preflight import Observations, human_metadata_problem, human_problem, robot_problem

    problems: list[tuple[str, str, str]] = []
    good_robots = []
    for name in robots:
        problem = robot_problem(name)
        if problem:
            problems.append(("robot", name, problem))
        else:
            good_robots.append(name)
    good_humans: dict[str, HumanPolicy] = {}
    observations = Observations(good_robots[0]) if good_robots else None
    for name, policy in humans.items():
        problem = human_metadata_problem(policy)
        if problem is None and observations is not None:
            problem = human_problem(policy, observations(policy.ablation))
        if problem:
            problems.append(("human", name, problem))
        else:
            good_humans[name] = policy
    return good_robots, good_humans, problems


def checked_pair(robot: str, human: str) -> HumanPolicy:
    """The human instance of one cell after the preflight (``plugin_problems``) of both
    plugins; a ValueError naming the plugin, its package and why when one fails it."""
    load_robot(robot)  # an unknown or broken robot: its PluginError first
    policy = load_human(human)
    _, _, problems = plugin_problems([robot], {human: policy})
    if problems:
        noun, name, problem = problems[0]
        record = (robot_plugins() if noun == "robot" else human_plugins())[name]
        raise ValueError(
            f"{noun} plugin {name!r} from {_origin(record)} cannot be evaluated: {problem}"
        )
    return policy


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


def describe_plugin(noun: str, name: str) -> str:
    """``"NOUN plugin 'NAME' from ORIGIN"``: a plugin in a message."""
    records = robot_plugins() if noun == "robot" else human_plugins()
    return f"{noun} plugin {name!r} from {_origin(records[name])}"


def _origin(plugin: Any) -> str:
    """Where a plugin comes from, for messages: ``'package version'``, or the policy file."""
    return plugin.package if plugin.from_policy_file else plugin.origin


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
                f"skipping broken {noun} plugin {name!r} from {_origin(plugin)}: {plugin.error}",
                stacklevel=3,
            )
    return [name for name in names if plugins[name].ok]
