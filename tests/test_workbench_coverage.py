"""Honest extrapolation: a fit's coverage, the runs beyond it, the jackknife bands, and improve's validation rule.

Synthetic logs (``ship_env.workbench.synthetic.synthetic``): zig-zags at small rudder are fitted, turning
circles at 35 deg rudder are the validation runs -- beyond the zig-zags' rudder angle and rate of
turn. The Esso Osaka checks read ``../shared/data/esso_osaka`` and skip without it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from ship_env.cli import main
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import FitOptions, Log, ReplayModel, cross_validate, improve, load_logs, simulate, write_log
from ship_env.workbench.fitting.errors import pooled, run_errors
from ship_env.workbench.judging.bands import jackknife_band, jackknife_bands
from ship_env.workbench.judging.compare import held_out_comparison, plot_run
from ship_env.workbench.judging.coverage import (
    COVERAGE_PERCENTILE,
    Coverage,
    check_coverage,
    coverage_of,
    errors_inside_beyond,
)
from ship_env.workbench.synthetic.synthetic import (
    Manoeuvre,
    SensorNoise,
    hidden_effect_logs,
    noise_scales,
)

#: The Esso Osaka hull with the nominal coefficients these checks were designed on (not the identified preset).
SHIP = str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")
APPROACH = 10.0
DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "esso_osaka"
needs_esso = pytest.mark.skipif(
    not DATA.is_dir(), reason=f"the Esso Osaka data is not at {DATA} (../shared/data/esso_osaka beside the repository)"
)


def zigzags(rudder_deg: float, seed: int = 1, hidden: tuple[str, ...] = ()):
    """Four zig-zags at +-``rudder_deg`` (switching at the same heading change), 50 s each: (truth, logs)."""
    manoeuvres = [
        Manoeuvre(
            f"zigzag_{i}",
            "zigzag",
            math.radians(sign * rudder_deg),
            50.0,
            approach=APPROACH,
            zigzag_angle=math.radians(rudder_deg),
            propeller_rate=rate,
            wind_direction=math.radians(wind_from),
        )
        for i, (sign, rate, wind_from) in enumerate([(1, 12.0, 280), (-1, 10.0, 250), (1, 14.0, 320), (-1, 12.0, 300)])
    ]
    return hidden_effect_logs(list(hidden), SHIP, seed=seed, manoeuvres=manoeuvres)


def turns(seed: int = 7):
    """Turning circles at +-35 deg rudder, 50 s each, sailed by the base model: (truth, logs)."""
    manoeuvres = [
        Manoeuvre(f"turn_{i}", "turn", math.radians(a), 50.0, approach=APPROACH) for i, a in enumerate([35, -35])
    ]
    return hidden_effect_logs([], SHIP, seed=seed, manoeuvres=manoeuvres)


def test_turning_runs_beyond_the_zigzags_are_flagged_with_the_share_and_the_reason():
    truth, fitted = zigzags(10.0)
    _, turning = turns()
    model = truth.model
    coverage = coverage_of(fitted, model)
    assert coverage.ranges["rudder"].high == pytest.approx(math.radians(10.0), abs=math.radians(0.5))
    for log in turning:
        check = check_coverage(log, coverage, model)
        found = {e.quantity: e for e in check.exceedances}
        # The rudder lies at 35 deg from the end of the approach on: every sample after it is beyond 10 deg.
        after_approach = float(np.mean(log.time >= APPROACH))
        assert found["rudder"].share == pytest.approx(after_approach, abs=1.0 / log.samples)
        assert found["rudder"].extreme / found["rudder"].limit == pytest.approx(3.5, rel=0.05)
        # The linear ship turns at r* = K' delta: 3.5 times the zig-zags' rudder, more than twice their r*.
        assert found["rate"].above and found["rate"].extreme / found["rate"].limit > 2.0
        assert "speed" not in found and "propeller" not in found  # the turns sail at the zig-zags' speed and rate
        assert check.share == pytest.approx(float(np.mean(found["rudder"].beyond | found["rate"].beyond)))
        words = check.describe()
        assert words.startswith(f"{100.0 * check.share:.0f} % of samples extrapolated: rudder up to 3.")
        assert "r* up to " in words and "the fitted runs' largest" in words
    # A zig-zag like the fitted ones (other noise and wind) stays inside.
    _, again = zigzags(10.0, seed=11)
    assert all(check_coverage(log, coverage, model).exceedances == () for log in again)


def test_a_log_without_a_gyro_takes_its_rate_of_turn_from_the_smoothed_heading():
    """A 320 m tanker's zig-zag in closed form, heading 10 deg sin(2 pi t / 300 s), read by a 0.5 deg compass every
    second and no rate gyro. The heading's plain derivative has noise sigma / (sqrt(2) dt) = 0.35 deg/s, above the
    ship's own largest rate (0.21 deg/s): the coverage took it for r*, nearly five times the ship's. The rate smoothed
    as the heading's noise asks comes an order of magnitude closer, and the coverage's r* within a third of the
    closed form's largest."""
    amplitude, period, sigma, length, speed = math.radians(10.0), 300.0, math.radians(0.5), 320.0, 8.0
    time = np.arange(0.0, 1200.0, 1.0)
    heading = amplitude * np.sin(2.0 * math.pi * time / period)
    rate = amplitude * 2.0 * math.pi / period * np.cos(2.0 * math.pi * time / period)
    noisy = heading + np.random.default_rng(0).normal(0.0, sigma, len(time))
    log = Log(name="zigzag", time=time, heading=noisy, rudder=np.zeros(len(time)), speed=np.full(len(time), speed))
    derivative_noise = sigma / math.sqrt(2.0)
    assert np.sqrt(np.mean((np.gradient(noisy, time) - rate) ** 2)) == pytest.approx(derivative_noise, rel=0.1)
    assert np.sqrt(np.mean((log.rate_of_turn_or_smoothed - rate) ** 2)) <= 0.1 * derivative_noise
    largest = length * np.max(np.abs(rate)) / speed
    assert coverage_of([log], ShipModel("kvlcc2")).ranges["rate"].high == pytest.approx(largest, rel=1.0 / 3.0)


