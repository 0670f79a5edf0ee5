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
    assert [r["what"] for r in rows] == ["cloth", "scene"]
    for row in rows:
        assert row["vertices"] > 400 and row["steps_per_second"] > 0
        assert not row["sim_failure"]
