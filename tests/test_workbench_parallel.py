"""Fits in worker processes: the same results, bit for bit, as one after another."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import FitError, FitOptions, ReplayModel, cross_validate, diagnose
from ship_env.workbench.deciding.diagnose import Diagnosis
from ship_env.workbench.judging.validation import CrossValidation
from ship_env.workbench.synthetic.synthetic import LogSettings, model_test_programme, sail_all

SHIP = "esso_osaka_model"


def logs_with_a_rudder_offset():
    # Two of the three runs accelerate, so that each fold sees the surge time constant tau_u*.
    truth = ReplayModel(ShipModel(SHIP, [*REQUIRED_EFFECTS, "rudder_offset"]))
    return sail_all(truth, model_test_programme(duration=40.0)[1::2], seed=5, settings=LogSettings())


def assert_same(one: CrossValidation, other: CrossValidation) -> None:
    np.testing.assert_array_equal(one.fit.solution, other.fit.solution)
    np.testing.assert_array_equal(one.fit.jacobian, other.fit.jacobian)
    assert [fold.values for fold in one.folds] == [fold.values for fold in other.folds]
    assert one.held_out == other.held_out


def candidates_of(diagnosis: Diagnosis) -> list[tuple[tuple[str, ...], str, list[np.ndarray]]]:
    return [
        (
            c.effects,
            c.skipped,
            [v.fit.solution for v in (c.screened, c.cross_validation) if v is not None],
        )
        for c in diagnosis.candidates
    ]


def test_two_workers_give_the_serial_results_bit_for_bit():
    logs = logs_with_a_rudder_offset()
    base = ShipModel(SHIP, REQUIRED_EFFECTS).with_parameters({"yaw.gain": 1.0})
    serial = FitOptions(fold_method="refit")  # every fold a full fit: a task for the workers
    parallel = replace(serial, workers=2)
    assert_same(cross_validate(base, logs, options=serial), cross_validate(base, logs, options=parallel))

    current = cross_validate(base, logs)
    effects = ["rudder_offset", "propeller_slipstream", "current"]
    one = diagnose(current, logs, FitOptions(), effects)
    two = diagnose(current, logs, FitOptions(workers=2), effects)
    assert [c.effect for c in one.ranked] == [c.effect for c in two.ranked]
    for (effects_one, skipped_one, fits_one), (effects_two, skipped_two, fits_two) in zip(
        candidates_of(one), candidates_of(two), strict=True
    ):
        assert (effects_one, skipped_one) == (effects_two, skipped_two)
        for a, b in zip(fits_one, fits_two, strict=True):
            np.testing.assert_array_equal(a, b)
    assert one.best is not None and one.best.effects == ("rudder_offset",)


def test_workers_must_be_at_least_one():
    with pytest.raises(FitError, match="workers must be at least 1, got 0"):
        FitOptions(workers=0)
