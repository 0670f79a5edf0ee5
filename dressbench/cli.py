"""The ``dressbench`` command line: thin wrappers over the library API."""

from __future__ import annotations

import json

import click


@click.group()
@click.version_option(package_name="dressbench")
def main() -> None:
    """dressbench: a benchmark suite for robot-assisted dressing."""


@main.command()
@click.option("--vertices", "-v", multiple=True, type=int, help="Gown resolutions (repeatable).")
@click.option("--steps", default=200, show_default=True, help="Policy steps timed per row.")
@click.option("--repeats", default=3, show_default=True, help="Timed runs; the fastest counts.")
@click.option("--quick", is_flag=True, help="Only the default resolution, 100 steps.")
@click.option("--device", default="cpu", show_default=True, help="Warp device for the cloth.")
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
def bench(
    vertices: tuple[int, ...], steps: int, repeats: int, quick: bool, device: str, as_json: bool
) -> None:
    """Time the cloth alone, the whole scene step and the env step (one process, one core)."""
    from .bench import bench_scene

    sizes = vertices or ((2000,) if quick else (1000, 2000, 4000))
    steps = 100 if quick else steps
    if not as_json:
        click.echo(f"{'vertices':>8} {'what':>6} {'steps/s':>9} {'ms/step':>9}")
    for n in sizes:
        for row in bench_scene(n, steps, device, repeats):
            if as_json:
                click.echo(json.dumps(row))
            else:
                flag = "  (sim failure)" if row["sim_failure"] else ""
                click.echo(
                    f"{row['vertices']:>8} {row['what']:>6} {row['steps_per_second']:>9.1f}"
                    f" {row['ms_per_step']:>9.3f}{flag}"
                )


@main.command()
def plugins() -> None:
    """List every robot strategy and human policy plugin, with its package and status."""
    from .plugins import all_plugins

    rows = all_plugins()
    click.echo(f"{'group':<7} {'name':<16} {'package':<22} {'version':<9} status")
    for p in rows:
        group = "robot" if p.group.endswith("robots") else "human"
        status = "ok" if p.ok else f"BROKEN: {p.error}"
        click.echo(f"{group:<7} {p.name:<16} {p.package:<22} {p.version:<9} {status}")
