"""The ``dressbench`` command line: thin wrappers over the library API.

Every option is checked (``dressbench.checks``) before any work starts, and a bad value ends
in one line that names the option and says what is allowed.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import click

from .scene.actuation import ACTUATIONS


class _Commands(click.Group):
    """Bad input (an unknown plugin, a broken policy file, a bad value) ends in one line."""

    def invoke(self, ctx: click.Context):
        import warnings

        from .cluster import ClusterError
        from .plugins.registry import PluginError

        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warning  # e.g. a skipped plugin: one line each
            try:
                return super().invoke(ctx)
            except (ClusterError, PluginError, ValueError) as error:
                raise click.ClickException(str(error)) from error


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Show a warning as ``Warning: message`` on stderr, without its source line."""
    click.echo(f"Warning: {message}", err=True)


def _checked(check: str, **arguments: Any) -> Callable[..., Any]:
    """An option callback running ``dressbench.checks.<check>(value, name="", **arguments)``
    on the value (each value of a repeatable option); its ValueError becomes a
    ``click.BadParameter``, which click prints naming the option."""

    def callback(ctx: click.Context, param: click.Parameter, value: Any) -> Any:
        from . import checks

        function = getattr(checks, check)
        values = value if isinstance(value, tuple) else () if value is None else (value,)
        try:
            for one in values:
                function(one, name="", **arguments)
        except ValueError as error:
            raise click.BadParameter(str(error), ctx=ctx, param=param) from None
        return value

    return callback


_EPISODES = _checked("check_episodes")
_SEED = _checked("check_seed")
_VERTICES = _checked("check_gown_vertices")
_HORIZON = _checked("check_horizon")
_WORKERS = _checked("check_processes", zero="one per core")
_FOLDER = _checked("check_folder")


def _at_least(minimum: int) -> Callable[..., Any]:
    """A callback refusing integers below ``minimum``."""
    return _checked("check_int", minimum=minimum)


def _cell_options(command: Callable[..., Any]) -> Callable[..., Any]:
    """``--episodes``, ``--seed``, ``--workers``, ``--gown-vertices`` and ``--horizon`` of an
    evaluation of many cells."""
    options = [
        click.option("--episodes", default=100, show_default=True, callback=_EPISODES),
        click.option("--seed", default=0, show_default=True, callback=_SEED),
        click.option("--workers", default=0, callback=_WORKERS,
                     help="Parallel processes (default: one per core)."),
        click.option("--gown-vertices", default=2000, show_default=True, callback=_VERTICES),
        click.option("--horizon", default=400, show_default=True, callback=_HORIZON),
    ]  # fmt: skip
    for option in reversed(options):
        command = option(command)
    return command


def _backend_options(command: Callable[..., Any]) -> Callable[..., Any]:
    """``--backend local|ray`` and ``--address`` (docs/cluster.md)."""
    from .cluster import BACKENDS

    address = click.option("--address", default=None,
                           help="Ray cluster to join: auto, HOST:PORT or ray://HOST:PORT "
                                "(default: start a local Ray instance).")  # fmt: skip
    backend = click.option("--backend", type=click.Choice(BACKENDS), default="local",
                           show_default=True,
                           help="Run the tasks in local processes, or as Ray tasks.")  # fmt: skip
    return backend(address(command))


_EPISODE_TIMEOUT = click.option(
    "--episode-timeout", type=click.FloatRange(min=0, min_open=True), default=None,
    help="Seconds an episode may run before its cell is flagged "
         "(default: max(60, horizon x gown vertices x 0.1 ms)).",
)  # fmt: skip


@click.group(cls=_Commands)
@click.version_option(package_name="dressbench")
def main() -> None:
    """dressbench: a benchmark suite for robot-assisted dressing."""


@main.command()
@click.option("--vertices", "-v", multiple=True, type=int, callback=_VERTICES,
              help="Gown resolutions (repeatable).")  # fmt: skip
@click.option("--steps", default=200, show_default=True, callback=_at_least(1),
              help="Policy steps timed per row.")  # fmt: skip
@click.option("--repeats", default=3, show_default=True, callback=_at_least(1),
              help="Timed runs; the fastest counts.")  # fmt: skip
@click.option("--quick", is_flag=True, help="Only the default resolution, 100 steps.")
@click.option("--device", default="cpu", show_default=True, callback=_checked("check_device"),
              help="Warp device for the cloth.")  # fmt: skip
