"""The ecosystem's conventions: gymnasium registration, PettingZoo's ``parallel_env``, an
aligned plugin listing, and a clear error for a plugin name given to ``load_policy``."""

import re
import subprocess
import sys
from pathlib import Path

import gymnasium
import numpy as np
import pytest
from click.testing import CliRunner
from pettingzoo import ParallelEnv

import dressbench
from dressbench.cli import main
from dressbench.evaluation.listing import aligned
from dressbench.policy_file import PolicyFileError

TINY = {"horizon": 3, "gown_vertices": 300}


def test_importing_dressbench_registers_the_env_without_the_physics():
    code = (
        "import sys, gymnasium, dressbench; "
        "print(dressbench.ENV_ID in gymnasium.registry, "
        "sorted({'warp', 'dartpy', 'torch'} & set(sys.modules)))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "[]"]


def test_gymnasium_make_builds_the_human_env_for_a_robot():
    env = gymnasium.make("dressbench/Dressing-v0", robot="front_linear", **TINY)
    observation, _ = env.reset(seed=0)
    assert observation.shape == (163,) and env.unwrapped.env.robot_name == "front_linear"
    for _ in range(TINY["horizon"]):
        *_, terminated, truncated, _ = env.step(np.zeros(11, dtype=np.float32))
    assert truncated or terminated
    env.close()


def test_parallel_env_is_the_pettingzoo_env():
    env = dressbench.parallel_env("fixed", **TINY)
    assert isinstance(env, ParallelEnv) and env.possible_agents == ["robot", "human"]
    observations, _ = env.reset(seed=0)
    assert set(observations) == {"robot", "human"}
    env.close()


def test_plugin_listing_is_aligned_for_long_names():
    rows = [("group", "name", "status"), ("human", "a" * 40, "ok"), ("robot", "b", "BROKEN: x")]
    lines = aligned(rows)
    assert len({line.index(row[2]) for line, row in zip(lines, rows, strict=True)}) == 1
    result = CliRunner().invoke(main, ["plugins"])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    status = lines[0].index("status")
    assert all(line[status - 2 : status] == "  " for line in lines[1:])
    assert {line[status:].split()[0] for line in lines[1:]} <= {"ok", "BROKEN:", "FAILS"}


@pytest.mark.parametrize("name", ["scripted", "passive"])
def test_load_policy_of_a_plugin_name_says_it_is_a_plugin(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(PolicyFileError) as error:
        dressbench.load_policy(name)
    message = str(error.value)
    assert "human plugin name" in message and f"load_human({name!r})" in message
    assert len(message.splitlines()) == 1


def test_load_policy_of_a_missing_path_keeps_its_error(tmp_path):
    with pytest.raises(PolicyFileError, match="missing"):
        dressbench.load_policy(tmp_path / "nothing")
    with pytest.raises(PolicyFileError, match="missing"):
        dressbench.load_policy("no_such_policy_or_plugin")


ROOT = Path(__file__).resolve().parent.parent
DEVELOPMENT_HISTORY = re.compile(r"\b(?:session|issue)\s+[0-9]+", re.IGNORECASE)  # across lines too


def _user_facing_files():
    yield ROOT / "README.md"
    yield from sorted((ROOT / "docs").rglob("*.md"))
    for folder in ("dressbench", "tests", "scripts"):
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix in {".py", ".md", ".sh", ".toml", ".cfg", ".txt"} and path.is_file():
                yield path


def test_docs_and_code_cite_no_sessions_or_issues():
    """The docs speak to users: what dressbench does and what it measured, never which working
    session or issue it came from (the dated experiments in docs/experiments/ keep dates)."""
    found = []
    for path in _user_facing_files():
        name = path.relative_to(ROOT).as_posix()
        text = path.read_text(encoding="utf-8")
        for match in DEVELOPMENT_HISTORY.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            found.append(f"{name}:{number}: {' '.join(match.group().split())}")
    assert not found, "\n".join(found)


MARKDOWN_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def _anchors(markdown: str) -> set[str]:
    """GitHub's anchors of a Markdown file's headings (lowercase, punctuation dropped, spaces
    to hyphens; a repeated heading gets -1, -2, ...)."""
    anchors, seen = set(), {}
    for line in _outside_code(markdown):
        if line.startswith("#"):
            text = line.lstrip("#").strip().lower()
            slug = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
            count = seen.get(slug, 0)
            seen[slug] = count + 1
            anchors.add(slug if count == 0 else f"{slug}-{count}")
    return anchors


def _outside_code(markdown: str):
    fenced = False
    for line in markdown.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            yield line


def test_every_relative_link_in_the_docs_resolves():
    """Every relative link and image in README.md and docs/**/*.md names a file that exists,
    and a #fragment into a Markdown file names one of its headings."""
    broken = []
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        text = doc.read_text(encoding="utf-8")
        for line in _outside_code(text):
            for target in MARKDOWN_LINK.findall(line):
                if re.match(r"[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                    continue
                path, _, fragment = target.partition("#")
                resolved = (doc.parent / path).resolve() if path else doc
                where = f"{doc.relative_to(ROOT).as_posix()}: {target}"
                if not resolved.exists():
                    broken.append(f"{where} (no such file)")
                elif fragment and resolved.suffix == ".md":
                    if fragment not in _anchors(resolved.read_text(encoding="utf-8")):
                        broken.append(f"{where} (no such heading)")
    assert not broken, "\n".join(broken)
