"""Reversed spiral test (Bech 1968; thesis 2.26; MSC/Circ.1053 2.2.1, spiral tests).

The spiral characteristic is the steady relation between rudder angle and rate of turn,
H(r_ss) = K delta (2.26). In Bech's reversed spiral the helmsman holds the ship at a chosen rate of
turn and the mean rudder that takes is measured; unlike Dieudonne's direct spiral it traces a
course-unstable ship's characteristic through its unstable part, as one curve with no hysteresis
loop. Here one batched ship holds each rate, steered by a rate-of-turn autopilot; two more ships
with the rudder hard over give the ends of the curve and set the default rates.

The autopilot is a PI controller tuned, like the thesis's autopilots, from the ship's normalised
Nomoto parameters at its present speed u (2.61): K = K* u/L, tau = tau* L/u, ordered rudder
kp (e + (1/tau) integral of e dt) with kp = CLOSED_LOOP_GAIN / K, e the rate-of-turn error. Its
integral action leaves no steady error, so the measured points lie on the characteristic itself.

Figures: the table of steady (rudder, rate of turn) pairs, the hard-over rates of turn and whether
the ship is course stable: whether the rudder rises with the rate of turn all along the curve.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ship_env.manoeuvres.results import Figure, ManoeuvreResult
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import rudder_label, run_trial
from ship_env.model import ShipModel, Simulator

#: Open-loop gain kp K of the rate-of-turn autopilot: the closed loop settles with time constant
#: tau / CLOSED_LOOP_GAIN, and stays stable where the spiral's slope dH/dr* > -CLOSED_LOOP_GAIN.
CLOSED_LOOP_GAIN = 2.0

#: The default rates of turn span this fraction of the hard-over rates to either side.
RATE_SPAN = 0.9

#: Columns of :attr:`SpiralTest.table`: rudder (rad), rate of turn (rad/s), normalised rate of turn
#: r* = L r / u (2.40), forward speed u (m/s), and whether the point is a hard-over run.
TABLE_COLUMNS = ("rudder", "rate_of_turn", "normalised_rate", "speed", "hard_over")


@dataclass(frozen=True)
class SpiralTest(ManoeuvreResult):
    """The spiral characteristic of a ship (see the module docstring).

    Attributes:
        table: steady points sorted by rate of turn, columns :data:`TABLE_COLUMNS`.
        hard_over_rate_starboard, hard_over_rate_port: steady rates of turn with the rudder hard
            over, rad/s, positive towards the turn.
    """

    manoeuvre = "reversed spiral"

    table: pd.DataFrame = field(compare=False, repr=False)
    hard_over_rate_starboard: float
    hard_over_rate_port: float

    @property
    def label(self) -> str:
        return ""

    @property
    def course_stable(self) -> bool:
        """Whether the rudder rises with the rate of turn along the whole curve (no unstable part)."""
        return bool(np.all(np.diff(self.table["rudder"].to_numpy()) > -1e-6))

    def figures(self) -> tuple[Figure, ...]:
        starboard, port = math.degrees(self.hard_over_rate_starboard), math.degrees(self.hard_over_rate_port)
        return (
            Figure("hard_over_rate_starboard", "rate of turn, hard over stbd", starboard, "deg/s", 3),
            Figure("hard_over_rate_port", "rate of turn, hard over port", port, "deg/s", 3),
            Figure(
                "course_stable", "course stable (rudder rises with rate)", "yes" if self.course_stable else "no", ""
            ),
        )


class RateOfTurnAutopilot:
    """PI control of each ship's rate of turn to its target, gains scheduled with speed (2.61).

    Args:
        model: the ship model; its K*, tau* and length tune the gains.
        targets: the rate of turn each ship holds, rad/s.
        dt: the control step, s.
    """

    def __init__(self, model: ShipModel, targets: np.ndarray, dt: float) -> None:
        self.targets = targets
        self.dt = dt
        self.length = model.length
        self.gain = model.parameter("yaw.gain")
        self.time_constant = model.parameter("yaw.time_constant")
        self.minimum_speed = model.parameter("minimum_speed")
        self.rudder_limit = model.rudder_limit
        self.integral = np.zeros_like(targets)

    def start(self, speed: float) -> np.ndarray:
        """The linear model's rudder for each target at ``speed`` (r = K delta); primes the integral."""
        self.integral = np.clip(self.targets * self.length / (self.gain * speed), -self.rudder_limit, self.rudder_limit)
        return self.integral.copy()

    def __call__(self, simulator: Simulator) -> np.ndarray:
        speed = np.maximum(simulator.speed, self.minimum_speed)
        proportional = CLOSED_LOOP_GAIN * self.length / (self.gain * speed)  # kp = CLOSED_LOOP_GAIN / K
        nomoto_time_constant = self.time_constant * self.length / speed  # tau = tau* L / u
        error = self.targets - simulator.rate_of_turn
        order = proportional * error + self.integral
        self.integral = np.clip(
            self.integral + proportional * error * self.dt / nomoto_time_constant, -self.rudder_limit, self.rudder_limit
        )
        return order


