"""The plugin contract, checked in one place: what a robot strategy's start poses and actions, a
human's actions, what a human declares (ablation, robot, actuation, profile) and what a
capability profile's body and involuntary motion must be.

Each check returns the one-line problem, or None when the plugin keeps the contract; the env,
its single-agent view, the preflight of evaluations, ``dressbench.testing`` and the registry ask
these and say whose problem it is. The protocols themselves are in ``protocols.py``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..observation import ABLATIONS, observation_size
from ..scene.actuation import ACTUATIONS
from ..scene.body import N_DOFS, BodyLimits
from .protocols import HUMAN_ACTION_SIZE, ROBOT_ACTION_SIZE, TYPICAL_PROFILE

WORKSPACE = (np.array([-0.3, -1.2, -0.5]), np.array([1.3, 0.8, 1.3]))  # gripper bounds, m
QUATERNION_TOLERANCE = 1e-3  # how far from 1 the norm of a start pose's quaternion may be
DEFAULT_ACTUATION = "pd"  # what a human that does not declare its actuation acts by
PLUGIN_METHODS = ("reset", "act")  # what robot strategies and humans both implement
HUMAN_ATTRIBUTES = ("robot", "ablation")  # what a human declares (actuation, profile optional)
PROFILE_METHODS = ("body", "involuntary")  # what a capability profile implements
CHECK_VERTICES = 300  # the gown of the checks' small env: coarse, the checks are of interfaces
CHECK_HORIZON = 2  # policy steps of the preflight's env
CHECK_SEED = 0


def declared_actuation(human: Any) -> str:
    """How a human's actions drive its joints, as it declares it (``DEFAULT_ACTUATION`` when it
    does not say)."""
    return getattr(human, "actuation", DEFAULT_ACTUATION)


def trains_generalists(robot: Any) -> bool:
    """Whether a robot strategy (a factory or an instance) declares ``generalist = True``: it
    is a distribution of strategies, a human trained against it is meant for any strategy
    (declares robot None), and a leaderboard scores it only when asked for by name."""
    return getattr(robot, "generalist", False) is True


def declared_profile(human: Any) -> str | None:
    """The capability profile a human was made for, as it declares it: a name, None for any
    profile, ``TYPICAL_PROFILE`` when it does not say."""
    return getattr(human, "profile", TYPICAL_PROFILE)


def describe_profile(name: str, origin: str | None = None) -> str:
    """A capability profile in a message: ``"capability profile 'NAME' from ORIGIN"``."""
    return f"capability profile {name!r}" + (f" from {origin}" if origin else "")


def describe_human(human: Any, name: str | None = None) -> str:
    """A human in a message: ``"human 'NAME'"`` by its plugin or policy name, else its class."""
    name = name or getattr(human, "name", None)
    return f"human {name!r}" if isinstance(name, str) else f"human {type(human).__qualname__}"


def describe_robot(robot: Any, name: str | None = None, origin: str | None = None) -> str:
    """A robot strategy in a message: ``"robot strategy 'NAME' from ORIGIN"`` for a plugin
    loaded by name (``origin``: its package and version), else its class and the distribution
    that provides its module."""
    if name is not None:
        return f"robot strategy {name!r}" + (f" from {origin}" if origin else "")
    import importlib.metadata

    cls = type(robot)
    packages = importlib.metadata.packages_distributions().get(cls.__module__.split(".")[0])
    where = f"robot strategy {cls.__module__}.{cls.__qualname__}"
    return where + (f" from {packages[0]}" if packages else "")


def missing_members(
    plugin: object, attributes: tuple[str, ...] = (), methods: tuple[str, ...] = PLUGIN_METHODS
) -> list[str]:
    """The protocol's ``methods`` and ``attributes`` that ``plugin`` lacks, as
    ``"method reset()"`` / ``"attribute ablation"``."""
    methods = tuple(m for m in methods if not callable(getattr(plugin, m, None)))
    attributes = tuple(a for a in attributes if not hasattr(plugin, a))
    return [f"method {m}()" for m in methods] + [f"attribute {a}" for a in attributes]


def api_version_problem(plugin: object, expected: int) -> str | None:
    """Why ``plugin`` (a factory or an instance) has the wrong ``api_version``, or None."""
    version = getattr(plugin, "api_version", None)
    if version is None:
        return f"api_version is missing (this dressbench expects {expected})"
    if isinstance(version, bool) or not isinstance(version, int):
        return f"api_version must be the integer {expected}, found {version!r}"
    if version != expected:
        return f"api_version {version} is not supported (this dressbench expects {expected})"
    return None


def interface_problem(
    plugin: object,
    noun: str,
    expected: int,
    attributes: tuple[str, ...] = (),
    methods: tuple[str, ...] = PLUGIN_METHODS,
) -> str | None:
    """Why ``plugin`` does not implement the ``noun`` ("robot", "human", "profile") protocol of
    API ``expected``: its missing ``methods`` and ``attributes``, then its ``api_version``; or
    None."""
    missing = missing_members(plugin, attributes, methods)
    problems = [f"not a {noun} plugin: missing " + ", ".join(missing)] if missing else []
    api = api_version_problem(plugin, expected)
    return "; ".join(problems + [api] if api else problems) or None


def start_pose_problem(pose: Any) -> str | None:
    """What is wrong with a start pose as a robot strategy's ``reset`` returned it, or None.

    A pose is ``(x, y, z, qx, qy, qz, qw)``: shape (7,), finite, a unit quaternion (norm within
    ``QUATERNION_TOLERANCE`` of 1; a zero quaternion is no rotation) and a position inside
    ``WORKSPACE``, absolute in the human frame.
    """
    p, problem = _finite_vector(pose, "reset", "a pose", 7, "(x, y, z, qx, qy, qz, qw)",
                                "(x, y, z, qx, qy, qz, qw) in the human frame")  # fmt: skip
    if problem:
        return problem
    norm = float(np.linalg.norm(p[3:]))
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        return (
            f"reset returned the quaternion (qx, qy, qz, qw) = {_cut(p[3:].tolist())} of norm "
            f"{norm:.4g}, expected a unit quaternion (norm 1 +- {QUATERNION_TOLERANCE:g})"
        )
    low, high = WORKSPACE
    if ((p[:3] < low) | (p[:3] > high)).any():
        bounds = zip("xyz", low, high, strict=True)
        box = ", ".join(f"{axis} in [{a:g}, {b:g}]" for axis, a, b in bounds)
        return (
            f"reset returned the position {_cut(p[:3].tolist())}, outside the workspace "
            f"({box} m; start poses are absolute, in the human frame)"
        )
    return None


def robot_action_problem(action: Any) -> str | None:
    """What is wrong with a robot strategy's ``act`` output, or None: it must be 3 finite
    numbers (values outside [-1, 1] are clipped by the step, not refused)."""
    velocity = "the gripper's velocity in [-1, 1] (times ROBOT_MAX_SPEED m/s)"
    _, problem = _finite_vector(
        action, "act", "an action", ROBOT_ACTION_SIZE, "3 numbers", velocity
    )
    return problem


def human_action_problem(action: Any) -> str | None:
    """What is wrong with a human's ``act`` output, or None: it must be HUMAN_ACTION_SIZE finite
    numbers (values outside [-1, 1] are clipped by the step, not refused)."""
    targets = "one number in [-1, 1] per actuated joint"
    _, problem = _finite_vector(
        action, "act", "an action", HUMAN_ACTION_SIZE, f"{HUMAN_ACTION_SIZE} numbers", targets
    )
    return problem


def step_action_problem(agent: str, action: Any, size: int) -> str | None:
    """What is wrong with an agent's action given to the env's ``step``, or None: ``size``
    finite numbers (values outside [-1, 1] are clipped, not refused)."""
    a = np.asarray(action, dtype=float)
    if a.shape != (size,):
        return f"{agent} action must have shape ({size},), got {a.shape}"
    if not np.isfinite(a).all():
        return f"{agent} action must be finite, got {a.tolist()}"
    return None


def human_declaration_problem(human: Any) -> str | None:
    """Why what a human declares cannot be right, or None: ``ablation`` one of ABLATIONS,
    ``robot`` None or a name, ``actuation`` (if it says) one of ACTUATIONS, and ``obs_dim``
    (when it has one, as a trained policy does) the length of that ablation's observation."""
    ablation = getattr(human, "ablation", None)
    if not isinstance(ablation, str) or ablation not in ABLATIONS:
        return f"it declares ablation {ablation!r}; expected one of {', '.join(ABLATIONS)}"
    robot = getattr(human, "robot", None)
    if robot is not None and not isinstance(robot, str):
        return f"it declares robot {robot!r}; expected a robot strategy name or None"
    actuation = declared_actuation(human)
    if actuation not in ACTUATIONS:
        return f"it declares actuation {actuation!r}; expected one of {', '.join(ACTUATIONS)}"
    profile = declared_profile(human)
    if profile is not None and not isinstance(profile, str):
        return f"it declares profile {profile!r}; expected a capability profile name or None"
    obs_dim = getattr(human, "obs_dim", None)
    size = observation_size(ablation)
    if obs_dim is not None and obs_dim != size:
        return (
            f"its obs_dim is {obs_dim}, but ablation {ablation!r} observes {size} numbers "
            "(the file's ablation does not match the network)"
        )
    return None


