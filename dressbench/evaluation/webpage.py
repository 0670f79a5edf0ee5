"""``write_report``: a results folder as one static web page, ``RESULTS/report/index.html``.

The page needs no server and no network when it is viewed: the leaderboard's numbers are in
the HTML (sorted by a few lines of inline JavaScript), the plots are copied next to it
(``report/images/``) and each cell's video is rendered once, from the cell's first seeded
episode, into ``report/videos/`` and reused by later reports (its name holds the cell's
identity key, the seed and the renderer's version). A video that cannot be rendered is
skipped with a note on the page. See docs/evaluation.md, "The report".
"""

from __future__ import annotations

import io
import json
import multiprocessing
import os
import sys
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..checks import RESULTS
from ..files import parse_json, read_untrusted, readable, slug, write_bytes, write_text
from ..plugins import TYPICAL_PROFILE
from .finetuned import FINETUNED, change_text
from .members import MEMBERS
from .report import rate_text, settings_text, stage_definitions, summary_text
from .rollouts import SUCCESS_DEPTH, episode_seed
from .schema import STAGE_COLUMNS, STAGE_LABELS
from .strategies import STRATEGY_CAPTION, score_text
from .workers import exit_with_parent

REPORT_FOLDER = "report"
# the leaderboard.csv columns the page cannot do without (older tables lack the stage rates)
_NEEDED = ("robot", "human", "ablation", "episodes", "horizon", "gown_vertices", "device", "seed",
           "config_id", "sim_failures", *(f"{m}_{s}" for m in ("final_arm_progress",
           "max_deformation") for s in ("mean", "ci_low", "ci_high")))  # fmt: skip
STRATEGY_FIGURE = "strategies.png"
VIDEO_SUFFIX = ".mp4"
STAGES = tuple((stage, STAGE_LABELS[stage]) for stage in STAGE_COLUMNS)


def write_report(
    results: str | os.PathLike = RESULTS,
    *,
    videos: bool = True,
    workers: int | None = 1,
    progress: bool = True,
) -> Path:
    """Write ``results/report/index.html`` from a results folder; returns the page's path.

    ``results`` must hold ``leaderboard.csv`` and ``run_meta.json`` (what ``leaderboard`` and
    ``evaluate`` write). With ``videos`` each cell gets its seeded rollout video (rendered
    unless cached), in ``workers`` processes (None: one per core; 1: this process);
    ``progress`` prints one line per video rendered.
    """
    results = Path(results)
    board, meta = _read_results(results)
    folder = results / REPORT_FOLDER
    for sub in (folder, folder / "images", *([folder / "videos"] if videos else [])):
        if sub.is_symlink():
            raise ValueError(f"{sub}: a link; the report writes only into a folder of its own")
        sub.mkdir(exist_ok=True)
    images = []
    for png in sorted(results.glob("*.png")):  # curves_<robot>.png, final_scores.png
        if not readable(png):
            continue  # not ours: a link could widen a private file's mode or reach anywhere
        write_bytes(folder / "images" / png.name, png.read_bytes())
        if png.name != STRATEGY_FIGURE:  # shown with the strategy table
            images.append(f"images/{png.name}")
    clips = {}
    if videos:
        clips = _cell_videos(folder, board, meta, workers, progress)
    page = folder / "index.html"
    sections = {"strategies": strategy_section(results), "members": member_section(results),
                "finetuned": finetuned_section(results)}  # fmt: skip
    write_text(page, report_html(board, meta, images, clips, **sections))
    return page


def _read_results(results: Path) -> tuple[pd.DataFrame, dict[str, Any]]:
    """``leaderboard.csv`` and ``run_meta.json`` of a results folder, each read as untrusted
    input (``files.read_untrusted``); a ValueError naming the file when one is missing or
    unreadable."""
    for name in ("leaderboard.csv", "run_meta.json"):
        if not (results / name).is_file():
            raise ValueError(
                f"{results}: no {name} (not a results folder; run dressbench evaluate first)"
            )
    path = results / "leaderboard.csv"
    data = read_untrusted(path, "a results file")
    try:
        board = pd.read_csv(io.BytesIO(data))
    except (ValueError, UnicodeDecodeError) as error:  # EmptyDataError, ParserError among them
        raise ValueError(f"{path}: not a leaderboard table ({_one_line(error)})") from None
    missing = [c for c in _NEEDED if c not in board.columns]
    if missing:
        raise ValueError(f"{path}: not a leaderboard table (no column {', '.join(missing[:3])})")
    path = results / "run_meta.json"
    try:
        meta = parse_json(read_untrusted(path, "a results file"))
    except ValueError as error:  # JSONDecodeError, UnicodeDecodeError, too deep
        raise ValueError(f"{path}: not valid JSON ({_one_line(error)})") from None
    if not isinstance(meta, dict):
        raise ValueError(f"{path}: not a run's metadata (a JSON {type(meta).__name__})")
    return board, meta


