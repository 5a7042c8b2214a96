"""Checks the effects that force the speed loss (2.55) share: a hard-over turn sailed with and without the effect at
its null, the steady part of a turning circle, and a hidden value recovered by a fit that adds the effect."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ship_env.manoeuvres import turning_circle
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import run_trial
from ship_env.model import REQUIRED_EFFECTS, ShipModel
from ship_env.workbench import FitOptions
from ship_env.workbench.fitting.fit import Estimate, fit
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.synthetic.synthetic import SensorNoise, model_test_programme, noise_scales, sail_all

HARD_OVER = math.radians(35.0)


def assert_same_hard_over_turn(first: ShipModel, second: ShipModel) -> None:
    """The two models sail a 900 s hard-over turn bit for bit alike."""
    frames = [
        run_trial(model, TrialSettings(), lambda simulator: HARD_OVER, ["turn"], 900.0) for model in (first, second)
    ]
    np.testing.assert_array_equal(frames[1].to_numpy(), frames[0].to_numpy())


def steady_turn(model: ShipModel, rudder: float = HARD_OVER) -> tuple[float, float]:
    """(r*, u*) in the steady part of a turning circle."""
    circle = turning_circle(model, rudder)
    speed = model.service_speed * (1.0 - circle.speed_loss)
    return model.length * abs(circle.steady_rate_of_turn) / speed, circle.speed_loss


def recovered(effect: str, values: Mapping[str, float], key: str, ship: str = "esso_osaka_model") -> Estimate:
    """``key``'s estimate from logs sailed with the speed loss and ``effect`` at ``values`` on the 3 m model's test
    programme (zig-zags and hard-over turns) with a basin's sensors and the speed measured, by a fit of the model
    with the effect added."""
    effects: Sequence[str] = [*REQUIRED_EFFECTS, "speed_loss", effect]
    logs = sail_all(ReplayModel(ShipModel(ship, effects, values)), model_test_programme(ship=ship), seed=4)
    result = fit(ShipModel(ship, effects), logs, options=FitOptions(scales=noise_scales(SensorNoise())))
    (estimate,) = [e for e in result.estimates if e.term.key == key]
    print(f"\n{key} = {estimate.value:.3f} +- {estimate.std_error:.3f} (truth {values[key]})")
    return estimate
