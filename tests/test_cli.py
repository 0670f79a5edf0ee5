"""The command line is a thin layer over the library."""

import json

from click.testing import CliRunner

from dressbench.cli import main


def test_bench_prints_one_json_object_per_measurement():
    result = CliRunner().invoke(
        main, ["bench", "--vertices", "600", "--steps", "5", "--repeats", "1", "--json"]
    )
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in result.output.splitlines() if line.startswith("{")]
    assert [r["what"] for r in rows] == ["cloth", "scene", "env"]
    for row in rows:
        assert row["vertices"] > 400 and row["steps_per_second"] > 0
        assert not row["sim_failure"]


def test_plugins_lists_every_plugin_with_its_package_and_status():
    result = CliRunner().invoke(main, ["plugins"])
    assert result.exit_code == 0, result.output
    for name in ("fixed", "front_linear", "side_linear", "passive", "random", "scripted"):
        line = next(row for row in result.output.splitlines() if f" {name} " in row)
        assert "dressbench" in line and line.rstrip().endswith("ok")
