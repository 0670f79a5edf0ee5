"""The layers of docs/architecture.md run one way: import-linter's contract in pyproject.toml
holds for the package, and breaks when a lower layer imports a higher one."""

from __future__ import annotations

import ast
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


# --- the plugin contract is checked in one module ----------------------------------------------

CONTRACT = Path("plugins") / "contract.py"
CONTRACT_WORDS = ("pose", "action", "quaternion", "api", "interface", "declar", "actuation",
                  "ablation", "pairing", "limits", "involuntary")  # fmt: skip


def contract_checks_outside(package: Path) -> list[str]:
    """Where a module of ``package`` other than plugins/contract.py checks the plugin contract
    itself: a ``*_problem`` function of a pose, an action, an api_version, an interface or a
    declaration; a quaternion's norm (``norm(x[3:])``); or one of the contract's messages."""
    contract = ast.parse((package / CONTRACT).read_text())
    messages = {
        part.value
        for node in ast.walk(contract)
        if isinstance(node, ast.JoinedStr)
        for part in node.values
        if isinstance(part, ast.Constant) and len(part.value.strip()) >= 20
    }
    found = []
    for path in sorted(package.rglob("*.py")):
        where = path.relative_to(package)
        if where == CONTRACT:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and node.name.endswith("_problem"):
                if any(word in node.name for word in CONTRACT_WORDS):
                    found.append(f"{where}: def {node.name}")
            elif isinstance(node, ast.Call) and _is_quaternion_norm(node):
                found.append(f"{where}:{node.lineno}: a quaternion's norm")
            elif isinstance(node, ast.Constant) and isinstance(node.value, str):
                found += [f"{where}:{node.lineno}: {m!r}" for m in messages if m in node.value]
    return found


def _is_quaternion_norm(call: ast.Call) -> bool:
    """``norm(x[3:])`` or ``np.linalg.norm(x[3:])``: the norm of a pose's quaternion."""
    name = call.func.attr if isinstance(call.func, ast.Attribute) else getattr(call.func, "id", "")
    if name != "norm" or not call.args or not isinstance(call.args[0], ast.Subscript):
        return False
    index = call.args[0].slice
    return isinstance(index, ast.Slice) and ast.unparse(index) == "3:"


def test_the_plugin_contract_is_checked_only_in_its_module():
    assert contract_checks_outside(ROOT / "dressbench") == []


def test_a_second_check_of_the_contract_would_be_caught(tmp_path):
    shutil.copytree(ROOT / "dressbench", tmp_path / "dressbench",
                    ignore=shutil.ignore_patterns("__pycache__", "policies"))  # fmt: skip
    env = tmp_path / "dressbench" / "env.py"
    env.write_text(env.read_text() + (
        "\n\ndef _pose_problem(pose):\n"
        "    if abs(np.linalg.norm(pose[3:]) - 1.0) > 1e-6:\n"
        "        return 'the quaternion must have unit length'\n"
        "\n\ndef _message(norm):\n"
        "    return f'norm {norm}, expected a unit quaternion (norm 1 +- 0.001)'\n"
    ))  # fmt: skip
    found = contract_checks_outside(tmp_path / "dressbench")
    in_env = [line for line in found if line.startswith("env.py")]
    assert "env.py: def _pose_problem" in in_env
    assert any("a quaternion's norm" in line for line in in_env)
    assert any("expected a unit quaternion" in line for line in in_env)