def _steady_points(series: pd.DataFrame, labels: Sequence[str], since: float, length: float) -> pd.DataFrame:
    """Per run, the means of rudder, rate of turn and speed from ``since`` on, in ``labels`` order."""
    steady = series[series["time"] >= since].groupby("run", sort=False)[["rudder", "rate_of_turn", "speed"]].mean()
    points = steady.loc[list(labels)].reset_index(drop=True)
    points["normalised_rate"] = length * points["rate_of_turn"] / points["speed"]
    return points


def reversed_spiral(
    model: ShipModel,
    rates: Sequence[float] | None = None,
    settings: TrialSettings = TrialSettings(),
    points: int = 11,
    settle_lengths: float = 40.0,
    average_lengths: float = 5.0,
) -> SpiralTest:
    """Measure the spiral characteristic with Bech's reversed spiral, one batched ship per rate.

    Args:
        model: the ship model.
        rates: the rates of turn to hold, rad/s; ``None`` spreads ``points`` rates over
            RATE_SPAN of the hard-over rates to either side.
        settings: approach speed and integration step.
        points: how many rates to hold when ``rates`` is None.
        settle_lengths: how long each ship sails, in ship lengths at the approach speed.
        average_lengths: the steady values are the means over this last part, in ship lengths.
    """
    if rates is None and points < 2:
        raise ValueError(f"points: expected at least 2 rates of turn, got {points!r}")
    if rates is not None and (len(rates) == 0 or not np.all(np.isfinite(rates))):
        raise ValueError(f"rates: expected finite rates of turn in rad/s, got {rates!r}")
    duration = settings.seconds_for(model, settle_lengths)
    since = duration - settings.seconds_for(model, average_lengths)
    hard_over = np.array([model.rudder_limit, -model.rudder_limit])
    hard_over_labels = [rudder_label(angle) for angle in hard_over]
    hard_over_series = run_trial(model, settings, lambda simulator: hard_over, hard_over_labels, duration)
    hard_over_points = _steady_points(hard_over_series, hard_over_labels, since, model.length)
    starboard_rate, port_rate = hard_over_points["rate_of_turn"]

    if rates is None:
        fractions = np.linspace(-RATE_SPAN, RATE_SPAN, points)
        targets = np.where(fractions >= 0.0, fractions * starboard_rate, -fractions * port_rate)
    else:
        targets = np.asarray(rates, dtype=float)
    autopilot = RateOfTurnAutopilot(model, targets, settings.dt)
    held_labels = [f"r = {math.degrees(rate):+.3f} deg/s" for rate in targets]
    held_series = run_trial(
        model,
        settings,
        autopilot,
        held_labels,
        duration,
        initial_rate_of_turn=targets,
        initial_rudder=autopilot.start(settings.approach_speed(model)),
    )
    held_points = _steady_points(held_series, held_labels, since, model.length)

    table = pd.concat([held_points.assign(hard_over=False), hard_over_points.assign(hard_over=True)], ignore_index=True)
    table = table.sort_values("rate_of_turn", ignore_index=True)[list(TABLE_COLUMNS)]
    return SpiralTest.sailed(
        model,
        settings,
        pd.concat([hard_over_series, held_series], ignore_index=True),
        table=table,
        hard_over_rate_starboard=float(starboard_rate),
        hard_over_rate_port=float(-port_rate),
    )
