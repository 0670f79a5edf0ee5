"""The ``dressbench`` command line: thin wrappers over the library API. An option of a config
(``TrainConfig``, ``EnvConfig``, ``BenchOptions``) takes its default, help, choices and check from
the field; a bad value ends, before any work starts, in one line naming the option and what is
allowed."""

from __future__ import annotations

import dataclasses
import functools
import shutil
import signal
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click
from click.core import ParameterSource

from .bench import BenchOptions, bench_lines
from .checks import (
    EPISODES,
    REPRODUCTION,
    RESULTS,
    check_episode_timeout,
    check_episodes,
    check_folder,
    check_output_file,
    check_seed,
)
from .cluster import BACKENDS, ClusterError
from .config import ANY_PROCESSES, EnvConfig
from .plugins.registry import PluginError
from .scoring import ScoreOptions
from .training import require_train_extra
from .training.bench import bench_rows
from .training.config import RECIPES, TrainConfig


class _Commands(click.Group):
    """Bad input (an unknown plugin, a broken policy file, a bad value) ends in one line."""

    def invoke(self, ctx: click.Context):
        with warnings.catch_warnings():
            # a warning (e.g. a skipped plugin) is one line on stderr, without its source line
            warnings.showwarning = lambda message, *_: click.echo(f"Warning: {message}", err=True)
            try:
                return super().invoke(ctx)
            except (ClusterError, PluginError, ValueError) as error:
                raise click.ClickException(str(error)) from error


def _checked(check: Callable[..., Any], **arguments: Any) -> Callable[..., Any]:
    """An option callback running ``check(value, name="", **arguments)`` on each value given;
    its ValueError becomes a ``click.BadParameter``, which click prints naming the option."""

    def callback(ctx: click.Context, param: click.Parameter, value: Any) -> Any:
        values = value if isinstance(value, tuple) else () if value is None else (value,)
        try:
            for one in values:
                check(one, name="", **arguments)
        except ValueError as error:
            raise click.BadParameter(str(error), ctx=ctx, param=param) from None
        return value

    return callback


def _option(config: type, name: str, *decls: str, recipe: bool = False, **settings: Any):
    """The option of ``config``'s field ``name``: its default, help, choices and check; with
    ``recipe``, no default (the recipe's, which the help lists); a bool is a flag (one that is
    on, a pair: ``--x/--no-x``). ``settings`` are click's."""
    (field,) = (f for f in dataclasses.fields(config) if f.name == name)
    meta, default = field.metadata, field.default
    kwargs = {"default": default, "help": meta.get("help")}
    flag = f"--{name.replace('_', '-')}"
    if isinstance(default, bool):
        kwargs["is_flag"] = True
        flag += f"/--no-{flag[2:]}" if default else ""
    if recipe:
        values = ", ".join(f"{r} {_shown(getattr(TrainConfig.preset(r), name))}" for r in RECIPES)
        help = f"{meta['help'].rstrip('.')} (default: the recipe's: {values})."
        kwargs |= {"default": None, "type": type(default), "help": help}
    if "choices" in meta:
        kwargs["type"] = click.Choice(meta["choices"])
    if meta.get("check"):
        kwargs["callback"] = _checked(meta["check"])
    kwargs |= settings  # a help that says its default shows no other
    kwargs.setdefault("show_default", "(default" not in (kwargs["help"] or ""))
    return click.option(*(decls or (flag,)), **kwargs)


def _fields(config: type, *names: str) -> Callable[..., Any]:
    """The options of ``config``'s fields ``names``, in that order."""
    return _options(*(_option(config, name) for name in names))


def _shown(value: Any) -> str:
    """A recipe's setting in the help: a part off, on (or its one number), a number, a name."""
    if dataclasses.is_dataclass(value):
        values = dataclasses.astuple(value)
        return _shown(values[0]) if len(values) == 1 else "on"
    number = "{:.3g}" if isinstance(value, float) else "{:,}" if isinstance(value, int) else "{}"
    return "off" if value is None else number.format(value)


def _options(*options: Callable[..., Any]) -> Callable[..., Any]:
    """``options`` as one decorator, in the order given."""
    return lambda command: functools.reduce(lambda c, option: option(c), reversed(options), command)


