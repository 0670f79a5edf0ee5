#!/usr/bin/env bash
# Set up dressbench in ./.venv on a fresh machine, then run the main job on small defaults
# (a leaderboard of 5 episodes a cell, and its report: results/quick/report/index.html).
#   bash scripts/setup.sh            # install + main job
#   bash scripts/setup.sh --no-run   # install only (what CI does)
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
[ -x .venv/bin/python ] || "$PYTHON" -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
# The CPU build of torch first, so that nothing else pulls a multi-gigabyte CUDA build: from
# wherever pip is set up to find it, or from TORCH_INDEX_URL (e.g. PyTorch's CPU index) if set.
.venv/bin/python -m pip install -q ${TORCH_INDEX_URL:+--index-url "$TORCH_INDEX_URL"} torch==2.13.0
.venv/bin/python -m pip install -q -e ".[dev,train,ray,compare]"
# The example third-party plugin package (plugins/), installed as a user would install theirs
.venv/bin/python -m pip install -q -e plugins/dressbench-arc
if [ "${1:-}" != "--no-run" ]; then
    # the main job: a small leaderboard, then its web page (a video per cell); paths printed
    .venv/bin/dressbench evaluate leaderboard --episodes 5 --out results/quick --report
fi
