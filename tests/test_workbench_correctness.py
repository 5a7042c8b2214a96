"""Correctness of replays and fits: no noise in a replay, the Jacobian's pattern at every point, terms the
data do not determine, replays that leave the model's validity, numerical warnings kept from the user."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from ship_env.model import ShipModel
from ship_env.workbench import FitOptions, ReplayModel, cross_validate, fit, simulate
from ship_env.workbench.deciding.diagnose import CandidateResult
from ship_env.workbench.deciding.improve import Rules, _terms_at_null, verdict
from ship_env.workbench.fitting.errors import ErrorScales, RunErrors, pooled, pooled_jackknife, run_errors
from ship_env.workbench.fitting.fit import Problem
from ship_env.workbench.fitting.terms import with_values
from ship_env.workbench.fitting.uncertainty import unknown_variances
from ship_env.workbench.reporting.documents import fit_document
from ship_env.workbench.reporting.tables import error_table, estimate_table
from ship_env.workbench.synthetic.synthetic import NO_NOISE, LogSettings, model_test_programme, sail_all

#: The Esso Osaka hull with the nominal coefficients these checks were designed on (not the identified preset).
SHIP = str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")


def windy_logs(effects: list[str], seed: int = 5) -> list:
    """Two short runs in wind, sailed by a model with ``effects``."""
    truth = ReplayModel(ShipModel(SHIP, effects))
    return sail_all(truth, model_test_programme(duration=30.0)[:2], seed=seed, settings=LogSettings(noise=NO_NOISE))


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
    logs = sail_all(base, [programme[0], programme[3]], seed=5, settings=LogSettings(noise=NO_NOISE))
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


class _Covariances:
    """A fit and its folds reduced to what the ladder's significance gate reads: two terms' values, standard errors
    and covariances (the Jacobian's and the jackknife's alike)."""

    def __init__(self, values: tuple[float, float], correlation: float) -> None:
        terms = [
            SimpleNamespace(key=f"norrbin.{name}", effect="norrbin", null=0.0) for name in ("odd_quadratic", "cubic")
        ]
        self.estimates = tuple(
            SimpleNamespace(term=term, value=value, std_error=1.0) for term, value in zip(terms, values, strict=True)
        )
        self.matrix = np.array([[1.0, correlation], [correlation, 1.0]])
        self.fit = self

    def covariance(self, keys):
        return self.matrix

    def jackknife_covariance(self, keys):
        return self.matrix

    def jackknife_errors(self):
        return {e.term.key: 1.0 for e in self.estimates}


@pytest.mark.parametrize(
    ("correlation", "clear"),
    [(-0.99, True), (0.0, False), (0.99, False)],
)
def test_two_correlated_terms_each_within_two_standard_errors_can_together_be_clear_of_their_nulls(correlation, clear):
    """Norrbin's |r|r and r^3 fitted on zig-zags trade one for the other: each 1.2 standard errors from 0, the pair
    is 17 apart where they are anti-correlated (-0.99: d^2 = (a^2 - 2 rho a b + b^2) / (1 - rho^2)), 1.7 apart
    where they are independent and 1.2 where they move together -- against the chi-square limit 2.49 (2 terms)."""
    fake = _Covariances((1.2, 1.2), correlation)
    reason = _terms_at_null(CandidateResult(("norrbin",), cross_validation=fake))  # type: ignore[arg-type]
    expected = math.sqrt((1.2**2 * (2.0 - 2.0 * correlation)) / (1.0 - correlation**2))
    if clear:
        assert reason is None
    else:
        assert reason is not None and "together within 2.49" in reason and f"{expected:.1f})" in reason
