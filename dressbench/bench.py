"""Speed of the physics: the cloth alone and the whole scene step, at several resolutions, and
beside PyBullet's soft-body cloth on the same gown (``compare_pybullet``, docs/benchmark.md).

``dressbench bench`` is ``BenchOptions`` (its options), ``bench_rows`` (the timings; with the
training run of ``--train``: ``dressbench.training.bench.bench_rows``) and ``bench_lines``."""

from __future__ import annotations

import json
import math
import tempfile
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from .checks import check_device, check_gown_vertices, check_int
from .config import (
    ANY_PROCESSES,
    AT_LEAST_ONE,
    SceneOptions,
    check_options,
    option,
    option_like,
)
from .observation import human_observation
from .scene.body import N_ACTIONS
from .scene.clock import POLICY_DT
from .scene.garment import Gown, GownConfig, make_gown, write_obj
from .scene.geometry import transform_points
from .scene.world import Scene, SceneConfig
from .state import measure

COMPARE_VERTICES = 4000  # the gown timed beside PyBullet's cloth when none is given
COMPARE_WITH = ("pybullet",)  # what --compare can time beside the env step
TRAIN_STEPS = 8192  # --train's run: two of the default recipe's updates (4,096 samples each)
Rows = tuple[list[dict], list[str]]  # timing rows, and the lines that read them


@dataclass(frozen=True)
class BenchOptions:
    """What ``dressbench bench`` times and how it prints it (the command's options)."""

    vertices: tuple[int, ...] = option((), "Gown resolutions (repeatable).", check_gown_vertices)
    steps: int = option(200, "Policy steps timed per row.", AT_LEAST_ONE)
    repeats: int = option(3, "Timed runs; the fastest counts.", AT_LEAST_ONE)
    quick: bool = option(False, "Only the default resolution, 100 steps.")
    device: str = option_like(SceneOptions, "device", SceneOptions.device)
    compare: str | None = option(
        None,
        f"Instead: PyBullet's cloth on the same gown (default {COMPARE_VERTICES:,} vertices) "
        "beside the env step, in simulated seconds per wall second.",
        choices=COMPARE_WITH,
    )
    pybullet_self_collision: bool = option(
        True,
        "PyBullet's cloth-cloth collisions (Assistive Gym's setting: on; dressbench's cloth has "
        "none).",
    )
    train: bool = option(False, "Instead: a short training run (the default recipe, one env "
                         "process per core, on the CPU) beside the env step.")  # fmt: skip
    train_steps: int = option(TRAIN_STEPS, "Environment steps of the --train run.", AT_LEAST_ONE)
    train_envs: int = option(0, "Env processes of the --train run (default: one per core).",
                             ANY_PROCESSES)  # fmt: skip
    train_envs_per_process: int = option(1, "Envs each env process of the --train run steps.",
                                         AT_LEAST_ONE)  # fmt: skip
    json: bool = option(False, "One JSON object per line.")

    def __post_init__(self) -> None:
        """Refuse what the command line refuses, before anything is timed (a ValueError); the
        device is checked where it is used."""
        check_options(self, skip=("device",))
        if self.compare not in (None, *COMPARE_WITH):
            raise ValueError(f"compare must be one of {COMPARE_WITH} or None, got {self.compare!r}")

    @property
    def timed_steps(self) -> int:
        """The policy steps each row times: ``steps``, or 100 when ``quick``."""
        return 100 if self.quick else self.steps


def bench_rows(options: BenchOptions) -> Iterator[Rows]:
    """The rows ``options`` asks for, timed one resolution at a time as they are read, each
    group with the lines that read it: PyBullet's cloth beside the env step (``compare``), else
    the cloth, the scene and the env step unless ``train`` (whose rows are
    ``dressbench.training.bench.bench_rows``'s). PyBullet is looked for now, before any row
    (a ModuleNotFoundError saying how to install it)."""
    if options.compare:
        pybullet_module()
    return _bench_rows(options)


def _bench_rows(options: BenchOptions) -> Iterator[Rows]:
    steps, device, repeats = options.timed_steps, options.device, options.repeats
    if options.compare:
        for n in options.vertices or (COMPARE_VERTICES,):
            rows = compare_pybullet(n, steps, device, repeats, options.pybullet_self_collision)
            ratio = "dressbench / PyBullet, simulated seconds per wall second"
            yield rows, [f"{ratio}: {rows[1]['times_pybullet']:.1f}x"]
    elif not options.train:
        for n in options.vertices or resolutions(options.quick):
            yield bench_scene(n, steps, device, repeats), []


