"""Turning circle at a chosen rudder angle (MSC.137(76) 4.2.2-4.2.4, MSC/Circ.1053 2.2.1).

From a steady straight approach at the test speed the rudder is ordered to the turning angle
(35 deg, or the largest the ship allows, for the IMO figures) and held while the ship turns three
full circles. Figures, all measured from the midship point and towards the side of the turn, so a
port turn gives positive figures too:

- **advance**: distance travelled in the direction of the original course from the position at
  which the rudder order is given to the position at which the heading has changed 90 deg
  (MSC.137(76) 4.2.3);
- **transfer**: distance travelled perpendicular to the original course up to the same moment;
- **tactical diameter**: distance travelled perpendicular to the original heading up to the
  moment the heading has changed 180 deg (MSC.137(76) 4.2.4);
- **steady turning radius**, from the steady part of the turn (the last full circle), twice:
  R = U/r with U the speed over the ground, and the radius of the circle fitted to the track;
- **steady rate of turn** r, **speed loss** 1 - u/V of the forward speed (the thesis's u*, 2.41),
  **drift angle** beta between the heading and the track (positive with the bow inside the circle);
- **times to 90 and 180 deg** heading change from the rudder order.

For the first-order Nomoto ship (2.58, 2.61) the steady turn is r = K delta = K* (u/L) delta, so
R = u/r = L / (K* delta): a check on the simulator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ship_env.manoeuvres.results import Figure, ManoeuvreResult, metre_digits
from ship_env.manoeuvres.series import first_crossing, value_at, velocity_over_ground, wrap_angle
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.manoeuvres.trial import check_rudder_angle, rudder_label, run_trial
from ship_env.model import ShipModel

#: Full circles the trial sails; the last one is the steady part. Three leave the first-order
#: transients of yaw (tau* = 1.7 ship lengths) and speed (tau_u* = 4) of the presets well behind.
TURNING_CIRCLES = 3


@dataclass(frozen=True)
class TurningCircle(ManoeuvreResult):
    """Figures of a turning circle, SI units and radians (see the module docstring).

    Attributes:
        rudder_angle: the ordered rudder, rad (positive: starboard).
        advance, transfer, tactical_diameter: m.
        steady_radius: U/r in the steady turn, m.
        fitted_radius: radius of the circle fitted to the steady part of the track, m.
        steady_rate_of_turn: r in the steady turn, rad/s, positive towards the turn.
        steady_speed: forward speed u in the steady turn, m/s.
        speed_loss: 1 - u/V in the steady turn.
        drift_angle: drift angle in the steady turn, rad, positive with the bow inside the circle.
        time_to_90, time_to_180: s from the rudder order to 90 and 180 deg of heading change.
    The steady figures are NaN when the ship does not complete its circles in the allowed time.
    """

    manoeuvre = "turning circle"

    rudder_angle: float
    advance: float
    transfer: float
    tactical_diameter: float
    steady_radius: float
    fitted_radius: float
    steady_rate_of_turn: float
    steady_speed: float
    speed_loss: float
    drift_angle: float
    time_to_90: float
    time_to_180: float

    @property
    def label(self) -> str:
        return rudder_label(self.rudder_angle)

    def figures(self) -> tuple[Figure, ...]:
        length, digits = self.length, metre_digits(self.length)
        return (
            Figure("advance", "advance", self.advance, "m", digits),
            Figure("advance_lengths", "advance", self.advance / length, "L", 2),
            Figure("transfer", "transfer", self.transfer, "m", digits),
            Figure("tactical_diameter", "tactical diameter", self.tactical_diameter, "m", digits),
            Figure("tactical_diameter_lengths", "tactical diameter", self.tactical_diameter / length, "L", 2),
            Figure("steady_radius", "steady radius U/r", self.steady_radius, "m", digits),
            Figure("fitted_radius", "steady radius, fitted circle", self.fitted_radius, "m", digits),
            Figure("steady_rate_of_turn", "steady rate of turn", math.degrees(self.steady_rate_of_turn), "deg/s", 3),
            Figure("speed_loss", "speed loss in steady turn", 100.0 * self.speed_loss, "%", 1),
            Figure("drift_angle", "drift angle in steady turn", math.degrees(self.drift_angle), "deg", 1),
            Figure("time_to_90", "time to 90 deg", self.time_to_90, "s", 0),
            Figure("time_to_180", "time to 180 deg", self.time_to_180, "s", 0),
        )


def fitted_circle_radius(north: np.ndarray, east: np.ndarray) -> float:
    """Radius of the least-squares circle through a track, m (algebraic fit, Kasa 1976).

    Solves n^2 + e^2 = 2 a n + 2 b e + c for the centre (a, b); the radius is sqrt(c + a^2 + b^2).
    """
    design = np.column_stack((2.0 * north, 2.0 * east, np.ones_like(north)))
    (centre_north, centre_east, offset), *_ = np.linalg.lstsq(design, north**2 + east**2, rcond=None)
    return float(math.sqrt(offset + centre_north**2 + centre_east**2))


def turning_circle(
    model: ShipModel,
    rudder_angle: float = math.radians(35.0),
    settings: TrialSettings = TrialSettings(),
    max_lengths: float = 1000.0,
) -> TurningCircle:
    """Sail a turning circle and read its figures.

    Args:
        model: the ship model.
        rudder_angle: the ordered rudder, rad; negative turns to port.
        settings: approach speed and integration step.
        max_lengths: the longest the trial may last, in ship lengths sailed at the approach speed.
    """
    rudder_angle = check_rudder_angle(model, rudder_angle)
    turn = math.copysign(1.0, rudder_angle)
    series = run_trial(
        model,
        settings,
        lambda simulator: rudder_angle,
        labels=[rudder_label(rudder_angle)],
        duration=settings.seconds_for(model, max_lengths),
        stop=lambda simulator: turn * simulator.heading[0] >= TURNING_CIRCLES * 2.0 * math.pi,
    )
    time, north, east = (series[c].to_numpy() for c in ("time", "north", "east"))
    heading_change = turn * series["heading"].to_numpy()
    across = turn * east  # towards the side of the turn
    time_to_90 = first_crossing(time, heading_change, 0.5 * math.pi)
    time_to_180 = first_crossing(time, heading_change, math.pi)

    steady = heading_change >= (TURNING_CIRCLES - 1) * 2.0 * math.pi
    completed = heading_change[-1] >= TURNING_CIRCLES * 2.0 * math.pi
    if completed:
        north_rate, east_rate = velocity_over_ground(time, north, east)
        course = np.arctan2(east_rate, north_rate)
        steady_rate = float(np.mean(turn * series["rate_of_turn"].to_numpy()[steady]))
        steady_ground_speed = float(np.mean(np.hypot(north_rate, east_rate)[steady]))
        steady_speed = float(np.mean(series["speed"].to_numpy()[steady]))
        drift_angle = float(np.mean(turn * wrap_angle(series["heading"].to_numpy() - course)[steady]))
        fitted_radius = fitted_circle_radius(north[steady], east[steady])
    else:
        steady_rate = steady_ground_speed = steady_speed = drift_angle = fitted_radius = math.nan
    approach_speed = settings.approach_speed(model)
    return TurningCircle.sailed(
        model,
        settings,
        series,
        rudder_angle=rudder_angle,
        advance=value_at(time, north, time_to_90),
        transfer=value_at(time, across, time_to_90),
        tactical_diameter=value_at(time, across, time_to_180),
        steady_radius=steady_ground_speed / steady_rate,
        fitted_radius=fitted_radius,
        steady_rate_of_turn=steady_rate,
        steady_speed=steady_speed,
        speed_loss=1.0 - steady_speed / approach_speed,
        drift_angle=drift_angle,
        time_to_90=time_to_90,
        time_to_180=time_to_180,
    )
