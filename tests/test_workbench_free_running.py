"""Free-running validation: the figures read off a series equal the manoeuvre runner's, and the true model
sailing a log's manoeuvre free predicts the measured figures."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from ship_env.cli import main
from ship_env.manoeuvres import turning_circle, zigzag
from ship_env.manoeuvres.results import Figure
from ship_env.model import ShipModel
from ship_env.workbench.deciding.improve import improve
from ship_env.workbench.fitting.errors import ErrorScales
from ship_env.workbench.fitting.fit import FitOptions
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.judging.free_running import (
    RunFigures,
    Series,
    compare_free_running,
    disagreements,
    figure_score,
    free_running_table,
    held_out_free_running,
    manoeuvre_figures,
    read_manoeuvre,
)
from ship_env.workbench.judging.validation import cross_validate
from ship_env.workbench.logs.logs import load_logs, write_log
from ship_env.workbench.reporting.presets import preset_document, write_preset
from ship_env.workbench.synthetic.synthetic import NO_NOISE, LogSettings, Manoeuvre, SensorNoise, sail_all

SHIP = "container_226m"
#: The container ship's preset without its wind effects and current: yaw, Norrbin, speed loss, sway, steering machine.
CALM_EFFECTS = ("yaw", "norrbin", "speed_loss", "sway", "steering_machine", "kinematics")
ESSO = Path(__file__).parents[2] / "shared" / "data" / "esso_osaka"


def _series(result) -> Series:
    frame = result.time_series
    columns = ("time", "north", "east", "heading", "rate_of_turn", "rudder")
    return Series(*(frame[c].to_numpy() for c in columns), speed=frame["speed"].to_numpy())


def _figures(series: Series, length: float) -> dict[str, float]:
    return {f.key: f.value for f in manoeuvre_figures(series, read_manoeuvre(series), length)}


def test_a_sailed_turning_circle_reads_as_the_manoeuvre_runner_reads_it():
    """A second reading of the same figures: advance and tactical diameter by the same interpolation, the
    steady rate and speed over the last full circle (the runner's steady part)."""
    model = ShipModel(SHIP)
    circle = turning_circle(model, math.radians(-35.0))
    series = _series(circle)
    manoeuvre = read_manoeuvre(series)
    assert (manoeuvre.kind, manoeuvre.side) == ("turning", -1.0)
    figures = _figures(series, model.length)
    assert figures["advance_lengths"] == pytest.approx(circle.advance / model.length, rel=1e-12)
    assert figures["tactical_diameter_lengths"] == pytest.approx(circle.tactical_diameter / model.length, rel=1e-12)
    # One sample of the last circle apart: the runner takes samples past 2 circles, this reading the last 360 deg.
    assert figures["steady_rate_of_turn"] == pytest.approx(math.degrees(circle.steady_rate_of_turn), rel=1e-3)
    assert figures["speed_loss"] == pytest.approx(100.0 * circle.speed_loss, rel=1e-3)
    assert figures["steady_radius"] == pytest.approx(circle.steady_radius, rel=1e-3)


def test_a_sailed_zigzag_reads_as_the_manoeuvre_runner_reads_it():
    model = ShipModel(SHIP)
    test = zigzag(model, math.radians(20.0), math.radians(20.0))
    series = _series(test)
    manoeuvre = read_manoeuvre(series)
    assert manoeuvre.kind == "zig-zag"
    assert math.degrees(manoeuvre.rudder_angle) == pytest.approx(20.0)
    # The helmsman reverses at the first step past b: the heading then is b and up to one step's turn more.
    step_turn = float(np.max(np.abs(series.rate_of_turn))) * 0.5
    assert 0.0 <= manoeuvre.heading_change - math.radians(20.0) <= step_turn
    figures = _figures(series, model.length)
    # The largest sampled deviation against the runner's interpolated peak (r = 0): within the heading's
    # change over one step at the peak, second order in the step (r ~ 0 there).
    peak_error = math.degrees(step_turn) ** 2
    b_excess = math.degrees(manoeuvre.heading_change - math.radians(20.0))
    assert figures["first_overshoot"] == pytest.approx(math.degrees(test.first_overshoot) - b_excess, abs=peak_error)
    assert figures["second_overshoot"] == pytest.approx(math.degrees(test.second_overshoot) - b_excess, abs=peak_error)


def _noise_free_logs(model: ShipModel, lengths: float = 60.0) -> list:
    """A zig-zag 15/15 and a 30 deg turn to port of ``lengths`` ship lengths each, noise-free and calm."""
    speed = model.service_speed
    unit = model.length / speed  # s per ship length
    runs = [
        Manoeuvre("zigzag_15", "zigzag", math.radians(15.0), lengths * unit, approach=2 * unit,
                  zigzag_angle=math.radians(15.0), start_speed=speed, final_speed=speed, wind_speed=0.0),
        Manoeuvre("turn_m30", "turn", math.radians(-30.0), lengths * unit, approach=2 * unit,
                  start_speed=speed, final_speed=speed, wind_speed=0.0),
    ]  # fmt: skip
    exact = LogSettings(noise=NO_NOISE, dt=0.5)
    return sail_all(ReplayModel(model), runs, seed=3, settings=exact)


def test_the_true_model_sailed_free_predicts_the_measured_figures():
    """Noise-free logs of the container ship in calm water: its own model, sailing the zig-zag closed loop and
    the turn on the held rudder from the measured state at the execute, gives the measured figures."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    truth = ReplayModel(model)
    logs = _noise_free_logs(model)
    results = compare_free_running(truth, logs)
    assert [r.manoeuvre.kind for r in results] == ["zig-zag", "turning"]
    for result in results:
        for measured, predicted in zip(result.measured, result.predicted, strict=True):
            assert predicted.key == measured.key
            # The same steps from the same state: the same numbers (NaN where the run does not reach a figure).
            assert predicted.value == pytest.approx(measured.value, rel=1e-9, abs=1e-9, nan_ok=True), measured.key
    table = free_running_table(results).text()
    assert "first overshoot" in table and "tactical diameter" in table


def test_a_model_with_half_the_gain_predicts_larger_turns_and_overshoots_than_measured():
    """The comparison says which way a wrong model errs: a ship half as quick to turn."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    logs = _noise_free_logs(model)
    slow = ReplayModel(model.with_parameters({"yaw.gain": 0.5 * model.parameter("yaw.gain")}))
    zig, turn = compare_free_running(slow, logs)
    measured = {f.key: f.value for f in turn.measured}
    predicted = {f.key: f.value for f in turn.predicted}
    assert predicted["tactical_diameter_lengths"] > measured["tactical_diameter_lengths"]
    assert predicted["steady_rate_of_turn"] < measured["steady_rate_of_turn"]
    measured = {f.key: f.value for f in zig.measured}
    predicted = {f.key: f.value for f in zig.predicted}
    assert predicted["initial_turning_time"] > measured["initial_turning_time"]


def test_a_model_that_cannot_sail_a_run_says_why_and_scores_infinite(tmp_path):
    """A model that leaves its validity in a run's manoeuvre (a speed loss past the ship's speed in the turn)
    gives that run no figures and the reason, the figure score is infinite, the disagreements name it, and the
    report and its drawing are written: the model is judged, not the workbench stopped (a traceback before)."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    logs = _noise_free_logs(model, lengths=16.0)
    wild = ReplayModel(model.with_parameters({"speed_loss.gain": 5.0}))  # u* = 5 r*^2 passes 1 in the turn only
    zig, turn = compare_free_running(wild, logs)
    assert turn.cannot_sail.startswith("ship 0 left the model's validity") and turn.predicted_series is None
    assert all(math.isnan(f.value) for f in turn.predicted) and not any(math.isnan(f.value) for f in turn.measured)
    assert figure_score([zig, turn]) == math.inf and math.isfinite(figure_score([zig]))
    assert any("1 of 2 runs cannot be sailed (turn_m30)" in line for line in disagreements([zig, turn], ()))
    assert "| turn_m30 | turning | tactical diameter, L |" in free_running_table([zig, turn]).markdown()
    assert "n/a" in free_running_table([turn]).text()


def test_a_run_that_is_neither_has_no_figures():
    model = ShipModel.minimal(SHIP)
    (log, _) = _noise_free_logs(model)
    straight = replace(log, rudder=np.zeros_like(log.rudder), name="straight")
    assert read_manoeuvre(Series.of_log(straight)).kind == "other"
    assert compare_free_running(ReplayModel(model), [straight]) == ()


@pytest.mark.skipif(not ESSO.is_dir(), reason=f"the Esso Osaka logs are not at {ESSO}")
@pytest.mark.filterwarnings("ignore::ship_env.workbench.LogWarning")  # a run's NaN tail, dropped and said
def test_the_esso_osaka_runs_read_as_their_manoeuvres():
    """Every zig-zag run a zig-zag with its a = b (15, 20 or 30 deg), every turning run a turn."""
    for log in load_logs(sorted((ESSO / "zigzag").glob("*.csv"))):
        manoeuvre = read_manoeuvre(Series.of_log(log))
        assert manoeuvre.kind == "zig-zag", log.name
        a = math.degrees(manoeuvre.rudder_angle)
        assert min(abs(a - 15.0), abs(a - 20.0), abs(a - 30.0)) < 1.0, (log.name, a)
        assert math.degrees(manoeuvre.heading_change) == pytest.approx(a, abs=0.35 * a), log.name
    for log in load_logs(sorted((ESSO / "turning").glob("*.csv"))):
        assert read_manoeuvre(Series.of_log(log)).kind == "turning", log.name


def test_the_improve_report_shows_each_run_s_figures_and_tracks(tmp_path):
    """The report's free-running section: a table row per figure of every run and model, and the drawings."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    folder = tmp_path / "logs"
    folder.mkdir()
    for log in _noise_free_logs(model, lengths=16.0):  # three reversals, a turn past 180 deg
        write_log(log, folder / f"{log.name}.csv")
    report = tmp_path / "report"
    arguments = [str(folder), "--ship", SHIP, "--candidates", "norrbin", "--max-steps", "1", "--report", str(report)]
    assert main(["improve", *arguments]) == 0
    text = (report / "report.md").read_text()
    section = text.split("## Manoeuvres sailed free: measured against predicted")[1].split("\n## ")[0]
    for run, figure in (("zigzag_15", "first overshoot, deg"), ("turn_m30", "tactical diameter, L")):
        assert section.count(f"| {run} | ") >= 5 and figure in section, (run, figure)
    for label in ("start", "final") if "### final model" in section else ("final",):
        assert (report / f"free_running_{label}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_validation_run_s_predicted_figures_carry_the_folds_jackknife_error():
    """A fit on three noisy zig-zags, validated on a turn it never saw: every fold sails the turn too, and each
    predicted figure's error is sqrt((n - 1) / n sum (x_i - mean x)^2) over the folds' figures, shown in the table."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    speed, unit = model.service_speed, model.length / model.service_speed
    runs = [
        Manoeuvre(f"zigzag_{a}", "zigzag", math.radians(a), 30 * unit, approach=2 * unit,
                  zigzag_angle=math.radians(abs(a)), start_speed=speed, final_speed=speed, wind_speed=0.0)
        for a in (10.0, -15.0, 20.0)
    ]  # fmt: skip
    turn = Manoeuvre("turn_m30", "turn", math.radians(-30.0), 30 * unit, approach=2 * unit, start_speed=speed,
                     final_speed=speed, wind_speed=0.0)  # fmt: skip
    settings = LogSettings(noise=SensorNoise(), dt=0.5)
    logs = sail_all(ReplayModel(model), [*runs, turn], seed=5, settings=settings)
    options = FitOptions(scales=ErrorScales.for_runs(model, logs[:3]), workers=1)
    validation = cross_validate(model, logs[:3], ["yaw.gain", "yaw.time_constant"], options, validate_on=logs[3:])
    predicted = held_out_free_running(validation, logs[:3])[-1]
    assert predicted.run == "turn_m30" and len(validation.folds) == 3
    by_fold = [compare_free_running(fold.setup, logs[3:])[0].predicted for fold in validation.folds]
    for i, figure in enumerate(predicted.predicted):
        values = np.array([float(figures[i].value) for figures in by_fold])
        expected = math.sqrt(2 / 3 * np.sum((values - values.mean()) ** 2))
        assert predicted.spread[i] == pytest.approx(expected, rel=1e-12, nan_ok=True), figure.key
    tactical = [figure.key for figure in predicted.predicted].index("tactical_diameter_lengths")
    assert predicted.spread[tactical] > 0.0
    assert f"+-{predicted.spread[tactical]:.2f}" in free_running_table([predicted]).text()


def test_a_fit_that_took_the_actual_rudder_sails_free_with_the_preset_s_steering_machine():
    """Logs that record the actual rudder are replayed with it as an input, so a fit leaves the steering machine
    out; sailed free, the model must still move the rudder at the preset's rate (2.5 deg/s), not jump to the order:
    the truth without its steering machine, given back the container preset's, predicts the measured figures."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    logs = _noise_free_logs(model)
    assert {log.rudder_kind for log in logs} == {"actual"}
    results = compare_free_running(ReplayModel(model.without_effects("steering_machine")), logs)
    for result in results:
        for measured, predicted in zip(result.measured, result.predicted, strict=True):
            assert predicted.value == pytest.approx(measured.value, rel=1e-9, abs=1e-9, nan_ok=True), measured.key


def test_a_preset_fitted_on_the_actual_rudder_keeps_the_starting_preset_s_steering_machine(tmp_path):
    """The preset sails rudder orders (manoeuvres, autopilots): it carries the starting preset's steering machine
    with its rate and source, and says so; logs of the ordered rudder keep the fit's model as it is."""
    model = ShipModel(SHIP, CALM_EFFECTS)
    logs = _noise_free_logs(model, lengths=20.0)
    setup = ReplayModel(model.without_effects("steering_machine"))
    options = FitOptions(scales=ErrorScales.for_runs(setup.model, logs), workers=1)
    validation = cross_validate(setup, logs, ["yaw.gain"], options)
    document = preset_document(validation, logs, "ship-env fit (test)", "kept")
    machine = document["effects"]["steering_machine"]
    assert machine["enabled"] is True
    assert machine["rudder_rate"]["value"] == 2.5 and "thesis" in machine["rudder_rate"]["source"]
    assert document["fitted"]["kept_from_preset"] == ["steering_machine"]
    assert any(w.startswith("steering machine:") and "2.5 deg/s" in w for w in document["fitted"]["not_identified"])
    path = write_preset(document, tmp_path / "kept.yaml")
    assert ShipModel(path).has("steering_machine")
    ordered = [replace(log, rudder_kind="ordered") for log in logs]
    document = preset_document(validation, ordered, "ship-env fit (test)", "ordered")
    assert document["effects"]["steering_machine"]["enabled"] is False
    assert "kept_from_preset" not in document["fitted"]


def _turn_figures() -> tuple[tuple[Figure, ...], tuple[Figure, ...]]:
    """A turn measured and predicted: tactical diameter +96 %, speed loss -75 %, advance +3.3 %, and a first
    overshoot the measured run does not reach (NaN)."""
    figure = {
        "tactical_diameter_lengths": ("tactical diameter", "L", 2),
        "speed_loss": ("speed loss in steady turn", "%", 1),
        "advance_lengths": ("advance", "L", 2),
        "first_overshoot": ("first overshoot", "deg", 1),
    }
    measured = dict(zip(figure, (2.5, 65.0, 3.0, math.nan), strict=True))
    predicted = dict(zip(figure, (4.9, 16.25, 3.1, 4.0), strict=True))
    return tuple(
        tuple(Figure(key, label, values[key], unit, digits) for key, (label, unit, digits) in figure.items())
        for values in (measured, predicted)
    )


def test_the_figures_that_disagree_are_named_with_the_effects_that_shape_them():
    """A turn predicted at twice the measured tactical diameter (+96 %) and a quarter of its speed loss: both beyond
    their bounds (5 %, 10 %), each naming the effects that shape it which the model lacks; figures within their
    bounds, or not reached (NaN), say nothing."""
    measured, predicted = _turn_figures()
    run = RunFigures("turn", None, measured, predicted, None)  # type: ignore[arg-type]
    lines = disagreements([run, run], ("yaw", "speed_loss", "sway", "kinematics"))
    assert lines == [
        "tactical diameter: 2 of 2 runs beyond 5 % (median +96 %); effects that shape it, not in the model: "
        "hull_crossflow, norrbin",
        "speed loss in steady turn: 2 of 2 runs beyond 10 % (median -75 %); effects that shape it, not in the model: "
        "turning_resistance, rudder_drag, drift_resistance",
    ]
    every = ("yaw", "speed_loss", "turning_resistance", "rudder_drag", "drift_resistance", "kinematics")
    assert disagreements([run], every)[-1] == (
        "speed loss in steady turn: 1 of 1 runs beyond 10 % (median -75 %); the model has every effect the library "
        "knows to shape it: their terms extrapolate"
    )
    assert disagreements([RunFigures("turn", None, measured, measured, None)], ("yaw",)) == []  # type: ignore[arg-type]


def test_the_figure_score_is_the_mean_error_over_the_bounds_and_the_ladder_takes_it_by_name():
    """Tactical diameter +96 % over its 5 % bound (19.2), speed loss -75 % over 10 % (7.5), advance +3.3 % over 5 %
    (0.67): their mean is the score; a figure not reached counts for nothing; no judged figure gives NaN. The ladder
    scores validation runs by replay or by figures, and names the field where it is neither."""
    measured, predicted = _turn_figures()
    run = RunFigures("turn", None, measured, predicted, None)  # type: ignore[arg-type]
    expected = (2.4 / 2.5 / 0.05 + 48.75 / 65.0 / 0.10 + 0.1 / 3.0 / 0.05) / 3.0
    assert figure_score([run]) == pytest.approx(expected, rel=1e-12)
    assert math.isnan(figure_score([RunFigures("turn", None, measured[3:], predicted[3:], None)]))  # type: ignore[arg-type]
    model = ShipModel(SHIP, CALM_EFFECTS)
    with pytest.raises(ValueError, match="validate_by: expected one of replay, figures, got 'imo'"):
        improve(model, _noise_free_logs(model, lengths=20.0), validate_by="imo")
