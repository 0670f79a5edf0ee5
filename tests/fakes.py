"""Fake plugin distributions for the tests: metadata, entry points and modules in a folder."""

from pathlib import Path

# A minimal human plugin module: the zero action, generic, complete observation.
HUMAN_MODULE = """
import numpy as np

class Human:
    api_version = 1
    robot = None
    ablation = "complete"

    def reset(self, seed=None):
        pass

    def act(self, observation):
        return np.zeros(11)
"""


def install(
    root: Path, package: str, version: str, entry_points: dict[str, dict[str, str]], **modules: str
) -> None:
    """Write a fake distribution: metadata, ``entry_points.txt`` and top-level modules."""
    info = root / f"{package.replace('-', '_')}-{version}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {package}\nVersion: {version}\n")
    sections = [
        "\n".join([section, *(f"{name} = {value}" for name, value in eps.items())])
        for section, eps in entry_points.items()
    ]
    (info / "entry_points.txt").write_text("\n\n".join(sections) + "\n")
    for module, source in modules.items():
        (root / f"{module}.py").write_text(source)
