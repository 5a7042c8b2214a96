"""The track predictor: the closed-loop prediction of the track for a trial heading (thesis ch. 3, 5.6).

Prediction model (the basic prediction scheme, Fig. 3.14): the first-order Nomoto ship steered by
the PD autopilot, sailing at the constant predicted speed U_p (3.96: the speed at the start),
with sway proportional to the rate of turn:

    tau* (L/U_p) dr_p/dt + r_p = K* (U_p/L) delta_p                                    (3.71)
    delta_p = clip(K_p (psi_t - psi_p) - K_d r_p, -delta_tmax, delta_tmax)             (3.45)
    v_p = -gamma_p r_p                                                                  (3.74)
    dx_p/dt = U_p cos psi_p - v_p sin psi_p,   dy_p/dt = U_p sin psi_p + v_p cos psi_p  (3.88, 3.89)

for a trial heading psi_t and trial rudder limit delta_tmax; K_p, K_d are scheduled on U_p as the
ship's autopilot is (3.52), so the prediction matches the ship in the distance domain whatever
U_p (3.55, 3.56). The actual rudder follows delta_p at the steering machine's rate (Fig. 2.9).
Each sample, r_p is advanced exactly for a rudder held at its mean over the sample (the steering
machine moves it linearly), psi_p by the trapezoid rule and the position at the mid-sample
heading. The current is not part of the model: the track adaptation adds it (5.113-5.116).

The result, :class:`PredictedTrack`, carries the predicted time series; its methods are the
track adaptation of 5.6.2.2 / 6.3.4 and the translation of 3.2.3:

- :meth:`PredictedTrack.adapted`: the track scaled by 1/K_rho about its start (5.102, 5.103: a
  ship turning K_rho times faster in s* sails the same turn shrunk by K_rho) plus the estimated
  current times the prediction's time, x_p(i) = x_0(i) / K_rho + u_c i T_s (6.3.4, 5.115, 5.116).
- :meth:`PredictedTrack.translated`: the part of the track still ahead, moved so that its point
  of the ship's present heading lies on the ship's present position (heading correspondence,
  3.30: psi_p = psi_s).
- :meth:`PredictedTrack.normalised_rate_at`: r_p*(psi), the look-up the track-scaling estimator
  (:mod:`ship_env.baselines.track_scaling`) observes K_rho through (5.111).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDDesign


@dataclass(frozen=True)
class ShipSituation:
    """Where the prediction starts: the filtered state of the ship.

    Attributes:
        north, east: position, m.
        heading: psi, rad, unwrapped.
        rate_of_turn: r, rad/s.
        rudder: actual rudder, rad.
        speed: forward speed, m/s (becomes U_p).
    """

    north: float
    east: float
    heading: float
    rate_of_turn: float
    rudder: float
    speed: float


@dataclass(frozen=True)
class PredictedTrack:
    """A predicted track: samples i = 0..N from the start, arrays of N + 1.

    Attributes:
        time: t_i, s since the start.
        north, east: positions, m.
        heading: psi_p, rad, unwrapped.
        rate_of_turn: r_p, rad/s.
        rudder: the predicted actual rudder, rad.
        speed: U_p, m/s.
        length: L, m.
    """

    time: np.ndarray
    north: np.ndarray
    east: np.ndarray
    heading: np.ndarray
    rate_of_turn: np.ndarray
    rudder: np.ndarray
    speed: float
    length: float

    @property
    def positions(self) -> np.ndarray:
        """(N + 1, 2) north, east, m."""
        return np.column_stack([self.north, self.east])

    @property
    def turn_direction(self) -> float:
        """+1 if the track turns to starboard overall, -1 to port."""
        return 1.0 if self.heading[-1] >= self.heading[0] else -1.0

    def _heading_progress(self) -> tuple[np.ndarray, int]:
        """Heading change made good, in the turn's direction, and the index up to which it only grows."""
        progress = self.turn_direction * (self.heading - self.heading[0])
        end = int(np.argmax(progress))
        return progress, end

    @property
    def largest_normalised_rate(self) -> float:
        """max |r_p*| over the track."""
        return float(np.max(np.abs(self.rate_of_turn))) * self.length / self.speed

    def normalised_rate_at(self, heading: float) -> float:
        """r_p* = L r_p / U_p at the point where the prediction reaches ``heading`` (rad, unwrapped), 5.111.

        Looked up on the part of the turn where the heading only moves on; beyond its ends the
        end values hold.
        """
        progress, end = self._heading_progress()
        normalised = self.length * self.rate_of_turn / self.speed
        return float(
            np.interp(self.turn_direction * (heading - self.heading[0]), progress[: end + 1], normalised[: end + 1])
        )

    def adapted(self, scaling: float, current: tuple[float, float]) -> PredictedTrack:
        """x_p(i) = x_0(i) / K_rho + u_c t_i about the start (6.3.4): the positions adapted, the time base kept."""
        if not scaling > 0.0:
            raise ValueError(f"scaling: expected K_rho > 0, got {scaling!r}")
        return replace(
            self,
            north=self.north[0] + (self.north - self.north[0]) / scaling + current[0] * self.time,
            east=self.east[0] + (self.east - self.east[0]) / scaling + current[1] * self.time,
        )

    def translated(self, heading: float, north: float, east: float) -> PredictedTrack:
        """The rest of the track from the point of heading ``heading``, moved onto (north, east) (3.30)."""
        progress, end = self._heading_progress()
        reached = self.turn_direction * (heading - self.heading[0])
        index = int(np.clip(np.searchsorted(progress[: end + 1], reached), 0, len(self.time) - 1))
        return replace(
            self,
            time=self.time[index:] - self.time[index],
            north=self.north[index:] - self.north[index] + north,
            east=self.east[index:] - self.east[index] + east,
            heading=self.heading[index:],
            rate_of_turn=self.rate_of_turn[index:],
            rudder=self.rudder[index:],
        )