def bench_lines(options: BenchOptions, groups: Iterable[Rows]) -> Iterator[str]:
    """``groups`` (of ``bench_rows``) as ``dressbench bench`` prints them, each line as soon as
    its rows are timed: one JSON object per row with ``json``, else a table (``table_header``,
    ``table_line``) with the lines that read its rows."""
    if not options.json:
        yield table_header(bool(options.compare))
    for rows, lines in groups:
        for row in rows:
            yield json.dumps(row) if options.json else table_line(row)
        yield from () if options.json else lines


def resolutions(quick: bool = False) -> tuple[int, ...]:
    """The gown resolutions timed when none is given: the scene's default, and unless ``quick``
    half and twice it."""
    default = SceneOptions.gown_vertices
    return (default,) if quick else (default // 2, default, 2 * default)


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
        timing_row(n_vertices, "cloth", steps, _best_time(cloth_alone, repeats)),
        timing_row(n_vertices, "scene", steps, _best_time(whole_step, repeats), scene.failed),
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
    return timing_row(len(env.env.scene.gown.positions), "env", steps, best, failed)


# Assistive Gym's dressing schedule in PyBullet: frames of 0.02 s, 5 to an env step of 0.1 s,
# each frame cut into 8 substeps (setPhysicsEngineParameter numSubSteps)
PYBULLET_FRAME_DT = 0.02
PYBULLET_FRAMES = 5
PYBULLET_SUBSTEPS = 8
PYBULLET_ENV_DT = PYBULLET_FRAME_DT * PYBULLET_FRAMES
PYBULLET_SETTLE_FRAMES = 50  # untimed: Assistive Gym's dressing reset lets the gown settle 50
# loadSoftBody's cloth in Assistive Gym's PyBullet-FEM dressing env: a mass-spring cloth with
# bending springs, self-collision and face contacts (the gown's mass is dressbench's own)
PYBULLET_CLOTH = {
    "useMassSpring": 1,
    "useBendingSprings": 1,
    "springElasticStiffness": 5.0,
    "springDampingStiffness": 0.01,
    "springDampingAllDirections": 1,
    "springBendingStiffness": 0.0,
    "useSelfCollision": 1,
    "collisionMargin": 0.0001,
    "frictionCoeff": 0.1,
    "useFaceContact": 1,
}
COMPARE_EXTRA = "pip install 'dressbench[compare]'"


def pybullet_module() -> Any:
    """PyBullet (the ``compare`` extra), or a ModuleNotFoundError whose one line says how to
    install it: the comparison is optional, dressbench itself never needs PyBullet."""
    try:
        import pybullet  # prints its build time on stderr: --json's stdout stays clean
    except ImportError as error:
        raise ModuleNotFoundError(f"--compare pybullet needs PyBullet: {COMPARE_EXTRA}") from error
    return pybullet


def compare_pybullet(
    vertices: int = COMPARE_VERTICES,
    steps: int = 200,
    device: str = "cpu",
    repeats: int = 3,
    self_collision: bool = True,
) -> list[dict]:
    """PyBullet's cloth and dressbench's whole env step on the same gown, in one run.

    Both sides simulate the same span, ``steps`` policy steps of dressbench (0.04 s each);
    PyBullet in env steps of 0.1 s. Each row has ``sim_seconds_per_second`` (simulated seconds
    per wall second); dressbench's row also has ``times_pybullet``, the ratio of the two.
    ``self_collision=False`` turns off PyBullet's cloth-cloth collisions, which Assistive Gym
    keeps on and dressbench's cloth does not have.
    """
    check_inputs(vertices, steps, device, repeats)
    pybullet_steps = max(1, math.ceil(steps * POLICY_DT / PYBULLET_ENV_DT - 1e-9))
    theirs = bench_pybullet(vertices, pybullet_steps, repeats, self_collision)
    ours = bench_env(vertices, steps, device, repeats)
    ours["sim_seconds_per_second"] = round(steps * POLICY_DT / ours["seconds"], 3)
    # three significant figures: two decimals of a ratio below 1 (a tiny gown) lost over 1%
    ratio = ours["sim_seconds_per_second"] / theirs["sim_seconds_per_second"]
    ours["times_pybullet"] = float(f"{ratio:.3g}")
    return [theirs, ours]


def bench_pybullet(
    vertices: int, steps: int, repeats: int = 3, self_collision: bool = True
) -> dict:
    """Time PyBullet's soft-body cloth on dressbench's gown (``vertices``), held at the grip
    points dressbench's gripper holds, for ``steps`` env steps of Assistive Gym's dressing
    schedule; the fastest of ``repeats`` consecutive runs, after an untimed settle."""
    p = pybullet_module()
    check_gown_vertices(vertices, "vertices")
    check_int(steps, "steps", 1)
    check_int(repeats, "repeats", 1)
    gown = make_gown(GownConfig(target_vertices=vertices))
    positions = transform_points(BENCH_GRIPPER, gown.positions)
    client = p.connect(p.DIRECT)
    try:
        with tempfile.TemporaryDirectory(prefix="dressbench-gown-") as folder:
            obj = write_obj(gown, Path(folder) / "gown.obj", positions)
            cloth = _pybullet_world(p, client, gown, obj, positions, self_collision)
        _pybullet_frames(p, client, PYBULLET_SETTLE_FRAMES)
        seconds = min(
            _timed(lambda: _pybullet_frames(p, client, steps * PYBULLET_FRAMES))
            for _ in range(repeats)
        )
        held = _pybullet_positions(p, client, cloth)
    finally:
        p.disconnect(client)
    failed = not np.all(np.isfinite(held))
    row = timing_row(gown.num_vertices, "pybullet", steps, seconds, failed)
    row["sim_seconds_per_second"] = round(steps * PYBULLET_ENV_DT / seconds, 3)
    row["self_collision"] = self_collision
    return row


def _pybullet_world(
    p: Any, client: int, gown: Gown, obj: Path, positions: np.ndarray, self_collision: bool
) -> int:
    """A deformable world stepping on Assistive Gym's schedule, holding the gown (``obj``, at
    ``positions``) by its sleeve opening: each grip vertex anchored to a still, massless body at
    the gripper, as Assistive Gym anchors its gown to the end effector."""
    p.resetSimulation(p.RESET_USE_DEFORMABLE_WORLD, physicsClientId=client)
    p.setTimeStep(PYBULLET_FRAME_DT, physicsClientId=client)
    p.setPhysicsEngineParameter(numSubSteps=PYBULLET_SUBSTEPS, physicsClientId=client)
    p.setGravity(0.0, 0.0, -9.81, physicsClientId=client)
    settings = PYBULLET_CLOTH | {"useSelfCollision": int(self_collision)}
    cloth = p.loadSoftBody(str(obj), mass=gown.total_mass, physicsClientId=client, **settings)
    loaded = _pybullet_positions(p, client, cloth)
    if loaded.shape != positions.shape or not np.allclose(loaded, positions, atol=1e-4):
        # the anchors below index dressbench's vertices: PyBullet must keep the OBJ's order
        raise RuntimeError(f"PyBullet did not load the gown's {gown.num_vertices} vertices "
                           f"in order ({len(loaded)} loaded)")  # fmt: skip
    grip = BENCH_GRIPPER[:3]
    gripper = p.createMultiBody(baseMass=0.0, basePosition=grip.tolist(), physicsClientId=client)
    for vertex in np.sort(gown.feature_loop):  # the pinned vertices of dressbench's Scene
        offset = (loaded[vertex] - grip).tolist()
        p.createSoftBodyAnchor(cloth, int(vertex), gripper, -1, offset, physicsClientId=client)
    return cloth


def _pybullet_frames(p: Any, client: int, frames: int) -> None:
    """Step PyBullet's world ``frames`` frames (each ``PYBULLET_SUBSTEPS`` substeps)."""
    for _ in range(frames):
        p.stepSimulation(physicsClientId=client)


def _pybullet_positions(p: Any, client: int, cloth: int) -> np.ndarray:
    """The cloth's simulated vertex positions, (V, 3), in the OBJ's vertex order."""
    _, points = p.getMeshData(cloth, -1, flags=p.MESH_DATA_SIMULATION_MESH,
                              physicsClientId=client)  # fmt: skip
    return np.asarray(points, dtype=float)


def _timed(run) -> float:
    """Wall seconds ``run()`` takes."""
    start = time.perf_counter()
    run()
    return time.perf_counter() - start


def _best_time(run, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def table_header(compare: bool = False) -> str:
    """The header of ``table_line``'s columns (with simulated seconds per wall second)."""
    sim = f" {'sim s/s':>9}" if compare else ""
    return f"{'vertices':>8} {'what':>8} {'steps/s':>9} {'ms/step':>9}{sim}"


def table_line(row: dict) -> str:
    """A timing row as a line of ``table_header``'s columns."""
    sim = f" {row['sim_seconds_per_second']:>9.3f}" if "sim_seconds_per_second" in row else ""
    flag = "  (sim failure)" if row["sim_failure"] else ""
    return (f"{row['vertices']:>8} {row['what']:>8} {row['steps_per_second']:>9.1f}"
            f" {row['ms_per_step']:>9.3f}{sim}{flag}")  # fmt: skip


def timing_row(vertices: int, what: str, steps: int, seconds: float, failed: bool = False) -> dict:
    """One row of a benchmark table: ``steps`` steps of ``what`` on a gown of ``vertices`` took
    ``seconds``."""
    return {
        "vertices": vertices,
        "what": what,
        "steps": steps,
        "seconds": round(seconds, 4),
        "steps_per_second": round(steps / seconds, 1),
        "ms_per_step": round(1e3 * seconds / steps, 3),
        "sim_failure": failed,
    }
