"""Which trained humans are seeds of one training: a human's group (robot, recipe, ablation,
capability profile)."""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..plugins import TYPICAL_PROFILE, human_plugins
from ..policy_file import PolicyFileError, load_policy

if TYPE_CHECKING:
    import pandas as pd


@dataclass(frozen=True)
class TrainedHuman:
    """A trained human as the strategy table counts it: its group and its training seed."""

    robot: str | None  # the strategy it was trained for; None: any (a generalist)
    recipe: str
    ablation: str
    seed: int
    profile: str = TYPICAL_PROFILE  # the body it was trained in
    parent: str | None = None  # the human it was fine-tuned from (``--init``); None: from scratch

    @property
    def group(self) -> tuple[str, str, str, str]:
        """Humans of one group differ only by their training seed."""
        return self.robot, self.recipe, self.ablation, self.profile


def human_group(
    name: str, robot: str, ablation: str, metadata: Mapping[str, Any] | None = None
) -> TrainedHuman | None:
    """The group and seed of the human ``name``; None for a human that is no seed of a training
    (a baseline such as ``passive``, or a name that says nothing of a seed).

    ``metadata`` is its policy file's (``TrainedPolicy.metadata``); without it (a name no longer
    installed), the name tells: ROBOT-[ABLATION-][PROFILE-]RECIPE-sSEED[-SUFFIXES].
    """
    config = (metadata or {}).get("config") or {}
    profile = (metadata or {}).get("profile", TYPICAL_PROFILE)
    if metadata:
        robot, ablation = metadata["robot"], metadata["ablation"]
    spelled = _NAME.fullmatch(_strip(_strip(_strip(name, robot), ablation), profile))
    seed = (metadata or {}).get("seed", config.get("seed"))
    if seed is None and spelled:
        seed = int(spelled["seed"])
    recipe = spelled["recipe"] + (spelled["suffixes"] or "") if spelled else config.get("recipe")
    if seed is None or recipe is None:
        return None
    parent = (metadata or {}).get("parent")
    parent = parent.get("name") if isinstance(parent, dict) else None
    return TrainedHuman(robot, recipe, ablation, int(seed), profile,
                        parent if isinstance(parent, str) else None)  # fmt: skip


_NAME = re.compile(r"(?P<recipe>.+?)-s(?P<seed>\d+)(?P<suffixes>-.+)?")


def _strip(name: str, prefix: str) -> str:
    """``name`` without a leading ``prefix-``."""
    return name.removeprefix(f"{prefix}-")


def episode_humans(episodes: pd.DataFrame) -> dict[str, TrainedHuman]:
    """``trained_humans`` of an episodes table (as in episodes.csv): each policy file it names
    read once."""
    return trained_humans(
        episodes[["human", "robot", "ablation"]].itertuples(index=False, name=None)
    )


def trained_humans(humans: Iterable[tuple[str, str, str]]) -> dict[str, TrainedHuman]:
    """The group of each ``(name, robot, ablation)`` (an episodes table's) that is a seed of a
    training: from its policy file when one is installed under that name, else from the name
    (a name scored on several strategies being a generalist's)."""
    plugins = human_plugins()
    found = {}
    humans = list(dict.fromkeys(humans))
    robots: dict[str, set[str]] = {}
    for name, robot, _ in humans:
        robots.setdefault(name, set()).add(robot)
    for name, robot, ablation in humans:
        if len(robots[name]) > 1:  # scored on several strategies: a generalist
            robot = None
        plugin = plugins.get(name)
        metadata = None
        if plugin is not None and plugin.ok and plugin.from_policy_file:
            try:
                metadata = load_policy(plugin.value).metadata
            except PolicyFileError:  # changed since listed: the name still tells
                metadata = None
        human = human_group(name, robot, ablation, metadata)
        if human is not None:
            found[name] = human
    return found