def pairing_problem(
    human: Any, ablation: str | None, actuation: str | None, name: str | None = None
) -> str | None:
    """Why an env of ``ablation`` whose human is driven by ``actuation`` is not the one
    ``human`` was made for, or None (None for either: not asked for, so the human's own). A
    capability profile is no such mismatch: a body another than its own is a question asked of
    the human (how does it fare with a weak arm?), not a broken observation or action."""
    who = describe_human(human, name)
    if ablation is not None and ablation != human.ablation:
        return (
            f"{who} declares ablation {human.ablation!r}; it cannot run with ablation {ablation!r}"
        )
    own = declared_actuation(human)
    if actuation is not None and actuation != own:
        return f"{who} acts by {own!r} actuation; it cannot run under {actuation!r} actuation"
    return None


def profile_limits_problem(limits: Any, typical: BodyLimits) -> str | None:
    """What is wrong with the body a capability profile's ``body`` returned for the ``typical``
    one, or None: ``lower``, ``upper`` and ``max_torque`` of N_DOFS finite numbers each, every
    range within the typical one and around the rest pose, every cap above 0 and at most the
    typical one (a profile narrows a body; it cannot make it reach or push further)."""
    parts = ("lower", "upper", "max_torque")
    if not all(hasattr(limits, part) for part in parts):
        return f"body returned {_cut(limits)}, expected BodyLimits (lower, upper, max_torque)"
    values = {}
    for part in parts:
        values[part], problem = _finite_vector(
            getattr(limits, part), "body", f"BodyLimits.{part}", N_DOFS, f"{N_DOFS} numbers",
            "one per degree of freedom, in DOF_NAMES order",
        )  # fmt: skip
        if problem:
            return problem
    lower, upper, torque = values["lower"], values["upper"], values["max_torque"]
    for wrong, what in (
        (lower < typical.lower, "a lower limit below the typical body's"),
        (upper > typical.upper, "an upper limit above the typical body's"),
        ((lower > typical.rest) | (upper < typical.rest), "a range without the rest pose"),
        ((torque <= 0.0) | (torque > typical.max_torque), "a torque cap not in (0, typical]"),
    ):
        if wrong.any():
            return f"body returned {what} at degree of freedom {int(np.argmax(wrong))}"
    return None