def _one_line(error: BaseException) -> str:
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return f"{type(error).__name__}: {lines[0]}" if lines else type(error).__name__


def strategy_section(results: Path) -> dict[str, Any] | None:
    """The strategy table (``strategies.csv``, read as untrusted input) as the page shows it
    first: its header, its rows as text and its figure; None where there is no table."""
    rows = _table_rows(
        results / "strategies.csv", "a strategy table",
        lambda r: (r.rank, r.robot, r.recipe, r.ablation, _profile(r), r.seeds, r.episodes,
                   score_text(r, "final_arm_progress", "mean", "{:.3f}"),
                   score_text(r, "max_deformation", "mean", "{:.2f}"),
                   *(score_text(r, stage, "rate", "{:.0%}") for stage, _ in STAGES), r.note),
        lambda table: table.fillna({"note": ""}), dtype={"note": str},
    )  # fmt: skip
    if not rows:
        return None
    header = ["rank", "robot", "recipe", "ablation", "profile", "seeds", "episodes",
              "final arm progress (m)", "max deformation", *(label for _, label in STAGES),
              "note"]  # fmt: skip
    figure = STRATEGY_FIGURE if (results / STRATEGY_FIGURE).is_file() else None
    return {"header": header, "rows": rows, "caption": STRATEGY_CAPTION, "figure": figure}


def member_section(results: Path) -> dict[str, Any] | None:
    """The member table (``members.csv``, read as untrusted input) as the page shows it: its
    header and rows as text; None where the results scored no family strategy."""
    rows = _table_rows(
        results / f"{MEMBERS}.csv", "a member table",
        lambda r: (r.human, _profile(r), r.split, r.member, r.episodes,
                   summary_text(r, "final_arm_progress", "{:.3f}"),
                   summary_text(r, "max_deformation", "{:.2f}"),
                   *(rate_text(r, stage) for stage, _ in STAGES)),
    )  # fmt: skip
    header = ["human", "profile", "split", "member", "episodes", "final arm progress (m)",
              "max deformation", *(label for _, label in STAGES)]  # fmt: skip
    return {"header": header, "rows": rows} if rows else None


def finetuned_section(results: Path) -> dict[str, Any] | None:
    """The fine-tuned humans against their parents (``finetuned.csv``, read as untrusted input)
    as the page shows them: header and rows as text; None where the results hold no such pair."""
    rows = _table_rows(
        results / f"{FINETUNED}.csv", "a table of fine-tuned humans",
        lambda r: (r.robot, _profile(r), r.human, r.parent, r.episodes,
                   change_text(r, "final_arm_progress", "{:.3f}", "{:+.3f}"),
                   change_text(r, "max_deformation", "{:.2f}", "{:+.2f}"),
                   change_text(r, "success", "{:.0%}", "{:+.0%}"), r.verdict),
    )  # fmt: skip
    header = ["robot", "profile", "human", "fine-tuned from", "rollouts",
              "final arm progress (m)", "max deformation", "past the elbow", "verdict"]  # fmt: skip
    return {"header": header, "rows": rows} if rows else None


def _table_rows(
    path: Path,
    what: str,
    row: Callable[[Any], Sequence[Any]],
    prepare: Callable[[pd.DataFrame], pd.DataFrame] = lambda table: table,
    **read: Any,
) -> list[list[str]] | None:
    """A results table's rows as text (``row`` of each), read as untrusted input and made
    ready by ``prepare``; None where the file is missing, a ValueError naming it (``what`` it
    should be) where it is malformed."""
    if not path.is_file():
        return None
    data = read_untrusted(path, "a results file")
    try:
        table = prepare(pd.read_csv(io.BytesIO(data), **read))
        return [[str(value) for value in row(r)] for r in table.itertuples()]
    except (ValueError, UnicodeDecodeError, AttributeError) as error:
        raise ValueError(f"{path}: not {what} ({_one_line(error)})") from None