@click.option("--compare", type=click.Choice(["pybullet"]), default=None,
              help="Instead: PyBullet's cloth on the same gown (default 4,000 vertices) beside "
                   "the env step, in simulated seconds per wall second.")  # fmt: skip
@click.option("--pybullet-self-collision/--no-pybullet-self-collision", default=True,
              show_default=True,
              help="PyBullet's cloth-cloth collisions (Assistive Gym's setting: on; dressbench's "
                   "cloth has none).")  # fmt: skip
@click.option("--train", "train_run", is_flag=True,
              help="Instead: a short training run (the default recipe, one env process per "
                   "core, on the CPU) beside the env step.")  # fmt: skip
@click.option("--train-steps", default=8192, show_default=True, callback=_at_least(1),
              help="Environment steps of the --train run.")  # fmt: skip
@click.option("--train-envs", default=0, callback=_WORKERS,
              help="Env processes of the --train run (default: one per core).")  # fmt: skip
@click.option("--train-envs-per-process", default=1, show_default=True, callback=_at_least(1),
              help="Envs each env process of the --train run steps.")  # fmt: skip
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
def bench(
    vertices: tuple[int, ...],
    steps: int,
    repeats: int,
    quick: bool,
    device: str,
    compare: str | None,
    pybullet_self_collision: bool,
    train_run: bool,
    train_steps: int,
    train_envs: int,
    train_envs_per_process: int,
    as_json: bool,
) -> None:
    """Time the cloth alone, the whole scene step and the env step (one process, one core);
    with --compare or --train, those comparisons instead (docs/benchmark.md)."""
    from .bench import bench_scene, compare_pybullet, pybullet_module

    if compare:
        try:
            pybullet_module()
        except ImportError as error:
            raise click.ClickException(str(error)) from None
    if train_run:
        _require_train_extra()
    steps = 100 if quick else steps

    def show(row: dict) -> None:
        if as_json:
            click.echo(json.dumps(row))
            return
        sim = f" {row['sim_seconds_per_second']:>9.3f}" if "sim_seconds_per_second" in row else ""
        flag = "  (sim failure)" if row["sim_failure"] else ""
        click.echo(f"{row['vertices']:>8} {row['what']:>8} {row['steps_per_second']:>9.1f}"
                   f" {row['ms_per_step']:>9.3f}{sim}{flag}")  # fmt: skip

    def say(line: str) -> None:
        if not as_json:
            click.echo(line)

    say(
        f"{'vertices':>8} {'what':>8} {'steps/s':>9} {'ms/step':>9}"
        + (f" {'sim s/s':>9}" * bool(compare))
    )
    if compare:
        for n in vertices or (4000,):
            theirs, ours = compare_pybullet(n, steps, device, repeats, pybullet_self_collision)
            show(theirs)
            show(ours)
            say(f"dressbench / PyBullet, simulated seconds per wall second: "
                f"{ours['times_pybullet']:.1f}x")  # fmt: skip
    if train_run:
        from .training.bench import bench_training

        for n in vertices or (2000,):
            single, alone, run = bench_training(n, train_steps, steps, repeats, train_envs,
                                                train_envs_per_process)  # fmt: skip
            for row in (single, alone, run):
                show(row)
            say(f"its envs alone: {100 * alone['share_of_cores']:.0f}% of {run['envs']} cores x "
                f"the env step")  # fmt: skip
            say(f"training: {100 * run['share_of_cores']:.0f}% of {run['envs']} cores x the env "
                f"step (issue 12's target: 85%), {100 * run['share_of_envs']:.0f}% of its envs "
                f"alone")  # fmt: skip
    if not (compare or train_run):
        for n in vertices or ((2000,) if quick else (1000, 2000, 4000)):
            for row in bench_scene(n, steps, device, repeats):
                show(row)


@main.command()
@click.option("--episodes", default=6, show_default=True, callback=_EPISODES,
              help="Episodes per human motion.")  # fmt: skip
def calibrate(episodes: int) -> None:
    """Measure how much careful, pressing and careless motions deform the gown (the table of
    docs/reward.md, behind the deformation threshold)."""
    from .calibration import calibration, markdown

    click.echo(markdown(calibration(episodes)), nl=False)


