"""A curriculum over start states: some episodes begin with the hand already before the opening,
farther away as the policy learns to get it in.

The policy's observation is unchanged (the human perceives what it always does); only where an
episode starts uses privileged state, the opening's pose and where the robot is about to move
it, as a coach placing the arm would.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import gymnasium as gym
import numpy as np

from ..checks import check_int
from ..metrics import STAGE_DEPTHS, feature_plane

if TYPE_CHECKING:
    from ..scene.world import Scene


JUDGES = ("mean", "training")


@dataclass(frozen=True)
class CurriculumConfig:
    """How near starts are drawn and how they widen."""

    # of episodes that start near the opening while the curriculum runs, where the robot's first
    # move brings the opening onto the hand (from rest, too, it comes to the hand: near starts
    # teach most of the way); ``held_share`` where it does not (held still, or moved elsewhere:
    # the whole reach is learned from rest), docs/experiments/2026-12-05-held-share-fixed.md
    share: float = 0.8
    held_share: float = 0.5
    first_reach: float = 0.05  # m: at the first level the fingertip starts up to this far away
    step: float = 0.05  # m the reach widens by at each promotion
    last_reach: float = 0.35  # m: past this the curriculum ends and every start is at rest
    promote_at: float = 0.5  # hand-in rate of the recent near starts that earns a promotion
    # what the rate is taken over: "training", the last ``window`` near starts among the
    # training episodes; "mean", ``trials`` near starts played with the policy's mean actions
    # every ``judge_every`` steps, free of the exploration noise that random-walks ``delta``
    # targets, but measured no higher and some 10% more steps
    # (docs/experiments/2026-12-03-judge-mean-actions.md)
    judge: str = "training"
    trials: int = 8
    judge_every: int = 20_000  # environment steps
    window: int = 40
    hand_in: float = STAGE_DEPTHS["hand_in"]  # m of final arm progress that counts as the hand in

    def __post_init__(self) -> None:
        for field in ("share", "held_share"):
            if not 0.0 <= getattr(self, field) <= 1.0:
                raise ValueError(f"{field} must be in [0, 1], got {getattr(self, field)}")
        if not 0.0 < self.first_reach <= self.last_reach:
            raise ValueError("need 0 < first_reach <= last_reach")
        if self.judge not in JUDGES:
            raise ValueError(f"unknown judge {self.judge!r}: use one of {', '.join(JUDGES)}")
        for field in ("trials", "judge_every", "window"):
            check_int(getattr(self, field), field, 1)


class NearStarts(gym.Wrapper):
    """Starts a share of episodes with the fingertip up to ``reach`` before the opening's centre,
    on the line the robot is moving the opening along and the hand pointing along it (the
    opening's axis when it holds still); ``info["near_start"]`` is that distance (0 for a rest
    start). The share is ``share`` where the robot's first move brings the opening onto the
    hand, else ``held_share``.

    Along the motion, because the driven rim slides up an arm lying on its path and stops
    against one across it: held still, such near starts end with the hand in about twice as
    often as ones along the axis (docs/experiments/2026-12-03-near-starts-on-path.md).
    """

    def __init__(self, env: gym.Env, config: CurriculumConfig, seed: int = 0) -> None:
        super().__init__(env)
        self.config = config
        self.reach = config.first_reach
        self._rng = np.random.default_rng(seed)
        self._distance = 0.0
        self._approach: np.ndarray | None = None
        self._trials = False

    def set_reach(self, reach: float) -> None:
        """The curriculum's level: how far in front of the opening a near start may be."""
        self.reach = float(reach)

    def set_trials(self, trials: bool) -> None:
        """While on, every episode is a near start at the current level (the judge's trials)."""
        self._trials = bool(trials)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is not None:
            self._rng = np.random.default_rng([seed, 1])
        cfg = self.config
        shares = (1.0, 1.0) if self._trials else (cfg.share, cfg.held_share)
        draw = self._rng.random()
        near = self.reach <= cfg.last_reach and draw < max(shares)
        self._distance = float(self._rng.uniform(0.02, self.reach)) if near else 0.0
        if near:
            if seed is None:  # both resets below must start the same episode
                seed = int(self._rng.integers(2**32))
            rest = self.env.reset(seed=seed, options=options)
            self._approach = self.env.unwrapped.robot_next_move()
            approach = approach_line(self.env.unwrapped.env.scene, self._approach)
            if draw >= shares[0 if approach.onto_hand else 1]:  # a rest start after all
                self._distance = 0.0
                observation, info = rest
                return observation, info | {"near_start": 0.0}
            options = (options or {}) | {"human_start": self._start_pose}
        observation, info = self.env.reset(seed=seed, options=options)
        return observation, info | {"near_start": self._distance}

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        return observation, reward, terminated, truncated, info | {"near_start": self._distance}

    def _start_pose(self, scene: Scene) -> np.ndarray:
        """The fingertip ``distance`` before the opening's centre along the direction the hand
        points (``approach_line``, taken again on the scene as this reset placed it)."""
        approach = approach_line(scene, self._approach)
        tip = approach.centre - self._distance * approach.direction
        return scene.human.reaching_pose(tip, approach.direction)


class Approach(NamedTuple):
    """The line a hand comes into the opening along."""

    centre: np.ndarray  # the opening's centre
    direction: np.ndarray  # unit, into the sleeve
    onto_hand: bool  # whether the robot's move brings the opening along it onto the hand


def approach_line(scene: Scene, move: np.ndarray | None) -> Approach:
    """Against the robot's ``move`` if that brings the opening onto the hand, else the opening's
    axis."""
    plane = feature_plane(scene.cloth_positions()[scene.gown.feature_loop])
    onto_hand = move is not None and np.dot(move, plane.normal) < -1e-9
    direction = -move / np.linalg.norm(move) if onto_hand else plane.normal
    return Approach(plane.centroid, direction, bool(onto_hand))