def _profile(row: Any) -> str:
    """A row's capability profile; a results folder made before profiles has typical humans."""
    return str(getattr(row, "profile", TYPICAL_PROFILE))


def _cell_key(row: Any) -> tuple[str, str, str]:
    return str(row.robot), str(row.human), str(row.config_id)


def _rollout_folder(row: Any, meta: dict[str, Any]) -> str:
    """The cell's rollout folder name (it holds the cell's identity key), or a stand-in."""
    for cell, folder in zip(meta.get("cells", []), meta.get("rollouts", []), strict=False):
        if not isinstance(cell, dict) or not isinstance(folder, str):
            continue
        if (cell.get("robot"), cell.get("human"), cell.get("config_id")) == _cell_key(row):
            return slug(Path(folder).name)
    return f"{slug(str(row.robot))}__{slug(str(row.human))}-{slug(str(row.config_id))}"


@dataclass(frozen=True)
class VideoTask:
    """One cell's video: which rollout, and where it goes (``path`` relative to ``folder``)."""

    robot: str
    human: str
    seed: int
    options: tuple[tuple[str, Any], ...]  # horizon, gown_vertices, device
    folder: Path
    path: str


def _video_task(folder: Path, row: Any, meta: dict[str, Any]) -> VideoTask:
    from ..render import RENDER_VERSION

    seed = episode_seed(int(meta.get("seed", row.seed)), 0)
    name = slug(f"{_rollout_folder(row, meta)}-seed{seed}-r{RENDER_VERSION}") + VIDEO_SUFFIX
    options = (("horizon", int(row.horizon)), ("gown_vertices", int(row.gown_vertices)),
               ("device", str(row.device)))  # fmt: skip
    return VideoTask(str(row.robot), str(row.human), seed, options, folder, f"videos/{name}")


def _note(task: VideoTask) -> str:
    options = dict(task.options)
    return (
        f"episode 0 (seed {task.seed}), horizon {options['horizon']}, "
        f"{options['gown_vertices']}-vertex gown, device {options['device']}"
    )


def render_video(task: VideoTask) -> tuple[str | None, str]:
    """``(relative path, note)`` of a cell's video, rendered unless it exists; ``(None, why)``
    if rendering fails. Written to a hidden partial file first, so a killed run leaves no
    half video under the final name."""
    from .. import video

    path = task.folder / task.path
    if not path.is_file():
        partial = path.with_name(f".{path.stem}.partial{VIDEO_SUFFIX}")
        try:
            video.render_rollout(task.robot, task.human, partial, seed=task.seed,
                                  **dict(task.options))  # fmt: skip
            write_poster(partial, path.with_suffix(".png"))
            partial.replace(path)
        except Exception as error:  # any failure: the page says so and goes on
            partial.unlink(missing_ok=True)
            reason = str(error).strip().splitlines()[0] if str(error).strip() else ""
            return None, f"video not rendered: {type(error).__name__}: {reason}"
    elif not path.with_suffix(".png").is_file():
        try:  # a video of an earlier report without its still
            write_poster(path, path.with_suffix(".png"))
        except Exception:  # the video plays without it
            pass
    return task.path, _note(task)


def write_poster(video: Path, poster: Path, at: float = 0.6) -> None:
    """Save the frame ``at`` (a share of the clip) of an MP4 as a PNG: the still the page
    shows before the video plays."""
    import imageio.v3 as iio
    import imageio_ffmpeg

    count = imageio_ffmpeg.count_frames_and_secs(str(video))[0]
    target = int(at * max(count - 1, 0))
    frames = imageio_ffmpeg.read_frames(str(video))
    meta = next(frames)
    width, height = meta["size"]
    try:
        for index, frame in enumerate(frames):
            if index == target:
                image = np.frombuffer(frame, np.uint8).reshape(height, width, 3)
                iio.imwrite(poster, image)
                return
    finally:
        frames.close()


