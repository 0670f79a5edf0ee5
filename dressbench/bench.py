"""Speed of the physics: the cloth alone and the whole scene step, at several resolutions."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from .checks import check_device, check_gown_vertices, check_int
from .observation import human_observation
from .scene.body import N_ACTIONS
from .scene.garment import GownConfig
from .scene.world import Scene, SceneConfig
from .state import measure

# The gripper in front of the right shoulder, the sleeve pointing away from the human.
BENCH_GRIPPER = np.array([0.45, -0.19, 0.52, 0.0, 0.0, 0.0, 1.0])


def reach_action(step: int, period: int = 200) -> np.ndarray:
    """A scripted right arm that swings forward to shoulder height, reaching straight ahead
    through the sleeve held in front of the shoulder, and back (a period of ``period`` steps)."""
    phase = 0.5 - 0.5 * np.cos(2.0 * np.pi * step / period)
    action = np.zeros(N_ACTIONS)
    action[5] = -0.45 * phase  # shoulder elevation: from hanging to horizontal
    action[7] = 0.66 * phase  # shoulder swing: from the side to straight ahead
    action[8] = -phase  # elbow: straighten
    return action


def bench_scene(vertices: int, steps: int, device: str = "cpu", repeats: int = 3) -> list[dict]:
    """Time the cloth alone and the whole step for one resolution; one row per measurement.

    Each is timed ``repeats`` times and the fastest run is reported, as timeit does: the
    slower runs measure the machine's other load, not the code.
    """
    check_inputs(vertices, steps, device, repeats)
    config = replace(SceneConfig(device=device), gown=GownConfig(target_vertices=vertices))
    scene = Scene(config)
    n_vertices = len(scene.gown.positions)

    def cloth_alone() -> None:
        scene.reset(BENCH_GRIPPER)
        for _ in range(steps * config.frame_skip):
            scene.cloth.step()

    def whole_step() -> None:
        scene.reset(BENCH_GRIPPER)
        for k in range(steps):
            scene.step(reach_action(k), BENCH_GRIPPER)
            human_observation(scene, measure(scene))

    return [
        _row(n_vertices, "cloth", steps, _best_time(cloth_alone, repeats)),
        _row(n_vertices, "scene", steps, _best_time(whole_step, repeats), scene.failed),
        bench_env(vertices, steps, device, repeats),
    ]


def check_inputs(vertices: int, steps: int, device: str, repeats: int) -> None:
    """Refuse, before anything is built, what ``bench_scene`` cannot time (a ValueError)."""
    check_gown_vertices(vertices, "vertices")
    check_int(steps, "steps", 1)
    check_int(repeats, "repeats", 1)
    check_device(device)


def bench_env(vertices: int, steps: int, device: str = "cpu", repeats: int = 3) -> dict:
    """Time the single-agent env's step (``fixed`` robot, the scripted human's actions).

    Only ``env.step`` is timed: the policy's own thinking is not the environment's cost.
    """
    from .factory import make_human_env
    from .plugins import load_human

    env = make_human_env("fixed", gown_vertices=vertices, horizon=steps, device=device)
    human = load_human("scripted")
    best, failed = float("inf"), False
    for episode in range(repeats):
        observation, _ = env.reset(seed=episode)
        elapsed = 0.0
        for _ in range(steps):
            action = human.act(observation)
            start = time.perf_counter()
            observation, _, terminated, _, info = env.step(action)
            elapsed += time.perf_counter() - start
            failed |= info["sim_failure"]
            if terminated:
                break
        best = min(best, elapsed)
    return _row(len(env.env.scene.gown.positions), "env", steps, best, failed)


def _best_time(run, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def _row(vertices: int, what: str, steps: int, seconds: float, failed: bool = False) -> dict:
    return {
        "vertices": vertices,
        "what": what,
        "steps": steps,
        "seconds": round(seconds, 4),
        "steps_per_second": round(steps / seconds, 1),
        "ms_per_step": round(1e3 * seconds / steps, 3),
        "sim_failure": failed,
    }
