#!/usr/bin/env bash
# Regenerates the README's two pictures from the shipped humans:
#   docs/images/rollout.png  the last frame of a shipped human's rollout (`dressbench render`)
#   docs/images/report.png   a headless-Chromium screenshot of results/quick/report/index.html
# Run from the repository's root after `bash scripts/setup.sh` (which writes the report).
# Override the rollout with ROBOT, HUMAN and SEED; the browser with CHROMIUM.
set -euo pipefail

ROBOT="${ROBOT:-front_linear}"
HUMAN="${HUMAN:-front_linear-default-s0}"
SEED="${SEED:-3685993406}"  # episode 3 of its leaderboard cell (results/episodes.csv): 0.661 m
CHROMIUM="${CHROMIUM:-chromium}"
PY="${PY:-.venv/bin/python}"
DRESSBENCH="${DRESSBENCH:-.venv/bin/dressbench}"
REPORT="results/quick/report/index.html"

cd "$(dirname "$0")/.."
mkdir -p docs/images
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# 1. The rollout: render it as a GIF, keep its last frame (the arm where the episode ends).
"$DRESSBENCH" render --robot "$ROBOT" --human "$HUMAN" --seed "$SEED" --out "$tmp/rollout.gif"
"$PY" - "$tmp/rollout.gif" docs/images/rollout.png <<'PYEOF'
import sys
from PIL import Image

gif, png = sys.argv[1], sys.argv[2]
with Image.open(gif) as im:
    im.seek(im.n_frames - 1)
    im.convert("RGB").save(png)
print(f"wrote {png}")
PYEOF

# 2. The report: a screenshot of the small leaderboard's page.
if [ ! -f "$REPORT" ]; then
    echo "no $REPORT: run 'bash scripts/setup.sh' (or 'dressbench evaluate leaderboard --episodes 5 --out results/quick --report') first" >&2
    exit 1
fi
"$CHROMIUM" --headless --no-sandbox --disable-gpu --hide-scrollbars \
    --screenshot="$PWD/docs/images/report.png" --window-size=1280,900 "file://$PWD/$REPORT"
echo "wrote docs/images/report.png"
