"""``dressbench report``: a static page of a results folder, checked in a real headless Chromium.

The results folder is tiny (2 cells, 1 episode, horizon 6, a 300-vertex gown) so the videos
are a few frames. Chromium comes from the system packages (``apt-get install chromium``; CI
installs it in ``.ci/run``); this test installs it when missing and it may (root), else skips.
"""

import json
import os
import re
import shutil
import subprocess

import pandas as pd
import pytest
from click.testing import CliRunner

from dressbench.cli import main
from dressbench.evaluation import leaderboard
from dressbench.evaluation.finetuned import write_finetuned
from dressbench.evaluation.members import write_members
from dressbench.evaluation.strategies import write_strategies
from dressbench.evaluation.webpage import write_report

HUMANS = ["passive", "scripted"]
TRAINED = ["fixed-default-s0", "fixed-default-s1"]


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    leaderboard(episodes=1, seed=0, workers=1, out=out, robots=["fixed"], humans=HUMANS,
                progress=False, horizon=6, gown_vertices=300)  # fmt: skip
    return out


def chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found is None and os.geteuid() == 0 and shutil.which("apt-get"):
        install = ["apt-get", "install", "-y", "-q", "--no-install-recommends", "chromium"]
        if subprocess.run(install, capture_output=True).returncode != 0:
            subprocess.run(["apt-get", "update", "-q"], capture_output=True)
            subprocess.run(install, capture_output=True)
        found = shutil.which("chromium")
    if found is None:
        pytest.skip("no chromium (apt-get install chromium)")
    return found


# Injected into a copy of the page: record errors (scripts, and images or videos that fail to
# load), wait for every image and video, sort the table by a column, then write what it saw.
PROBE = """<script>window.__errors = [];
addEventListener('error', function (e) {
  __errors.push(e.message || ('failed to load ' + (e.target.src || e.target.href)));
}, true);</script>"""
CHECK = """<script>
function ready(m) {
  if (m.tagName === 'IMG') return m.complete ? Promise.resolve() :
    new Promise(function (r) { m.onload = m.onerror = r; });
  return m.readyState >= 1 ? Promise.resolve() : new Promise(function (r) {
    m.addEventListener('loadedmetadata', r); m.addEventListener('error', r); });
}
function column(i) {
  return Array.from(document.querySelectorAll('#leaderboard tbody tr')).map(
    function (tr) { return tr.cells[i].textContent; });
}
addEventListener('load', function () {
  var media = Array.from(document.querySelectorAll('img, video'));
  var posters = Array.from(document.querySelectorAll('video')).map(function (v) {
    var i = new Image(); i.src = v.getAttribute('poster'); return i; });
  Promise.all(media.concat(posters).map(ready)).then(function () {
    var ths = document.querySelectorAll('#leaderboard th');
    ths[1].click(); var up = column(1); ths[1].click(); var down = column(1);
    ths[5].click(); var deformation = Array.from(document.querySelectorAll(
      '#leaderboard tbody tr')).map(function (tr) { return +tr.cells[5].dataset.value; });
    var out = {errors: __errors, rows: column(0).length, up: up, down: down,
      deformation: deformation,
      headings: Array.from(document.querySelectorAll('h2')).map(function (h) {
        return h.textContent; }),
      tables: Array.from(document.querySelectorAll('table')).map(function (t) { return t.id; }),
      strategies: document.querySelectorAll('#strategies tbody tr').length,
      images: Array.from(document.images).map(function (i) {
        return [i.getAttribute('src'), i.naturalWidth]; }),
      posters: posters.map(function (i) { return [i.getAttribute('src'), i.naturalWidth]; }),
      videos: Array.from(document.querySelectorAll('video')).map(function (v) {
        return [v.getAttribute('src'), v.videoWidth, v.error && v.error.code]; })};
    var pre = document.createElement('pre'); pre.id = 'check';
    pre.textContent = JSON.stringify(out); document.body.appendChild(pre);
  });
});
</script>"""


def browse(page, tmp_path) -> dict:
    """What the page showed in headless Chromium."""
    probe = page.with_name("check.html")
    text = page.read_text()
    probe.write_text(
        text.replace("<head>", "<head>" + PROBE, 1).replace("</body>", CHECK + "</body>")
    )
    command = [chromium(), "--headless", "--no-sandbox", "--disable-gpu",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               "--no-first-run", f"--user-data-dir={tmp_path / 'profile'}",
               "--virtual-time-budget=20000", "--dump-dom", probe.as_uri()]  # fmt: skip
    run = subprocess.run(command, capture_output=True, text=True, timeout=180)
    probe.unlink()
    found = re.search(r'<pre id="check">(.*?)</pre>', run.stdout, re.S)
    assert found, f"no result from chromium: {run.stdout[-2000:]} {run.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def test_the_report_loads_in_a_browser_with_every_row_image_and_video(results, tmp_path):
    page = write_report(results, progress=False)
    assert page == results / "report" / "index.html"
    seen = browse(page, tmp_path)
    assert seen["errors"] == []
    assert seen["rows"] == len(HUMANS)  # one row per cell
    assert seen["up"] == sorted(HUMANS) and seen["down"] == sorted(HUMANS)[::-1]  # sortable
    assert seen["deformation"] == sorted(seen["deformation"])
    assert len(seen["images"]) == 2 and all(width > 0 for _, width in seen["images"])
    assert len(seen["videos"]) == len(HUMANS)
    assert all(width > 0 and error is None for _, width, error in seen["videos"])
    assert len(seen["posters"]) == len(HUMANS) and all(w > 0 for _, w in seen["posters"])
    assert seen["headings"][:2] == ["Strategies", "Leaderboard"]  # none trained: a line says so
    assert seen["strategies"] == 0