def involuntary_problem(motion: Any, frames: int) -> str | None:
    """What is wrong with a capability profile's ``involuntary`` output for an episode of
    ``frames`` simulation steps, or None: None, or finite joint accelerations of shape
    (frames, N_DOFS)."""
    if motion is None:
        return None
    try:
        a = np.asarray(motion, dtype=float)
    except (TypeError, ValueError):
        return f"involuntary returned {_cut(motion)}, expected None or an array"
    if a.shape != (frames, N_DOFS):
        return (
            f"involuntary returned motion of shape {a.shape}, expected ({frames}, {N_DOFS}): "
            "joint accelerations per simulation step"
        )
    if not np.isfinite(a).all():
        return "involuntary returned non-finite joint accelerations"
    return None


def _finite_vector(
    value: Any, method: str, noun: str, size: int, wanted: str, meaning: str
) -> tuple[np.ndarray, str | None]:
    """``value`` (what a plugin's ``method`` returned) as a finite float vector of ``size``, or
    the one-line problem with it: ``noun`` names it ("a pose"), ``wanted`` what any value should
    be, ``meaning`` what its numbers are."""
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return np.zeros(0), f"{method} returned {_cut(value)}, expected {wanted}"
    if v.shape != (size,):
        return v, f"{method} returned {noun} of shape {v.shape}, expected ({size},): {meaning}"
    if not np.isfinite(v).all():
        kind = noun.split()[-1]
        return v, f"{method} returned a non-finite {kind} {_cut(v.tolist())}"
    return v, None


def _cut(value: Any, width: int = 80) -> str:
    """A value in a one-line message, cut to ``width`` characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= width else text[: width - 3] + "..."