def _cell_videos(
    folder: Path, board: pd.DataFrame, meta: dict[str, Any], workers: int | None, progress: bool
) -> dict[tuple[str, str, str], tuple[str | None, str]]:
    """Every cell's ``(path, note)``: cached videos reused, the others rendered."""
    tasks = {_cell_key(row): _video_task(folder, row, meta) for row in board.itertuples()}
    clips = {key: (task.path, _note(task)) for key, task in tasks.items()
             if (folder / task.path).is_file()
             and (folder / task.path).with_suffix(".png").is_file()}  # fmt: skip
    missing = {key: task for key, task in tasks.items() if key not in clips}
    workers = min(workers or os.cpu_count() or 1, max(len(missing), 1))

    def report(key: tuple[str, str, str]) -> None:
        if progress:
            print(f"dressbench report: rendered {key[0]} / {key[1]}", file=sys.stderr)

    if workers == 1:
        for key, task in missing.items():
            clips[key] = render_video(task)
            report(key)
    else:
        context = multiprocessing.get_context("spawn")  # as evaluations: fork is unsafe
        with ProcessPoolExecutor(workers, mp_context=context, initializer=exit_with_parent,
                                 initargs=(os.getpid(),)) as pool:  # fmt: skip
            futures = {pool.submit(render_video, task): key for key, task in missing.items()}
            for future in as_completed(futures):
                clips[futures[future]] = future.result()
                report(futures[future])
    return {key: clips[key] for key in tasks}  # in the leaderboard's order


# --- the page -----------------------------------------------------------------------------------


def _number(value: Any, digits: int) -> str:
    return "" if pd.isna(value) else f"{value:.{digits}f}"


def _metric_cell(row: Any, metric: str, digits: int) -> dict[str, Any]:
    mean = getattr(row, f"{metric}_mean")
    std = getattr(row, f"{metric}_std", float("nan"))
    low, high = getattr(row, f"{metric}_ci_low"), getattr(row, f"{metric}_ci_high")
    spread = "" if pd.isna(std) else f" ± {_number(std, digits)}"
    text = f"{_number(mean, digits)}{spread} [{_number(low, digits)}, {_number(high, digits)}]"
    return {"value": mean, "text": text}


def _rate_cell(row: Any, stage: str) -> dict[str, Any]:
    rate = getattr(row, f"{stage}_rate", None)
    if rate is None or pd.isna(rate):
        return {"value": -1, "text": "n/a"}
    low, high = getattr(row, f"{stage}_ci_low"), getattr(row, f"{stage}_ci_high")
    return {"value": rate, "text": f"{rate:.0%} [{low:.0%}, {high:.0%}]"}


def _anchor(key: tuple[str, str, str]) -> str:
    return "video-" + slug("-".join(key))


def report_html(
    board: pd.DataFrame,
    meta: dict[str, Any],
    images: list[str],
    clips: dict[tuple[str, str, str], tuple[str | None, str]],
    strategies: dict[str, Any] | None = None,
    members: dict[str, Any] | None = None,
    finetuned: dict[str, Any] | None = None,
) -> str:
    """The whole page as one string (no external resource but the images and videos beside it);
    every value is escaped by the template engine (values come from files of a results folder);
    ``strategies`` is the strategy section (``strategy_section``), shown first; ``members``
    the family's episodes by member (``member_section``) and ``finetuned`` the fine-tuned
    humans against their parents (``finetuned_section``), after the leaderboard."""
    import jinja2

    depth = float(meta.get("success_depth", SUCCESS_DEPTH))
    header = ["robot", "human", "ablation", "profile", "episodes", "final arm progress (m)",
              "max deformation", *(label for _, label in STAGES), "sim failures",
              "video"]  # fmt: skip
    numeric = {4, 5, 6, 7, 8, 9, 10}
    rows = []
    for row in board.itertuples():
        key = _cell_key(row)
        clip = clips.get(key)
        rows.append({
            "text": [str(row.robot), str(row.human), str(row.ablation), _profile(row)],
            "numbers": [
                {"value": row.episodes, "text": row.episodes},
                _metric_cell(row, "final_arm_progress", 3),
                _metric_cell(row, "max_deformation", 2),
                *(_rate_cell(row, stage) for stage, _ in STAGES),
                {"value": row.sim_failures, "text": row.sim_failures},
            ],
            "video": _anchor(key) if clip and clip[0] else None,
        })  # fmt: skip
    stages = stage_definitions(depth)
    videos = [
        {"anchor": _anchor(key), "title": f"{key[0]} / {key[1]}", "src": src, "note": note,
         "poster": Path(src).with_suffix(".png").as_posix() if src else None}
        for key, (src, note) in clips.items()
    ]  # fmt: skip
    page = jinja2.Environment(autoescape=True).from_string(PAGE)
    return page.render(
        title="dressbench report",
        settings=settings_text(board),
        strategies=strategies,
        members=members,
        finetuned=finetuned,
        header=[(h, "number" if i in numeric else "text") for i, h in enumerate(header)],
        rows=rows,
        definitions=[(label, stages[stage]) for stage, label in STAGES],
        interval=str(meta.get("confidence_interval", "")),
        images=[(src, Path(src).stem, Path(src).name) for src in images],
        videos=videos,
        meta=_meta_items(meta),
        configs=json.dumps(meta.get("configs", {}), indent=2, sort_keys=True),
        script=jinja2.filters.Markup(SORT_SCRIPT),  # our own code, not a value
    )


