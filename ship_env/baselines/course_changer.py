"""The predictor-based course changer: wheel-over point and new heading from the predicted track (thesis 6.4).

The thesis's navigators sailed the reference tracks with the track predictor: set the next
leg's heading as the trial heading, watch the predicted track, and execute when it lands on the
next leg, allowing for the current (6.4.2, 6.4.4.2). This automates that, on the thesis's
PRESYS chain (Figs. 5.9, 5.16, 5.19): the yaw filter inside the autopilot (MRAC or indirect
adaptive), the position filter fed by the yaw filter, the track predictor with the autopilot's
model and tuning, and the track-scaling factor K_rho.

On a leg k (waypoint k to k + 1, course chi_k), every sample:

- **track keeping**: the heading that makes the course over the ground run back onto the leg,
  chi_d = chi_k - clip(atan(e / Delta), +-c_max) with e the filtered position's signed distance
  from the leg (positive to starboard) and Delta a look-ahead distance, corrected for the
  estimated current u_c (which holds the wind's leeway too): psi = chi_d - asin(u_c,perp / u),
  u_c,perp the current's component to starboard of chi_d;
- **wheel-over** (every ``decision_interval`` s within ``approach_distance`` of the waypoint, once
  the position filter's current is settled: its standard deviation below ``settled_current`` times
  the speed, about 25 s after a start for the container ship, so a ship started near a turn does
  not turn on the filter's first guess of the current): the
  trial heading psi_t for leg k + 1 (its course corrected for the current likewise), predicted
  for executing now and for executing one decision interval later, both adapted with K_rho and
  the current (6.3.4). Their mean squared distance to the reference track over the turn is
  compared; the wheel goes over at the first decision where now is no worse than later (the
  wheel-over point that lands the ship on the next leg). A ship already past the waypoint
  (along the leg) turns at once.
- **turning**: the autopilot steers for psi_t; K_rho is estimated against the wheel-over
  prediction (5.110-5.112); when the heading is within ``settle_band`` of psi_t, track keeping
  on leg k + 1 takes over. K_rho is kept from turn to turn: the next wheel-over decision uses it.

The decisions read the filters' estimates of the previous sample (the autopilot steps the yaw
filter when it orders the rudder).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ship_env.baselines.measurement import Measurement, wrap_angle
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.pd_autopilot import PDDesign
from ship_env.baselines.position_filter import PositionFilter
from ship_env.baselines.track_predictor import PredictedTrack, ShipSituation, TrackPredictor
from ship_env.baselines.track_scaling import TrackScalingEstimator
from ship_env.baselines.yaw_filter import YawFilter
from ship_env.envs.ship_scales import ShipScales
from ship_env.envs.tracks import ReferenceTrack, cross_track_error


class FilteredAutopilot(Protocol):
    """An autopilot steering on its yaw filter, with the model the predictor should use."""

    design: PDDesign
    yaw_filter: YawFilter

    def reset(self, measurement: Measurement) -> None: ...

    def order(self, setpoint: float, measurement: Measurement) -> float: ...

    @property
    def prediction_model(self) -> NomotoParameters: ...


@dataclass(frozen=True)
class CourseChangerSettings:
    """How the course changer sails a track.

    Attributes:
        rudder_rate: the steering machine's rate limit, rad/s (for the predictions).
        prediction_step: the predictor's sample time, s.
        decision_interval: s between wheel-over decisions (the thesis's predictor ran every 2 s, 6.2.2).
        approach_distance: m before the waypoint (along the leg) where wheel-over decisions start.
        settle_time: s the predictions run on after the turn's nominal end.
        look_ahead: Delta of the track keeping, m.
        largest_correction: c_max, the track keeping's largest heading correction, rad.
        settle_band: heading error below which a turn is over, rad.
        settled_current: the current estimate's standard deviation, as a fraction of the speed, below
            which wheel-over decisions are made (0.02: a heading error of about 1 deg from the current).
    """

    rudder_rate: float
    prediction_step: float = 2.0
    decision_interval: float = 2.0
    approach_distance: float = 2500.0
    settle_time: float = 200.0
    look_ahead: float = 1000.0
    largest_correction: float = math.radians(10.0)
    settle_band: float = math.radians(3.0)
    settled_current: float = 0.02

    def for_ship(self, scales: ShipScales) -> CourseChangerSettings:
        """These settings, made for the reference ship, on a ship of ``scales``
        (:mod:`ship_env.envs.ship_scales`): times in L / U, distances in ship lengths, angles and
        the steering machine's rate as they are."""
        return dataclasses.replace(
            self,
            prediction_step=self.prediction_step * scales.time,
            decision_interval=self.decision_interval * scales.time,
            approach_distance=self.approach_distance * scales.length,
            settle_time=self.settle_time * scales.time,
            look_ahead=self.look_ahead * scales.length,
        )


class PredictiveCourseChanger:
    """Sails a :class:`~ship_env.envs.tracks.ReferenceTrack` with the adaptive track predictor.

    Args:
        autopilot: the autopilot (its PD tuning and rudder limit are the trial's; its yaw filter
            feeds the position filter and K_rho).
        position_filter: the position filter.
        settings: see :class:`CourseChangerSettings`.
        scaling: the K_rho estimator.
        sample_time: s between samples (the autopilot's).
    """

    def __init__(
        self,
        autopilot: FilteredAutopilot,
        position_filter: PositionFilter,
        settings: CourseChangerSettings,
        sample_time: float,
        scaling: TrackScalingEstimator | None = None,
    ) -> None:
        self.autopilot = autopilot
        self.position_filter = position_filter
        self.settings = settings
        self.sample_time = sample_time
        self.scaling = scaling or TrackScalingEstimator()
        self._track: ReferenceTrack | None = None
        self.leg = 0
        self.turning = False
        self.setpoint = 0.0
        self.wheel_over_prediction: PredictedTrack | None = None
        self._time_since_decision = 0.0
        self._first_sample = True

    # -- running --------------------------------------------------------------------------------
    def reset(self, measurement: Measurement, track: ReferenceTrack, leg: int = 0) -> None:
        """Start on ``track``'s ``leg`` (0: from its first waypoint), keeping to that leg until its wheel-over."""
        if not 0 <= leg < len(track.courses):
            raise ValueError(f"CourseChanger.reset: leg {leg} is not one of the track's 0..{len(track.courses) - 1}")
        self._track = track
        self.leg = leg
        self.turning = False
        self.wheel_over_prediction = None
        self.scaling.reset()
        self.autopilot.reset(measurement)
        yaw_filter = self.autopilot.yaw_filter
        self.position_filter.reset(measurement, yaw_filter.rate_of_turn, yaw_filter.heading)
        self.setpoint = float(track.courses[leg])
        self._time_since_decision = self.settings.decision_interval
        self._first_sample = True

    @property
    def track(self) -> ReferenceTrack:
        """The reference track being sailed (given to :meth:`reset`)."""
        if self._track is None:
            raise RuntimeError("CourseChanger: call reset(measurement, track) before sailing")
        return self._track

    def order(self, measurement: Measurement) -> float:
        """The ordered rudder for this sample, rad."""
        first_sample, self._first_sample = self._first_sample, False
        if not first_sample:
            self._plan()
        rudder = self.autopilot.order(self.setpoint, measurement)
        yaw_filter = self.autopilot.yaw_filter
        if not first_sample:
            self.position_filter.step(measurement, yaw_filter.rate_of_turn, yaw_filter.heading)
        if self.turning and self.wheel_over_prediction is not None:
            self.scaling.update(
                yaw_filter.rate_of_turn, yaw_filter.heading, self.position_filter.speed, self.wheel_over_prediction
            )
        return rudder

    # -- planning -------------------------------------------------------------------------------
    def _plan(self) -> None:
        track = self.track
        yaw_filter = self.autopilot.yaw_filter
        if self.turning:
            if abs(wrap_angle(self.setpoint - yaw_filter.heading)) < self.settings.settle_band:
                self.turning = False
            return
        self.setpoint = self._keeping_heading(self.leg)
        self._time_since_decision += self.sample_time
        last_leg = len(track.courses) - 1
        if self.leg == last_leg or self._time_since_decision < self.settings.decision_interval - 1e-9:
            return
        self._time_since_decision = 0.0
        to_go = self._distance_to_waypoint(self.leg)
        position_filter = self.position_filter
        unsettled = position_filter.current_uncertainty > self.settings.settled_current * position_filter.speed
        if to_go > self.settings.approach_distance or (unsettled and to_go >= 0.0):
            return
        trial_heading = self._course_heading(float(track.courses[self.leg + 1]))
        start = self._situation()
        predictor = self._predictor()
        horizon = self._turn_horizon(trial_heading, start)
        now = predictor.predict(start, trial_heading, self.autopilot.design.rudder_limit, horizon)
        later = predictor.predict(
            start,
            trial_heading,
            self.autopilot.design.rudder_limit,
            horizon,
            delay=self.settings.decision_interval,
            present_heading=self.setpoint,
        )
        if to_go < 0.0 or self._track_cost(now) <= self._track_cost(later):
            self.leg += 1
            self.turning = True
            self.setpoint = trial_heading
            self.wheel_over_prediction = now

    def _predictor(self) -> TrackPredictor:
        return TrackPredictor(
            self.autopilot.prediction_model,
            self.autopilot.yaw_filter.length,
            self.autopilot.design,
            self.position_filter.sway_constant,
            self.settings.rudder_rate,
            self.settings.prediction_step,
        )

    def _situation(self) -> ShipSituation:
        yaw_filter = self.autopilot.yaw_filter
        north, east = self.position_filter.position
        return ShipSituation(
            north, east, yaw_filter.heading, yaw_filter.rate_of_turn, yaw_filter.last_rudder, self.position_filter.speed
        )

    def _turn_horizon(self, trial_heading: float, start: ShipSituation) -> float:
        """The turn at full trial rudder plus ``settle_time``, s."""
        model = self.autopilot.prediction_model
        steady_rate = model.gain * start.speed / self.autopilot.yaw_filter.length * self.autopilot.design.rudder_limit
        return abs(wrap_angle(trial_heading - start.heading)) / steady_rate + self.settings.settle_time

    def _track_cost(self, prediction: PredictedTrack) -> float:
        """Mean squared distance of the adapted prediction to the reference track, m^2."""
        adapted = prediction.adapted(self.scaling.value, self.position_filter.current)
        return float(np.mean(cross_track_error(adapted.positions, self.track) ** 2))

    # -- geometry -------------------------------------------------------------------------------
    def _distance_to_waypoint(self, leg: int) -> float:
        """Along-track distance from the filtered position to the leg's end waypoint, m."""
        course = float(self.track.courses[leg])
        end = self.track.waypoints[leg + 1]
        north, east = self.position_filter.position
        return (end[0] - north) * math.cos(course) + (end[1] - east) * math.sin(course)

    def _keeping_heading(self, leg: int) -> float:
        """The track-keeping heading on ``leg`` (module docstring), rad."""
        course = float(self.track.courses[leg])
        start = self.track.waypoints[leg]
        north, east = self.position_filter.position
        off_track = -(north - start[0]) * math.sin(course) + (east - start[1]) * math.cos(course)
        correction = max(
            min(math.atan2(off_track, self.settings.look_ahead), self.settings.largest_correction),
            -self.settings.largest_correction,
        )
        return self._course_heading(course - correction)

    def _course_heading(self, course: float) -> float:
        """The heading whose course over the ground is ``course`` in the estimated current, rad."""
        current_north, current_east = self.position_filter.current
        across = -current_north * math.sin(course) + current_east * math.cos(course)
        speed = max(self.position_filter.speed, 1e-3)
        return course - math.asin(max(min(across / speed, 1.0), -1.0))


class TrackFollowController:
    """A :class:`PredictiveCourseChanger` on TrackFollow-v0, a :class:`~ship_env.baselines.controller.Controller`.

    Args:
        course_changer: the course changer.
        tracks: the reference tracks by id (``env.unwrapped.task.tracks``).
        rudder_limit: the environment's rudder limit delta_max, rad, which scales the action.
    """

    def __init__(
        self, course_changer: PredictiveCourseChanger, tracks: Mapping[str, ReferenceTrack], rudder_limit: float
    ) -> None:
        self.course_changer = course_changer
        self.tracks = tracks
        self.rudder_limit = rudder_limit

    def reset(self, observation: np.ndarray, info: Mapping[str, Any]) -> None:
        """Start on the leg the episode starts on (``info["leg"]``: not the first with ``start="before_turn"``)."""
        track = self.tracks[info["scenario"].track]
        self.course_changer.reset(Measurement.from_info(info), track, int(info["leg"]))

    def act(self, observation: np.ndarray, info: Mapping[str, Any]) -> np.ndarray:
        rudder = self.course_changer.order(Measurement.from_info(info))
        return np.array([np.clip(rudder / self.rudder_limit, -1.0, 1.0)], dtype=np.float32)
