"""The wheel a user installs: it carries the trained humans and needs no torch to use them.

The wheel is built from this checkout (``pip wheel . --no-deps``, no build isolation: nothing is
downloaded) and installed into a fresh venv whose other packages are this venv's, minus torch,
stable-baselines3, sb3-contrib, tensorboard and dressbench itself (a ``.pth`` names a folder
of links to the rest). Then, from a folder outside the checkout, ``dressbench plugins`` lists
the shipped human and a one-episode, short evaluation of it runs without importing torch.
"""

import importlib.util
import json
import os
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
ITS_ROBOT = "front_linear"
SHIPPED = next((ROOT / "dressbench" / "policies").glob(f"{ITS_ROBOT}-*.json")).stem  # its human
# What the wheel must work without (the ``train`` extra), and what comes from the wheel itself.
LEFT_OUT = ("torch", "functorch", "torchgen", "stable_baselines3", "sb3_contrib", "tensorboard",
            "dressbench", "__editable__", "_dressbench", "tests")  # fmt: skip


def _run(args, **kwargs) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("DRESSBENCH_POLICIES", "PYTHONPATH")}
    run = subprocess.run(args, capture_output=True, text=True, timeout=600, env=env, **kwargs)
    assert run.returncode == 0, f"{args}\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    return run


@pytest.fixture(scope="module")
def user_venv(tmp_path_factory) -> Path:
    """A fresh venv with the wheel installed and no torch."""
    root = tmp_path_factory.mktemp("wheel")
    # without build isolation when setuptools is here (Python < 3.12 venvs have it): no download
    isolation = [] if importlib.util.find_spec("setuptools") is None else ["--no-build-isolation"]
    _run([sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", *isolation, "-q",
          "-w", str(root / "dist")])  # fmt: skip
    (wheel,) = (root / "dist").glob("dressbench-*.whl")
    deps = root / "deps"
    deps.mkdir()
    here = Path(sysconfig.get_paths()["purelib"])
    for entry in here.iterdir():
        lowered = entry.name.lower().replace("-", "_")
        if not lowered.startswith(tuple(name.lower() for name in LEFT_OUT)) and not (
            entry.suffix == ".pth" and "dressbench" in lowered
        ):
            (deps / entry.name).symlink_to(entry)
    user = root / "venv"
    venv.create(user, with_pip=False, symlinks=True)
    python = user / "bin" / "python"
    purelib = _run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"])
    Path(purelib.stdout.strip(), "deps.pth").write_text(f"{deps}\n")
    # pip resolves the wheel's dependencies from what is installed: nothing is downloaded
    _run([sys.executable, "-m", "pip", "--python", str(python), "install", "-q", "--no-index",
          str(wheel)])  # fmt: skip
    return user


def test_the_wheel_ships_the_trained_humans_and_evaluates_them_without_torch(user_venv, tmp_path):
    bin_ = user_venv / "bin"
    where = tmp_path / "elsewhere"  # outside the checkout: no ./policies, no source tree
    where.mkdir()
    no_torch = subprocess.run([str(bin_ / "python"), "-c", "import torch"], capture_output=True)
    assert no_torch.returncode != 0  # the point: the wheel works without torch

    listing = _run([str(bin_ / "dressbench"), "plugins"], cwd=where).stdout
    line = next(row for row in listing.splitlines() if f" {SHIPPED} " in row)
    assert line.rstrip().endswith("ok") and "site-packages" in line, listing
    assert str(ROOT) not in listing
    profiles = {row.split()[1] for row in listing.splitlines() if row.startswith("profile ")}
    assert {"typical", "limited_shoulder", "weak_arm", "tremor"} <= profiles, listing

    code = (
        "import json, sys\n"
        "from dressbench.evaluation import evaluate\n"
        "if __name__ == '__main__':\n"
        f"    table = evaluate({ITS_ROBOT!r}, {SHIPPED!r}, episodes=1, workers=1, out='out',\n"
        "                     progress=False, horizon=5, gown_vertices=300)\n"
        "    heavy = sorted({'torch', 'stable_baselines3', 'sb3_contrib', 'tensorboard'}\n"
        "                   & set(sys.modules))\n"
        "    print(json.dumps({'episodes': len(table), 'heavy': heavy}))\n"
    )
    (where / "score.py").write_text(code)
    out = _run([str(bin_ / "python"), "score.py"], cwd=where).stdout.strip().splitlines()[-1]
    assert json.loads(out) == {"episodes": 1, "heavy": []}
    board = pd.read_csv(where / "out" / "leaderboard.csv")
    assert list(board["human"]) == [SHIPPED] and list(board["episodes"]) == [1]

    train = subprocess.run([str(bin_ / "dressbench"), "train"], cwd=where, capture_output=True,
                           text=True)  # fmt: skip
    assert train.returncode == 1 and "pip install 'dressbench[train]'" in train.stderr