def _stated(options: dict[str, Any]) -> dict[str, Any]:
    """``options`` without a ``profile`` left out (None): each human then runs under its own."""
    return {key: value for key, value in options.items() if key != "profile" or value is not None}


def _episodes(**settings: Any):
    return click.option("--episodes", callback=_checked(check_episodes),
                        **{"default": EPISODES, "show_default": True, **settings})  # fmt: skip


def _workers(what: str = "Parallel processes"):
    """``--workers``: its default, 0, is one per core, which the library reads as None."""
    check = _checked(ANY_PROCESSES)
    return click.option("--workers", default=0, help=f"{what} (default: one per core).",
                        callback=lambda *given: check(*given) or None)  # fmt: skip


def _folder(default: str = RESULTS, decl: str = "--out", **settings: Any):
    """An option naming a folder that exists or can be created (``default``)."""
    return click.option(decl, default=default, show_default=True, callback=_checked(check_folder),
                        **settings)  # fmt: skip


_SEED_OPTION = click.option("--seed", default=0, show_default=True, callback=_checked(check_seed))
_GOWN = _option(EnvConfig, "gown_vertices")
_PROFILE = _option(EnvConfig, "profile", default=None, show_default=False,
                   help="The human's capability profile (default: its own; typical for the "
                        "untrained baselines).")  # fmt: skip
# a leaderboard's: repeatable, each human scored under each profile named (a tuple, or None)
_PROFILES = _option(EnvConfig, "profile", multiple=True, default=(), show_default=False,
                    callback=lambda _context, _option, given: given or None,
                    help="The humans' capability profile (default: each human's own; typical "
                         "for the untrained baselines): the humans trained for it, and those "
                         "--human names, are scored under it. Repeatable: under each (a named "
                         "human adapted to one of them: under that one alone).")  # fmt: skip
_HORIZON = _option(EnvConfig, "horizon")
_BACKEND = _options(
    click.option("--backend", type=click.Choice(BACKENDS), default="local", show_default=True,
                 help="Run the tasks in local processes, or as Ray tasks."),
    click.option("--address", default=None,
                 help="Ray cluster to join: auto, HOST:PORT or ray://HOST:PORT (default: start "
                      "a local Ray instance)."),
)  # fmt: skip
_CELLS = _options(_episodes(), _SEED_OPTION, _workers(), _GOWN, _HORIZON)
_EPISODE_TIMEOUT = click.option(
    "--episode-timeout", type=float, default=None, callback=_checked(check_episode_timeout),
    help="Seconds an episode may run before its cell is flagged (default: in proportion to "
         "the horizon x the gown's vertices, with a floor; docs/evaluation.md).",
)  # fmt: skip


@click.group(cls=_Commands)
@click.version_option(package_name="dressbench")
def main() -> None:
    """dressbench: a benchmark suite for robot-assisted dressing."""


@main.command()
@_option(BenchOptions, "vertices", "--vertices", "-v", multiple=True, type=int, default=None,
         show_default=False)  # fmt: skip
@_fields(BenchOptions, "steps", "repeats", "quick", "device", "compare", "pybullet_self_collision",
         "train", "train_steps", "train_envs", "train_envs_per_process", "json")  # fmt: skip
def bench(**options: Any) -> None:
    """Time the cloth alone, the whole scene step and the env step (one process, one core);
    with --compare or --train, those comparisons instead (docs/benchmark.md)."""
    chosen = BenchOptions(**options)
    try:
        rows = bench_rows(chosen)  # PyBullet and the train extra: looked for before any row
    except ModuleNotFoundError as error:  # no PyBullet: one line saying how to install it
        raise click.ClickException(str(error)) from None
    for line in bench_lines(chosen, rows):
        click.echo(line)


@main.command()
@_episodes(default=6, help="Episodes per human motion.")
def calibrate(episodes: int) -> None:
    """Measure how much careful, pressing and careless motions deform the gown (the table of
    docs/reward.md, behind the deformation threshold)."""
    from .calibration import calibration, markdown

    click.echo(markdown(calibration(episodes)), nl=False)


@main.command()
@click.option("--check", is_flag=True, help="Also run each ok plugin once, as evaluations do.")
def plugins(check: bool) -> None:
    """List every robot strategy, human policy and capability profile plugin, with its package
    and status.

    "ok" means the plugin imports and has the protocol's methods and attributes; it is not run.
    With --check, each ok plugin also gets the preflight of evaluations (one reset and one act
    in a small env, a policy's metadata; docs/plugins.md), and "FAILS CHECK" says why not.
    """
    from .evaluation.listing import aligned, plugin_rows

    for line in aligned(plugin_rows(check)):
        click.echo(line)


