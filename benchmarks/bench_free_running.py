"""A fit on zig-zags predicts the turning circle it never saw: a full-scale ship with sea-trial sensors.

The truth is the ``kvlcc2`` preset's calm-water model (yaw, Norrbin, asymmetry, speed loss, sway, steering
machine) with its values moved (``TRUTH_FACTORS``), so that the workbench, which starts from the preset,
starts away from the truth. The truth sails four zig-zags (10/10 and 20/20 to both sides) at its service
speed, logged by sea-trial sensors (``SEA_TRIAL_NOISE``: 0.5 deg compass, 3 m GPS, 1 Hz); then, as a user
would and with the defaults:

    ship-env improve LOGS/zigzag --ship kvlcc2 --preset fitted.yaml

and the fitted preset sails the IMO manoeuvres (``ship_env.manoeuvres``) against the truth: the 35 deg
turning circle to both sides (advance and tactical diameter within 5 %, steady rate of turn and speed loss
within 10 %) and the 10/10 zig-zag (first overshoot within 2 deg). Prints one table with PASS or FAIL per
figure and the time the fit took, for each of five sea trials (the sensors' noise drawn from another seed)
and how many pass every bound.

Run:  python benchmarks/bench_free_running.py [--keep DIR] [--seeds N ...] [--truth PRESET]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ship_env.cli import main
from ship_env.manoeuvres import turning_circle, zigzag
from ship_env.model import ShipModel
from ship_env.text_table import Table
from ship_env.workbench.free_running import JUDGED_FIGURES
from ship_env.workbench.logs import write_log
from ship_env.workbench.replay import ReplayModel
from ship_env.workbench.synthetic import SEA_TRIAL_NOISE, LogSettings, Manoeuvre, sail_all

SHIP = "kvlcc2"
#: The truth's effects: the preset's calm-water model.
TRUTH_EFFECTS = ("yaw", "asymmetry", "norrbin", "speed_loss", "sway", "steering_machine", "kinematics")
#: The truth's values: the preset's times these factors.
TRUTH_FACTORS = {
    "yaw.gain": 1.15,
    "yaw.time_constant": 0.85,
    "norrbin.cubic": 0.7,
    "speed_loss.gain": 0.8,
    "sway.linear": 1.2,
}
#: The zig-zags logged: (name, rudder a in deg, heading change b in deg), a negative a to port.
ZIGZAGS = (
    ("zigzag_10_stbd", 10, 10),
    ("zigzag_10_port", -10, 10),
    ("zigzag_20_stbd", 20, 20),
    ("zigzag_20_port", -20, 20),
)
#: The sensor noise's seeds: each a sea trial of the same ship.
SEEDS = (1, 2, 3, 4, 5)
#: Each zig-zag's length in ship lengths sailed (five executes of a 10/10 take about 20).
ZIGZAG_LENGTHS = 30.0
#: The judged figures: the name printed and the free-running figure whose bound (relative, a fraction, or in
#: deg) the workbench judges a prediction by (``free_running.JUDGED_FIGURES``).
JUDGED = (
    ("advance", "advance_lengths"),
    ("tactical diameter", "tactical_diameter_lengths"),
    ("steady rate of turn", "steady_rate_of_turn"),
    ("speed loss", "speed_loss"),
    ("first overshoot 10/10", "first_overshoot"),
)
#: (figure, bound, relative) of each judged figure.
CRITERIA = tuple((name, *JUDGED_FIGURES[key][:2]) for name, key in JUDGED)


def truth_model(ship: str = SHIP) -> ShipModel:
    preset = ShipModel(ship, TRUTH_EFFECTS)
    return preset.with_parameters({key: factor * preset.parameter(key) for key, factor in TRUTH_FACTORS.items()})


def write_zigzag_logs(truth: ShipModel, folder: Path, seed: int) -> None:
    speed = truth.service_speed
    unit = truth.length / speed
    runs = [
        Manoeuvre(name, "zigzag", math.radians(a), ZIGZAG_LENGTHS * unit, approach=2.0 * unit,
                  zigzag_angle=math.radians(b), start_speed=speed, final_speed=speed, wind_speed=0.0)
        for name, a, b in ZIGZAGS
    ]  # fmt: skip
    settings = LogSettings(dt=1.0, noise=SEA_TRIAL_NOISE)
    folder.mkdir(parents=True)
    for log in sail_all(ReplayModel(truth), runs, seed=seed, settings=settings):
        write_log(log, folder / f"{log.name}.csv")


def figures(model: ShipModel) -> dict[str, float]:
    """The judged figures: both turning circles' means (the truth is not symmetric), the 10/10's overshoot."""
    circles = [turning_circle(model, math.radians(angle)) for angle in (35.0, -35.0)]

    def mean(name: str) -> float:
        return sum(getattr(c, name) for c in circles) / len(circles)

    return {
        "advance": mean("advance") / model.length,
        "tactical diameter": mean("tactical_diameter") / model.length,
        "steady rate of turn": math.degrees(mean("steady_rate_of_turn")),
        "speed loss": 100.0 * mean("speed_loss"),
        "first overshoot 10/10": math.degrees(zigzag(model, math.radians(10.0), math.radians(10.0)).first_overshoot),
    }


@dataclass(frozen=True)
class Verdict:
    """One seed's fit: the seconds it took, the figures' rows (truth, fitted, error, bound, PASS/FAIL) and how
    many failed (every figure fails where the fitted preset cannot sail the turn: ``cannot_turn`` says why)."""

    seed: int
    seconds: float
    rows: tuple[tuple[str, ...], ...]
    failed: int
    cannot_turn: str = ""


def judge(seed: int, folder: Path, ship: str = SHIP) -> Verdict:
    """Sail the truth's zig-zags with this seed's sensor noise, fit them with ``improve``'s defaults, and judge the
    fitted preset's manoeuvres against the truth's."""
    truth = truth_model(ship)
    write_zigzag_logs(truth, folder / "zigzag", seed)
    preset = folder / "fitted.yaml"
    start = time.perf_counter()
    command = ["improve", str(folder / "zigzag"), "--ship", ship, "--preset", str(preset)]
    status = main([*command, "--report", str(folder / "report")])
    seconds = time.perf_counter() - start
    if status != 0:
        raise RuntimeError(f"ship-env {' '.join(command)} failed ({status})")
    expected = figures(truth)
    try:
        predicted = figures(ShipModel(preset))
    except FloatingPointError as error:  # the fitted ship left its model's validity in the turn
        return Verdict(seed, seconds, (), len(CRITERIA), str(error))
    rows = []
    for name, bound, relative in CRITERIA:
        error = predicted[name] - expected[name]
        judged = abs(error) / abs(expected[name]) if relative else abs(error)
        verdict = "PASS" if judged <= bound else "FAIL"
        limit = f"{100 * bound:g} %" if relative else f"{bound:g} deg"
        shown = f"{100 * error / expected[name]:+.1f} %" if relative else f"{error:+.2f} deg"
        rows.append((name, f"{expected[name]:.3f}", f"{predicted[name]:.3f}", shown, limit, verdict))
    return Verdict(seed, seconds, tuple(rows), sum(row[-1] == "FAIL" for row in rows))


def main_benchmark(keep: Path | None, seeds: Sequence[int], ship: str = SHIP) -> int:
    folder = Path(tempfile.mkdtemp(prefix="free_running_")) if keep is None else keep
    verdicts = [judge(seed, folder / f"seed_{seed}", ship) for seed in seeds]
    header = ("figure (mean of 35 deg stbd and port)", "truth", "fitted preset", "error", "within", "")
    for verdict in verdicts:
        print(f"\nseed {verdict.seed}: the fit on {len(ZIGZAGS)} zig-zags ({ship}, sea-trial sensors) took "
              f"{verdict.seconds:.0f} s; logs, report and preset in {folder / f'seed_{verdict.seed}'}")  # fmt: skip
        print(
            f"the fitted preset cannot turn: {verdict.cannot_turn}"
            if verdict.cannot_turn
            else Table(header, verdict.rows).text()
        )
    passed = sum(verdict.failed == 0 for verdict in verdicts)
    print(f"\n{passed} of {len(verdicts)} seeds within every bound")
    return 0 if passed == len(verdicts) else 1


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--keep", type=Path, default=None, help="write each seed's logs, report and preset here")
    parser.add_argument(
        "--seeds", type=int, nargs="+", default=list(SEEDS), help="the sensor-noise seeds (default: %(default)s)"
    )
    parser.add_argument("--truth", default=SHIP, help="the preset the truth is made from (default: %(default)s)")
    arguments = parser.parse_args()
    raise SystemExit(main_benchmark(arguments.keep, arguments.seeds, arguments.truth))