@main.command()
@click.option("--check", is_flag=True, help="Also run each ok plugin once, as evaluations do.")
def plugins(check: bool) -> None:
    """List every robot strategy and human policy plugin, with its package and status.

    "ok" means the plugin imports and has the protocol's methods and attributes; it is not run.
    With --check, each ok plugin also gets the preflight of evaluations (one reset and one act
    in a small env, a policy's metadata; docs/plugins.md), and "FAILS CHECK" says why not.
    """
    from .plugins import all_plugins

    rows = all_plugins()
    failed = _preflight(rows) if check else {}
    table = [("group", "name", "package", "version", "status")]
    for p in rows:
        group = "robot" if p.group.endswith("robots") else "human"
        status = "ok" if p.ok else f"BROKEN: {p.error}"
        if p.ok and (group, p.name) in failed:
            status = f"FAILS CHECK: {failed[group, p.name]}"
        table.append((group, p.name, p.package, p.version, status))
    for line in aligned(table):
        click.echo(line)


def aligned(rows: list[tuple[str, ...]]) -> list[str]:
    """Rows as lines of columns padded to their widest cell (the last column is not padded),
    so long names never push a row out of line."""
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    padded = ([cell.ljust(w) for cell, w in zip(row[:-1], widths, strict=True)] for row in rows)
    return ["  ".join([*cells, row[-1]]).rstrip() for cells, row in zip(padded, rows, strict=True)]


def _preflight(rows: list[Any]) -> dict[tuple[str, str], str]:
    """Why each ok plugin among ``rows`` fails the preflight of evaluations, by (group, name)."""
    from .evaluation.cells import _instances, plugin_problems
    from .plugins import human_plugins

    robots = [p.name for p in rows if p.ok and p.group.endswith("robots")]
    humans = [p.name for p in rows if p.ok and p.group.endswith("humans")]
    policies, problems = _instances(human_plugins(), humans)
    problems += plugin_problems(robots, policies)[2]
    return {(noun, name): why for noun, name, why in problems}


@main.command()
@click.option("--robot", default="fixed", show_default=True, help="Robot strategy to train for.")
@click.option("--algo", type=click.Choice(["trpo", "ppo"]), default="trpo", show_default=True)
@click.option(
    "--ablation",
    type=click.Choice(["complete", "no_haptics", "no_task"]),
    default="complete",
    show_default=True,
)
@click.option("--timesteps", type=int, default=None, callback=_at_least(1),
              help="Environment steps (default: the recipe's).")  # fmt: skip
@click.option("--hours", type=click.FloatRange(min=0.0, min_open=True), default=None,
              help="Stop and export once the run has learned this long, its sessions summed "
                   "(default: no budget).")  # fmt: skip
@click.option("--envs", default=0, callback=_WORKERS,
              help="Parallel env processes (default: one per core).")  # fmt: skip
@click.option("--envs-per-process", default=1, show_default=True, callback=_at_least(1),
              help="Envs each env process steps one after another.")  # fmt: skip
@click.option("--seed", default=0, show_default=True, callback=_SEED)
@click.option("--gown-vertices", default=2000, show_default=True, callback=_VERTICES)
@click.option("--out", default="runs", show_default=True, callback=_FOLDER,
              help="Folder of training runs.")  # fmt: skip
@click.option("--policies", default="policies", show_default=True, callback=_FOLDER,
              help="Where models go.")  # fmt: skip
@click.option("--name", default="", callback=_checked("check_name"),
              help="Run and policy name (default ROBOT-ABLATION-ALGO-sSEED).")  # fmt: skip
@click.option("--resume/--fresh", default=True, show_default=True,
              help="Continue from the run's last checkpoint, or start over.")  # fmt: skip
