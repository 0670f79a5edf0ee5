"""Leaderboard cells: a robot strategy × a human model, with the env options they run under."""

from __future__ import annotations

import hashlib
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

from ..plugins import human_plugins, load_human, load_robot, robot_plugins

if TYPE_CHECKING:
    from ..config import EnvConfig
    from ..plugins import HumanPolicy


@dataclass(frozen=True)
class Cell:
    """A robot strategy and a human model, and the ``make_human_env`` options of their episodes.

    ``options`` always holds the human's own ``ablation``: a policy is scored in the setting it
    was trained for.
    """

    robot: str
    human: str
    options: Mapping[str, Any] = field(default_factory=dict, hash=False)

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


def config_id(config: EnvConfig) -> str:
    """A short stable name of a whole env configuration, so different settings never mix."""
    return "cfg-" + hashlib.sha1(repr(config).encode()).hexdigest()[:10]


def make_cell(robot: str, human: str, policy: HumanPolicy | None = None, **options: Any) -> Cell:
    """A checked cell: both plugins exist, the options are valid, and the ablation is the human's.

    Errors surface here, in the calling process, rather than inside a worker.
    """
    load_robot(robot)
    policy = policy if policy is not None else load_human(human)
    if options.get("ablation", policy.ablation) != policy.ablation:
        raise ValueError(
            f"human {human!r} declares ablation {policy.ablation!r}; it is evaluated with it, "
            f"not with ablation={options['ablation']!r}"
        )
    cell = Cell(robot, human, {**options, "ablation": policy.ablation})
    cell.config()  # an unknown option raises TypeError now
    return cell


def leaderboard_cells(
    robots: Iterable[str] | None = None, humans: Iterable[str] | None = None, **options: Any
) -> list[Cell]:
    """Every ok robot strategy × every ok human meant for it (trained for it, or generic).

    A human is meant for a robot when its ``robot`` attribute names it; humans whose ``robot`` is
    None (the built-in baselines passive, random, scripted) are generic and face every robot.
    ``robots`` / ``humans`` restrict the names; broken plugins are skipped with a warning.
    """
    robot_names = _usable(robot_plugins(), robots, "robot")
    records = human_plugins()
    policies = {name: records[name].factory() for name in _usable(records, humans, "human")}
    return [
        make_cell(robot, name, policy, **options)
        for robot in robot_names
        for name, policy in policies.items()
        if policy.robot in (None, robot)
    ]


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
                f"skipping broken {noun} plugin {name!r} from {plugin.origin}: {plugin.error}",
                stacklevel=3,
            )
    return [name for name in names if plugins[name].ok]
