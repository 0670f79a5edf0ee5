"""``family``: a different robot strategy every episode, drawn from one documented distribution.

A human trained against the family faces the gripper still, moving straight or along a curve
toward the shoulder with pauses, or following its hand, from anywhere in front of and beside
the right arm: wide enough that the built-in strategies and the example ``arc`` plugin lie
inside it (``FamilyConfig.holds``). Such a human is meant for any strategy (``generalist``).
Positions are in the human frame relative to the right shoulder; see docs/robots.md.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..scene.garment import GownConfig, make_gown
from ..scene.geometry import capsule_depth, transform_points
from ..scene.human import Human
from .protocols import OBS_TIME, ROBOT_DT, ROBOT_MAX_SPEED, ROBOT_OBS
from .robots import RIGHT_SHOULDER, yaw_quaternion

KINDS = ("still", "straight", "curve", "reactive")
MAX_DRAWS = 100  # draws of a member before giving up (the rejection rate is some 3%)
FINGERTIP, ELBOW, SHOULDER = (ROBOT_OBS[point] for point in ("fingertip", "elbow", "shoulder"))
Range = tuple[float, float]


@dataclass(frozen=True)
class FamilyConfig:
    """The family's distribution: the kind by ``weights``, every range drawn uniformly.

    Starts and targets are cylindrical about the right shoulder: a horizontal distance, an
    azimuth about the vertical from straight ahead (+x; negative toward the human's right) and
    a height. The sleeve points away from the shoulder as seen from the start, turned about the
    vertical by up to ``yaw_spread``.
    """

    weights: tuple[float, ...] = (0.2, 0.3, 0.25, 0.25)  # of KINDS
    start_distance: Range = (0.45, 0.75)  # m
    start_azimuth: Range = (-1.90, 0.60)  # rad: from behind the right side to ahead-left
    start_height: Range = (-0.30, 0.20)  # m
    yaw_spread: float = 0.70  # rad
    target_distance: Range = (0.14, 0.36)  # m
    target_azimuth: Range = (-1.95, 0.80)  # rad
    target_height: Range = (-0.25, 0.15)  # m
    # s to travel start -> target; longer where the path needs more at ROBOT_MAX_SPEED
    duration: Range = (5.0, 15.0)
    pause_chance: float = 0.5  # of a straight or curved member stopping once on its way
    pause: Range = (1.0, 3.0)  # s
    pause_at: Range = (0.2, 0.8)  # of the way
    bulge: Range = (0.03, 0.20)  # m: a curve's middle off the straight line (at most 0.8 x half)
    delay: Range = (0.0, 3.0)  # s a reactive member waits before it follows the hand
    standoff: Range = (0.08, 0.25)  # m before the fingertip, along the forearm, it heads for
    speed: Range = (0.03, ROBOT_MAX_SPEED)  # m/s of a reactive member

    def __post_init__(self) -> None:
        if len(self.weights) != len(KINDS) or min(self.weights) < 0 or sum(self.weights) <= 0:
            raise ValueError(f"weights must be {len(KINDS)} non-negative numbers, not all 0")

    def holds(self, start: np.ndarray, target: np.ndarray | None = None) -> bool:
        """Whether a start pose (and a target position, absolute in the human frame) could be
        drawn: what makes a strategy a member of the family."""
        distance, azimuth, height = cylindrical(start[:3])
        yaw = 2.0 * np.arctan2(start[5], start[6])
        turn = (yaw - azimuth + np.pi) % (2.0 * np.pi) - np.pi
        inside = (
            _within(distance, self.start_distance)
            and _within(azimuth, self.start_azimuth)
            and _within(height, self.start_height)
            and abs(turn) <= self.yaw_spread
            and abs(start[3]) < 1e-9
            and abs(start[4]) < 1e-9
        )
        if target is None or not inside:
            return inside
        distance, azimuth, height = cylindrical(target)
        return (
            _within(distance, self.target_distance)
            and _within(azimuth, self.target_azimuth)
            and _within(height, self.target_height)
        )


def cylindrical(position: np.ndarray) -> tuple[float, float, float]:
    """(horizontal distance, azimuth, height) of an absolute position about the right shoulder."""
    r = np.asarray(position, dtype=float) - RIGHT_SHOULDER
    return float(np.hypot(r[0], r[1])), float(np.arctan2(r[1], r[0])), float(r[2])


def from_cylindrical(distance: float, azimuth: float, height: float) -> np.ndarray:
    """The absolute position at these cylindrical coordinates about the right shoulder."""
    offset = [distance * np.cos(azimuth), distance * np.sin(azimuth), height]
    return RIGHT_SHOULDER + np.array(offset)


def _within(value: float, bounds: Range, tolerance: float = 1e-9) -> bool:
    return bounds[0] - tolerance <= value <= bounds[1] + tolerance


@dataclass(frozen=True)
class Arc:
    """The circular arc from ``start`` to ``end`` whose middle lies ``bulge`` off the chord
    toward the unit vector ``side`` (perpendicular to the chord)."""

    start: np.ndarray
    end: np.ndarray
    bulge: float
    side: np.ndarray
    centre: np.ndarray = field(init=False)
    radius: float = field(init=False)
    sweep: float = field(init=False)  # rad, at most pi
    u: np.ndarray = field(init=False)  # unit, centre -> start
    v: np.ndarray = field(init=False)  # unit, perpendicular to u in the arc's plane, toward end

    def __post_init__(self) -> None:
        half = float(np.linalg.norm(self.end - self.start)) / 2.0
        radius = (half**2 + self.bulge**2) / (2.0 * self.bulge)
        centre = (self.start + self.end) / 2.0 - (radius - self.bulge) * self.side
        u = (self.start - centre) / radius
        towards = self.end - centre
        v = towards - np.dot(towards, u) * u
        object.__setattr__(self, "centre", centre)
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "sweep", 2.0 * float(np.arctan2(half, radius - self.bulge)))
        object.__setattr__(self, "u", u)
        object.__setattr__(self, "v", v / np.linalg.norm(v))

    def point(self, fraction: float) -> np.ndarray:
        """The point a ``fraction`` in [0, 1] of the way along the arc."""
        angle = self.sweep * fraction
        return self.centre + self.radius * (np.cos(angle) * self.u + np.sin(angle) * self.v)


@dataclass(frozen=True)
class Member:
    """One episode's strategy: what ``Family.reset`` drew."""

    kind: str
    start: np.ndarray  # (7,) pose
    target: np.ndarray | None  # (3,) where a straight or curved member ends; None: no end
    duration: float = 0.0  # s of travel
    pause_at: float = 1.0  # of the way
    pause: float = 0.0  # s
    arc: Arc | None = None  # a curve's path
    delay: float = 0.0  # s, reactive
    standoff: float = 0.0  # m, reactive
    speed: float = 0.0  # m/s, reactive

    @property
    def ends(self) -> list[np.ndarray]:
        """The positions it holds the gripper still at: its start, and its target if any."""
        return [self.start[:3]] + ([] if self.target is None else [self.target])

    def position(self, t: float) -> np.ndarray:
        """Where a straight or curved member holds the gripper at time ``t`` s."""
        stop = self.duration * self.pause_at  # the pause starts here, ends ``pause`` s later
        moving = min(t, stop) + max(t - stop - self.pause, 0.0)  # s spent moving by ``t``
        fraction = min(max(moving / self.duration, 0.0), 1.0)
        if self.arc is not None:
            return self.arc.point(fraction)
        return self.start[:3] + fraction * (self.target - self.start[:3])


class Family:
    """Each episode, a member of ``FamilyConfig``'s distribution, drawn from the env's rng."""

    api_version: ClassVar[int] = 1
    generalist: ClassVar[bool] = True  # a human trained against it is meant for any strategy
    config = FamilyConfig()

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        """Draw the episode's member (``self.member``); return its start pose."""
        self.member = draw_member(self.config, rng)
        return self.member.start

    def act(self, observation: np.ndarray) -> np.ndarray:
        """The velocity that follows the member's path (or the hand) over the next step."""
        member, t = self.member, float(observation[OBS_TIME])
        if member.kind == "still":
            return np.zeros(3)
        if member.kind == "reactive":
            return _follow(member, observation, self.config.target_distance[0], t)
        step = member.position(t + ROBOT_DT) - member.position(t)
        return np.clip(step / ROBOT_DT / ROBOT_MAX_SPEED, -1.0, 1.0)


def episode_members(episode_seeds: list[int], config: FamilyConfig | None = None) -> list[Member]:
    """The member each episode of these seeds (episodes.csv's ``episode_seed``) faced: an env
    reset with a seed draws the robot's episode first from a generator of that seed, so the
    members are known without running anything (to score a human per kind of member)."""
    config = config or Family.config
    return [draw_member(config, np.random.default_rng(seed)) for seed in episode_seeds]


def draw_member(config: FamilyConfig, rng: np.random.Generator) -> Member:
    """A member of the family whose held opening lies outside the resting human at its start
    and its target: a draw that puts it inside (near the body, some 5% of moving members) is
    drawn again, as a robot would not plan to push the gown into a person."""
    for _ in range(MAX_DRAWS):
        member = _draw(config, rng)
        if all(opening_is_clear(np.concatenate([p, member.start[3:]])) for p in member.ends):
            return member
    raise RuntimeError(f"no member of the family clear of the body in {MAX_DRAWS} draws")


def opening_is_clear(pose: np.ndarray) -> bool:
    """Whether the gown's opening, held at ``pose``, lies outside the resting human."""
    opening, capsules, radii = _resting_body()
    return bool((capsule_depth(transform_points(pose, opening), capsules, radii) < 0.0).all())


@functools.cache
def _resting_body() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The held opening in the gown's frame (the default gown), and the resting human's
    capsules and radii."""
    gown = make_gown(GownConfig())
    human = Human()
    human.reset()
    capsules = human.capsules(human.body_transforms())
    return gown.positions[gown.feature_loop], capsules, human.capsule_radius


def _draw(config: FamilyConfig, rng: np.random.Generator) -> Member:
    """A member of the family: its kind, start and target, then what its kind needs."""
    weights = np.asarray(config.weights, dtype=float)
    kind = KINDS[int(rng.choice(len(KINDS), p=weights / weights.sum()))]
    start = _draw_point(rng, config.start_distance, config.start_azimuth, config.start_height)
    target = _draw_point(rng, config.target_distance, config.target_azimuth, config.target_height)
    _, azimuth, _ = cylindrical(start)
    yaw = azimuth + rng.uniform(-config.yaw_spread, config.yaw_spread)
    pose = np.concatenate([start, yaw_quaternion(np.array([np.cos(yaw), np.sin(yaw), 0.0]))])
    if kind == "still":
        return Member(kind, pose, None)
    if kind == "reactive":
        delay, standoff = rng.uniform(*config.delay), rng.uniform(*config.standoff)
        return Member(kind, pose, None, delay=delay, standoff=standoff,
                      speed=rng.uniform(*config.speed))  # fmt: skip
    arc = _curve(start, target, config, rng) if kind == "curve" else None
    length = arc.radius * arc.sweep if arc else float(np.linalg.norm(target - start))
    duration = max(rng.uniform(*config.duration), length / (0.95 * ROBOT_MAX_SPEED))
    pause_at, pause = 1.0, 0.0
    if rng.random() < config.pause_chance:
        pause_at, pause = rng.uniform(*config.pause_at), rng.uniform(*config.pause)
    return Member(kind, pose, target, duration, pause_at, pause, arc)


def _draw_point(rng: np.random.Generator, *bounds: Range) -> np.ndarray:
    """A position drawn uniformly in (distance, azimuth, height) ``bounds`` about the shoulder."""
    distance, azimuth, height = (rng.uniform(*b) for b in bounds)
    return from_cylindrical(distance, azimuth, height)


def _curve(start: np.ndarray, end: np.ndarray, config: FamilyConfig, rng) -> Arc:
    """An arc from ``start`` to ``end`` bulging toward a random side of the chord."""
    chord = (end - start) / np.linalg.norm(end - start)
    side = rng.normal(size=3)
    side -= np.dot(side, chord) * chord
    half = float(np.linalg.norm(end - start)) / 2.0
    bulge = min(rng.uniform(*config.bulge), 0.8 * half)
    return Arc(start, end, bulge, side / np.linalg.norm(side))


def _follow(member: Member, observation: np.ndarray, nearest: float, t: float) -> np.ndarray:
    """A reactive member's velocity: after its delay, at its speed toward ``standoff`` before
    the fingertip along the forearm, kept ``nearest`` m or more from the shoulder horizontally."""
    if t < member.delay:
        return np.zeros(3)
    tip, elbow, shoulder = observation[FINGERTIP], observation[ELBOW], observation[SHOULDER]
    forearm = tip - elbow
    goal = tip + member.standoff * forearm / max(float(np.linalg.norm(forearm)), 1e-9)
    away = goal[:2] - shoulder[:2]
    if (reach := float(np.linalg.norm(away))) < nearest:
        goal[:2] = shoulder[:2] + away * nearest / max(reach, 1e-9)
    step = goal - observation[:3]
    distance = float(np.linalg.norm(step))
    speed = min(member.speed, distance / ROBOT_DT)
    velocity = step / max(distance, 1e-9) * speed
    return np.clip(velocity / ROBOT_MAX_SPEED, -1.0, 1.0)