def test_the_report_shows_the_strategy_table_and_its_figure_first(results, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
    episodes = pd.read_csv(copy / "episodes.csv")  # two seeds of one recipe, say
    episodes["human"] = episodes["human"].map(dict(zip(HUMANS, TRAINED, strict=True)))
    write_strategies(copy, episodes)
    seen = browse(write_report(copy, videos=False, progress=False), tmp_path)
    assert seen["errors"] == []
    assert seen["tables"][:2] == ["strategies", "leaderboard"]
    assert seen["strategies"] == 1  # fixed with its two humans
    source, width = seen["images"][0]
    assert source == "images/strategies.png" and width > 0
    assert [src for src, _ in seen["images"]].count(source) == 1


def test_the_report_shows_the_familys_episodes_by_member_only_where_it_was_scored(
    results, tmp_path
):
    assert 'id="members"' not in write_report(results, videos=False, progress=False).read_text()
    copy = tmp_path / "copy"
    shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
    episodes = pd.read_csv(copy / "episodes.csv").assign(robot="family")  # as if against it
    table = write_members(copy, episodes)
    page = write_report(copy, videos=False, progress=False).read_text()
    shown = re.search(r'<table id="members">.*?</table>', page, re.S).group(0)
    assert shown.count("<tr>") == 1 + len(table)  # the header and every row
    assert "passive" in shown and "kind" in shown and "approach" in shown
    (copy / "members.csv").write_text("split,member\nkind\n")
    with pytest.raises(ValueError, match=r"members\.csv: not a member table") as refused:
        write_report(copy, videos=False, progress=False)
    assert "\n" not in str(refused.value)


def test_the_report_shows_fine_tuned_humans_against_their_parents_where_both_played(
    results, tmp_path
):
    assert 'id="finetuned"' not in write_report(results, videos=False, progress=False).read_text()
    copy = tmp_path / "copy"
    shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
    played = pd.read_csv(copy / "episodes.csv").assign(robot="front_linear")
    named = {"passive": "front_linear-default-s0", "scripted": "front_linear-tremor-tuned-s0"}
    table = write_finetuned(copy, played.replace({"human": named}))  # a shipped pair, as if
    page = write_report(copy, videos=False, progress=False).read_text()
    shown = re.search(r'<table id="finetuned">.*?</table>', page, re.S).group(0)
    assert shown.count("<tr>") == 1 + len(table) == 2
    assert "front_linear-tremor-tuned-s0" in shown and "front_linear-default-s0" in shown
    (copy / "finetuned.csv").write_text("robot,human\nfixed\n")
    with pytest.raises(ValueError, match=r"finetuned\.csv: not a table of fine-tuned") as refused:
        write_report(copy, videos=False, progress=False)
    assert "\n" not in str(refused.value)


def test_the_report_is_self_contained_and_videos_are_cached(results):
    page = write_report(results, progress=False)
    text = page.read_text()
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", text)  # no network at view time
    for stage in ("hand in", "past the elbow (success)", "dressed", "0.44 m"):
        assert stage in text
    meta = json.loads((results / "run_meta.json").read_text())
    assert meta["versions"]["numpy"] in text and str(meta["seed"]) in text
    videos = sorted((results / "report" / "videos").glob("*.mp4"))
    assert len(videos) == len(HUMANS)
    for video in videos:  # each with its still, shown before it plays
        assert video.with_suffix(".png").stat().st_size > 0
        assert f'poster="videos/{video.with_suffix(".png").name}"' in text
    stamps = [v.stat().st_mtime_ns for v in videos]
    write_report(results, progress=False)  # reuses them
    assert [v.stat().st_mtime_ns for v in videos] == stamps


def test_a_video_that_fails_to_render_is_a_note(results, tmp_path, monkeypatch):
    import dressbench.video

    def broken(*args, **kwargs):
        raise RuntimeError("no ffmpeg here")

    copy = tmp_path / "copy"
    shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
    monkeypatch.setattr(dressbench.video, "render_rollout", broken)
    text = write_report(copy, progress=False).read_text()
    assert text.count("video not rendered: RuntimeError: no ffmpeg here") == len(HUMANS)
    assert "<video" not in text


def test_the_cli_writes_the_report_and_prints_its_path(results):
    run = CliRunner().invoke(main, ["report", str(results), "--no-videos"])
    assert run.exit_code == 0, run.output
    assert run.output.strip() == f"report in {results / 'report' / 'index.html'}"
    bad = CliRunner().invoke(main, ["report", str(results / "nothing")])
    assert bad.exit_code == 1 and "not a results folder" in bad.output


def test_videos_render_in_worker_processes(results, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
    text = write_report(copy, workers=2, progress=False).read_text()
    videos = sorted((copy / "report" / "videos").glob("*.mp4"))
    assert len(videos) == len(HUMANS) and text.count("<video") == len(HUMANS)
    assert not list((copy / "report" / "videos").glob(".*partial*"))