def _meta_items(meta: dict[str, Any]) -> list[tuple[str, str]]:
    versions = meta.get("versions", {})
    versions = versions if isinstance(versions, dict) else {}
    items = [
        ("git commit", meta.get("git_commit") or "unknown (not a git checkout)"),
        ("versions", ", ".join(f"{k} {v}" for k, v in versions.items() if v)),
        ("command", meta.get("command")),
        ("started", meta.get("started")),
        ("elapsed", f"{meta.get('elapsed_seconds')} s"),
        ("episodes per cell", meta.get("episodes_per_cell")),
        ("base seed", meta.get("seed")),
        ("episode seeds", meta.get("episode_seeds")),
        ("workers", meta.get("workers")),
        ("options", json.dumps(meta.get("options", {}), sort_keys=True)),
    ]
    return [(k, str(v)) for k, v in items]


SORT_SCRIPT = """
document.querySelectorAll('#leaderboard th').forEach(function (th, column) {
  th.addEventListener('click', function () {
    var body = th.closest('table').tBodies[0];
    var up = th.dataset.order !== 'asc';
    th.closest('tr').querySelectorAll('th').forEach(function (o) { delete o.dataset.order; });
    th.dataset.order = up ? 'asc' : 'desc';
    var number = th.dataset.type === 'number';
    var key = function (tr) {
      var td = tr.cells[column];
      return number ? parseFloat(td.dataset.value) : td.textContent.toLowerCase();
    };
    Array.from(body.rows).sort(function (a, b) {
      var x = key(a), y = key(b);
      return (x < y ? -1 : x > y ? 1 : 0) * (up ? 1 : -1);
    }).forEach(function (tr) { body.appendChild(tr); });
  });
});
"""

