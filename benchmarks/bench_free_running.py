"""A fit on zig-zags predicts the turning circle it never saw: a full-scale ship with sea-trial sensors, or a model
in a basin.

The truth is one of three ships:

- ``--truth kvlcc2`` (the default; or another preset): the preset's calm-water model (yaw, Norrbin, asymmetry,
  speed loss, sway, steering machine) with its values moved (``TRUTH_FACTORS``), so that the workbench, which
  starts from the preset, starts away from the truth;
- ``--truth mmg``: shipmmg's MMG model of KVLCC2 (Yasukawa & Yoshimura 2015, Froude-scaled to 320 m;
  ``ship_env.model.mmg_kvlcc2``), a 3-DOF ship whose physics none of the workbench's effects share, its
  propeller at the constant rate that holds 15.5 kn (needs ``pip install shipmmg``);
- ``--truth mmg-basin``: the same MMG ship as the 7 m model it was identified from, sailed as a basin runs its
  free-running tests: thirteen zig-zags from 5/1 to 35/5 (``BASIN_ZIGZAGS``), the propeller at the constant rate
  of the model's self-propulsion point, the basin's sensors (``SensorNoise()``) at 5 Hz, no wind. The workbench
  starts from the ``kvlcc2`` preset scaled to the model as a user would (``ship-env scale kvlcc2 --length 7``).
- ``--truth kvlcc2-basin``: the ``kvlcc2`` truth (values moved) sailing the basin's thirteen zig-zags at full scale,
  with sea-trial sensors: runs to the hard-over rudder of a ship whose form is the workbench's own, where ``fit`` and
  ``improve --preset`` also fit the MMG forces and must keep the effects
  (``ship_env.workbench.judging.dynamics_choice``).

The sea-trial truths sail four zig-zags (10/10 and 20/20 to both sides) at their service speed, logged by
sea-trial sensors (``SEA_TRIAL_NOISE``: 0.5 deg compass, 3 m GPS, 1 Hz); then, as a user would and with the
defaults:

    ship-env improve LOGS/zigzag --ship kvlcc2 --preset fitted.yaml

The truth also sails, without sensor noise, the 35 deg turning circle to both sides and the 10/10 zig-zag;
the workbench's free-running validation (``ship_env.workbench.judging.free_running``) sails the fitted preset through
the same manoeuvres from the same state and reads both sides' figures with the same code: advance and tactical
diameter within 5 %, steady rate of turn and speed loss within 10 % (the means of the two turns), first
overshoot within 2 deg. Prints one table with PASS or FAIL per figure and the time the fit took, for each of five
trials (the sensors' noise drawn from another seed) and how many pass every bound.

``--fit fit-mmg`` fits the MMG standard's 3-DOF forces by inverse dynamics instead (``ship-env fit-mmg LOGS/zigzag
--ship PRESET -o fitted_mmg.yaml``); the fitted model and the truth sail the judged manoeuvres from the same
approach with the same rudder programme, and each side's figures are read from its time series by the same code.
``--zigzag-lengths`` and ``--sample-interval`` log the fitted zig-zags shorter (a basin's length) or at another rate;
``--without rate_of_turn`` (or ``speed``, ``propeller_rate``) leaves channels out of them (a basin without a gyro).
``--validate-on-turns`` logs the two judged turning circles with the same sensors and gives them to ``improve`` as
``--validate-on`` runs, as an engineer with a sea trial's turning circles would; they are never fitted.

Run:  python benchmarks/bench_free_running.py [--keep DIR] [--seeds N ...] [--truth PRESET|mmg|mmg-basin|kvlcc2-basin]
          [--fit improve|fit-mmg] [--zigzag-lengths L] [--sample-interval S] [--without CHANNEL ...]
          [--validate-on-turns]
"""

from __future__ import annotations

