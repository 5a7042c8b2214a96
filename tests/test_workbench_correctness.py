"""Correctness of replays and fits: no noise in a replay, the Jacobian's pattern at every point, terms the
data do not determine, replays that leave the model's validity, numerical warnings kept from the user."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from ship_env.model import ShipModel
from ship_env.workbench import FitOptions, ReplayModel, cross_validate, fit, simulate
from ship_env.workbench.diagnose import CandidateResult
from ship_env.workbench.documents import fit_document
from ship_env.workbench.errors import ErrorScales, RunErrors, pooled, pooled_jackknife, run_errors
from ship_env.workbench.fit import Problem, unknown_variances
from ship_env.workbench.improve import Rules, _terms_at_null, verdict
from ship_env.workbench.synthetic import LogSettings, SensorNoise, model_test_programme, sail_all
from ship_env.workbench.tables import error_table, estimate_table
from ship_env.workbench.terms import with_values

#: The Esso Osaka hull with the nominal coefficients these checks were designed on (not the identified preset).
SHIP = str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")
SILENT = SensorNoise(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def windy_logs(effects: list[str], seed: int = 5) -> list:
    """Two short runs in wind, sailed by a model with ``effects``."""
    truth = ReplayModel(ShipModel(SHIP, effects))
    return sail_all(truth, model_test_programme(duration=30.0)[:2], seed=seed, settings=LogSettings(noise=SILENT))


def test_a_replay_with_gusts_equals_the_one_without():
    """Gusts are zero-mean white-noise driven: a replay meets their expected value, zero, and is unchanged."""
    effects = ["yaw", "kinematics", "wind_moment"]
    logs = windy_logs(effects)
    calm = simulate(ReplayModel(ShipModel(SHIP, effects)), logs)
    gusty_model = with_values(ReplayModel(ShipModel(SHIP, [*effects, "gusts"])), {"gusts.intensity": 0.3})
    gusty = simulate(gusty_model, logs)
    for without, with_gusts in zip(calm, gusty, strict=True):
        np.testing.assert_allclose(with_gusts.heading, without.heading, rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(with_gusts.north, without.north, rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(with_gusts.track_north, without.track_north, rtol=0.0, atol=1e-12)


def test_the_jacobian_at_a_point_does_not_depend_on_the_points_before():
    """A current moves the heading only through the wind moment: at a zero yaw coefficient its heading column is
    zero, once the coefficient has grown it is not -- and the Jacobian there is a fresh problem's."""
    effects = ["yaw", "kinematics", "wind_moment", "current"]
    logs = windy_logs(effects)
    setup = with_values(ReplayModel(ShipModel(SHIP, effects)), {"wind_moment.yaw_coefficient": 0.0})
    keys = ["wind_moment.yaw_coefficient", "current.north", "current.east"]
    options = FitOptions(max_evaluations=5)
    problem = Problem(setup, logs, keys, options)
    at_zero = problem.jacobian(problem.start())
    heading_rows = problem._rows(0, track=False)
    assert not np.any(at_zero[heading_rows, 1:])  # the current cannot turn the ship without a wind moment
    coupled = problem.point_of({"wind_moment.yaw_coefficient": 0.01, "current.north": 0.05, "current.east": 0.0})
    fresh = Problem(setup, logs, keys, options).jacobian(coupled)
    assert np.any(fresh[heading_rows, 1:])
    np.testing.assert_array_equal(problem.jacobian(coupled), fresh)


def test_a_term_that_moves_nothing_is_not_determined_and_not_added():
    """Propeller walk acts only astern: on runs ahead its column is zero, its standard error infinite (not the
    pseudo-inverse's 0), and the significance gate does not read it as clear of its null value."""
    effects = ["yaw", "kinematics", "propeller_astern"]
    logs = windy_logs(["yaw", "kinematics"])
    setup = with_values(ReplayModel(ShipModel(SHIP, effects)), {"propeller_astern.walk": 0.05})
    terms = ["yaw.gain", "propeller_astern.walk"]
    fitted = fit(setup, logs, terms, FitOptions(max_evaluations=10))
    errors = {e.term.key: e.std_error for e in fitted.estimates}
    assert errors["propeller_astern.walk"] == math.inf
    assert 0.0 < errors["yaw.gain"] < math.inf
    validation = cross_validate(setup, logs, terms, FitOptions(max_evaluations=10))
    reason = _terms_at_null(CandidateResult(("propeller_astern",), cross_validation=validation))
    assert reason is not None and "propeller_astern.walk 0.0" in reason
    assert "not determined" in estimate_table(validation).text()
    document = fit_document(validation, ErrorScales())
    assert document["std_errors"]["propeller_astern.walk"] is None