@main.command()
@_fields(TrainConfig, "robot", "algo", "ablation", "profile")
@_option(TrainConfig, "timesteps", recipe=True)
@_option(TrainConfig, "hours", type=float)
@_fields(TrainConfig, "envs", "envs_per_process", "seed")
@_option(TrainConfig, "gown_vertices", recipe=True)
@_fields(TrainConfig, "out", "policies", "name")
@click.option("--resume/--fresh", default=True, show_default=True,
              help="Continue from the run's last checkpoint, or start over.")  # fmt: skip
@_option(TrainConfig, "recipe")
@_option(TrainConfig, "curriculum", "--curriculum/--no-curriculum", recipe=True, type=None)
@_option(TrainConfig, "warmup", "--warmup/--no-warmup", recipe=True, type=None)
@_option(TrainConfig, "tear", "--tear-limit", "tear_limit", recipe=True,
         type=click.FloatRange(min=1.0, min_open=True))  # fmt: skip
@click.option("--no-tear-limit", is_flag=True, help="Never end a training episode for tearing.")
@_option(TrainConfig, "actuation", recipe=True)
@_option(TrainConfig, "action_std", recipe=True)
@_option(TrainConfig, "haptics", recipe=True)
@_option(TrainConfig, "init")
def train(resume: bool, **options: Any) -> None:
    """Train a human model for a robot strategy (re-running resumes after a kill)."""
    require_train_extra()
    from .training import train as train_policy
    from .training import train_config
    from .training.run import TrainingStopped

    ctx = click.get_current_context()  # an option left out is the recipe's, or as recorded
    default = ParameterSource.DEFAULT
    given = {k: v for k, v in options.items() if ctx.get_parameter_source(k) != default}
    config = train_config(resume=resume, **given)
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


@main.command()
@_option(TrainConfig, "robot", "--robot", "robots", multiple=True, default=(TrainConfig.robot,),
         help="Robot strategies to train for (repeatable: a grid axis).")  # fmt: skip
@_option(TrainConfig, "ablation", "--ablation", "ablations", multiple=True,
         default=(TrainConfig.ablation,), help="Ablations (repeatable: a grid axis).")  # fmt: skip
@_option(TrainConfig, "profile", "--profile", "profiles", multiple=True,
         default=(TrainConfig.profile,),
         help="Capability profiles (repeatable: a grid axis; see dressbench plugins).")  # fmt: skip
@_option(TrainConfig, "seed", "--seed", "seeds", multiple=True, default=(TrainConfig.seed,),
         type=int, help="Training seeds (repeatable: a grid axis).")  # fmt: skip
@_option(TrainConfig, "algo", "--algo", "algos", multiple=True, default=None,
         help="Algorithms (repeatable: a grid axis; default: the recipe's).")  # fmt: skip
@_option(TrainConfig, "recipe")
@_option(TrainConfig, "timesteps", recipe=True)
@_option(TrainConfig, "hours", type=float)
@_option(TrainConfig, "envs", default=1,
         help="Env processes per run, each a CPU it reserves (0: one per core).")  # fmt: skip
@_option(TrainConfig, "gown_vertices", recipe=True)
@_option(TrainConfig, "horizon")
@_option(EnvConfig, "gown_vertices", "--eval-gown-vertices", "eval_gown_vertices",
         help="The leaderboard's gown, in vertices.")  # fmt: skip
