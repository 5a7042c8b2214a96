"""The free-running benchmark's verdict: a fit on four sea-trial zig-zags of a full-scale tanker, with ``improve``'s
defaults, predicts the 35 deg turning circles and the 10/10 zig-zag it never saw within the issue's bounds
(advance and tactical diameter 5 %, steady rate and speed loss 10 %, first overshoot 2 deg).

The truth is kvlcc2's calm model with its values moved (``benchmarks/bench_free_running.py``). Seed 1 is the
sea trial on which the ladder once took the hull's cross-flow drag for Norrbin's cubic and wrote a preset that
stopped dead in the port turn; the slow set judges all five seeds the benchmark judges.
"""

from __future__ import annotations

from pathlib import Path

import pytest

BENCH = Path(__file__).parents[1] / "benchmarks" / "bench_free_running.py"


def _judged(load_script, seed: int, folder: Path):
    bench = load_script(BENCH, "bench_free_running")
    return bench.judge(seed, folder)


def test_a_fit_on_sea_trial_zigzags_predicts_the_turning_circle(load_script, tmp_path):
    verdict = _judged(load_script, 1, tmp_path)
    assert verdict.cannot_turn == "" and verdict.failed == 0, verdict.rows


@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 3, 4, 5])
def test_every_sea_trial_of_the_benchmark_predicts_the_turning_circle(load_script, tmp_path, seed):
    verdict = _judged(load_script, seed, tmp_path)
    assert verdict.cannot_turn == "" and verdict.failed == 0, verdict.rows
