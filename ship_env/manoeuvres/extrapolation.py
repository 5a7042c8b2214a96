"""How far a fitted preset's manoeuvres sail beyond the ranges its runs covered.

A fitted preset records the ranges its runs covered (``fitted.coverage``: r*, rudder angle, speed through the
water, drift, propeller rate; :mod:`ship_env.model.operating_point`), and a simulator sailing it warns once per
quantity where it first crosses one, with the value at that step: a hard-over turn fitted on zig-zags warns at
r* 0.5844 against the runs' 0.5842 as it passes, whatever r* it then settles at. A figure read where the ship has
gone far beyond its runs rests on the model's form, not on the runs, and its jackknife band
(:mod:`ship_env.manoeuvres.uncertainty`) does not cover that. This module says, for each manoeuvre, how far it went:
the largest r* = L |r| / max(u, u_min) (2.40), drift angle (the heading against the course over ground, where the
ship makes at least u_min) and rudder angle, and the lowest and highest speed along its time series, against the
runs' ranges.
"""

from __future__ import annotations

import numpy as np

from ship_env.manoeuvres.results import ManoeuvreResult
from ship_env.manoeuvres.series import velocity_over_ground, wrap_angle
from ship_env.model import ShipModel
from ship_env.model.operating_point import COVERAGE_QUANTITIES, FittedRanges


def beyond_coverage(result: ManoeuvreResult, model: ShipModel, ranges: FittedRanges | None = None) -> list[str]:
    """Each quantity the manoeuvre sailed beyond the fitted runs' range, in words ("r* up to 0.594 (|r*| <=
    0.584)", "speed down to 0.631 m/s (speed 0.737 to 1.18 m/s)"); none for a preset without a coverage.
    ``ranges``: the runs' ranges (default: ``model``'s preset's, ``fitted_ranges``)."""
    ranges = model.fitted_ranges if ranges is None else ranges
    if ranges is None:
        return []
    series = result.time_series
    speed = series["speed"].to_numpy()
    scheduling_speed = np.maximum(speed, model.parameter("minimum_speed"))
    rate = model.length * np.abs(series["rate_of_turn"].to_numpy()) / scheduling_speed
    north_rate, east_rate = velocity_over_ground(*(series[key].to_numpy() for key in ("time", "north", "east")))
    drift = np.abs(wrap_angle(series["heading"].to_numpy() - np.arctan2(east_rate, north_rate)))
    moving = speed >= model.parameter("minimum_speed")
    sailed = {
        "rate": (float(rate.min()), float(rate.max())),
        "drift": (0.0, float(drift[moving].max(initial=0.0))),
        "rudder": (0.0, float(np.abs(series["rudder"].to_numpy()).max())),
        "speed": (float(speed.min()), float(speed.max())),
    }
    words = []
    for quantity, (lowest, highest) in sailed.items():
        shown = COVERAGE_QUANTITIES[quantity]
        for value, limit in ranges.beyond(quantity, lowest, highest):
            covered = shown.range_words(*ranges.ranges[quantity])
            words.append(f"{shown.words} {'up' if value > limit else 'down'} to {shown.value_words(value)} ({covered})")
    return words


def hard_over_turn_beyond(model: ShipModel) -> list[str]:
    """How far ``model``'s turning circle at its rudder limit, to starboard, sails beyond its runs
    (:func:`beyond_coverage`). The turn is sailed by a copy that does not check the coverage, so that the
    simulator's warnings, said once per preset and quantity in a process, are left for a user's own sailing."""
    from ship_env.manoeuvres.turning_circle import turning_circle

    if model.fitted_ranges is None:
        return []
    return beyond_coverage(turning_circle(model.without_coverage_check(), model.rudder_limit), model)
