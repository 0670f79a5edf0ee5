"""Shared fixtures: a folder on ``sys.path`` for fake plugin distributions, a policies folder
of the test's own, and a guard that no test writes among the shipped policies."""

import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from dressbench import plugins


@pytest.fixture
def site(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A fresh folder on ``sys.path`` for fake distributions; their modules are forgotten after."""
    root = tmp_path / "site"
    root.mkdir()
    monkeypatch.syspath_prepend(str(root))
    plugins.refresh()
    yield root
    for name, module in list(sys.modules.items()):
        if str(getattr(module, "__file__", None) or "").startswith(str(root)):
            del sys.modules[name]
    plugins.refresh()


@pytest.fixture
def policies_on_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Make the registry look for trained models in this test's ``policies`` folder only."""
    (tmp_path / "policies").mkdir(exist_ok=True)
    monkeypatch.setenv("DRESSBENCH_POLICIES", str(tmp_path / "policies"))
    plugins.refresh()
    yield
    monkeypatch.delenv("DRESSBENCH_POLICIES")
    plugins.refresh()


SHIPPED = Path(__file__).resolve().parents[1] / "dressbench" / "policies"


@pytest.fixture(autouse=True)
def shipped_policies_untouched() -> Iterator[None]:
    """No test leaves a model among the shipped humans (or takes one away)."""
    before = sorted(path.name for path in SHIPPED.iterdir())
    yield
    after = sorted(path.name for path in SHIPPED.iterdir())
    assert after == before, "a test changed dressbench/policies/"