def test_a_replay_that_leaves_the_models_validity_is_flagged_and_not_added():
    """A speed-loss gain of 20 stops the ship in a 35 deg turn (u* > 1): the run is flagged with the time its replay
    left validity, in its errors, the pooled row and the table, and the ladder refuses the effect."""
    base = ReplayModel(ShipModel(SHIP, ["yaw", "kinematics"]))
    programme = model_test_programme(duration=30.0)
    logs = sail_all(base, [programme[0], programme[3]], seed=5, settings=LogSettings(noise=SILENT))
    stopping = with_values(ReplayModel(ShipModel(SHIP, ["yaw", "kinematics", "speed_loss"])), {"speed_loss.gain": 20.0})
    zigzag, turn = simulate(stopping, logs)
    assert zigzag.valid and not turn.valid and 0 < turn.valid_samples < len(turn.time)
    errors = [run_errors(log, replayed) for log, replayed in zip(logs, (zigzag, turn), strict=True)]
    assert errors[0].diverged == 0 and math.isnan(errors[0].diverged_at)
    assert errors[1].diverged == 1 and errors[1].diverged_at == turn.time[turn.valid_samples]
    total = pooled(errors)
    assert total.diverged == 1
    text = error_table(errors, ErrorScales(), total).text()
    assert f"diverged at t = {errors[1].diverged_at:.1f} s" in text and "1 run diverged" in text

    options = FitOptions(max_evaluations=10)
    current = cross_validate(base, logs, ["yaw.gain"], options)
    candidate = CandidateResult(("speed_loss",), cross_validation=cross_validate(stopping, logs, ["yaw.gain"], options))
    reason = verdict(candidate, current, ErrorScales(), Rules())
    assert "leave the model's validity" in reason and "turn_35_n10 at t = " in reason


class OverflowingProblem(Problem):
    """A problem whose every residual evaluation overflows once on the way (as a diverging replay's does)."""

    overflows = 0

    def residual(self, x: np.ndarray) -> np.ndarray:
        self.overflows += 1
        np.float64(1e300) * np.float64(1e300)
        return super().residual(x)


def test_numerical_warnings_of_a_fit_are_counted_not_shown():
    logs = windy_logs(["yaw", "kinematics"])
    setup = ReplayModel(ShipModel(SHIP, ["yaw", "kinematics"]))
    problem = OverflowingProblem(setup, logs, ["yaw.gain"], FitOptions(max_evaluations=5))
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        fitted = problem.solve()
    assert [str(w.message) for w in shown if issubclass(w.category, RuntimeWarning)] == []
    ((message, count),) = fitted.warnings
    assert "overflow" in message and count == problem.overflows > 0
    assert fitted.warnings_line() == f"{count} numerical warnings while fitting ({count} x {message})"


def test_the_variances_of_a_long_jacobian_are_those_of_the_normal_equations():
    """A log's Jacobian has as many rows as samples and channels (10^5): the decomposition keeps it thin."""
    jacobian = np.random.default_rng(2).normal(size=(100_000, 3))
    expected = np.diag(np.linalg.inv(jacobian.T @ jacobian))
    np.testing.assert_allclose(unknown_variances(jacobian), expected, rtol=1e-10)
    jacobian[:, 2] = 2.0 * jacobian[:, 0]  # two terms that move the replays only together: neither is determined
    determined = np.linalg.inv(jacobian[:, :2].T @ jacobian[:, :2])[1, 1]  # the third adds nothing to the second's
    assert list(unknown_variances(jacobian)) == [math.inf, pytest.approx(determined, rel=1e-10), math.inf]


def test_the_jackknife_of_pooled_errors_is_half_the_difference_of_two_runs_and_zero_for_equal_ones():
    """Two runs: leaving one out pools the other, so the spread is |E_1 - E_2| / 2 whatever their lengths."""
    short, long = RunErrors("a", 100, 0.02, 0.001, 0.5, 0.3), RunErrors("b", 900, 0.06, 0.003, 0.5, math.nan)
    spread = pooled_jackknife([short, long])
    assert spread.heading == pytest.approx(0.02) and spread.rate_of_turn == pytest.approx(0.001)
    assert spread.position == 0.0 and math.isnan(spread.track)  # one run measures the track: no spread known
    assert pooled_jackknife([short, short, short]).heading == 0.0
    assert math.isnan(pooled_jackknife([short]).heading)
