"""Wall time for PPO to beat the best classic baseline on CourseChange, from scratch.

    python benchmarks/bench_training.py [--every 100000] [--max-steps 3000000] [--seed 0] [--out DIR]

Trains PPO with the shipped agent config (``configs/agents/ppo.yaml``, CourseChange-v0) and,
every ``--every`` environment steps, sails the leaderboard's calm CourseChange suite (quick:
15..105 deg both ways, nominal ship) with the policy so far. It stops at the first check where the
policy beats the best classic baseline of that suite the leaderboard's way (lower integrated
heading error, rudder travel at most 1.5 times the baseline's) and prints the wall time: training
alone, and with the checks. Target: under 5 minutes on 2 cores. The machine's load average is
printed with it (the cores may be shared).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from stable_baselines3.common.callbacks import BaseCallback

from ship_env.leaderboard.entrants import Entrant, classic_entrants
from ship_env.leaderboard.sailing import sail_suite
from ship_env.leaderboard.suites import COURSE_CHANGE, NOMINAL, SUITE_SPECS, Suite
from ship_env.leaderboard.tables import Comparison, comparisons, rank
from ship_env.rl.agents import DEFAULT_TORCH_THREADS, load_agent_config
from ship_env.rl.training import train

TARGET_SECONDS = 300.0


def calm_suite() -> Suite:
    """The quick leaderboard's CourseChange calm suite on the nominal ship."""
    name = f"CourseChange calm | {NOMINAL.name}"
    return next(suite for suite in SUITE_SPECS["quick"].suites() if suite.name == name)


class BeatBaselineCheck(BaseCallback):
    """Every ``every`` steps, save the policy, sail the suite with it, and stop training once it wins.

    Args:
        suite: the suite sailed.
        baseline_results: the classic baselines' episodes on it (sailed once, before training).
        every: environment steps between checks.
        folder: where the checkpoints go.
    """

    def __init__(self, suite: Suite, baseline_results: list, every: int, folder: Path) -> None:
        super().__init__()
        self.suite = suite
        self.baseline_results = baseline_results
        self.every = every
        self.folder = folder
        self.next_check = every
        self.check_seconds = 0.0
        self.winner: Comparison | None = None
        self.history: list[tuple[int, Comparison]] = []

    def _on_step(self) -> bool:
        if self.num_timesteps < self.next_check:
            return True
        self.next_check += self.every
        start = time.perf_counter()
        path = self.folder / f"ppo_{self.num_timesteps}.zip"  # a new file per check: entrants cache by path
        self.model.save(path)
        entrant = Entrant("PPO", COURSE_CHANGE, "learned", (path,), (0,))
        table = rank(self.suite, self.baseline_results + sail_suite(entrant, self.suite))
        (comparison,) = comparisons(table)
        self.check_seconds += time.perf_counter() - start
        self.history.append((self.num_timesteps, comparison))
        print(
            f"{self.num_timesteps:>9} steps: integrated heading error x{comparison.score_ratio:.3f}, "
            f"rudder travel x{comparison.travel_ratio:.2f} against {comparison.classic}"
            + ("  -> beats it" if comparison.beats else ""),
            flush=True,
        )
        if comparison.beats:
            self.winner = comparison
        return not comparison.beats


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("--every", type=int, default=100_000, help="environment steps between checks")
    parser.add_argument("--max-steps", type=int, default=3_000_000, help="give up after this many steps")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="folder for the run (default: a temporary one)")
    args = parser.parse_args()

    suite = calm_suite()
    baseline_results = [
        result for entrant in classic_entrants([COURSE_CHANGE]) for result in sail_suite(entrant, suite)
    ]
    config = load_agent_config("ppo", COURSE_CHANGE)
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or Path(scratch)
        check = BeatBaselineCheck(suite, baseline_results, args.every, out)
        command = f"python benchmarks/bench_training.py --every {args.every} --seed {args.seed}"
        start = time.perf_counter()
        run = train(config, out, command, steps=args.max_steps, seed=args.seed, progress_bar=False, callback=check)
        total = time.perf_counter() - start
    training = total - check.check_seconds
    print(
        f"\nPPO ({config.n_envs} envs, {DEFAULT_TORCH_THREADS} torch thread, seed {args.seed}) on {suite.name}, "
        f"{len(suite.episodes)} course changes; load average {load_before[0]:.1f} before, "
        f"{os.getloadavg()[0]:.1f} after, on {os.cpu_count()} cores"
    )
    if check.winner is None:
        print(f"did not beat the best classic baseline within {run.metadata.timesteps} steps ({total:.0f} s)")
        return
    verdict = "within" if training < TARGET_SECONDS else "over"
    print(
        f"beat {check.winner.classic} after {run.metadata.timesteps} steps: {training:.0f} s of training "
        f"({total:.0f} s with {len(check.history)} checks), {verdict} the {TARGET_SECONDS:.0f}-s target"
    )


if __name__ == "__main__":
    main()