import argparse
import functools
import math
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from ship_env.cli import main
from ship_env.model import ShipModel
from ship_env.model.external import DynamicsSource
from ship_env.text_table import Table
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.judging.free_running import JUDGED_FIGURES, compare_free_running
from ship_env.workbench.logs.logs import Log, write_log
from ship_env.workbench.synthetic.synthetic import SEA_TRIAL_NOISE, LogSettings, Manoeuvre, SensorNoise, sail_all

#: A zig-zag programme: (name, rudder a in deg, heading change b in deg), a negative a to port.
Programme = tuple[tuple[str, float, float], ...]

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
#: The sea trial's zig-zags.
ZIGZAGS: Programme = (
    ("zigzag_10_stbd", 10, 10),
    ("zigzag_10_port", -10, 10),
    ("zigzag_20_stbd", 20, 20),
    ("zigzag_20_port", -20, 20),
)
#: ``--truth mmg-basin``: the MMG KVLCC2 as the 7 m model, a basin's free-running programme.
MMG_BASIN = "mmg-basin"
#: ``--truth kvlcc2-basin``: the kvlcc2 truth sailing the basin's programme at full scale, sea-trial sensors.
NATIVE_BASIN = "kvlcc2-basin"
#: A basin's zig-zags from 5/1 to 35/5: small heading changes at every rudder angle, the standard 10/10 and 20/20
#: to both sides, 35/5 to both sides (thirteen runs).
BASIN_ZIGZAGS: Programme = (
    ("zigzag_05_01", 5, 1),
    ("zigzag_05_05", 5, 5),
    ("zigzag_10_02", 10, 2),
    ("zigzag_10_10_stbd", 10, 10),
    ("zigzag_10_10_port", -10, 10),
    ("zigzag_15_05", 15, 5),
    ("zigzag_20_05", -20, 5),
    ("zigzag_20_20_stbd", 20, 20),
    ("zigzag_20_20_port", -20, 20),
    ("zigzag_25_05", 25, 5),
    ("zigzag_30_05", -30, 5),
    ("zigzag_35_05_stbd", 35, 5),
    ("zigzag_35_05_port", -35, 5),
)
#: The basin's sample interval, s.
BASIN_DT = 0.2
#: The sensor noise's seeds: each a sea trial of the same ship.
SEEDS = (1, 2, 3, 4, 5)
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