@dataclass(frozen=True)
class TrackPredictor:
    """The prediction model of Fig. 3.14 (see the module docstring).

    Attributes:
        ship: K*, tau* of the prediction model (the yaw filter's or the reference model's).
        length: L, m.
        autopilot: the PD autopilot's tuning, the one the ship sails with (its rudder limit is
            replaced by the trial rudder limit).
        sway_constant: gamma_p, m (v_p = -gamma_p r_p).
        rudder_rate: the steering machine's rate limit, rad/s.
        sample_time: T_s of the predicted samples, s.
    """

    ship: NomotoParameters
    length: float
    autopilot: PDDesign
    sway_constant: float
    rudder_rate: float
    sample_time: float = 1.0

    def predict(
        self,
        start: ShipSituation,
        trial_heading: float,
        trial_rudder_limit: float,
        horizon: float,
        delay: float = 0.0,
        present_heading: float | None = None,
    ) -> PredictedTrack:
        """The track ``horizon`` s ahead for ordering ``trial_heading`` (rad; the shorter way round).

        ``trial_rudder_limit`` (rad) limits the autopilot's rudder (the trial setting of 5.6.1).

        With ``delay`` > 0 the order is given ``delay`` s from now; until then the autopilot keeps
        steering for ``present_heading`` (rad) within the same rudder limit: the prediction of
        putting the wheel over a little later.
        """
        steps = int(math.ceil(horizon / self.sample_time))
        step = self.sample_time
        speed = start.speed
        design = replace(self.autopilot, rudder_limit=trial_rudder_limit)
        gains = design.gains(self.ship, self.length, speed)
        time_constant = self.ship.time_constant * self.length / speed
        steady_gain = self.ship.gain * speed / self.length
        decay = math.exp(-step / time_constant)
        largest_rudder_move = self.rudder_rate * step
        target = _nearest_branch(trial_heading, start.heading)
        present_target = target if present_heading is None else _nearest_branch(present_heading, start.heading)

        track = np.empty((steps + 1, 6))
        north, east, heading, rate, rudder = start.north, start.east, start.heading, start.rate_of_turn, start.rudder
        track[0] = (0.0, north, east, heading, rate, rudder)
        for i in range(1, steps + 1):
            setpoint = target if (i - 1) * step >= delay else present_target
            order = design.rudder(setpoint - heading, rate, gains)
            next_rudder = rudder + min(max(order - rudder, -largest_rudder_move), largest_rudder_move)
            next_rate = decay * rate + (1.0 - decay) * steady_gain * 0.5 * (rudder + next_rudder)
            next_heading = heading + 0.5 * step * (rate + next_rate)
            middle_heading = 0.5 * (heading + next_heading)
            sway = -self.sway_constant * 0.5 * (rate + next_rate)
            north += step * (speed * math.cos(middle_heading) - sway * math.sin(middle_heading))
            east += step * (speed * math.sin(middle_heading) + sway * math.cos(middle_heading))
            rudder, rate, heading = next_rudder, next_rate, next_heading
            track[i] = (i * step, north, east, heading, rate, rudder)
        times, norths, easts, headings, rates, rudders = track.T
        return PredictedTrack(times, norths, easts, headings, rates, rudders, speed=speed, length=self.length)


def _nearest_branch(angle: float, reference: float) -> float:
    """``angle`` plus whole turns, within half a turn of ``reference`` (rad)."""
    return reference + (angle - reference + math.pi) % (2.0 * math.pi) - math.pi
