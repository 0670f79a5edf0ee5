"""One seeded episode of a human model with a robot strategy, measured step by step."""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np

from ..metrics import STAGE_DEPTHS
from .cells import Cell, make_cell, plugin_identities, profile_identity
from .identity import difference, same

# Success: the arm through the sleeve opening past the elbow (metrics.STAGE_DEPTHS)
SUCCESS_DEPTH = STAGE_DEPTHS["past_elbow"]


def episode_seed(seed: int, episode: int) -> int:
    """The seed of episode ``episode`` of an evaluation seeded ``seed``.

    It is ``numpy.random.SeedSequence(seed).spawn(n)[episode].generate_state(1)[0]`` for any
    n > episode: independent of how many episodes are asked for, so adding episodes or resuming
    never changes the earlier ones, and every cell gets the same seeds (paired comparisons).
    """
    return int(np.random.SeedSequence(seed, spawn_key=(episode,)).generate_state(1)[0])


@dataclass(frozen=True, eq=False)
class EpisodeRecord:
    """What one rollout measured: the per-step curves and the final scores of the leaderboard.

    The curves have one value per policy step (length ``horizon``). After a simulation failure
    they are padded with the last values measured before it, and ``sim_failure`` is set.
    """

    robot: str
    human: str
    ablation: str
    episode_seed: int
    arm_progress: np.ndarray  # (horizon,) m: r_p's depth, 0 when the arm is not contained
    max_deformation_curve: np.ndarray  # (horizon,) running max of the triangle area ratio
    final_arm_progress: float  # m
    max_deformation: float  # the episode's largest area ratio
    sim_failure: bool
    failure_reason: str  # "" without a failure
    episode_return: float  # sum of the human's rewards
    steps: int  # policy steps run (fewer than horizon after a failure)
    success_depth: float = SUCCESS_DEPTH

    @property
    def success(self) -> bool:
        """The arm ended through the opening past the elbow, the simulation intact."""
        return is_success(self.final_arm_progress, self.sim_failure, self.success_depth)

    def reached(self, stage: str) -> bool:
        """The arm ended at least as deep as a stage of ``STAGE_DEPTHS``, the simulation intact."""
        return is_success(self.final_arm_progress, self.sim_failure, STAGE_DEPTHS[stage])

    def scores(self) -> dict[str, Any]:
        """The scalar results, named as the columns of episodes.csv."""
        return {
            "episode_seed": self.episode_seed,
            "final_arm_progress": self.final_arm_progress,
            "max_deformation": self.max_deformation,
            "hand_in": self.reached("hand_in"),
            "success": self.success,
            "dressed": self.reached("dressed"),
            "sim_failure": self.sim_failure,
            "return": self.episode_return,
            "steps": self.steps,
        }

    def contradiction(self) -> str:
        """What in the record contradicts itself ('' if nothing): a final score that is not
        its curve's (the last arm progress, the largest deformation)."""
        for score, curve, what, of in (
            ("final_arm_progress", "arm_progress", "the last value", lambda c: c[-1]),
            ("max_deformation", "max_deformation_curve", "the largest value", np.max),
        ):
            value, values = float(getattr(self, score)), getattr(self, curve)
            if values.size and not np.array_equal(value, of(values), equal_nan=True):
                expected = float(of(values))
                return f"its {score} {value!r} is not {what} of its {curve} curve ({expected!r})"
        return ""

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict (arrays as lists; floats round-trip exactly)."""
        data = asdict(self)
        for name in ("arm_progress", "max_deformation_curve"):
            data[name] = data[name].tolist()
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EpisodeRecord:
        """The record that ``to_dict`` wrote."""
        values = {f.name: data[f.name] for f in fields(cls)}
        for name in ("arm_progress", "max_deformation_curve"):
            values[name] = np.asarray(values[name], dtype=float)
        return cls(**values)


def is_success(final_arm_progress: float, sim_failure: bool, depth: float = SUCCESS_DEPTH) -> bool:
    """Success: final arm progress >= ``depth`` (default hand + forearm) and no sim failure."""
    return bool(final_arm_progress >= depth and not sim_failure)


class Runner:
    """One cell's env and human policy, built once and reused for many seeded episodes."""

    def __init__(self, cell: Cell) -> None:
        from ..factory import make_human_env

        self.cell = cell
        robot, human = cell.resolved()
        self.policy = human.factory()
        plugins = plugin_identities(robot, human, self.policy) | profile_identity(cell.profile)
        _check_unchanged(cell, plugins)
        self.env = make_human_env(robot, human=self.policy, **cell.options)
        self.horizon = cell.config().horizon

    def run(self, seed: int, success_depth: float = SUCCESS_DEPTH) -> EpisodeRecord:
        """One episode: ``env.reset(seed=seed)``, ``policy.reset(seed)``, act to the end."""
        observation, info = self.env.reset(seed=seed)
        self.policy.reset(seed)
        last = (float(info["arm_progress"]), float(info["max_deformation"]))
        curves = np.empty((self.horizon, 2))
        total, steps, failed, reason, done = 0.0, 0, False, "", False
        while not done:
            action = self.policy.act(observation)
            observation, reward, terminated, truncated, info = self.env.step(action)
            total += float(reward)
            if info["sim_failure"]:
                failed, reason = True, str(info.get("failure_reason", ""))
            else:
                last = (float(info["arm_progress"]), float(info["max_deformation"]))
            curves[steps] = last
            steps += 1
            done = terminated or truncated
        curves[steps:] = last
        return EpisodeRecord(
            robot=self.cell.robot,
            human=self.cell.human,
            ablation=self.cell.ablation,
            episode_seed=seed,
            arm_progress=curves[:, 0].copy(),
            max_deformation_curve=curves[:, 1].copy(),
            final_arm_progress=last[0],
            max_deformation=last[1],
            sim_failure=failed,
            failure_reason=reason,
            episode_return=total,
            steps=steps,
            success_depth=success_depth,
        )


def _check_unchanged(cell: Cell, plugins: dict[str, Any]) -> None:
    """Refuse to run a cell whose robot, human or capability profile is no longer what the cell
    was made with (e.g. a policy file replaced, or a plugin upgraded, while an evaluation runs)."""
    expected = {who: cell.identity[who] for who in ("robot", "human", "profile")
                if who in cell.identity}  # fmt: skip
    if not same(plugins, expected):
        raise RuntimeError(
            f"{cell.robot!r} x {cell.human!r} changed since the evaluation started "
            f"({difference(plugins, expected)}): run it again"
        )


def run_episode(
    robot: str, human: str, seed: int, success_depth: float = SUCCESS_DEPTH, **options: Any
) -> EpisodeRecord:
    """One seeded episode of ``human`` with ``robot`` (``options`` go to ``make_human_env``)."""
    return Runner(make_cell(robot, human, **options)).run(seed, success_depth)