@_option(TrainConfig, "samples_per_update", recipe=True)
@_option(TrainConfig, "curriculum", "--curriculum/--no-curriculum", recipe=True, type=None)
@_option(TrainConfig, "haptics", recipe=True)
@_fields(TrainConfig, "out", "policies")
@_episodes(help="Rollouts per trained policy in the leaderboard.")
@_folder(decl="--results", help="The leaderboard's folder.")
@_workers("Evaluation processes")
@_BACKEND
def sweep(robots, ablations, profiles, seeds, algos, episodes, results, workers, backend,
          address, eval_gown_vertices, **options) -> None:  # fmt: skip
    """Train a grid of human models (robots x ablations x profiles x seeds x algorithms), then
    score them in one leaderboard. Each run is a normal run folder: re-running resumes."""
    from .sweep import Sweep
    from .sweep import sweep as run_sweep
    from .training.config import option_changes

    if backend == "local":
        require_train_extra()  # on the ray backend, the workers train
    axes = (robots, ablations, profiles, seeds, algos)
    grid = dict(zip(("robot", "ablation", "profile", "seed", "algo"), axes, strict=True))
    config = Sweep({axis: values for axis, values in grid.items() if values},
                   option_changes(**options), episodes=episodes, results=results,
                   workers=workers, eval_gown_vertices=eval_gown_vertices)  # fmt: skip
    run_sweep(config, backend=backend, address=address)
    board = Path(results, "leaderboard.md")
    click.echo(f"policies in {options['policies']}, leaderboard in {board}")


@main.group(invoke_without_command=True)
@click.option("--robot", help="Robot strategy.")
@click.option("--human", help="Human policy (a plugin or a trained model in policies/).")
@_CELLS
@_PROFILE
@_folder()
@_EPISODE_TIMEOUT
@_BACKEND
@click.pass_context
def evaluate(ctx: click.Context, robot, human, out, **options):
    """Score a human with a robot strategy over seeded rollouts; see also `leaderboard`."""
    if ctx.invoked_subcommand is not None:
        return
    if not robot or not human:
        raise click.UsageError("give --robot and --human, or use `dressbench evaluate leaderboard`")
    from .evaluation import evaluate as run_evaluation

    run_evaluation(robot, human, out=out, **_stated(options))
    click.echo(f"results in {out} (episodes.csv, curves.csv, leaderboard.md, plots)")


@evaluate.command("leaderboard")
@_CELLS
@_PROFILES
@_folder()
@click.option("--robot", "robots", multiple=True, help="Only these robot strategies (repeatable).")
@click.option("--human", "humans", multiple=True, help="Only these humans (repeatable).")
@click.option("--report", is_flag=True,
              help="Also write OUT/report/index.html (a web page with videos).")  # fmt: skip
@click.option("--doc", type=click.Path(dir_okay=False, exists=True),
              help="Also rewrite this doc's strategies block with the strategy table "
                   "(README.md).")  # fmt: skip
@_EPISODE_TIMEOUT
@_BACKEND
def leaderboard_command(workers, out, robots, humans, report, doc, **options):
    """Every robot strategy against the humans trained for it and the baselines.

    Finished rollouts in OUT are reused, so a leaderboard can be built a few cells at a time.
    """
    from .evaluation import leaderboard_results
    from .evaluation.strategies import STRATEGIES_BLOCK, strategy_rows_markdown

    if doc:
        STRATEGIES_BLOCK.read(doc)  # a doc without the block fails before anything runs
    results = leaderboard_results(workers=workers, out=out, robots=robots or None,
                                  humans=humans or None, **_stated(options))  # fmt: skip
    click.echo(f"leaderboard in {Path(out, 'leaderboard.md')}, plots in {Path(out, '*.png')}")
    if doc:
        STRATEGIES_BLOCK.write(doc, strategy_rows_markdown(results.strategies))
        click.echo(f"strategies block of {doc} rewritten from {Path(out, 'strategies.csv')}")
    if report:
        from .evaluation.webpage import write_report

        click.echo(f"report in {write_report(out, workers=workers)}")


@main.command()
@click.option("--robot", required=True, help="The robot strategy to score.")
@click.option("--from", "humans", multiple=True,
              help="Only these generalists (repeatable; default: all installed).")  # fmt: skip
