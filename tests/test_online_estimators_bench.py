"""``ship-env identify-bench``: the table, the plots and the JSON; bad arguments are named."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ship_env.cli import main

BENCHMARK = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_identification.py"


@pytest.mark.slow
def test_identify_bench_prints_the_table_and_writes_plots_and_json(tmp_path, capsys):
    plots, results = tmp_path / "plots", tmp_path / "bench.json"
    status = main(
        [
            "identify-bench",
            "--scenarios",
            "zigzag,perera-violent",
            "--scale",
            "0.1",
            "--no-adaptation",
            "--plot",
            str(plots),
            "--json",
            str(results),
        ]
    )
    out = capsys.readouterr().out
    print(out)
    assert status == 0
    for estimator in (
        "Nguyen RLS",
        "MRAS combined",
        "Song EKF",
        "Passenier EKF",
        "Perera EKF",
        "Perera EKF as printed",
    ):
        assert estimator in out
    assert "J_p" in out and "us/step" in out  # a table wider than the terminal wraps its header (text_table)
    assert sorted(path.name for path in plots.iterdir()) == ["perera-violent.png", "zigzag.png"]
    document = json.loads(results.read_text())
    assert len(document["runs"]) == 6 and document["adaptation"] == []
    zigzag = [run for run in document["runs"] if run["scenario"] == "zigzag"]
    assert all(run["failure"] is None and run["microseconds_per_step"] > 0.0 for run in zigzag)
    assert set(zigzag[0]["final_relative_error"]) == {"K*", "tau*"}


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--scenarios", "zigzag,circle"], "argument --scenarios: unknown scenario 'circle'"),
        (["--scale", "0"], "argument --scale: expected a factor between 0.05 and 10"),
    ],
)
def test_bad_arguments_are_named(arguments, message, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["identify-bench", *arguments])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_the_whole_bench_with_the_adaptation_comparison(tmp_path, capsys):
    assert main(["identify-bench", "--plot", str(tmp_path), "--scale", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "stelling 5" in out
    assert (tmp_path / "adaptation.png").is_file()


def test_cost_benchmark_runs_with_tiny_logs(load_script):
    bench = load_script(BENCHMARK, "bench_identification")
    results = bench.run(repeats=1, scale=0.05)
    assert set(results["costs"]) == {"zigzag", "perera-violent"}
    assert all(cost["best"] > 0.0 for costs in results["costs"].values() for cost in costs.values())
    assert "us/step" in bench.format_report(results, "cmd")
    json.dumps(results)
