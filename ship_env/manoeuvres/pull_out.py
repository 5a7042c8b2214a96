"""Pull-out test (MSC/Circ.1053 2.2.1; Burcher's test of straight-line stability).

The ship turns steadily with the rudder at delta, one batched ship to starboard and one to port;
then the rudder is returned to midships and the rate of turn decays. With the rudder at zero the
thesis's yaw equation (2.43) reads tau* dr*/ds* + H(r*) = 0: the rate settles where H(r*) = 0.
A course-stable ship has one such rate, so both ships settle to it (zero for a symmetric ship,
alpha0 = 0 in 2.27); a course-unstable ship keeps turning each way, and the difference of the two
residual rates is the height of its spiral loop. Figures, per side:

- **steady rate of turn** at the moment the rudder is returned, positive towards the turn;
- **residual rate of turn** at the end of the test, positive when the ship keeps turning the way it
  turned: for a symmetric ship a positive residual means course instability;
- **course stable**: whether both sides settle to the same rate (within 1 % of the steady rate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ship_env.manoeuvres.results import Figure, ManoeuvreResult, degrees_label
from ship_env.manoeuvres.series import value_at
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import check_rudder_angle, rudder_label, run_trial
from ship_env.model import ShipModel, Simulator

#: Largest difference of the two sides' residual rates, as a fraction of the steady rate, that
#: still counts as one settled rate (a course-stable ship).
STABILITY_TOLERANCE = 0.01


@dataclass(frozen=True)
class PullOut(ManoeuvreResult):
    """Figures of a pull-out test, rad/s (see the module docstring).

    Attributes:
        rudder_angle: |delta| of the steady turns before the pull-out, rad.
        steady_rate_starboard, steady_rate_port: rate of turn when the rudder is returned, rad/s,
            positive towards the turn.
        residual_rate_starboard, residual_rate_port: rate of turn at the end, rad/s, positive
            when the ship keeps turning the way it turned.
    """

    manoeuvre = "pull-out"

    rudder_angle: float
    steady_rate_starboard: float
    steady_rate_port: float
    residual_rate_starboard: float
    residual_rate_port: float

    @property
    def label(self) -> str:
        return f"{degrees_label(self.rudder_angle)} deg"

    @property
    def course_stable(self) -> bool:
        """Whether both sides settle to one rate of turn: the ship is straight-line stable."""
        settled_rates_apart = abs(self.residual_rate_starboard + self.residual_rate_port)
        return settled_rates_apart <= STABILITY_TOLERANCE * max(self.steady_rate_starboard, self.steady_rate_port)

    def figures(self) -> tuple[Figure, ...]:
        rates = (
            ("steady_rate_starboard", "steady rate of turn, stbd", self.steady_rate_starboard, 3),
            ("residual_rate_starboard", "residual rate of turn, stbd", self.residual_rate_starboard, 4),
            ("steady_rate_port", "steady rate of turn, port", self.steady_rate_port, 3),
            ("residual_rate_port", "residual rate of turn, port", self.residual_rate_port, 4),
        )
        return (
            *(Figure(key, label, math.degrees(rate), "deg/s", digits) for key, label, rate, digits in rates),
            Figure("course_stable", "course stable", "yes" if self.course_stable else "no", ""),
        )


def pull_out(
    model: ShipModel,
    rudder_angle: float = math.radians(20.0),
    settings: TrialSettings = TrialSettings(),
    turn_lengths: float = 40.0,
    pull_out_lengths: float = 30.0,
) -> PullOut:
    """Sail a pull-out test to both sides and read its figures.

    Args:
        model: the ship model.
        rudder_angle: the rudder of the steady turns, rad (its sign does not matter).
        settings: approach speed and integration step.
        turn_lengths: how long the ships turn before the rudder is returned, in ship lengths
            sailed at the approach speed; long enough for the turn to be steady.
        pull_out_lengths: how long the rate of turn is then left to settle, in ship lengths.
    """
    rudder_angle = abs(check_rudder_angle(model, rudder_angle))
    release_time = settings.seconds_for(model, turn_lengths)
    turning_rudders = np.array([rudder_angle, -rudder_angle])
    midships = np.zeros(2)

    def helmsman(simulator: Simulator) -> np.ndarray:
        return turning_rudders if simulator.time[0] < release_time else midships

    labels = [rudder_label(rudder_angle), rudder_label(-rudder_angle)]
    series = run_trial(
        model,
        settings,
        helmsman,
        labels=labels,
        duration=release_time + settings.seconds_for(model, pull_out_lengths),
    )
    steady_rates, residual_rates = [], []
    for label, turn in zip(labels, (1.0, -1.0), strict=True):
        run = series[series["run"] == label]
        time, rate_of_turn = run["time"].to_numpy(), turn * run["rate_of_turn"].to_numpy()
        steady_rates.append(value_at(time, rate_of_turn, release_time))
        residual_rates.append(float(rate_of_turn[-1]))
    return PullOut.sailed(
        model,
        settings,
        series,
        rudder_angle=rudder_angle,
        steady_rate_starboard=steady_rates[0],
        steady_rate_port=steady_rates[1],
        residual_rate_starboard=residual_rates[0],
        residual_rate_port=residual_rates[1],
    )
