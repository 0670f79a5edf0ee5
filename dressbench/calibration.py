"""How much each kind of motion deforms the gown: the measurements behind the deformation
threshold of the reward (docs/reward.md). ``dressbench calibrate`` prints them as a table.

Each motion is run through the real physics and reports, per episode, the largest triangle
area ratio (the paper's deformation metric) and the largest total cloth force on the body.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .plugins.robots import FRONT, PAPER_STRATEGIES, RIGHT_SHOULDER
from .scene.world import Scene, SceneConfig
from .state import measure


@dataclass(frozen=True)
class Measurement:
    """One motion's episodes: their max area ratios and peak contact forces (N)."""

    motion: str
    ratios: tuple[float, ...]
    forces: tuple[float, ...]


def sleeve_over_arm(scene: Scene, seconds: float) -> tuple[float, float]:
    """The gripper slides the sleeve 0.7 m over a still, outstretched arm in ``seconds``."""
    q = scene.human.outstretched()
    start, end = RIGHT_SHOULDER + [1.05, 0.0, 0.0], RIGHT_SHOULDER + [0.35, 0.0, 0.0]
    scene.reset(np.concatenate([start, FRONT]), human_q=q)
    hold = scene.human.action_for(q)
    steps = max(1, round(seconds / (scene.config.dt * scene.config.frame_skip)))
    ratio, force = 0.0, 0.0
    for k in range(1, steps + 31):  # and 1.2 s still at the end
        grip = start + (end - start) * min(1.0, k / steps)
        scene.step(hold, np.concatenate([grip, FRONT]))
        ratio = max(ratio, measure(scene).max_area_ratio)
        force = max(force, float(np.linalg.norm(scene.contact_force)))
    return ratio, force


def episode(robot: str, human: str, seed: int, horizon: int = 400) -> tuple[float, float]:
    """One seeded episode of a human plugin with a robot strategy."""
    from .factory import make_env
    from .plugins import load_human

    env = make_env(robot, horizon=horizon)
    policy = load_human(human)
    observations, _ = env.reset(seed=seed)
    policy.reset(seed)
    force, info = 0.0, {}
    while env.agents:
        actions = {
            "human": policy.act(observations["human"]),
            "robot": env.robot_strategy.act(observations["robot"]),
        }
        observations, _, _, _, infos = env.step(actions)
        info = infos["human"]
        force = max(force, info["contact_force"])
    return info["max_deformation"], force


def calibration(episodes: int = 6) -> list[Measurement]:
    """The motions of docs/reward.md's table, from hanging still to flailing."""
    robots = PAPER_STRATEGIES
    scene = Scene(SceneConfig())
    rows = [
        ("hanging, the passive human under each strategy", [
            episode(robot, "passive", 0) for robot in robots]),
        ("careful: the sleeve slid over a still, outstretched arm in 9.6, 4.8, 1.6 s", [
            sleeve_over_arm(scene, s) for s in (9.6, 4.8, 1.6)]),
        ("scripted human (reaches in, backs off at 20 N), fixed", [
            episode("fixed", "scripted", s) for s in range(episodes)]),
        ("scripted human, front_linear", [
            episode("front_linear", "scripted", s) for s in range(episodes)]),
        ("scripted human, side_linear", [
            episode("side_linear", "scripted", s) for s in range(episodes)]),
        ("random human (flails), fixed", [
            episode("fixed", "random", s) for s in range(episodes)]),
        ("random human, front_linear", [
            episode("front_linear", "random", s) for s in range(episodes)]),
    ]  # fmt: skip
    return [
        Measurement(name, tuple(r for r, _ in runs), tuple(f for _, f in runs))
        for name, runs in rows
    ]


def markdown(rows: list[Measurement]) -> str:
    """The table as docs/reward.md shows it."""
    lines = [
        "| motion | max area ratio per episode | peak contact force (N) |",
        "|---|---|---|",
    ]
    for row in rows:
        ratios = ", ".join(f"{r:.2f}" for r in row.ratios)
        forces = ", ".join(f"{f:.0f}" for f in row.forces)
        lines.append(f"| {row.motion} | {ratios} | {forces} |")
    return "\n".join(lines) + "\n"