PAGE = """<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{{ title }}</title>
<style>
body { font: 15px/1.45 system-ui, sans-serif; margin: 1.5em auto; max-width: 1400px;
       padding: 0 1em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1em; }
th, td { border-bottom: 1px solid #ddd; padding: 0.3em 0.6em; text-align: left; }
.scroll { overflow-x: auto; }
#leaderboard { font-size: 0.85em; }
#leaderboard td { white-space: nowrap; }
#leaderboard th { cursor: pointer; background: #f2f4f8; user-select: none; }
#leaderboard th[data-order=asc]::after { content: " \\25B2"; }
#leaderboard th[data-order=desc]::after { content: " \\25BC"; }
#leaderboard td[data-value] { text-align: right; font-variant-numeric: tabular-nums;
                              white-space: nowrap; }
figure { display: inline-block; margin: 0.5em; vertical-align: top; }
figure img { max-width: 560px; border: 1px solid #ddd; }
figure.video video { width: 560px; border: 1px solid #ddd; }
figcaption, .note { font-size: 0.85em; color: #555; max-width: 560px; }
dt { font-weight: 600; }
pre { background: #f6f6f6; padding: 0.6em; overflow: auto; font-size: 0.8em; }
</style>
</head>
<body>
<h1>{{ title }}</h1>
<p>Settings: {{ settings }}. Click a column's header to sort by it.</p>
<h2>Strategies</h2>
{% if strategies -%}
<div class="scroll"><table id="strategies"><thead><tr>
{%- for label in strategies.header %}<th>{{ label }}</th>{% endfor -%}
</tr></thead><tbody>
{%- for row in strategies.rows %}<tr>{% for value in row %}<td>{{ value }}</td>{% endfor %}</tr>
{%- endfor %}</tbody></table></div>
<p>{{ strategies.caption }} The pairwise probabilities of improvement are in improvement.md.</p>
{%- if strategies.figure %}
<figure><img src="images/{{ strategies.figure }}" alt="strategies">
<figcaption>{{ strategies.figure }}</figcaption></figure>
{%- endif %}
{%- else -%}
<p>No strategy table: no human trained for a strategy in these results.</p>
{%- endif %}
<h2>Leaderboard</h2>
<div class="scroll">
<table id="leaderboard"><thead><tr>
{%- for label, kind in header -%}
<th data-type="{{ kind }}" title="click to sort">{{ label }}</th>
{%- endfor -%}
</tr></thead><tbody>
{%- for row in rows %}<tr class="cell">
{%- for text in row.text %}<td>{{ text }}</td>{% endfor %}
{%- for cell in row.numbers %}<td data-value="{{ cell.value }}">{{ cell.text }}</td>{% endfor -%}
<td>{% if row.video %}<a href="#{{ row.video }}">watch</a>{% else %}none{% endif %}</td></tr>
{%- endfor %}</tbody></table>
</div>
<p>Each cell is a robot strategy x a human model over seeded rollouts: mean ± sample std and,
in brackets, the confidence interval of the mean ({{ interval }}); rates carry their 95% Wilson
interval. Arm progress is the arm's depth in the sleeve (m); max deformation is the largest
triangle area ratio (stretched / rest) of the episode.</p>
{% if members -%}
<h2>The family's episodes by member</h2>
<div class="scroll"><table id="members"><thead><tr>
{%- for label in members.header %}<th>{{ label }}</th>{% endfor -%}
</tr></thead><tbody>
{%- for row in members.rows %}<tr>{% for value in row %}<td>{{ value }}</td>{% endfor %}</tr>
{%- endfor %}</tbody></table></div>
<p>Each family cell's episodes split by the member each faced: its kind, and the direction of
its start from the right shoulder (members.md defines the directions). Means ± sample std, the
interval of the mean in brackets; rates with their 95% Wilson interval.</p>
{% endif -%}
{% if finetuned -%}
<h2>Fine-tuned humans against their parents</h2>
<div class="scroll"><table id="finetuned"><thead><tr>
{%- for label in finetuned.header %}<th>{{ label }}</th>{% endfor -%}
</tr></thead><tbody>
{%- for row in finetuned.rows %}<tr>{% for value in row %}<td>{{ value }}</td>{% endfor %}</tr>
{%- endfor %}</tbody></table></div>
<p>Each human fine-tuned from another, against that parent on the same seeded rollouts (the same
strategy, profile, start, gown and involuntary motion): the parent's mean → the fine-tuned
human's, then the mean change over the paired rollouts with its 95% bootstrap interval
(finetuned.md). The verdict names each change whose interval excludes 0.</p>
{% endif -%}
<h2>What success means</h2>
<dl>{% for label, text in definitions %}<dt>{{ label }}</dt><dd>{{ text }}.</dd>{% endfor %}</dl>
<h2>Curves and scores</h2>
{% for src, alt, name in images -%}
<figure><img src="{{ src }}" alt="{{ alt }}"><figcaption>{{ name }}</figcaption></figure>
{%- else %}<p>No plots in the results folder.</p>{% endfor %}
<h2>Videos</h2>
<p>One seeded rollout per cell (the cell's first episode), rendered once and cached.</p>
{% for v in videos -%}
<figure class="video" id="{{ v.anchor }}">
{%- if v.src %}<video controls muted loop playsinline preload="metadata" src="{{ v.src }}"
 poster="{{ v.poster }}"></video><figcaption>{{ v.title }}: {{ v.note }}</figcaption>
{%- else %}<p class="note">{{ v.title }}: {{ v.note }}</p>{% endif %}</figure>
{%- else %}<p>No videos (written with --no-videos).</p>{% endfor %}
<h2>Run</h2>
<table id="meta">{% for k, v in meta %}<tr><th>{{ k }}</th><td>{{ v }}</td></tr>{% endfor %}</table>
<details><summary>environment configurations</summary><pre>{{ configs }}</pre></details>
<script>{{ script }}</script>
</body>
</html>
"""
