"""The layers of docs/architecture.md run one way: import-linter's contract in pyproject.toml
holds for the package, and breaks when a lower layer imports a higher one."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def lint_imports(root: Path) -> subprocess.CompletedProcess:
    """Run import-linter on the ``dressbench`` package under ``root`` (the project's contract)."""
    env = os.environ | {"PYTHONPATH": str(root)}
    command = [sys.executable, "-c", "from importlinter.cli import lint_imports_command as c; c()"]
    command += ["--config", str(ROOT / "pyproject.toml"), "--no-cache"]
    return subprocess.run(command, cwd=root, env=env, capture_output=True, text=True, timeout=300)


def test_the_layers_run_one_way():
    result = lint_imports(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 kept, 0 broken" in result.stdout


def test_an_import_from_the_physics_up_to_the_cli_breaks_the_contract(tmp_path):
    shutil.copytree(ROOT / "dressbench", tmp_path / "dressbench",
                    ignore=shutil.ignore_patterns("__pycache__", "policies"))  # fmt: skip
    world = tmp_path / "dressbench" / "scene" / "world.py"
    world.write_text(world.read_text() + "\n\ndef _upward():\n    from ..cli import main\n")
    result = lint_imports(tmp_path)
    assert result.returncode != 0
    assert "dressbench.scene is not allowed to import dressbench.cli" in result.stdout
