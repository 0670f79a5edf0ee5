"""What a plugin must pass before an evaluation runs it: one ``reset`` and one ``act`` in a real
(small) env, what a human declares against the observation it will get, and a capability
profile's body and involuntary motion.

``dressbench plugins`` only checks that a plugin imports and has the protocol's names; a robot
whose ``reset`` returns a (6,) pose, or a policy file whose ``obs_dim`` contradicts its
ablation, passes that and would abort a leaderboard in a worker. These checks run in the
calling process first, so that ``leaderboard`` skips such plugins with one line each and
``evaluate`` refuses them with one line. The checks themselves are the contract's
(``plugins/contract.py``).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .plugins.contract import (
    CHECK_HORIZON,
    CHECK_SEED,
    CHECK_VERTICES,
    human_action_problem,
    human_declaration_problem,
    involuntary_problem,
    profile_limits_problem,
    robot_action_problem,
    start_pose_problem,
)
from .plugins.protocols import HUMAN_ACTION_SIZE
from .plugins.registry import PluginError, _one_line, profile_plugin
from .scene.body import body_limits
from .scene.clock import FRAME_SKIP, SIM_DT

if TYPE_CHECKING:
    from .plugins import Plugin


def robot_problem(plugin: Plugin) -> str | None:
    """Why the robot strategy of a resolved record cannot be evaluated, or None: a fresh
    instance's start pose for the check's seed (``start_pose_problem``), then one ``act`` on the
    robot observation of a real env, and one env step with that action. A robot whose ``reset``
    or ``act`` draws from NumPy's global random state passes, with a warning naming it."""
    from .config import EnvConfig  # here: it loads the physics
    from .env import HUMAN, ROBOT, DressingEnv

    drawn: list[str] = []  # its methods that drew from NumPy's global random state
    try:
        robot = plugin.factory()
        pose = _watched(drawn, "reset", robot.reset, np.random.default_rng(CHECK_SEED))
        problem = start_pose_problem(pose)
        if problem:
            return problem
        config = EnvConfig(gown_vertices=CHECK_VERTICES, horizon=CHECK_HORIZON)
        env = DressingEnv(robot, config, robot_name=plugin.name, robot_origin=plugin.origin)
        observations, _ = env.reset(seed=CHECK_SEED)
        action = _watched(drawn, "act", robot.act, observations[ROBOT])
        problem = robot_action_problem(action)
        if problem:
            return problem
        env.step({ROBOT: np.asarray(action, dtype=float), HUMAN: np.zeros(HUMAN_ACTION_SIZE)})
    except Exception as exc:  # a plugin may raise anything; say what, in one line
        return f"its check (one reset and one act) failed: {_one_line(exc)}"
    if drawn:
        warnings.warn(
            f"robot plugin {plugin.name!r} from {plugin.source} draws from NumPy's global random "
            f"state (np.random) in {' and '.join(drawn)}: its episodes cannot be repeated; draw "
            f"from the generator reset gets",
            stacklevel=2,
        )
    return None


def _watched(drawn: list[str], method: str, call: Callable[..., Any], *args: Any) -> Any:
    """``call(*args)``; ``method`` is added to ``drawn`` when the call changed NumPy's global
    random state (a robot whose episodes no seed repeats)."""
    before = np.random.get_state()  # noqa: NPY002 - the legacy global state is what is watched
    result = call(*args)
    after = np.random.get_state()  # noqa: NPY002
    if before[0] != after[0] or not np.array_equal(before[1], after[1]) or before[2:] != after[2:]:
        drawn.append(method)
    return result


def human_problem(policy: Any, observation: np.ndarray) -> str | None:
    """Why a human policy cannot be evaluated, or None: what it declares
    (``human_declaration_problem``), then ``reset`` and one ``act`` on ``observation`` (a real
    one, of its ablation), which must keep the contract (``human_action_problem``)."""
    problem = human_declaration_problem(policy)
    if problem:
        return problem
    try:
        policy.reset(CHECK_SEED)
        action = policy.act(observation)
    except Exception as exc:
        return (
            f"act failed on a {policy.ablation!r} observation of {observation.size} numbers: "
            f"{_one_line(exc)}"
        )
    return human_action_problem(action)


def profile_problem(name: str) -> str | None:
    """Why the capability profile ``name`` cannot be run, or None: it resolves to a working
    plugin (else its ``PluginError``'s line), and a fresh instance's body for the typical one and
    its involuntary motion for a short episode keep the contract."""
    try:
        profile = profile_plugin(name).factory()
        typical = body_limits()
        problem = profile_limits_problem(profile.body(typical), typical)
        if problem:
            return problem
        frames = CHECK_HORIZON * FRAME_SKIP
        motion = profile.involuntary(np.random.default_rng(CHECK_SEED), frames, SIM_DT)
        return involuntary_problem(motion, frames)
    except PluginError as exc:
        return str(exc)
    except Exception as exc:  # a plugin may raise anything; say what, in one line
        return f"its check (its body and one episode's motion) failed: {_one_line(exc)}"


class Observations:
    """A real human observation of each ablation, from one small env per ablation with a robot
    that passed ``robot_problem`` (the observation's length depends only on the ablation)."""

    def __init__(self, robot: Plugin) -> None:
        self.robot = robot
        self._cache: dict[str, np.ndarray] = {}

    def __call__(self, ablation: str) -> np.ndarray:
        if ablation not in self._cache:
            from .factory import make_human_env

            env = make_human_env(
                self.robot, ablation=ablation, gown_vertices=CHECK_VERTICES, horizon=CHECK_HORIZON
            )
            self._cache[ablation], _ = env.reset(seed=CHECK_SEED)
        return self._cache[ablation]
