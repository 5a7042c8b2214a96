"""Zig-zag test a/b (MSC.137(76) 4.2.5-4.2.9, MSC/Circ.1053 2.2.1).

From a steady straight approach the rudder is put over to a deg (first execute). When the heading
has changed b deg off the original heading the rudder is reversed to a deg to the other side
(second execute); when the heading has changed b deg to that side it is reversed again (third
execute), and so on. The trial here runs to the fifth execute, two full swings. Figures:

- **first overshoot angle**: the additional heading deviation beyond b after the second execute
  (MSC.137(76) 4.2.7), read where the rate of turn passes zero;
- **second overshoot angle**: the same beyond b to the other side after the third execute (4.2.8);
- **initial turning time**: time from the first execute to the heading change b, the moment of
  the second execute;
- **initial turning distance**: the distance sailed along the track in that time; with a = b = 10 deg
  it is the IMO initial turning ability (MSC.137(76) 5.3.2: at most 2.5 L);
- **time to check yaw**: time from the second execute to the peak of the first overshoot, when the
  rate of turn has fallen to zero.

The helmsman reverses the rudder at the first step that finds the heading past b, so the executes
fall on the integration steps, up to dt after the heading crossing; the initial turning time and
distance are read at the crossing itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ship_env.manoeuvres.results import Figure, ManoeuvreResult, degrees_label
from ship_env.manoeuvres.series import distance_sailed, first_crossing, value_at
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import check_rudder_angle, run_trial
from ship_env.model import ShipModel, Simulator

#: Executes the trial runs to: the fifth reverses the rudder after the second overshoot.
EXECUTES = 5


@dataclass(frozen=True)
class ZigZag(ManoeuvreResult):
    """Figures of a zig-zag test, SI units and radians (see the module docstring).

    Attributes:
        rudder_angle: a, rad; positive puts the rudder to starboard first.
        heading_change: b, rad, the heading deviation that triggers each reversal (positive).
        first_overshoot, second_overshoot: rad.
        initial_turning_time: s from the first execute to the heading change b.
        initial_turning_distance: m sailed along the track in that time.
        time_to_check_yaw: s from the second execute to the first overshoot's peak.
    A figure is NaN when its event does not occur in the allowed time.
    """

    manoeuvre = "zig-zag"

    rudder_angle: float
    heading_change: float
    first_overshoot: float
    second_overshoot: float
    initial_turning_time: float
    initial_turning_distance: float
    time_to_check_yaw: float

    @property
    def label(self) -> str:
        return zigzag_label(self.rudder_angle, self.heading_change)

    def figures(self) -> tuple[Figure, ...]:
        return (
            Figure("first_overshoot", "first overshoot angle", math.degrees(self.first_overshoot), "deg", 1),
            Figure("second_overshoot", "second overshoot angle", math.degrees(self.second_overshoot), "deg", 1),
            Figure("initial_turning_time", "initial turning time (to 2nd execute)", self.initial_turning_time, "s", 0),
            Figure(
                "initial_turning_distance_lengths",
                "distance sailed to 2nd execute",
                self.initial_turning_distance / self.length,
                "L",
                2,
            ),
            Figure("time_to_check_yaw", "time to check yaw", self.time_to_check_yaw, "s", 0),
        )


def zigzag_label(rudder_angle: float, heading_change: float) -> str:
    """The test's name "a/b" in degrees, signed like the first rudder ("10/10", "-20/-20")."""
    return f"{degrees_label(rudder_angle)}/{degrees_label(math.copysign(heading_change, rudder_angle))}"


class ZigZagHelmsman:
    """The rudder law of a zig-zag test: reverse the rudder whenever the heading passes +-b.

    Args:
        rudder_angle: a, rad; its sign says which side the rudder goes first.
        heading_change: b, rad, positive.
        original_heading: the heading at the first execute, rad, that b is counted off (a trial starts on 0).
    """

    def __init__(self, rudder_angle: float, heading_change: float, original_heading: float = 0.0) -> None:
        self.rudder_angle = abs(rudder_angle)
        self.heading_change = heading_change
        self.original_heading = original_heading
        self.side = math.copysign(1.0, rudder_angle)
        self.executes = 1

    def __call__(self, simulator: Simulator) -> float:
        if self.side * (simulator.heading[0] - self.original_heading) >= self.heading_change:
            self.side = -self.side
            self.executes += 1
        return self.side * self.rudder_angle


def zigzag(
    model: ShipModel,
    rudder_angle: float = math.radians(10.0),
    heading_change: float = math.radians(10.0),
    settings: TrialSettings = TrialSettings(),
    max_lengths: float = 200.0,
) -> ZigZag:
    """Sail a zig-zag test a/b and read its figures.

    Args:
        model: the ship model.
        rudder_angle: a, rad; negative starts to port (the mirrored test).
        heading_change: b, rad, a positive heading deviation.
        settings: approach speed and integration step.
        max_lengths: the longest the trial may last, in ship lengths sailed at the approach speed.
    """
    rudder_angle = check_rudder_angle(model, rudder_angle)
    if not (math.isfinite(heading_change) and heading_change > 0.0):
        raise ValueError(f"heading_change: expected a positive angle in rad, got {heading_change!r}")
    helmsman = ZigZagHelmsman(rudder_angle, heading_change)
    series = run_trial(
        model,
        settings,
        helmsman,
        labels=[zigzag_label(rudder_angle, heading_change)],
        duration=settings.seconds_for(model, max_lengths),
        stop=lambda simulator: helmsman.executes >= EXECUTES,
    )
    time, rate_of_turn = series["time"].to_numpy(), series["rate_of_turn"].to_numpy()
    deviation = math.copysign(1.0, rudder_angle) * series["heading"].to_numpy()  # towards the first rudder
    orders = series["ordered_rudder"].to_numpy()
    executes = np.concatenate(([time[0]], time[1:][np.diff(orders) != 0.0]))
    second, third = (float(executes[i]) if executes.size > i else math.nan for i in (1, 2))
    first_peak = first_crossing(time, rate_of_turn, 0.0, after=second)
    second_peak = first_crossing(time, rate_of_turn, 0.0, after=third)
    heading_change_reached = first_crossing(time, deviation, heading_change)
    track = distance_sailed(series["north"].to_numpy(), series["east"].to_numpy())
    return ZigZag.sailed(
        model,
        settings,
        series,
        rudder_angle=rudder_angle,
        heading_change=heading_change,
        first_overshoot=value_at(time, deviation, first_peak) - heading_change,
        second_overshoot=-value_at(time, deviation, second_peak) - heading_change,
        initial_turning_time=heading_change_reached - executes[0],
        initial_turning_distance=value_at(time, track, heading_change_reached),
        time_to_check_yaw=first_peak - second,
    )
