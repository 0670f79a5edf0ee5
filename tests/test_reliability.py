"""Issue 15: a bad plugin, policy, option or path ends in one clear line, before work starts.

Plugins are fake distributions in a fresh folder on ``sys.path`` (as in
tests/test_plugins_registry.py); episodes are tiny (horizon 3-5, a 300-vertex gown).
"""

import os
import stat

import pytest

from dressbench.evaluation import io as atomic


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_evaluation_files_follow_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        atomic.write_text(tmp_path / "leaderboard.md", "| a |\n")
    finally:
        os.umask(old)
    mode = stat.S_IMODE((tmp_path / "leaderboard.md").stat().st_mode)
    assert mode == 0o666 & ~umask
    assert [p.name for p in tmp_path.iterdir()] == ["leaderboard.md"]  # no temp left
