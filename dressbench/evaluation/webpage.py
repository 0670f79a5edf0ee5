"""``write_report``: a results folder as one static web page, ``RESULTS/report/index.html``.

The page needs no server and no network when it is viewed: the leaderboard's numbers are in
the HTML (sorted by a few lines of inline JavaScript), the plots are copied next to it
(``report/images/``) and each cell's video is rendered once, from the cell's first seeded
episode, into ``report/videos/`` and reused by later reports (its name holds the cell's
identity key, the seed and the renderer's version). A video that cannot be rendered is
skipped with a note on the page. See docs/evaluation.md, "The report".
"""

from __future__ import annotations

import html
import json
import multiprocessing
import os
import shutil
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..files import slug, write_text
from .report import stage_definitions
from .rollouts import SUCCESS_DEPTH, episode_seed
from .strategies import STRATEGY_CAPTION, score_text
from .workers import exit_with_parent

REPORT_FOLDER = "report"
STRATEGY_FIGURE = "strategies.png"
VIDEO_SUFFIX = ".mp4"
STAGES = (("hand_in", "hand in"), ("success", "past the elbow (success)"), ("dressed", "dressed"))


def write_report(
    results: str | os.PathLike = "results",
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
    for name in ("leaderboard.csv", "run_meta.json"):
        if not (results / name).is_file():
            raise ValueError(
                f"{results}: no {name} (not a results folder; run dressbench evaluate first)"
            )
    board = pd.read_csv(results / "leaderboard.csv")
    meta = json.loads((results / "run_meta.json").read_text())
    folder = results / REPORT_FOLDER
    (folder / "images").mkdir(parents=True, exist_ok=True)
    images = []
    for png in sorted(results.glob("*.png")):  # curves_<robot>.png, final_scores.png
        shutil.copyfile(png, folder / "images" / png.name)
        if png.name != STRATEGY_FIGURE:  # shown with the strategy table
            images.append(f"images/{png.name}")
    clips = {}
    if videos:
        (folder / "videos").mkdir(exist_ok=True)
        clips = _cell_videos(folder, board, meta, workers, progress)
    page = folder / "index.html"
    write_text(page, report_html(board, meta, images, clips, strategies_html(results)))
    return page


def strategies_html(results: Path) -> str:
    """The strategy table (``strategies.csv``) and its figure, as the page shows them first;
    a line saying why there is none."""
    e = html.escape
    path = results / "strategies.csv"
    table = pd.read_csv(path, dtype={"note": str}).fillna({"note": ""}) if path.is_file() else None
    if table is None or table.empty:
        return "<p>No strategy table: no human trained for a strategy in these results.</p>"
    rows = [
        "<tr>" + "".join(f"<td>{e(str(value))}</td>" for value in (
            r.rank, r.robot, r.recipe, r.ablation, r.seeds, r.episodes,
            score_text(r, "final_arm_progress", "mean", "{:.3f}"),
            score_text(r, "max_deformation", "mean", "{:.2f}"),
            *(score_text(r, stage, "rate", "{:.0%}") for stage, _ in STAGES), r.note)) + "</tr>"
        for r in table.itertuples()
    ]  # fmt: skip
    header = ["rank", "robot", "recipe", "ablation", "seeds", "episodes",
              "final arm progress (m)", "max deformation", *(label for _, label in STAGES),
              "note"]  # fmt: skip
    figure = (f'<figure><img src="images/{STRATEGY_FIGURE}" alt="strategies">'
              f"<figcaption>{STRATEGY_FIGURE}</figcaption></figure>"
              if (results / STRATEGY_FIGURE).is_file() else "")  # fmt: skip
    return (
        '<div class="scroll"><table id="strategies"><thead><tr>'
        + "".join(f"<th>{e(h)}</th>" for h in header)
        + f"</tr></thead><tbody>{''.join(rows)}</tbody></table></div>"
        + f"<p>{e(STRATEGY_CAPTION)} The pairwise probabilities of improvement are in "
        "improvement.md.</p>" + figure
    )


def _cell_key(row: Any) -> tuple[str, str, str]:
    return str(row.robot), str(row.human), str(row.config_id)


def _rollout_folder(row: Any, meta: dict[str, Any]) -> str:
    """The cell's rollout folder name (it holds the cell's identity key), or a stand-in."""
    for cell, folder in zip(meta.get("cells", []), meta.get("rollouts", []), strict=False):
        if (cell["robot"], cell["human"], cell["config_id"]) == _cell_key(row):
            return Path(folder).name
    return f"{slug(str(row.robot))}__{slug(str(row.human))}-{row.config_id}"


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
    name = f"{_rollout_folder(row, meta)}-seed{seed}-r{RENDER_VERSION}{VIDEO_SUFFIX}"
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


def _metric_cell(row: Any, metric: str, digits: int) -> str:
    mean = getattr(row, f"{metric}_mean")
    std = getattr(row, f"{metric}_std", float("nan"))
    low, high = getattr(row, f"{metric}_ci_low"), getattr(row, f"{metric}_ci_high")
    spread = "" if pd.isna(std) else f" ± {_number(std, digits)}"
    text = f"{_number(mean, digits)}{spread} [{_number(low, digits)}, {_number(high, digits)}]"
    return f'<td data-value="{mean}">{html.escape(text)}</td>'


def _rate_cell(row: Any, stage: str) -> str:
    rate = getattr(row, f"{stage}_rate", None)
    if rate is None or pd.isna(rate):
        return '<td data-value="-1">n/a</td>'
    low, high = getattr(row, f"{stage}_ci_low"), getattr(row, f"{stage}_ci_high")
    return f'<td data-value="{rate}">{rate:.0%} [{low:.0%}, {high:.0%}]</td>'


def _anchor(key: tuple[str, str, str]) -> str:
    return "video-" + slug("-".join(key))


def report_html(
    board: pd.DataFrame,
    meta: dict[str, Any],
    images: list[str],
    clips: dict[tuple[str, str, str], tuple[str | None, str]],
    strategies: str = "",
) -> str:
    """The whole page as one string (no external resource but the images and videos beside it);
    ``strategies`` is the strategy section's HTML (``strategies_html``), shown first."""
    e = html.escape
    depth = float(meta.get("success_depth", SUCCESS_DEPTH))
    header = ["robot", "human", "ablation", "episodes", "final arm progress (m)",
              "max deformation", *(label for _, label in STAGES), "sim failures",
              "video"]  # fmt: skip
    numeric = {3, 4, 5, 6, 7, 8, 9}
    head = "".join(
        f'<th data-type="{"number" if i in numeric else "text"}" title="click to sort">{e(h)}</th>'
        for i, h in enumerate(header)
    )
    rows = []
    for row in board.itertuples():
        key = _cell_key(row)
        clip = clips.get(key)
        video = f'<a href="#{_anchor(key)}">watch</a>' if clip and clip[0] else "none"
        cells = [
            f"<td>{e(str(row.robot))}</td>",
            f"<td>{e(str(row.human))}</td>",
            f"<td>{e(str(row.ablation))}</td>",
            f'<td data-value="{row.episodes}">{row.episodes}</td>',
            _metric_cell(row, "final_arm_progress", 3),
            _metric_cell(row, "max_deformation", 2),
            *(_rate_cell(row, stage) for stage, _ in STAGES),
            f'<td data-value="{row.sim_failures}">{row.sim_failures}</td>',
            f"<td>{video}</td>",
        ]
        rows.append(f'<tr class="cell">{"".join(cells)}</tr>')
    stages = stage_definitions(depth)
    definitions = "".join(
        f"<dt>{e(label)}</dt><dd>{e(stages[stage])}.</dd>" for stage, label in STAGES
    )
    figures = "".join(
        f'<figure><img src="{e(src)}" alt="{e(Path(src).stem)}">'
        f"<figcaption>{e(Path(src).name)}</figcaption></figure>"
        for src in images
    )
    videos = []
    for key, (src, note) in clips.items():
        title = f"{key[0]} / {key[1]}"
        if src:
            poster = Path(src).with_suffix(".png").as_posix()
            body = (
                f'<video controls muted loop playsinline preload="metadata" src="{e(src)}" '
                f'poster="{e(poster)}"></video><figcaption>{e(title)}: {e(note)}</figcaption>'
            )
        else:
            body = f'<p class="note">{e(title)}: {e(note)}</p>'
        videos.append(f'<figure class="video" id="{_anchor(key)}">{body}</figure>')
    videos_html = "".join(videos) or "<p>No videos (written with --no-videos).</p>"
    return PAGE.format(
        title="dressbench report",
        settings=e(_settings(board)),
        strategies=strategies,
        head=head,
        rows="".join(rows),
        definitions=definitions,
        interval=e(str(meta.get("confidence_interval", ""))),
        figures=figures or "<p>No plots in the results folder.</p>",
        videos=videos_html,
        meta=_meta_table(meta),
        configs=e(json.dumps(meta.get("configs", {}), indent=2, sort_keys=True)),
        script=SORT_SCRIPT,
    )


def _settings(board: pd.DataFrame) -> str:
    settings = board[["horizon", "gown_vertices", "device", "seed"]].drop_duplicates()
    return "; ".join(
        f"horizon {r.horizon} steps, {r.gown_vertices}-vertex gown, device {r.device}, "
        f"base seed {r.seed}"
        for r in settings.itertuples()
    )


def _meta_table(meta: dict[str, Any]) -> str:
    e = html.escape
    versions = meta.get("versions", {})
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
    return "".join(f"<tr><th>{e(k)}</th><td>{e(str(v))}</td></tr>" for k, v in items)


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
<title>{title}</title>
<style>
body {{ font: 15px/1.45 system-ui, sans-serif; margin: 1.5em auto; max-width: 1400px;
       padding: 0 1em; color: #222; }}
table {{ border-collapse: collapse; margin: 0.5em 0 1em; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 0.3em 0.6em; text-align: left; }}
.scroll {{ overflow-x: auto; }}
#leaderboard {{ font-size: 0.85em; }}
#leaderboard td {{ white-space: nowrap; }}
#leaderboard th {{ cursor: pointer; background: #f2f4f8; user-select: none; }}
#leaderboard th[data-order=asc]::after {{ content: " \\25B2"; }}
#leaderboard th[data-order=desc]::after {{ content: " \\25BC"; }}
#leaderboard td[data-value] {{ text-align: right; font-variant-numeric: tabular-nums;
                              white-space: nowrap; }}
figure {{ display: inline-block; margin: 0.5em; vertical-align: top; }}
figure img {{ max-width: 560px; border: 1px solid #ddd; }}
figure.video video {{ width: 560px; border: 1px solid #ddd; }}
figcaption, .note {{ font-size: 0.85em; color: #555; max-width: 560px; }}
dt {{ font-weight: 600; }}
pre {{ background: #f6f6f6; padding: 0.6em; overflow: auto; font-size: 0.8em; }}
</style>
</head>
<body>
<h1>{title}</h1>
<p>Settings: {settings}. Click a column's header to sort by it.</p>
<h2>Strategies</h2>
{strategies}
<h2>Leaderboard</h2>
<div class="scroll">
<table id="leaderboard"><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>
</div>
<p>Each cell is a robot strategy x a human model over seeded rollouts: mean ± sample std and,
in brackets, the confidence interval of the mean ({interval}); rates carry their 95% Wilson
interval. Arm progress is the arm's depth in the sleeve (m); max deformation is the largest
triangle area ratio (stretched / rest) of the episode.</p>
<h2>What success means</h2>
<dl>{definitions}</dl>
<h2>Curves and scores</h2>
{figures}
<h2>Videos</h2>
<p>One seeded rollout per cell (the cell's first episode), rendered once and cached.</p>
{videos}
<h2>Run</h2>
<table id="meta">{meta}</table>
<details><summary>environment configurations</summary><pre>{configs}</pre></details>
<script>{script}</script>
</body>
</html>
"""
