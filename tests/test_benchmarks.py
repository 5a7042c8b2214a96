"""The benchmark scripts run with tiny counts, so that they cannot rot."""

from __future__ import annotations

import json
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_simulator.py"


def test_benchmark_functions_run_with_tiny_counts(monkeypatch, load_script):
    bench = load_script(BENCH, "bench_simulator")
    results = bench.run(
        sizes=(1, 8),
        single_steps=40,
        batch_budget=32,
        repeats=1,
        mmg_steps=2,
        profile_ships=8,
    )
    for name in ("full", "minimal"):
        assert results["single"][name]["median"] > 0.0
        assert set(results["batch"][name]) == {"1", "8"}
        assert all(r["median"] > 0.0 for r in results["batch"][name].values())
    assert [row["variant"] for row in results["profile"]["rows"]] == [v[0] for v in bench.PROFILE_VARIANTS]
    assert "targets" not in results  # no absolute verdict: a shared machine cannot judge one
    if results["shipmmg"] is not None:
        assert results["shipmmg"]["median"] > 0.0
        assert results["ratio_ours_to_shipmmg"]["full"] > 0.0
    report = bench.format_report(results, "python benchmarks/bench_simulator.py --tiny")
    assert "single ship, Simulator.step(float)" in report and "FAIL" not in report and "PASS" not in report
    if results["shipmmg"] is not None:
        assert "ours / shipmmg" in report
    json.dumps(results)  # the --json output is plain JSON

    # Without shipmmg the comparison is skipped, saying how to install it.
    monkeypatch.setattr(bench, "shipmmg_rate", lambda *args, **kwargs: None)
    results = bench.run(sizes=(2,), single_steps=10, batch_budget=8, repeats=1, with_profile=False)
    assert results["shipmmg"] is None
    assert 'pip install -e ".[bench]"' in bench.format_report(results, "cmd")


def test_env_benchmark_step_parts_run_with_tiny_counts(load_script):
    bench = load_script(BENCH.with_name("bench_envs.py"), "bench_envs")
    single, vector = bench.single_step_parts(5), bench.vector_step_parts(2)
    for parts in (single, vector):
        assert all(median > 0.0 and mean > 0.0 for median, mean in parts.values())
    assert {"whole step through gym.make's wrappers", "the same, info_keys=()", "info dict"} <= set(single)
