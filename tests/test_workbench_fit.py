"""Replay and output-error fitting: the replay is the simulator, the fit finds known parameters."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.model import state as S
from ship_env.workbench import (
    FitError,
    FitOptions,
    ReplayModel,
    cross_validate,
    fit,
    simulate,
)
from ship_env.workbench.fitting.fit import DIFFERENCE_STEP, Problem
from ship_env.workbench.fitting.replay import initial_state, initial_window, moved_replays
from ship_env.workbench.fitting.terms import acts_on, default_terms, make_term, value_of, with_values
from ship_env.workbench.synthetic.synthetic import (
    HIDDEN_VALUES,
    NO_NOISE,
    SEA_TRIAL_NOISE,
    LogSettings,
    Manoeuvre,
    SensorNoise,
    free_running,
    model_test_programme,
    noise_scales,
    sail_all,
)

SHIP = "esso_osaka_model"
EVERY_EFFECT = [
    *REQUIRED_EFFECTS,
    "steering_machine",
    "rudder_offset",
    "propeller_slipstream",
    "sway",
    "current",
    "wind_moment",
    "wind_drift",
    "norrbin",
]


def short_programme() -> list[Manoeuvre]:
    return model_test_programme(duration=40.0)[::2]


def test_free_replay_is_the_simulator_and_the_track_replay_follows_it():
    truth = free_running(ReplayModel(ShipModel(SHIP, EVERY_EFFECT), 0.02, -0.03))
    logs = sail_all(truth, short_programme(), seed=3, settings=LogSettings(noise=NO_NOISE, rudder_kind="ordered"))
    for log, replayed in zip(logs, simulate(truth, logs, window=0.0), strict=True):
        assert replayed.valid
        np.testing.assert_allclose(replayed.heading, log.heading, rtol=0.0, atol=1e-9)
        np.testing.assert_allclose(replayed.north, log.north, rtol=0.0, atol=1e-9)
        np.testing.assert_allclose(replayed.speed, log.speed, rtol=0.0, atol=1e-9)  # the model's own speed
        # Heun's method on the imposed measured heading: second order in the 0.2 s step.
        assert np.max(np.hypot(replayed.track_north - log.north, replayed.track_east - log.east)) < 2e-3


def test_fit_finds_the_parameters_of_noise_free_logs():
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "speed_loss", "rudder_offset"], HIDDEN_VALUES))
    logs = sail_all(truth, short_programme(), seed=1, settings=LogSettings(noise=NO_NOISE))
    start = truth.model.with_parameters({"yaw.gain": 1.0, "yaw.time_constant": 1.0, "rudder_offset.angle": 0.0})
    result = fit(start, logs, options=FitOptions(initial_window=0.0))  # the first sample is the exact start
    for estimate in result.estimates:
        assert estimate.value == pytest.approx(truth.model.parameter(estimate.term.key), rel=1e-5)
    assert math.degrees(result.pooled.heading) < 1e-4
    assert result.setup.model.parameter("rudder_offset.angle") == pytest.approx(math.radians(3.0), rel=1e-5)


def test_fit_with_sensor_noise_reports_its_uncertainty():
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "speed_loss", "propeller_slipstream"], HIDDEN_VALUES))
    noise = SensorNoise()
    logs = sail_all(truth, model_test_programme(duration=60.0), seed=2, settings=LogSettings(noise=noise))
    start = truth.model.with_parameters({"yaw.gain": 1.0})
    validation = cross_validate(start, logs, options=FitOptions(scales=noise_scales(noise)))
    jackknife = validation.jackknife_errors()
    for estimate in validation.fit.estimates:
        true_value = truth.model.parameter(estimate.term.key)
        assert estimate.value == pytest.approx(true_value, rel=0.05)
        # The Jacobian's standard error ignores the residuals' correlation in time: it is smaller
        # than the jackknife's, which covers the error.
        assert 0.0 < estimate.std_error < jackknife[estimate.term.key]
        assert abs(estimate.value - true_value) < 4.0 * jackknife[estimate.term.key]
        assert not estimate.at_bound


def test_cross_validation_leaves_each_run_out():
    truth = ReplayModel(ShipModel(SHIP, REQUIRED_EFFECTS))
    logs = sail_all(truth, short_programme(), seed=4)
    validation = cross_validate(truth.model, logs)
    assert [e.name for e in validation.held_out] == [log.name for log in logs]
    assert len(validation.folds) == len(logs)
    assert [fold.left_out for fold in validation.folds] == [(log.name,) for log in logs]
    assert validation.pooled.samples == sum(log.samples for log in logs)
    with pytest.raises(FitError, match="at least two runs"):
        cross_validate(truth.model, logs[:1])


def test_nuisance_terms_are_fitted_per_run():
    truth = ReplayModel(ShipModel(SHIP, REQUIRED_EFFECTS))
    logs = sail_all(truth, short_programme(), seed=5)
    plain = fit(truth.model, logs)
    with_nuisance = fit(truth.model, logs, options=FitOptions(nuisance=("heading", "rate_of_turn")))
    assert set(with_nuisance.nuisance) == {log.name for log in logs}
    assert all(set(terms) == {"heading", "rate_of_turn"} for terms in with_nuisance.nuisance.values())
    assert with_nuisance.pooled.heading <= plain.pooled.heading + 1e-9


@pytest.mark.parametrize(
    "terms, message",
    [
        (["rudder_offset.angle"], "belongs to the effect 'rudder_offset', which is not in the model"),
        (["yaw.stiffness"], "unknown term 'yaw.stiffness'"),
        (["yaw.gain", "yaw.gain"], "terms repeat"),
    ],
)
def test_fit_set_up_errors(terms, message):
    logs = sail_all(ReplayModel(ShipModel(SHIP, REQUIRED_EFFECTS)), short_programme()[:1])
    with pytest.raises((FitError, ValueError), match=message):
        fit(ShipModel(SHIP, REQUIRED_EFFECTS), logs, terms)
    with pytest.raises(FitError, match="unknown nuisance terms"):
        FitOptions(nuisance=("yaw",))


def test_the_batched_jacobian_is_the_derivative_of_the_residual():
    """Each column of ``Problem.jacobian`` (forward differences, every perturbation in one batch,
    replays a term cannot move skipped after the first call) against central differences of the
    residual itself. A forward difference with step h errs by h/2 times the second derivative, which
    the same three points estimate: the two must agree within that (and the rounding of the residual
    over h), not within a tolerance chosen to pass."""
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "rudder_offset", "current"]), 0.02, -0.01)
    logs = sail_all(truth, short_programme(), seed=6)
    setup = ReplayModel(truth.model.with_effects())
    keys = ["yaw.gain", "yaw.time_constant", "rudder_offset.angle", "current.north", "current.east"]
    problem = Problem(setup, logs, keys, FitOptions(nuisance=("heading",)))
    x = problem.start() + 0.1
    first, again = problem.jacobian(x), problem.jacobian(x)
    np.testing.assert_array_equal(again, first)  # the skipped replays were exactly zero
    h = DIFFERENCE_STEP
    base = problem.residual(x)
    rounding = 4.0 * np.finfo(float).eps * (np.abs(base) + 1.0) / h
    for j in range(problem.size):
        step = np.zeros(problem.size)
        step[j] = h
        ahead, behind = problem.residual(x + step), problem.residual(x - step)
        central = (ahead - behind) / (2.0 * h)
        curvature = np.abs(ahead - 2.0 * base + behind) / h**2
        assert np.all(np.abs(first[:, j] - central) <= 0.5 * h * curvature + rounding), keys[j : j + 1] or j
        assert np.any(first[:, j] != 0.0)


@pytest.mark.parametrize("effects", [EVERY_EFFECT, [e for e in EVERY_EFFECT if e != "wind_moment"]])
def test_a_term_moves_exactly_the_replays_its_equations_say(effects):
    """``moved_replays`` reads from the equations which replays a term can move: a changed term must
    leave the others bit for bit as they were (the Jacobian skips them) and move the ones it names.
    Without the wind moment the sway and the current move only the track; with it, the heading too."""
    setup = ReplayModel(ShipModel(SHIP, effects), 0.02, -0.03)
    logs = sail_all(setup, short_programme(), seed=3)
    before = simulate(setup, logs)
    moved = {}
    for key in default_terms(setup.model.effects):
        term = make_term(key, setup)
        value = value_of(setup, key) + term.scale
        after = simulate(with_values(setup, {key: value if value <= term.upper else value - 2 * term.scale}), logs)
        free = any(not np.array_equal(a.heading, b.heading) for a, b in zip(after, before, strict=True))
        track = any(not np.array_equal(a.track_north, b.track_north) for a, b in zip(after, before, strict=True))
        moved[key] = (free, track)
        assert moved[key] == moved_replays(setup.model, key), key
    assert moved["yaw.gain"] == moved["steering_machine.rudder_rate"] == (True, False)
    assert (
        moved["current.north"] == moved["sway.linear"] == ((True, True) if "wind_moment" in effects else (False, True))
    )


def test_propeller_astern_moves_no_replay_of_logs_that_never_reverse_the_propeller():
    """``acts_on``: where the propeller never turns astern the effect returns what it is given, so its
    terms leave every replay bit for bit as it was (the Jacobian skips them); astern, they move the heading."""
    setup = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "propeller_slipstream", "propeller_astern"]))
    ahead = sail_all(setup, short_programme(), seed=3)
    astern = [dataclasses.replace(log, propeller_rate=-log.propeller_rate) for log in ahead]
    assert not acts_on("propeller_astern", ahead) and acts_on("propeller_astern", astern)
    assert acts_on("yaw", ahead)
    for key in ("propeller_astern.rudder_inflow", "propeller_astern.walk"):
        changed = with_values(setup, {key: value_of(setup, key) + 0.5})
        for logs, moves in ((ahead, False), (astern, True)):
            pairs = zip(simulate(changed, logs), simulate(setup, logs), strict=True)
            assert any(not np.array_equal(a.heading, b.heading) for a, b in pairs) == moves, key
    problem = Problem(setup, ahead, default_terms(setup.model.effects), FitOptions())
    jacobian = problem.jacobian(problem.start())
    columns = [j for j, term in enumerate(problem.terms) if term.effect == "propeller_astern"]
    assert len(columns) == 2 and not np.any(jacobian[:, columns]) and np.all(np.any(jacobian, axis=0)[: columns[0]])


def test_the_initial_state_of_sea_trial_logs_averages_the_compass_over_half_a_ship_length():
    """A free replay carries its initial heading to the end: at 1 Hz the first 2 s keep most of the compass's
    0.5 deg noise (a parabola through 3 samples kept all of it); with the rate gyro integrated over the time to
    sail half a ship length (20 s for the 320 m tanker at 7.97 m/s, 21 samples) it falls by sqrt(21). The window
    scales with the ship: 5 s for the 3 m Esso Osaka model at 0.3 m/s, at least 2 s, at most half the run."""
    tanker = ShipModel("kvlcc2", ["yaw", "norrbin", "kinematics"])
    speed = tanker.service_speed
    run = Manoeuvre("z", "zigzag", math.radians(10.0), 600.0, approach=60.0, start_speed=speed, final_speed=speed)
    (exact,) = sail_all(ReplayModel(tanker), [run], seed=1, settings=LogSettings(dt=1.0, noise=NO_NOISE))
    assert initial_window(exact, tanker.length, speed) == pytest.approx(0.5 * tanker.length / speed)
    esso = ShipModel(SHIP)
    assert initial_window(exact, esso.length, esso.service_speed) == pytest.approx(5.0, rel=0.01)
    assert initial_window(exact, esso.length, 100.0) == 2.0
    short = dataclasses.replace(run, duration=30.0, approach=10.0)
    (brief,) = sail_all(ReplayModel(tanker), [short], seed=1, settings=LogSettings(dt=1.0, noise=NO_NOISE))
    assert initial_window(brief, tanker.length, speed) == 15.0

    rng = np.random.default_rng(5)
    errors = {"2 s": [], "scaled": []}
    for _ in range(100):
        noisy = dataclasses.replace(
            exact,
            heading=exact.heading + rng.normal(0.0, SEA_TRIAL_NOISE.heading, exact.samples),
            rate_of_turn=exact.rate_of_turn + rng.normal(0.0, SEA_TRIAL_NOISE.rate_of_turn, exact.samples),
        )
        for name, window in (("2 s", 2.0), ("scaled", initial_window(noisy, tanker.length, speed))):
            errors[name].append(initial_state(noisy, window)[S.HEADING] - exact.heading[0])
    spread = {name: float(np.sqrt(np.mean(np.square(e)))) / SEA_TRIAL_NOISE.heading for name, e in errors.items()}
    assert spread["2 s"] > 0.45  # the mean of 3 samples: 1 / sqrt(3) = 0.58
    assert spread["scaled"] < 0.3  # of 21: 1 / sqrt(21) = 0.22, with the integrated gyro's share