@click.option(
    "--recipe",
    type=click.Choice(["default", "paper"]),
    default="default",
    show_default=True,
    help="paper: TRPO, torques = action x 10 N m, 50k batches.",
)
@click.option(
    "--curriculum/--no-curriculum",
    default=None,
    help="Start some episodes with the hand near the opening (default: the recipe's).",
)
@click.option(
    "--warmup/--no-warmup",
    default=None,
    help="Bring the deformation term in after the first steps (default: the recipe's).",
)
@click.option(
    "--tear-limit",
    type=click.FloatRange(min=1.0, min_open=True),
    default=None,
    help="End training episodes where the gown's max area ratio passes this (default: the "
    "recipe's; the default recipe's is the deformation threshold, 2.02).",
)
@click.option("--no-tear-limit", is_flag=True, help="Never end a training episode for tearing.")
@click.option(
    "--actuation",
    type=click.Choice(ACTUATIONS),
    default=None,
    help="What an action drives: PD targets, moves of them, torques (default: the recipe's).",
)
@click.option(
    "--action-std",
    type=click.FloatRange(min=0.0, min_open=True),
    default=None,
    help="Initial std of the policy's actions (default: the recipe's: 0.5; paper: 1).",
)
@click.option(
    "--haptics",
    type=click.Choice(["log", "newtons"]),
    default=None,
    help="How the policy reads contact forces (default: the recipe's; paper: newtons).",
)
def train(
    resume: bool,
    recipe: str,
    curriculum: bool | None,
    warmup: bool | None,
    haptics: str | None,
    tear_limit: float | None,
    no_tear_limit: bool,
    **options,
) -> None:
    """Train a human model for a robot strategy (re-running resumes after a kill)."""
    import shutil
    import signal

    _require_train_extra()

    from .training import TrainConfig
    from .training import train as train_policy
    from .training.curriculum import CurriculumConfig
    from .training.run import TrainingStopped, continued_config
    from .training.tear import TearConfig
    from .training.warmup import WarmupConfig

    if tear_limit is not None and no_tear_limit:
        raise click.UsageError("--tear-limit and --no-tear-limit exclude each other")
    options = {key: value for key, value in options.items() if value is not None}  # the recipe's
    if curriculum is not None:  # a part turned off is None, so after the recipe's are kept
        options["curriculum"] = CurriculumConfig() if curriculum else None
    if warmup is not None:
        options["warmup"] = WarmupConfig() if warmup else None
    if haptics is not None:
        options["haptics"] = haptics
    if tear_limit is not None:
        options["tear"] = TearConfig(tear_limit)
    if no_tear_limit:
        options["tear"] = None
    config = TrainConfig.preset(recipe, **options)
    if resume:  # an option left out goes on as the run recorded it
        config = continued_config(config, _given_train_fields(click.get_current_context()))
    config.check()  # the robot loads, the env options are valid: before anything is removed
    if not resume:
        shutil.rmtree(f"{config.out}/{config.run_name}", ignore_errors=True)
    signal.signal(signal.SIGTERM, signal.default_int_handler)  # `kill` stops it like Ctrl-C
    try:
        path = train_policy(config)
    except TrainingStopped as stopped:
        click.echo(f"dressbench: {stopped}", err=True)
        raise SystemExit(130) from None
    click.echo(f"policy written to {path}")


def _given_train_fields(ctx: click.Context) -> set[str]:
    """The ``TrainConfig`` fields the command line set: a recipe sets them all."""
    from dataclasses import fields

    from click.core import ParameterSource

    from .training import TrainConfig

    known = {field.name for field in fields(TrainConfig)}
    given = {
        name for name in ctx.params if ctx.get_parameter_source(name) != ParameterSource.DEFAULT
    }
    if "recipe" in given:
        return known
    renamed = {"tear_limit": "tear", "no_tear_limit": "tear"}
    return {renamed.get(name, name) for name in given} & known


TRAIN_MODULES = {"torch": "torch", "stable_baselines3": "stable-baselines3",
                 "sb3_contrib": "sb3-contrib", "tensorboard": "tensorboard"}  # fmt: skip


def _require_train_extra() -> None:
    """Training's packages (the ``train`` extra) are installed, or one line saying what to do."""
    import importlib.util

    missing = [
        dist for module, dist in TRAIN_MODULES.items() if not importlib.util.find_spec(module)
    ]
    if missing:
        raise click.ClickException(
            f"training needs {', '.join(missing)}: pip install 'dressbench[train]' "
            f"(evaluating and rendering trained humans does not)"
        )


@main.command()
@click.option("--robot", "robots", multiple=True, default=("fixed",), show_default=True,
              help="Robot strategies to train for (repeatable: a grid axis).")  # fmt: skip
@click.option("--ablation", "ablations", multiple=True, default=("complete",), show_default=True,
              type=click.Choice(["complete", "no_haptics", "no_task"]),
              help="Ablations (repeatable: a grid axis).")  # fmt: skip
@click.option("--seed", "seeds", multiple=True, type=int, default=(0,), show_default=True,
              callback=_SEED, help="Training seeds (repeatable: a grid axis).")  # fmt: skip
@click.option("--algo", "algos", multiple=True, type=click.Choice(["trpo", "ppo"]),
              help="Algorithms (repeatable: a grid axis; default: the recipe's).")  # fmt: skip