def test_the_errors_inside_and_beyond_the_coverage_pool_to_the_whole_run():
    truth, fitted = zigzags(10.0)
    _, turning = turns()
    coverage = coverage_of(fitted, truth.model)
    checks = [check_coverage(log, coverage, truth.model) for log in turning]
    wrong = ReplayModel(truth.model.with_parameters({"yaw.gain": 1.3 * truth.model.parameter("yaw.gain")}))
    replays = simulate(wrong, turning)
    inside, beyond = errors_inside_beyond(turning, replays, checks)
    for log, replay, part_in, part_out in zip(turning, replays, inside, beyond, strict=True):
        whole = run_errors(log, replay)
        together = pooled([part_in, part_out])
        assert part_in.samples + part_out.samples == log.samples
        assert 0 < part_out.samples < log.samples
        for channel in ("heading", "rate_of_turn", "position", "track"):
            assert getattr(together, channel) == pytest.approx(getattr(whole, channel), rel=1e-12)


def test_a_coverage_survives_the_fit_json_and_compare_flags_the_runs_beyond_it(tmp_path, capsys):
    _, fitted = zigzags(10.0)
    _, turning = turns()
    for folder, logs in (("zigzag", fitted[:3]), ("turning", turning)):
        (tmp_path / folder).mkdir()
        for log in logs:
            write_log(log, tmp_path / folder / f"{log.name}.csv")
    document = tmp_path / "fit.json"
    common = ["--ship", SHIP, "--workers", "1"]
    assert (
        main(
            [
                "fit",
                str(tmp_path / "zigzag"),
                "--validate-on",
                str(tmp_path / "turning"),
                "--json",
                str(document),
                *common,
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "validation runs beyond the fitted runs' coverage" in out
    assert "validation runs, RMS errors over the samples beyond the fitted runs' coverage" in out
    stored = json.loads(document.read_text())
    coverage = Coverage.from_dict(stored["coverage"])
    assert coverage.percentile == COVERAGE_PERCENTILE and coverage.runs == tuple(log.name for log in fitted[:3])
    for log in turning:
        assert stored["validation_coverage"][log.name]["extrapolated"] > 0.5
        assert "rudder up to" in stored["validation_coverage"][log.name]["why"]
    assert main(["compare", str(tmp_path / "turning"), "--parameters", str(document), "--ship", SHIP]) == 0
    out = capsys.readouterr().out
    assert "runs beyond the fitted runs' coverage" in out and "runs, RMS errors over the samples inside" in out
    rows = [line for line in out.splitlines() if line.startswith("turn_0 ")]
    assert any("x (" in row for row in rows)  # the coverage table's ratios


def test_the_jackknife_band_holds_every_fold_replay_and_has_no_width_where_the_folds_agree():
    replays = np.random.default_rng(3).normal(size=(7, 40, 4))
    band = jackknife_band(replays)
    for replay in replays:
        assert np.all(band.centre - band.spread <= replay + 1e-12) and np.all(
            replay <= band.centre + band.spread + 1e-12
        )
    agreeing = jackknife_band(np.repeat(replays[:1], 5, axis=0))
    assert np.array_equal(agreeing.spread, np.zeros_like(agreeing.spread))
    assert np.array_equal(agreeing.centre, replays[0])


def test_the_bands_of_a_cross_validation_replay_every_fold_on_every_run_in_one_batch(tmp_path):
    truth, fitted = zigzags(10.0)
    _, turning = turns()
    start = ReplayModel(truth.model.with_parameters({"yaw.gain": 0.8 * truth.model.parameter("yaw.gain")}))
    validation = cross_validate(start, fitted[:3], validate_on=turning, options=FitOptions(workers=1))
    logs = [*fitted[:3], *turning]
    bands = jackknife_bands(validation.folds, logs, validation.window)
    assert len(bands) == len(logs)
    for log, band in zip(logs, bands, strict=True):
        assert band.replays == len(validation.folds) == 3
        alone = np.stack([simulate(fold.setup, [log], validation.window)[0].heading for fold in validation.folds])
        assert np.allclose(band.centre[:, 2], alone.mean(axis=0), rtol=0.0, atol=1e-9)
        assert np.all(np.abs(alone - band.centre[:, 2]) <= band.spread[:, 2] + 1e-9)
        assert np.max(band.spread[:, 2]) > 0.0
    comparison = held_out_comparison(validation, fitted[:3])
    assert len(comparison.bands) == len(comparison.logs) == 5
    assert comparison.roles[-1].startswith("validation run")
    path = plot_run(
        comparison.logs[-1],
        comparison.simulated[-1],
        comparison.errors[-1],
        "t",
        tmp_path / "turn.png",
        comparison.bands[-1],
    )
    assert path.stat().st_size > 0


def norrbin_case():
    """Zig-zags at 20 deg sailed with Norrbin's terms, turning circles without: the term fitted on the zig-zags
    lowers their held-out score but extrapolates to the tight turns badly."""
    _, fitted = zigzags(20.0, hidden=("norrbin",))
    _, turning = turns()
    return fitted, turning, FitOptions(scales=noise_scales(SensorNoise()), workers=1)


def test_improve_does_not_add_an_effect_that_makes_the_validation_runs_worse():
    fitted, turning, options = norrbin_case()
    base = ShipModel(SHIP, REQUIRED_EFFECTS)
    said: list[str] = []
    arguments = {"candidates": ["norrbin"], "pair_width": 0, "validate_on": turning}
    ladder = improve(base, fitted, options, progress=said.append, **arguments)
    assert ladder.added == []
    assert ladder.stopped.startswith("the best next effect, norrbin: lowers the held-out score by ")
    assert "but raises the validation runs' score by " in ladder.stopped
    assert "validation runs beyond the fitted runs' rudder" in ladder.stopped and "r* " in ladder.stopped
    assert any(line.startswith("not added: norrbin:") for line in said)
    allowed = improve(base, fitted, options, allow_worse_validation=True, **arguments)
    assert allowed.added == ["norrbin"]
    scales = options.scales
    before, after = (rung.validation.pooled_validation.score(scales) for rung in allowed.rungs)
    assert after > (1.0 + 0.05) * before  # what the default refused
    assert allowed.rungs[1].validation.score(scales) < 0.95 * allowed.rungs[0].validation.score(scales)


@pytest.mark.slow
def test_improve_on_the_command_line_says_why_it_stopped_and_reports_the_validation_runs(tmp_path, capsys):
    fitted, turning, _ = norrbin_case()
    for folder, logs in (("zigzag", fitted), ("turning", turning)):
        (tmp_path / folder).mkdir()
        for log in logs:
            write_log(log, tmp_path / folder / f"{log.name}.csv")
    arguments = [
        "--validate-on",
        str(tmp_path / "turning"),
        "--candidates",
        "norrbin",
        "--pairs",
        "0",
        "--workers",
        "1",
    ]
    scales = ["--heading-scale", "0.2", "--rate-scale", "0.05", "--position-scale", str(0.02 * math.sqrt(2.0))]
    report = tmp_path / "report"
    assert (
        main(["improve", str(tmp_path / "zigzag"), *arguments, *scales, "--ship", SHIP, "--report", str(report)]) == 0
    )
    out = capsys.readouterr().out
    print(out)
    stopped = next(line for line in out.splitlines() if line.startswith("stopped: "))
    assert "norrbin: lowers the held-out score by" in stopped and "(--allow-worse-validation adds it)" in stopped
    lines = out.splitlines()
    header = lines[lines.index("error ladder (held out: leave one run out)") + 1 :][:3]
    # The ladder's last column is the validation runs' change, its header wrapped over two lines.
    assert header[1].endswith("validation") and header[2].endswith("change"), header
    assert "validation runs beyond the fitted runs' coverage" in out
    text = (report / "report.md").read_text()
    assert "## Validation runs and the fitted runs' coverage" in text
    assert (report / "final" / "turn_0.png").is_file()  # the validation runs drawn, with their band


@needs_esso
@pytest.mark.filterwarnings("ignore::ship_env.workbench.logs.logs.LogWarning")
def test_the_esso_turning_runs_lie_beyond_the_zigzags_rate_of_turn():
    model = ShipModel(SHIP)
    zigzag, turning = load_logs([DATA / "zigzag"]), load_logs([DATA / "turning"])
    coverage = coverage_of(zigzag, model)
    checks = [check_coverage(log, coverage, model) for log in turning]
    beyond_rudder = [c for c in checks if any(e.quantity == "rudder" for e in c.exceedances)]
    assert len(beyond_rudder) >= len(turning) // 2
    # Every turning run at a larger rudder than the zig-zags' turns faster than they ever do.
    for check in beyond_rudder:
        rate = next(e for e in check.exceedances if e.quantity == "rate")
        assert rate.above and rate.extreme > rate.limit and rate.share > 0.1, check.describe()
    assert max(next(e.extreme / e.limit for e in c.exceedances if e.quantity == "rate") for c in beyond_rudder) > 2.0


@pytest.mark.slow
@needs_esso
def test_fit_on_the_esso_zigzags_flags_the_turning_runs_r_star(tmp_path, capsys):
    document = tmp_path / "fit.json"
    arguments = ["--validate-on", str(DATA / "turning"), "--every", "4", "--json", str(document)]
    assert main(["fit", str(DATA / "zigzag"), *arguments]) == 0
    assert "validation runs beyond the fitted runs' coverage" in capsys.readouterr().out
    turning = json.loads(document.read_text())["validation_coverage"]
    assert len(turning) == 15
    beyond_rate = {run: entry for run, entry in turning.items() if "r* up to " in entry["why"]}
    assert len(beyond_rate) >= 8, turning
    # Every turning run at a larger rudder than the zig-zags' turns faster than they ever do.
    beyond_rudder = [run for run, entry in turning.items() if "rudder up to " in entry["why"]]
    assert beyond_rudder and set(beyond_rudder) <= set(beyond_rate), turning