@_fields(ScoreOptions, "minutes", "episodes", "profile", "out", "runs", "policies")
@_options(_SEED_OPTION, _workers(), _GOWN, _HORIZON)
def score(robot, humans, seed, workers, gown_vertices, horizon, **options) -> None:
    """Score a robot strategy: fine-tune each generalist human on it (--minutes in all), then
    evaluate each over seeded rollouts and write the strategy's row (docs/plugins.md)."""
    from .scoring import score as run_score

    if options["minutes"] > 0:
        require_train_extra()
    rows = run_score(robot, ScoreOptions(**options), humans=list(humans) or None,
                     workers=workers, seed=seed, gown_vertices=gown_vertices,
                     horizon=horizon)  # fmt: skip
    minutes = rows.attrs["seconds"] / 60.0
    for row in rows.itertuples():
        click.echo(f"{robot} with {row.recipe} humans ({row.seeds} seeds, {row.episodes} "
                   f"rollouts): final arm progress {row.final_arm_progress_mean:.3f} m "
                   f"[{row.final_arm_progress_ci_low:.3f}, {row.final_arm_progress_ci_high:.3f}], "
                   f"past the elbow {row.success_rate:.0%}, max deformation "
                   f"{row.max_deformation_mean:.2f}")  # fmt: skip
    click.echo(f"scored in {minutes:.1f} min; strategy table in "
               f"{Path(options['out'], 'strategies.md')}")  # fmt: skip


@evaluate.command("reproduce")
@_CELLS
@_folder(REPRODUCTION)
@click.option("--human", "humans", multiple=True,
              help="Only these trained humans (repeatable; default: every one that plays one of "
                   "the paper's policies).")  # fmt: skip
@click.option("--recipe", help="Without --human: only the seeds of this recipe play the "
              "paper's policies (default: every recipe's; always those of the typical "
              "body).")  # fmt: skip
@click.option("--doc", type=click.Path(dir_okay=False, exists=True),
              help="Also rewrite this doc's results block (docs/reproduction.md).")  # fmt: skip
@_BACKEND
def reproduce_command(out, humans, recipe, doc, **options):
    """The paper's comparison: its five policies, the cross-play, a verdict per claim."""
    from .evaluation import reproduction

    if doc:
        reproduction.documented_results(doc)  # a doc without a results block fails before
    humans = reproduction.paper_humans(humans or None, recipe)
    claims = reproduction.reproduce(out=out, humans=humans, **options)
    for claim in claims.itertuples():
        click.echo(f"claim {claim.claim}: {claim.verdict}")
    click.echo(f"claims in {out}/claims.md, figures in {out}/*.png")
    if doc:
        reproduction.write_doc_results(doc, out)
        click.echo(f"results block of {doc} rewritten from {out}")


@main.command("report")
@click.argument("results", default=RESULTS, type=click.Path(file_okay=False))
@click.option("--videos/--no-videos", default=True, show_default=True,
              help="Render (or reuse) one seeded rollout video per cell.")  # fmt: skip
@_workers("Processes rendering videos")
def report_command(results: str, videos: bool, workers: int | None) -> None:
    """Write RESULTS/report/index.html: a static page of the leaderboard, the success
    definitions, the plots, a video per cell and the run's metadata (no server needed)."""
    from .evaluation.webpage import write_report

    click.echo(f"report in {write_report(results, videos=videos, workers=workers)}")


@main.command()
@_option(TrainConfig, "robot", help=None)
@click.option("--human", default="scripted", show_default=True)
@click.option("--out", "path", default="rollout.gif", show_default=True,
              callback=_checked(check_output_file, suffixes=(".gif", ".mp4")),
              help="A .gif or .mp4, in a folder that exists.")  # fmt: skip
@_options(_SEED_OPTION, _GOWN, _HORIZON, _PROFILE)
def render(robot: str, human: str, path: str, **episode: Any) -> None:
    """A headless video of one rollout (the human's capsules, the gown, the gripper), in the
    env the human was made for: the episode its evaluation scores for the same seed."""
    from .video import render_rollout

    video = render_rollout(robot, human, path, **_stated(episode))
    click.echo(f"video written to {video.path}: {video.summary()}")


@main.command()
@click.argument("summaries", nargs=-1, required=True)
@click.option("--out", default="curves.png", show_default=True,
              callback=_checked(check_output_file, suffixes=(".png",)),
              help="A .png, in a folder that exists.")  # fmt: skip
@click.option("--title", default="learning against time", show_default=True)
def curves(summaries: tuple[str, ...], out: str, title: str) -> None:
    """Hand-in and past-the-elbow rates, final progress and max deformation against hours of
    learning (minutes where every run learned an hour or less): one curve per learning summary
    (NAME-progress.csv, as training writes it)."""
    from .training.summary import write_time_comparison

    runs = {Path(s).name.removesuffix("-progress.csv"): s for s in summaries}
    click.echo(f"curves of {len(runs)} runs in {write_time_comparison(runs, out, title)}")