@click.option("--recipe", type=click.Choice(["default", "paper"]), default="default",
              show_default=True)  # fmt: skip
@click.option("--timesteps", type=int, default=None, callback=_at_least(1),
              help="Environment steps per run (default: the recipe's).")  # fmt: skip
@click.option("--hours", type=click.FloatRange(min=0.0, min_open=True), default=None,
              help="Learning hours per run, then it exports (default: no budget).")  # fmt: skip
@click.option("--envs", default=1, show_default=True, callback=_WORKERS,
              help="Env processes per run, each a CPU it reserves (0: one per core).")  # fmt: skip
@click.option("--gown-vertices", default=2000, show_default=True, callback=_VERTICES)
@click.option("--horizon", default=400, show_default=True, callback=_HORIZON,
              help="Policy steps per episode.")  # fmt: skip
@click.option("--samples-per-update", type=click.IntRange(min=1),
              help="Samples per update (default: the recipe's).")  # fmt: skip
@click.option("--curriculum/--no-curriculum", default=None,
              help="Near starts that widen (default: the recipe's).")  # fmt: skip
@click.option("--haptics", type=click.Choice(["log", "newtons"]), default=None,
              help="How the policy reads contact forces (default: the recipe's).")  # fmt: skip
@click.option("--out", default="runs", show_default=True, callback=_FOLDER,
              help="Folder of training runs.")  # fmt: skip
@click.option("--policies", default="policies", show_default=True, callback=_FOLDER,
              help="Where models go (a folder dressbench finds humans in).")  # fmt: skip
@click.option("--episodes", default=100, show_default=True, callback=_EPISODES,
              help="Rollouts per trained policy in the leaderboard.")  # fmt: skip
@click.option("--results", default="results", show_default=True, callback=_FOLDER,
              help="The leaderboard's folder.")  # fmt: skip
@click.option("--workers", default=0, callback=_WORKERS,
              help="Evaluation processes (default: one per core).")  # fmt: skip
@_backend_options
def sweep(robots, ablations, seeds, algos, curriculum, episodes, results, workers, backend,
          address, **options) -> None:  # fmt: skip
    """Train a grid of human models (robots x ablations x seeds x algorithms), then score them
    in one leaderboard. Each run is a normal run folder: re-running resumes."""
    from pathlib import Path

    from .sweep import Sweep
    from .sweep import sweep as run_sweep
    from .training.curriculum import CurriculumConfig

    if backend == "local":
        _require_train_extra()  # on the ray backend, the workers train
    grid = {"robot": robots, "ablation": ablations, "seed": seeds}
    if algos:
        grid["algo"] = algos
    train = {key: value for key, value in options.items() if value is not None}  # None: recipe's
    if curriculum is not None:
        train["curriculum"] = CurriculumConfig() if curriculum else None
    config = Sweep(grid, train, episodes=episodes, results=results, workers=workers or None)
    run_sweep(config, backend=backend, address=address)
    click.echo(f"policies in {train['policies']}, leaderboard in {Path(results, 'leaderboard.md')}")


@main.group(invoke_without_command=True)
@click.option("--robot", help="Robot strategy.")
@click.option("--human", help="Human policy (a plugin or a trained model in policies/).")
@click.option("--episodes", default=100, show_default=True, callback=_EPISODES)
@click.option("--seed", default=0, show_default=True, callback=_SEED)
@click.option("--workers", default=0, callback=_WORKERS,
              help="Parallel processes (default: one per core).")  # fmt: skip
@click.option("--gown-vertices", default=2000, show_default=True, callback=_VERTICES)
@click.option("--out", default="results", show_default=True, callback=_FOLDER)
@_EPISODE_TIMEOUT
@_backend_options
@click.pass_context
def evaluate(
    ctx: click.Context, robot, human, episodes, seed, workers, gown_vertices, out, episode_timeout,
    backend, address
):  # fmt: skip
    """Score a human with a robot strategy over seeded rollouts; see also `leaderboard`."""
    if ctx.invoked_subcommand is not None:
        return
    if not robot or not human:
        raise click.UsageError("give --robot and --human, or use `dressbench evaluate leaderboard`")
    from .evaluation import evaluate as run_evaluation

    run_evaluation(robot, human, episodes=episodes, seed=seed, workers=workers or None, out=out,
                   gown_vertices=gown_vertices, backend=backend, address=address,
                   episode_timeout=episode_timeout)  # fmt: skip
    click.echo(f"results in {out} (episodes.csv, curves.csv, leaderboard.md, plots)")


