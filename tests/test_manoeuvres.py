"""Standard manoeuvres: closed forms of the Nomoto ship, symmetry, stability and the IMO criteria."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from ship_env.manoeuvres import (
    TIME_SERIES_COLUMNS,
    PullOut,
    TrialSettings,
    check_criteria,
    plot_manoeuvre,
    pull_out,
    reversed_spiral,
    turning_circle,
    zigzag,
)
from ship_env.manoeuvres.extrapolation import beyond_coverage
from ship_env.manoeuvres.imo import first_overshoot_limit_10_10, second_overshoot_limit_10_10
from ship_env.manoeuvres.series import crossing_times, first_crossing, value_at
from ship_env.model import ShipModel
from ship_env.model.operating_point import FittedRanges

CONTAINER = "container_226m"
SETTINGS = TrialSettings(dt=1.0)


@pytest.fixture(scope="module")
def minimal() -> ShipModel:
    return ShipModel.minimal(CONTAINER)


@pytest.fixture(scope="module")
def default() -> ShipModel:
    return ShipModel(CONTAINER)


@pytest.fixture(scope="module")
def default_results(default):
    return [
        turning_circle(default, math.radians(35.0), SETTINGS),
        zigzag(default, math.radians(10.0), math.radians(10.0), SETTINGS),
        zigzag(default, math.radians(20.0), math.radians(20.0), SETTINGS),
        pull_out(default, settings=SETTINGS),
        reversed_spiral(default, settings=SETTINGS),
    ]


# -- the shared crossing helper ----------------------------------------------------------------------
def test_crossings_are_interpolated_between_samples():
    time = np.arange(0.0, 10.0, 0.5)
    values = np.sin(time)
    np.testing.assert_allclose(crossing_times(time, values, 0.0), [math.pi, 2.0 * math.pi, 3.0 * math.pi], atol=0.02)
    assert first_crossing(time, values, 0.0, after=4.0) == pytest.approx(2.0 * math.pi, abs=0.02)
    assert math.isnan(first_crossing(time, values, 2.0))  # never reached
    assert math.isnan(first_crossing(time, values, 0.0, after=math.nan))  # after an event not reached
    assert value_at(time, 2.0 * time, 1.25) == pytest.approx(2.5)
    assert math.isnan(value_at(time, values, math.nan))


def test_a_signal_starting_on_the_level_does_not_cross_it():
    time = np.arange(5.0)
    assert crossing_times(time, np.array([0.0, 1.0, 2.0, 1.0, -1.0]), 0.0) == pytest.approx([3.5])


# -- turning circle ------------------------------------------------------------------------------------
@pytest.mark.parametrize("rudder_deg", [35.0, 15.0, -20.0])
def test_nomoto_steady_turning_radius_is_length_over_gain_times_rudder(minimal, rudder_deg):
    rudder = math.radians(rudder_deg)
    circle = turning_circle(minimal, rudder, SETTINGS)
    expected = minimal.length / (minimal.parameter("yaw.gain") * abs(rudder))  # u/r with r = K* (u/L) delta (2.61)
    assert circle.steady_radius == pytest.approx(expected, rel=0.01)
    assert circle.fitted_radius == pytest.approx(expected, rel=0.01)
    assert circle.steady_rate_of_turn == pytest.approx(minimal.service_speed / expected, rel=0.01)
    assert circle.speed_loss == pytest.approx(0.0, abs=1e-12)
    assert abs(circle.drift_angle) < math.radians(0.05)
    assert 0.0 < circle.time_to_90 < circle.time_to_180


def test_turning_circle_figures_follow_the_imo_geometry(default_results):
    circle = default_results[0]
    series = circle.time_series
    assert list(series.columns) == list(TIME_SERIES_COLUMNS)
    # At 90 deg of heading change the ship is ahead (advance) and to starboard (transfer) of the execute.
    assert circle.advance > circle.transfer > 0.0
    # Tactical diameter: the transfer at 180 deg, past the widest point of the first half circle.
    assert circle.tactical_diameter > circle.transfer
    assert circle.steady_radius == pytest.approx(circle.fitted_radius, rel=0.01)
    assert 0.2 < circle.speed_loss < 0.5
    assert circle.drift_angle > 0.0  # bow inside the circle
    peak_rate = series["rate_of_turn"].max()
    assert peak_rate > 1.2 * circle.steady_rate_of_turn  # the rate-of-turn overshoot of Fig. 2.7


def test_port_turning_circle_mirrors_starboard(default, default_results):
    starboard = default_results[0]
    port = turning_circle(default, math.radians(-35.0), SETTINGS)
    for name in ("advance", "transfer", "tactical_diameter", "steady_radius", "steady_rate_of_turn", "drift_angle"):
        assert getattr(port, name) == pytest.approx(getattr(starboard, name), rel=1e-9), name
    assert port.time_series["east"].min() < -100.0  # it went to port
    assert port.label == "35 deg port"


def test_turning_circle_rejects_impossible_rudder(default):
    with pytest.raises(ValueError, match="rudder_angle"):
        turning_circle(default, 0.0)
    with pytest.raises(ValueError, match="exceeds the rudder limit of 35 deg"):
        turning_circle(default, math.radians(40.0))
    with pytest.raises(ValueError, match="speed"):
        TrialSettings(speed=0.0)


# -- zig-zag -----------------------------------------------------------------------------------------
def test_mirrored_zigzag_gives_the_same_figures(default, default_results):
    starboard_first = default_results[1]
    port_first = zigzag(default, math.radians(-10.0), math.radians(10.0), SETTINGS)
    assert port_first.label == "-10/-10"
    for name in ("first_overshoot", "second_overshoot", "initial_turning_time", "time_to_check_yaw"):
        assert getattr(port_first, name) == pytest.approx(getattr(starboard_first, name), rel=1e-9, abs=1e-12), name


def test_zigzag_reverses_the_rudder_at_the_heading_change(default_results):
    test = default_results[1]
    series = test.time_series
    executes = series.index[series["ordered_rudder"].diff().fillna(0.0) != 0.0]
    headings = np.degrees(series.loc[executes, "heading"].to_numpy())
    largest_step = math.degrees(series["rate_of_turn"].abs().max()) * SETTINGS.dt
    assert len(headings) == 4  # second to fifth execute
    np.testing.assert_allclose(np.abs(headings), 10.0, atol=largest_step)
    assert list(np.sign(headings)) == [1.0, -1.0, 1.0, -1.0]
    assert 0.0 < test.first_overshoot < test.second_overshoot
    # The peak heading between the second and third executes is b plus the first overshoot.
    second, third = series.loc[executes[:2], "time"]
    first_swing = series[(series["time"] >= second) & (series["time"] <= third)]
    assert math.radians(10.0) + test.first_overshoot == pytest.approx(first_swing["heading"].max(), abs=1e-4)


def test_zigzag_overshoot_grows_with_the_rudder(default_results):
    ten, twenty = default_results[1], default_results[2]
    assert twenty.first_overshoot > 2.0 * ten.first_overshoot


def test_zigzag_event_not_reached_is_nan(default):
    short = zigzag(default, math.radians(10.0), math.radians(10.0), SETTINGS, max_lengths=1.0)
    assert math.isnan(short.first_overshoot) and math.isnan(short.time_to_check_yaw)
    assert short.figures()[0].text == "n/a"


# -- pull-out ----------------------------------------------------------------------------------------
def test_symmetric_ship_pulls_out_to_zero_rate(default_results):
    test = default_results[3]
    assert test.steady_rate_starboard == pytest.approx(test.steady_rate_port, rel=1e-9)
    assert test.steady_rate_starboard > math.radians(0.5)
    assert abs(test.residual_rate_starboard) < 1e-4 * test.steady_rate_starboard
    assert abs(test.residual_rate_port) < 1e-4 * test.steady_rate_port
    assert test.course_stable


def test_asymmetric_ship_settles_to_one_rate_from_both_sides(default):
    asymmetry = 0.02  # alpha0 of H(r*) (2.27): steady r* = -alpha0 (to first order) at zero rudder
    test = pull_out(
        default.with_effects("asymmetry").with_parameters({"asymmetry.constant": asymmetry}), settings=SETTINGS
    )
    rate_at_zero_rudder = test.residual_rate_starboard  # positive: keeps turning to starboard
    assert rate_at_zero_rudder < 0.0 < test.residual_rate_port
    assert rate_at_zero_rudder == pytest.approx(-test.residual_rate_port, rel=1e-3)
    assert rate_at_zero_rudder == pytest.approx(-asymmetry * default.service_speed / default.length, rel=0.05)
    assert test.course_stable


def test_residual_rates_to_either_side_mean_course_instability():
    unstable = PullOut(
        ship=CONTAINER,
        length=226.0,
        approach_speed=9.5,
        time_series=pd.DataFrame(),
        rudder_angle=math.radians(20.0),
        steady_rate_starboard=0.02,
        steady_rate_port=0.02,
        residual_rate_starboard=0.005,
        residual_rate_port=0.005,
    )
    assert not unstable.course_stable
    assert unstable.figures()[-1].value == "no"


# -- reversed spiral ---------------------------------------------------------------------------------
def test_nomoto_spiral_is_the_straight_line_r_equals_k_delta(minimal):
    spiral = reversed_spiral(minimal, settings=SETTINGS, points=7)
    table = spiral.table
    assert len(table) == 9 and table["hard_over"].sum() == 2
    gain = minimal.parameter("yaw.gain") * minimal.service_speed / minimal.length  # K = K* u/L (2.61)
    np.testing.assert_allclose(table["rate_of_turn"], gain * table["rudder"], rtol=1e-3, atol=1e-7)
    assert spiral.course_stable


def test_spiral_follows_norrbin_steady_turn():
    """With speed loss and sway but no wind, each point solves r* + alpha3 r*^3 = K* delta (2.26)."""
    model = ShipModel(CONTAINER, ["yaw", "norrbin", "speed_loss", "sway", "steering_machine"])
    spiral = reversed_spiral(model, rates=np.radians([-0.8, -0.3, 0.1, 0.5, 0.9]), settings=SETTINGS)
    held = spiral.table[~spiral.table["hard_over"]]
    np.testing.assert_allclose(held["rate_of_turn"], np.radians([-0.8, -0.3, 0.1, 0.5, 0.9]), rtol=1e-3)
    rate = held["normalised_rate"]
    restoring = rate + model.parameter("norrbin.cubic") * rate**3
    np.testing.assert_allclose(restoring, model.parameter("yaw.gain") * held["rudder"], rtol=2e-3, atol=1e-6)
    assert spiral.course_stable


def test_spiral_of_the_default_ship_bends_below_the_linear_line(default_results):
    spiral = default_results[4]
    table = spiral.table
    assert (np.diff(table["rudder"]) > 0).all() and spiral.course_stable
    linear_rate = ShipModel.minimal(CONTAINER).parameter("yaw.gain") * table["rudder"]
    hard_over = table[table["hard_over"]]
    assert (hard_over["normalised_rate"].abs() < 0.8 * linear_rate[table["hard_over"]].abs()).all()
    assert spiral.hard_over_rate_starboard == pytest.approx(spiral.hard_over_rate_port, rel=1e-9)


# -- IMO criteria ------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("length_over_speed", "first", "second"),
    [(5.0, 10.0, 25.0), (10.0, 10.0, 25.0), (20.0, 15.0, 32.5), (30.0, 20.0, 40.0), (45.0, 20.0, 40.0)],
)
def test_10_10_overshoot_limits_depend_on_length_over_speed(length_over_speed, first, second):
    assert first_overshoot_limit_10_10(length_over_speed * 10.0, 10.0) == pytest.approx(first)
    assert second_overshoot_limit_10_10(length_over_speed * 10.0, 10.0) == pytest.approx(second)


def test_criteria_apply_to_the_imo_manoeuvres_only(default, default_results):
    checks = check_criteria(default_results)
    assert [c.clause for c in checks] == ["5.3.1", "5.3.1", "5.3.2", "5.3.3.1", "5.3.3.2", "5.3.3.3"]
    assert all(c.passed for c in checks)
    assert checks[1].value == pytest.approx(default_results[0].tactical_diameter / default.length)
    assert checks[3].limit == pytest.approx(5.0 + 0.5 * default.length / default.service_speed)
    assert check_criteria([turning_circle(default, math.radians(20.0), SETTINGS)]) == []


# -- drawings ----------------------------------------------------------------------------------------
def test_plot_writes_a_png(default_results, tmp_path):
    path = plot_manoeuvre(default_results[1], tmp_path / "zigzag.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 20_000


def test_a_turn_beyond_the_runs_drift_angle_says_so_with_its_steady_drift(default, default_results):
    """A fit's runs that drifted 5 deg at most: the container ship's hard-over turn, whose steady drift is its
    figure (heading against the track), sails beyond them by at least that drift; runs that drifted 40 deg cover it."""
    turn = default_results[0]
    steady_drift = math.degrees(turn.drift_angle)
    assert steady_drift > 5.0
    narrow = FittedRanges("runs", {"drift": (None, math.radians(5.0))})
    (words,) = beyond_coverage(turn, default, narrow)
    assert words.startswith("drift angle up to ") and words.endswith("(|drift angle| <= 5 deg)"), words
    assert float(words.split()[4]) >= round(steady_drift, 1)
    assert beyond_coverage(turn, default, FittedRanges("runs", {"drift": (None, math.radians(40.0))})) == []