#: ``--fit``: the workbench's error ladder (``ship-env improve``, the default) or the MMG standard's forces by
#: inverse dynamics (``ship-env fit-mmg``).
IMPROVE = "improve"
FIT_MMG = "fit-mmg"
#: ``--truth mmg``: shipmmg's MMG KVLCC2, sailed through the external-dynamics protocol; the workbench starts from
#: the ``kvlcc2`` preset.
MMG = "mmg"
#: The judged manoeuvres, sailed by the truth without sensor noise: (name, rudder in deg, heading change b in deg;
#: None for a turning circle).
JUDGED_RUNS = (("turning_35_stbd", 35, None), ("turning_35_port", -35, None), ("zigzag_10_stbd", 10, 10))
#: Each judged turning circle's length in ship lengths sailed at the approach speed (two and more circles).
TURNING_LENGTHS = 60.0
#: The channels ``--without`` may leave out of the fitted logs.
OPTIONAL_CHANNELS = ("rate_of_turn", "speed", "propeller_rate")
#: No sensor noise: the truth's own figures.
EXACT = SensorNoise(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Truth:
    """The ship the logs are sailed by: ``ship`` the preset the workbench starts from, ``model`` the true model
    (an external truth's particulars and rudder limit), ``dynamics`` the external truth (None: ``model``),
    ``propeller_rate`` its constant propeller rate, rps; ``zigzags`` the programme fitted, logged by ``noise``'s
    sensors every ``dt`` seconds, each ``zigzag_lengths`` ship lengths sailed (five executes of a 10/10 take about
    20), ``without`` the channels named (a basin that logs no rate of turn)."""

    ship: str
    model: ShipModel
    dynamics: DynamicsSource | None = None
    propeller_rate: float = Manoeuvre.propeller_rate
    zigzags: Programme = ZIGZAGS
    noise: SensorNoise = SEA_TRIAL_NOISE
    dt: float = 1.0
    zigzag_lengths: float = 30.0
    without: tuple[str, ...] = ()
    validate_on_turns: bool = False


def truth_model(ship: str = SHIP) -> ShipModel:
    preset = ShipModel(ship, TRUTH_EFFECTS)
    return preset.with_parameters({key: factor * preset.parameter(key) for key, factor in TRUTH_FACTORS.items()})


def make_truth(name: str = SHIP, folder: Path | None = None) -> Truth:
    """``--truth``'s ship: a preset with its values moved, :data:`NATIVE_BASIN`, :data:`MMG` or :data:`MMG_BASIN`
    (whose starting preset, ``kvlcc2`` scaled to the model by ``ship-env scale``, is written into ``folder``)."""
    if name in (MMG, MMG_BASIN):
        from ship_env.model.mmg_kvlcc2 import MODEL_LENGTH, MmgKvlcc2, service_propeller_rate

        if name == MMG:
            return Truth("kvlcc2", ShipModel("kvlcc2"), MmgKvlcc2, service_propeller_rate())
        if folder is None:
            raise ValueError(f"--truth {MMG_BASIN}: give the folder its starting preset is written into")
        preset = folder / "kvlcc2_model.yaml"
        if not preset.exists():
            folder.mkdir(parents=True, exist_ok=True)
            main(["scale", "kvlcc2", "--length", f"{MODEL_LENGTH:g}", "-o", str(preset)])
        dynamics = functools.partial(MmgKvlcc2, scale=1.0)  # the 7 m model itself
        rate = service_propeller_rate(1.0)
        return Truth(str(preset), ShipModel(preset), dynamics, rate, BASIN_ZIGZAGS, SensorNoise(), BASIN_DT)
    if name == NATIVE_BASIN:
        return Truth(SHIP, truth_model(SHIP), zigzags=BASIN_ZIGZAGS)
    return Truth(name, truth_model(name))


def sail_truth(
    truth: Truth, runs: Sequence[tuple[str, float, float | None]], lengths: float, seed: int, noise: SensorNoise
) -> list[Log]:
    """The truth's logs of ``runs`` (a zig-zag where b is given, else a turn), each ``lengths`` ship lengths
    long at the service speed after an approach of two, sampled every ``truth.dt`` seconds."""
    speed = truth.model.service_speed
    unit = truth.model.length / speed
    manoeuvres = [
        Manoeuvre(
            name,
            "turn" if b is None else "zigzag",
            math.radians(a),
            lengths * unit,
            approach=2.0 * unit,
            zigzag_angle=math.radians(b or 0.0),
            start_speed=speed,
            final_speed=speed,
            propeller_rate=truth.propeller_rate,
            wind_speed=0.0,
        )
        for name, a, b in runs
    ]
    return sail_all(ReplayModel(truth.model), manoeuvres, seed, LogSettings(dt=truth.dt, noise=noise), truth.dynamics)
    # fmt: skip


def write_logs(
    truth: Truth, runs: Sequence[tuple[str, float, float | None]], lengths: float, folder: Path, seed: int
) -> None:
    """The truth's ``runs`` logged by its sensors (``seed`` their noise), less the channels it leaves out."""
    folder.mkdir(parents=True)
    for log in sail_truth(truth, runs, lengths, seed, truth.noise):
        write_log(replace(log, **dict.fromkeys(truth.without)), folder / f"{log.name}.csv")


def figures(truth_logs: Sequence[Log], model: ShipModel) -> tuple[dict[str, float], dict[str, float], str]:
    """The judged figures, the truth's and ``model``'s sailing the same manoeuvres (free-running validation):
    both turning circles' means (the truth is not symmetric), the 10/10's first overshoot; and why the model
    cannot sail a run ("" where it sails them all)."""
    results = compare_free_running(ReplayModel(model), truth_logs, model.ship.dynamics)  # as the preset sails
    cannot = "; ".join(f"{result.run}: {result.cannot_sail}" for result in results if result.cannot_sail)
    sides = []
    for side in ("measured", "predicted"):
        values: dict[str, list[float]] = {}
        for result in results:
            for figure in getattr(result, side):
                values.setdefault(figure.key, []).append(figure.value)
        sides.append({name: sum(values[key]) / len(values[key]) for name, key in JUDGED})
    return sides[0], sides[1], cannot


@dataclass(frozen=True)
class Verdict:
    """One seed's fit: the seconds it took, the figures' rows (truth, fitted, error, bound, PASS/FAIL) and how
    many failed (every figure fails where the fitted preset cannot sail a manoeuvre: ``cannot_turn`` says why)."""

    seed: int
    seconds: float
    rows: tuple[tuple[str, ...], ...]
    failed: int
    cannot_turn: str = ""


def mmg_figures(truth: Truth, truth_logs: Sequence[Log], fitted: Path) -> tuple[dict[str, float], dict[str, float]]:
    """The judged figures of the truth's runs and of the fitted MMG model (``ship-env fit-mmg``'s file) sailing the
    same manoeuvres from the same approach, each read by the same code from its time series."""
    from ship_env.model.mmg_fitted import MmgFitted, read_mmg
    from ship_env.workbench.judging.free_running import Series, manoeuvre_figures, read_manoeuvre

    predicted_logs = sail_truth(
        replace(truth, dynamics=functools.partial(MmgFitted, read_mmg(fitted))), JUDGED_RUNS, TURNING_LENGTHS, 0, EXACT
    )
    sides = []
    for logs in (truth_logs, predicted_logs):
        values: dict[str, list[float]] = {}
        for log in logs:
            series = Series.of_log(log)
            for figure in manoeuvre_figures(series, read_manoeuvre(series), truth.model.length):
                values.setdefault(figure.key, []).append(figure.value)
        sides.append({name: sum(values[key]) / len(values[key]) for name, key in JUDGED})
    return sides[0], sides[1]


def judge(
    seed: int, folder: Path, truth: Truth | None = None, truth_logs: Sequence[Log] | None = None, fit: str = IMPROVE
) -> Verdict:
    """Sail the truth's zig-zags with this seed's sensor noise, fit them with ``improve``'s defaults (or ``fit-mmg``'s,
    ``fit`` :data:`FIT_MMG`), and judge the fitted ship's manoeuvres against the truth's (``truth_logs``: the judged
    runs, sailed once for every seed)."""
    truth = make_truth() if truth is None else truth
    truth_logs = sail_truth(truth, JUDGED_RUNS, TURNING_LENGTHS, 0, EXACT) if truth_logs is None else truth_logs
    write_logs(truth, truth.zigzags, truth.zigzag_lengths, folder / "zigzag", seed)
    validation: list[str] = []
    if truth.validate_on_turns:  # the judged turns, logged by the same sensors (other noise), never fitted
        write_logs(truth, JUDGED_RUNS[:2], TURNING_LENGTHS, folder / "turning", seed + 1000)
        validation = ["--validate-on", str(folder / "turning")]
    preset = folder / ("fitted.yaml" if fit == IMPROVE else "fitted_mmg.yaml")
    start = time.perf_counter()
    if fit == IMPROVE:
        command = ["improve", str(folder / "zigzag"), "--ship", truth.ship, "--preset", str(preset)]
        command += ["--report", str(folder / "report"), *validation]
    else:
        command = ["fit-mmg", str(folder / "zigzag"), "--ship", truth.ship, "-o", str(preset)]
    status = main(command)
    seconds = time.perf_counter() - start
    if status != 0:
        raise RuntimeError(f"ship-env {' '.join(command)} failed ({status})")
    if fit == FIT_MMG:
        try:
            expected, predicted = mmg_figures(truth, truth_logs, preset)
        except FloatingPointError as error:  # the fitted model left its validity in a judged manoeuvre
            return Verdict(seed, seconds, (), len(CRITERIA), str(error))
        cannot = ""
    else:
        expected, predicted, cannot = figures(truth_logs, ShipModel(preset))
    if cannot:
        return Verdict(seed, seconds, (), len(CRITERIA), cannot)
    rows = []
    for name, bound, relative in CRITERIA:
        error = predicted[name] - expected[name]
        judged = abs(error) / abs(expected[name]) if relative else abs(error)
        verdict = "PASS" if judged <= bound else "FAIL"  # NaN (a figure not reached) fails
        limit = f"{100 * bound:g} %" if relative else f"{bound:g} deg"
        shown = f"{100 * error / expected[name]:+.1f} %" if relative else f"{error:+.2f} deg"
        rows.append((name, f"{expected[name]:.3f}", f"{predicted[name]:.3f}", shown, limit, verdict))
    return Verdict(seed, seconds, tuple(rows), sum(row[-1] == "FAIL" for row in rows))


def main_benchmark(
    keep: Path | None,
    seeds: Sequence[int],
    truth_name: str = SHIP,
    fit: str = IMPROVE,
    zigzag_lengths: float | None = None,
    sample_interval: float | None = None,
    without: Sequence[str] = (),
    validate_on_turns: bool = False,
) -> int:
    folder = Path(tempfile.mkdtemp(prefix="free_running_")) if keep is None else keep
    truth = make_truth(truth_name, folder)
    if zigzag_lengths is not None:
        truth = replace(truth, zigzag_lengths=zigzag_lengths)
    if sample_interval is not None:
        truth = replace(truth, dt=sample_interval)
    truth = replace(truth, without=tuple(without), validate_on_turns=validate_on_turns)
    truth_logs = sail_truth(truth, JUDGED_RUNS, TURNING_LENGTHS, 0, EXACT)
    verdicts = [judge(seed, folder / f"seed_{seed}", truth, truth_logs, fit) for seed in seeds]
    header = ("figure (mean of 35 deg stbd and port)", "truth", "fitted preset", "error", "within", "")
    for verdict in verdicts:
        print(f"\nseed {verdict.seed}: the fit on {len(truth.zigzags)} zig-zags ({truth_name}) took "
              f"{verdict.seconds:.0f} s; logs, report and preset in {folder / f'seed_{verdict.seed}'}")  # fmt: skip
        print(
            f"the fitted preset cannot sail: {verdict.cannot_turn}"
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
    parser.add_argument(
        "--truth",
        default=SHIP,
        help=f"the preset the truth is made from, {MMG!r}, {MMG_BASIN!r} or {NATIVE_BASIN!r} (default: %(default)s)",
    )
    parser.add_argument(
        "--fit",
        choices=(IMPROVE, FIT_MMG),
        default=IMPROVE,
        help="how the zig-zags are fitted: the error ladder (ship-env improve) or the MMG standard's forces by inverse "
        "dynamics (ship-env fit-mmg) (default: %(default)s)",
    )
    parser.add_argument(
        "--zigzag-lengths",
        type=float,
        default=None,
        metavar="L",
        help="each fitted zig-zag's length in ship lengths sailed (default: 30; a basin may hold fewer)",
    )
    parser.add_argument(
        "--sample-interval",
        type=float,
        default=None,
        metavar="S",
        help="the fitted zig-zags' sample interval, s (default: the truth's, 1 at sea and 0.2 in the basin)",
    )
    parser.add_argument(
        "--without",
        nargs="+",
        default=(),
        choices=OPTIONAL_CHANNELS,
        metavar="CHANNEL",
        help=f"channels the fitted logs leave out, of {', '.join(OPTIONAL_CHANNELS)} (default: none)",
    )
    parser.add_argument(
        "--validate-on-turns",
        action="store_true",
        help="log the judged turning circles with the fitted runs' sensors too and give them to improve as "
        "--validate-on runs (never fitted)",
    )
    arguments = parser.parse_args()
    raise SystemExit(
        main_benchmark(
            arguments.keep,
            arguments.seeds,
            arguments.truth,
            arguments.fit,
            arguments.zigzag_lengths,
            arguments.sample_interval,
            arguments.without,
            arguments.validate_on_turns,
        )
    )