@evaluate.command("leaderboard")
@_cell_options
@click.option("--out", default="results", show_default=True, callback=_FOLDER)
@click.option("--robot", "robots", multiple=True, help="Only these robot strategies (repeatable).")
@click.option("--human", "humans", multiple=True, help="Only these humans (repeatable).")
@click.option("--report", is_flag=True,
              help="Also write OUT/report/index.html (a web page with videos).")  # fmt: skip
@_EPISODE_TIMEOUT
@_backend_options
def leaderboard_command(
    episodes, seed, workers, gown_vertices, horizon, out, robots, humans, report, episode_timeout,
    backend, address
):  # fmt: skip
    """Every robot strategy against the humans trained for it and the baselines.

    Finished rollouts in OUT are reused, so a leaderboard can be built a few cells at a time.
    """
    from pathlib import Path

    from .evaluation import leaderboard

    leaderboard(episodes=episodes, seed=seed, workers=workers or None, out=out,
                robots=robots or None, humans=humans or None, gown_vertices=gown_vertices,
                horizon=horizon, backend=backend, address=address,
                episode_timeout=episode_timeout)  # fmt: skip
    click.echo(f"leaderboard in {Path(out, 'leaderboard.md')}, plots in {Path(out, '*.png')}")
    if report:
        from .evaluation.webpage import write_report

        click.echo(f"report in {write_report(out, workers=workers or None)}")


@evaluate.command("reproduce")
@_cell_options
@click.option("--out", default="results/reproduction", show_default=True, callback=_FOLDER)
@click.option("--human", "humans", multiple=True,
              help="Only these trained humans (repeatable; default: every one that plays one of "
                   "the paper's policies).")  # fmt: skip
@click.option("--doc", type=click.Path(dir_okay=False, exists=True),
              help="Also rewrite this doc's results block (docs/reproduction.md).")  # fmt: skip
@_backend_options
def reproduce_command(episodes, seed, workers, gown_vertices, horizon, out, humans, doc, backend,
                      address):  # fmt: skip
    """The paper's comparison: its five policies, the cross-play, a verdict per claim."""
    from .evaluation.reproduction import (
        documented_results,
        paper_humans,
        reproduce,
        write_doc_results,
    )

    if doc:
        documented_results(doc)  # a doc without a results block fails before the evaluation
    claims = reproduce(episodes=episodes, seed=seed, workers=workers or None, out=out,
                       humans=paper_humans(humans or None), gown_vertices=gown_vertices,
                       horizon=horizon, backend=backend, address=address)  # fmt: skip
    for claim in claims.itertuples():
        click.echo(f"claim {claim.claim}: {claim.verdict}")
    click.echo(f"claims in {out}/claims.md, figures in {out}/*.png")
    if doc:
        write_doc_results(doc, out)
        click.echo(f"results block of {doc} rewritten from {out}")


@main.command("report")
@click.argument("results", default="results", type=click.Path(file_okay=False))
@click.option("--videos/--no-videos", default=True, show_default=True,
              help="Render (or reuse) one seeded rollout video per cell.")  # fmt: skip
@click.option("--workers", default=0, callback=_WORKERS,
              help="Processes rendering videos (default: one per core).")  # fmt: skip
def report_command(results: str, videos: bool, workers: int) -> None:
    """Write RESULTS/report/index.html: a static page of the leaderboard, the success
    definitions, the plots, a video per cell and the run's metadata (no server needed)."""
    from .evaluation.webpage import write_report

    click.echo(f"report in {write_report(results, videos=videos, workers=workers or None)}")


@main.command()
@click.option("--robot", default="fixed", show_default=True)
@click.option("--human", default="scripted", show_default=True)
@click.option("--out", "path", default="rollout.gif", show_default=True,
              callback=_checked("check_output_file", suffixes=(".gif", ".mp4")),
              help="A .gif or .mp4, in a folder that exists.")  # fmt: skip
@click.option("--seed", default=0, show_default=True, callback=_SEED)
@click.option("--gown-vertices", default=2000, show_default=True, callback=_VERTICES)
def render(robot, human, path, seed, gown_vertices):
    """A headless video of one rollout (the human's capsules, the gown, the gripper)."""
    from .video import render_rollout

    video = render_rollout(robot, human, path, seed=seed, gown_vertices=gown_vertices)
    click.echo(f"video written to {video}")
