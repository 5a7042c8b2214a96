"""Cost of the on-line identification estimators per sample.

    python benchmarks/bench_identification.py [--repeats 3] [--scale 1.0] [--json FILE]

Each estimator runs over the same log, ``repeats`` times; the report gives the best and the median
microseconds per sample (wall time of a run over the log divided by its samples): the Nomoto
estimators on the container ship's 20/20 zig-zag (0.5 s samples), Perera's filter on its
violent-rudder log (0.1 s samples). The comparison of what they find is ``ship-env identify-bench``.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from ship_env.baselines.online_estimators.scenarios import SCENARIOS


def measure(scenario: str, repeats: int, scale: float) -> dict[str, dict[str, float]]:
    """Best and median microseconds per sample of each of ``scenario``'s estimators on its log."""
    trial = SCENARIOS[scenario].make_trial(0, scale)
    results = {}
    for estimator in SCENARIOS[scenario].make_estimators(trial):
        costs = []
        for _ in range(repeats):
            start = time.perf_counter()
            estimator.run(trial.log)
            costs.append((time.perf_counter() - start) / trial.log.samples * 1e6)
        results[estimator.name] = {"best": min(costs), "median": statistics.median(costs), "samples": trial.log.samples}
    return results


def run(repeats: int = 3, scale: float = 1.0) -> dict:
    return {
        "machine": f"{platform.processor() or platform.machine()}, Python {platform.python_version()}",
        "repeats": repeats,
        "costs": {scenario: measure(scenario, repeats, scale) for scenario in ("zigzag", "perera-violent")},
    }


def format_report(results: dict, command: str) -> str:
    lines = [f"$ {command}", f"machine: {results['machine']}; best and median of {results['repeats']} runs", ""]
    lines.append(f"{'log':<16} {'estimator':<44} {'samples':>8} {'best us/step':>13} {'median':>8}")
    for scenario, costs in results["costs"].items():
        for name, cost in costs.items():
            lines.append(f"{scenario:<16} {name:<44} {cost['samples']:>8} {cost['best']:>13.1f} {cost['median']:>8.1f}")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--repeats", type=int, default=3, help="runs per estimator (default: %(default)s)")
    parser.add_argument("--scale", type=float, default=1.0, help="multiply the logs' durations (default: %(default)s)")
    parser.add_argument("--json", type=Path, default=None, help="also write the results as JSON")
    args = parser.parse_args(argv)
    results = run(args.repeats, args.scale)
    print(
        format_report(
            results, "python benchmarks/bench_identification.py " + " ".join(sys.argv[1:] if argv is None else argv)
        )
    )
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
