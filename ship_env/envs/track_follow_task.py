"""The track-following task, shared by ``TrackFollowEnv`` (one ship) and ``TrackFollowVectorEnv`` (N).

- :class:`TrackFollowTask` holds the task's options (track, disturbances, reward weights, plus the
  ship, rudder, step, instruments and action of :class:`~ship_env.envs.task.ShipTask`), builds
  the six reference tracks for its ship (:mod:`ship_env.envs.tracks`) and draws an episode's
  :class:`TrackScenario`;
- :class:`TrackFollowBatch` sails N ships in one simulator and, in one compiled call
  (:func:`update_ship` per ship), follows each ship along its track's legs, measures, observes,
  rewards, ends the episode at the last waypoint and keeps the score (:mod:`ship_env.envs.metrics`).

The thesis's disturbances (Table 6.2): a current of 2.5 kn "South West" and a wind of 7 m/s
"North West", read with the usual conventions as the current setting *towards* SW (225 deg) and
the wind blowing *from* NW (315 deg): the ship is set to port on a northerly course and the wind
pushes the same way.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ship_env.envs.batch import ShipBatch, define_update_loops, measure_and_observe, pick
from ship_env.envs.checks import check_choice, check_number
from ship_env.envs.metrics import (
    SCORE_INTERVAL,
    THESIS_NAVIGATOR_RMS,
    TRACK_METRICS_DTYPE,
    start_track_metrics,
    update_track_metrics,
)
from ship_env.envs.sensors import (
    MEASURED_EAST,
    MEASURED_FIX_TIME,
    MEASURED_HEADING,
    MEASURED_NORTH,
    RATE_BOUND,
    SPEED_BOUND,
    wrap,
)
from ship_env.envs.task import ShipTask, TaskScenario
from ship_env.envs.tracks import (
    LEG_COURSE,
    LEG_DIRECTION_EAST,
    LEG_DIRECTION_NORTH,
    LEG_END_EAST,
    LEG_END_NORTH,
    NAUTICAL_MILE,
    THESIS_RUDDER_LIMIT_DEG,
    TRACK_IDS,
    TURN_CHANGE,
    ReferenceTrack,
    nearest_on_track,
    passed_waypoint,
    path_ahead,
    point_ahead,
    reference_track,
    signed_cross_track,
)
from ship_env.envs.weather import CALM, CUSTOM_DISTURBANCE, check_conditions
from ship_env.model import Conditions
from ship_env.model import state as S
from ship_env.model.kernel import kernel

#: Table 6.2, read as stated in the module docstring.
THESIS_CONDITIONS = Conditions(
    current_speed=2.5 * NAUTICAL_MILE / 3600.0,
    current_direction=math.radians(225.0),
    wind_speed=7.0,
    wind_direction=math.radians(315.0),
)
#: Disturbance levels: the thesis's (Table 6.2) or still water and air.
TRACK_DISTURBANCES = ("thesis", "calm")
RANDOM_TRACK = "random"
#: Where an episode starts: at the first waypoint (the thesis's run), or on a random leg before its
#: end turn (:data:`BEFORE_TURN_NM`), so that every episode soon meets a turn.
STARTS = ("first_waypoint", "before_turn")
#: nm before the leg's end waypoint where a ``"before_turn"`` episode starts (on the reference ship; times
#: ``track_scale`` on another): the arc of the largest change (105 deg) begins 0.6 nm before it, and its
#: wheel-over about 150 m earlier.
BEFORE_TURN_NM = (1.0, 1.6)

#: Keys ``reset(options=...)`` accepts.
RESET_OPTIONS = frozenset({"track", "conditions"})

# Observation layout (float32, normalised; see TrackFollowEnv's docstring).
OBS_CROSS_TRACK = 0  # cross-track error of the latest fix / L, positive to starboard of the track
OBS_HEADING_ERROR = 1  # wrap(leg course - compass heading) / pi
OBS_RATE_OF_TURN = 2  # gyro rate / (K* U0 / L * delta_max)
OBS_RUDDER = 3  # actual rudder / delta_max
OBS_SPEED = 4  # log speed / U0
OBS_NEXT_CHANGE = 5  # the course change at the leg's end waypoint / pi, 0 on the last leg
OBS_WAYPOINT_DISTANCE = 6  # distance of the fix to the leg's end waypoint along the leg, nm * track_scale
OBS_CROSS_TRACK_RATE = 7  # the fixes' cross-track error's rate, filtered, / U0
OBSERVATION_SIZE = 8
# With ``track_preview``: the rounded reference track at and ahead of the fix's nearest point on it.
OBS_PATH_HEADING_ERROR = 8  # wrap(the track's course there - compass heading) / pi
OBS_PATH_TURN = 9  # the track's curvature there * L / (K* delta_max): about +-1 on an arc, 0 on a straight
OBS_ARC_TIME = 10  # the distance along the track to the next arc's start / U0, min in L / U units, clipped
OBS_NEXT_TURN = 11  # the next arc's curvature * L / (K* delta_max) (the present arc's on one)
OBS_LINE_OF_SIGHT = 12  # wrap(bearing of the track point LOOKAHEAD ahead - compass heading) / pi
#: Ship lengths along the track from the fix's nearest point to the line-of-sight point.
LOOKAHEAD = 2.0
#: min (of the reference ship; in units of L / U): the arc-time observation's bound (the next arc, or none,
#: further ahead than this).
ARC_TIME_BOUND = 5.0
#: The preview's bounds: its turns are within twice the rudder limit's steady rate.
PREVIEW_LOW = np.array([-1.0, -2.0, 0.0, -2.0, -1.0], dtype=np.float32)
PREVIEW_HIGH = np.array([1.0, 2.0, ARC_TIME_BOUND, 2.0, 1.0], dtype=np.float32)
CROSS_TRACK_BOUND = 10.0  # ship lengths
DISTANCE_BOUNDS = (-1.0, 3.0)  # nm * track_scale: legs are at most 2.5 nm * track_scale
#: s (on the reference ship; in units of L / U): time constant of the first-order filter on the rate of
#: the fixes' cross-track error (the cross-track speed a track pilot shows); it takes out the fixes' noise
#: (5 m every 2 s: 3.5 m/s raw, about 0.6 m/s filtered) and lags a change of drift by about this time.
CROSS_TRACK_RATE_TIME = 30.0
OBSERVATION_LOW = np.array(
    [-CROSS_TRACK_BOUND, -1.0, -RATE_BOUND, -1.0, 0.0, -1.0, DISTANCE_BOUNDS[0], -1.0], dtype=np.float32
)
OBSERVATION_HIGH = np.array(
    [CROSS_TRACK_BOUND, 1.0, RATE_BOUND, 1.0, SPEED_BOUND, 1.0, DISTANCE_BOUNDS[1], 1.0], dtype=np.float32
)

#: Per-ship episode data besides the common record (:func:`~ship_env.envs.batch.episode_dtype`).
TASK_FIELDS = (
    ("track", np.int64),  # index into TRACK_IDS
    ("leg", np.int64),  # the leg being sailed: it advances across the bisector of its end corner
    ("cross_track_error", np.float64),  # m, true position, positive to starboard of the track
    ("fix_cross_track_error", np.float64),  # m, of the latest position fix
    ("fix_cross_track_rate", np.float64),  # m/s, its rate, filtered over CROSS_TRACK_RATE_TIME
    ("fix_time", np.float64),  # s, of the latest position fix
    ("north", np.float64),  # m, the true position at the previous update (for the course over ground)
    ("east", np.float64),
)


@dataclass(frozen=True)
class TrackScenario(TaskScenario):
    """One episode's track and the sea it is sailed in.

    Attributes (besides :class:`~ship_env.envs.task.TaskScenario`'s):
        track: ``"T1"`` .. ``"T6"``.
        initial_heading: the course of the leg it starts on, rad.
        initial_north, initial_east: where it starts, m (the first waypoint, the origin, unless
            the task's ``start`` is ``"before_turn"``).
    """

    track: str
    initial_heading: float
    initial_north: float = 0.0
    initial_east: float = 0.0


class TrackFollowTask(ShipTask):
    """The options of the track-following task; the environments' keyword arguments.

    Args:
        track: ``"T1"`` .. ``"T6"``, or ``"random"`` (one of the six per episode).
        disturbance: ``"thesis"`` (Table 6.2: current 2.5 kn towards SW, wind 7 m/s from NW, for the
            container ship at 19 kn; on another ship in units of its speed: ``thesis_conditions``) or
            ``"calm"``.
        rudder_limit_deg: delta_max, deg (default 10, the experiment's); the reference track
            turns on the ship's steady turn at this rudder.
        cross_track_weight: reward per step for (cross-track error / L)^2.
        rudder_travel_weight: reward per step for |actual rudder move| / delta_max.
        fix_interval: s between position fixes (default ``None``: the thesis's 2 s sampling in units
            of L / U, :mod:`ship_env.envs.ship_scales`).
        track_preview: add to the observation the rounded reference track at and ahead of the
            fix's nearest point on it (``OBS_PATH_HEADING_ERROR`` .. ``OBS_NEXT_TURN``): its course
            and curvature there, the time to the next arc (the wheel-over lies a reaction time
            before it) and that arc's curvature, and the bearing of the track point ``LOOKAHEAD``
            ship lengths ahead (line-of-sight steering: its bearing turns before the track does).
        line_of_sight_weight: reward shaping: per step for |wrap(bearing of that point - course over
            ground)| / pi, of the true position (0, default: none). Steering the ground track at a
            point on the track ahead puts the rudder over before the turn and holds the drift.
        cross_track_reward_bound: the cross-track error's bound in the reward, ship lengths (default
            ``CROSS_TRACK_BOUND``, 10: a lost ship costs at most 100 a step). A smaller bound keeps
            a lost ship's returns from swamping the value function while training.
        start: ``"first_waypoint"`` (default: the thesis's run of the whole track) or
            ``"before_turn"``: each episode starts on a random leg with a turn at its end (uniform
            over the track's first five), ``BEFORE_TURN_NM`` (1 to 1.6 nm, uniform) before that
            end waypoint, on the leg's course, and sails on to the track's end. Training episodes
            then meet a turn within minutes, every turn of the six tracks as often.
        track_scale: the legs' lengths times this; ``None`` (default): ``L / 226 m``, the thesis's 2
            to 2.5 nm legs, drawn for the 226 m container ship (1 for it), in proportion to a ship of
            length L (:mod:`ship_env.envs.ship_scales`). The ``before_turn`` start and the waypoint
            distance's unit scale with it; the score's sampling interval (the thesis's 2 s), the
            cross-track rate's filter time and the arc time's unit with L / U.
        **ship_options: the keywords every task shares (:class:`~ship_env.envs.task.ShipTask`):
            ``ship``, ``ship_parameters``, ``effects``, ``dt``, ``sensor_noise_scale``,
            ``action_type``, ``rudder_levels``.
    """

    history_observations = (OBS_HEADING_ERROR, OBS_RATE_OF_TURN, OBS_RUDDER)
    reference_fix_interval = SCORE_INTERVAL

    def __init__(
        self,
        *,
        track: str = RANDOM_TRACK,
        disturbance: str = "thesis",
        rudder_limit_deg: float = THESIS_RUDDER_LIMIT_DEG,
        cross_track_weight: float = 1.0,
        rudder_travel_weight: float = 0.1,
        track_preview: bool = False,
        line_of_sight_weight: float = 0.0,
        cross_track_reward_bound: float = CROSS_TRACK_BOUND,
        start: str = "first_waypoint",
        track_scale: float | None = None,
        **ship_options: Any,
    ) -> None:
        self.track = check_choice("track", track, (*TRACK_IDS, RANDOM_TRACK))
        self.disturbance = check_choice("disturbance", disturbance, TRACK_DISTURBANCES)
        self.cross_track_weight = check_number("cross_track_weight", cross_track_weight, 0.0)
        self.rudder_travel_weight = check_number("rudder_travel_weight", rudder_travel_weight, 0.0)
        self.line_of_sight_weight = check_number("line_of_sight_weight", line_of_sight_weight, 0.0)
        self.cross_track_reward_bound = check_number("cross_track_reward_bound", cross_track_reward_bound, 1e-3)
        self.start = check_choice("start", start, STARTS)
        if not isinstance(track_preview, bool):
            raise TypeError(f"track_preview: expected true or false, got {track_preview!r}")
        self.track_preview = track_preview
        super().__init__(rudder_limit_deg=rudder_limit_deg, **ship_options)
        #: The legs' lengths over the thesis's (default: the ship's length over the reference's).
        self.track_scale = self.scales.length if track_scale is None else check_number("track_scale", track_scale, 1e-3)
        #: The reference tracks, rounded by this ship's steady turns at delta_max.
        self.tracks: dict[str, ReferenceTrack] = {
            track_id: reference_track(track_id, self.model, math.degrees(self.rudder_limit), scale=self.track_scale)
            for track_id in TRACK_IDS
        }
        self.track_legs = np.stack([self.tracks[track_id].legs for track_id in TRACK_IDS])
        #: The ``"thesis"`` disturbance on this ship: Table 6.2's wind and current speeds in units of its
        #: speed U (as :meth:`~ship_env.envs.weather.WeatherRanges.scaled` scales the drawn weather).
        self.thesis_conditions = dataclasses.replace(
            THESIS_CONDITIONS,
            current_speed=THESIS_CONDITIONS.current_speed * self.scales.speed,
            wind_speed=THESIS_CONDITIONS.wind_speed * self.scales.speed,
        )

        #: The task's constants as the compiled update reads them.
        self.parameters = self.parameter_record(
            length=self.model.length,
            cross_track_weight=self.cross_track_weight,
            rudder_travel_weight=self.rudder_travel_weight,
            line_of_sight_weight=self.line_of_sight_weight,
            cross_track_reward_bound=self.cross_track_reward_bound,
            score_interval=SCORE_INTERVAL * self.scales.time,
            cross_track_rate_time=CROSS_TRACK_RATE_TIME * self.scales.time,
            arc_time_unit=60.0 * self.scales.time,
            waypoint_distance_unit=NAUTICAL_MILE * self.track_scale,
            track_preview=track_preview,
        )
        #: What the compiled update reads besides the simulator's and the batch's arrays.
        self.kernel_arguments = (self.parameters, self.sensors, self.track_legs)
        low, high = OBSERVATION_LOW, OBSERVATION_HIGH
        if track_preview:
            low, high = np.concatenate((low, PREVIEW_LOW)), np.concatenate((high, PREVIEW_HIGH))
        self.observation_space = self.observation_box(low, high)

    def draw_task_scenario(self, rng: np.random.Generator, options: Mapping[str, Any] | None = None) -> TrackScenario:
        """Draw an episode from ``rng``: the track uniformly over the six if ``"random"``.

        ``options`` may pin the ``track`` or give the ``conditions`` (a
        :class:`~ship_env.model.Conditions`, reported as disturbance ``"custom"``; ``ValueError``
        for weather the model does not sail, :func:`~ship_env.envs.weather.check_sailed`). Every draw
        takes the same numbers from ``rng``, so one seed gives one sequence of episodes; a
        ``"before_turn"`` start takes two more (the leg and the distance).
        """
        draw = float(rng.random())
        seed = int(rng.integers(2**31))
        options = self.check_options(options, RESET_OPTIONS)
        track = check_choice("options['track']", options.get("track", self.track), (*TRACK_IDS, RANDOM_TRACK))
        if track == RANDOM_TRACK:
            track = TRACK_IDS[int(draw * len(TRACK_IDS))]
        if "conditions" in options:
            conditions = check_conditions("options['conditions']", options["conditions"], self)
            disturbance = CUSTOM_DISTURBANCE
        else:
            disturbance = self.disturbance
            conditions = self.thesis_conditions if disturbance == "thesis" else CALM
        reference = self.tracks[track]
        if self.start == "first_waypoint":
            return TrackScenario(disturbance, conditions, seed, track, float(reference.courses[0]))
        leg = int(rng.integers(len(reference.course_changes)))
        before = float(rng.uniform(*BEFORE_TURN_NM)) * (NAUTICAL_MILE * self.track_scale)
        row = reference.legs[leg]
        return TrackScenario(
            disturbance,
            conditions,
            seed,
            track,
            float(row[LEG_COURSE]),
            float(row[LEG_END_NORTH] - before * row[LEG_DIRECTION_NORTH]),
            float(row[LEG_END_EAST] - before * row[LEG_DIRECTION_EAST]),
        )


@kernel
def update_ship(i, states, conditions, noise_keys, step_index, episodes, metrics, task, sensors, tracks):
    """Follow, measure, observe and reward ship ``i`` after a step (or after a restart, reward 0).

    The leg advances when the true position crosses the bisector of the leg's end corner; the
    episode terminates when it crosses the perpendicular at the last waypoint. Reward:
    -(w_x (e / L)^2 + w_d |delta - delta_prev| / delta_max + w_s |wrap(beta - chi)| / pi) with e the
    true cross-track error (e / L clipped to +-``cross_track_reward_bound``), beta
    the bearing of the track point ``LOOKAHEAD`` ship lengths ahead and chi the course over ground
    over the step, both of the true position (the last term only with ``line_of_sight_weight``).
    The observation comes from the measurements (the latest fix, compass, gyro, log).
    """
    episode = episodes[i]
    restarted = episode["restarted"]
    p = task[0]
    state = states[i]
    legs = tracks[episode["track"]]
    north, east = state[S.NORTH], state[S.EAST]
    leg = 0 if restarted else episode["leg"]
    last = legs.shape[0] - 1
    while leg < last and passed_waypoint(north, east, legs, leg):
        leg += 1
    episode["leg"] = leg
    episode["terminated"] = leg == last and passed_waypoint(north, east, legs, leg)
    cross_track, nearest_leg, on_arc = nearest_on_track(north, east, legs)
    episode["cross_track_error"] = cross_track
    rudder = state[S.RUDDER]
    if restarted:
        start_track_metrics(metrics[i], state[S.TIME], cross_track)
        episode["reward"] = 0.0
        episode["restarted"] = False
    else:
        rudder_move = abs(rudder - episode["rudder"])
        bound = p["cross_track_reward_bound"]
        relative = min(max(cross_track / p["length"], -bound), bound)
        reward = -(
            p["cross_track_weight"] * relative * relative + p["rudder_travel_weight"] * rudder_move / p["rudder_limit"]
        )
        if p["line_of_sight_weight"] > 0.0:
            ahead_north, ahead_east = point_ahead(north, east, legs, nearest_leg, on_arc, LOOKAHEAD * p["length"])
            bearing = math.atan2(ahead_east - east, ahead_north - north)
            ground_course = math.atan2(east - episode["east"], north - episode["north"])
            reward -= p["line_of_sight_weight"] * abs(wrap(bearing - ground_course)) / math.pi
        episode["reward"] = reward
        update_track_metrics(metrics[i], state[S.TIME], cross_track, rudder_move, p["score_interval"])
    episode["rudder"] = rudder
    episode["north"], episode["east"] = north, east

    measure_and_observe(i, state, conditions, noise_keys, step_index, episode, sensors, restarted, OBS_RATE_OF_TURN, p)
    service_speed = conditions[i, S.SERVICE_SPEED]
    measured = episode["measurement"]
    row = legs[leg]
    fix_north, fix_east = measured[MEASURED_NORTH], measured[MEASURED_EAST]
    if measured[MEASURED_FIX_TIME] == state[S.TIME]:  # a new fix
        fix_error = signed_cross_track(fix_north, fix_east, legs)
        if restarted:
            episode["fix_cross_track_rate"] = 0.0
        else:
            interval = state[S.TIME] - episode["fix_time"]
            raw_rate = (fix_error - episode["fix_cross_track_error"]) / interval
            weight = interval / (p["cross_track_rate_time"] + interval)
            episode["fix_cross_track_rate"] += weight * (raw_rate - episode["fix_cross_track_rate"])
        episode["fix_cross_track_error"] = fix_error
        episode["fix_time"] = state[S.TIME]
    observation = episode["observation"]
    relative = episode["fix_cross_track_error"] / p["length"]
    observation[OBS_CROSS_TRACK] = min(max(relative, -CROSS_TRACK_BOUND), CROSS_TRACK_BOUND)
    observation[OBS_HEADING_ERROR] = wrap(row[LEG_COURSE] - measured[MEASURED_HEADING]) / math.pi
    observation[OBS_NEXT_CHANGE] = row[TURN_CHANGE] / math.pi
    to_go_north = (row[LEG_END_NORTH] - fix_north) * row[LEG_DIRECTION_NORTH]
    to_go = to_go_north + (row[LEG_END_EAST] - fix_east) * row[LEG_DIRECTION_EAST]
    distance = to_go / p["waypoint_distance_unit"]
    observation[OBS_WAYPOINT_DISTANCE] = min(max(distance, DISTANCE_BOUNDS[0]), DISTANCE_BOUNDS[1])
    observation[OBS_CROSS_TRACK_RATE] = min(max(episode["fix_cross_track_rate"] / service_speed, -1.0), 1.0)
    if p["track_preview"]:
        _, nearest_leg, on_arc = nearest_on_track(fix_north, fix_east, legs)
        course, curvature, arc_distance, next_curvature = path_ahead(fix_north, fix_east, legs, nearest_leg, on_arc)
        turn_scale = 1.0 / p["full_rudder_rate_per_speed"]  # L / (K* delta_max)
        observation[OBS_PATH_HEADING_ERROR] = wrap(course - measured[MEASURED_HEADING]) / math.pi
        observation[OBS_PATH_TURN] = min(max(curvature * turn_scale, -2.0), 2.0)
        observation[OBS_ARC_TIME] = min(arc_distance / service_speed / p["arc_time_unit"], ARC_TIME_BOUND)
        observation[OBS_NEXT_TURN] = min(max(next_curvature * turn_scale, -2.0), 2.0)
        ahead_north, ahead_east = point_ahead(fix_north, fix_east, legs, nearest_leg, on_arc, LOOKAHEAD * p["length"])
        bearing = math.atan2(ahead_east - fix_east, ahead_north - fix_north)
        observation[OBS_LINE_OF_SIGHT] = wrap(bearing - measured[MEASURED_HEADING]) / math.pi


update_ships, update_ships_parallel, sail_ship = define_update_loops(globals())


class TrackFollowBatch(ShipBatch):
    """N ships following reference tracks (:class:`~ship_env.envs.batch.ShipBatch`).

    Each ship's ``episodes`` record holds ``observation`` float32 (8,), ``measurement``,
    ``reward``, ``terminated``, its ``track`` and ``leg`` and its true ``cross_track_error``;
    ``metrics`` the running track metrics (the score).
    """

    task_fields = TASK_FIELDS
    #: ``leg``: the leg being sailed (0-based); ``cross_track_error``: true, m, positive to starboard.
    task_info_keys = ("leg", "cross_track_error")
    metrics_dtype = TRACK_METRICS_DTYPE
    update_serial = staticmethod(update_ships)
    update_parallel = staticmethod(update_ships_parallel)
    sail_one = staticmethod(sail_ship)

    def restart(self, ships: np.ndarray, scenarios: Sequence[Any]) -> None:
        """Start new episodes for ``ships``, each where its scenario starts it."""
        super().restart(ships, scenarios)
        state = self.simulator.state
        state[ships, S.NORTH] = [scenario.initial_north for scenario in scenarios]
        state[ships, S.EAST] = [scenario.initial_east for scenario in scenarios]

    def start_episode(self, episode: np.void, scenario: TrackScenario) -> None:
        episode["track"] = TRACK_IDS.index(scenario.track)
        episode["leg"] = 0

    def end_info(self, ships: int | slice) -> dict[str, Any]:
        """``score``: the episode's ``rms_cross_track_error`` (m, eq. 6.5) beside the thesis's
        navigators' (Table 6.4) as ``thesis_parallel_indexing``, ``thesis_ground_speed_vector``
        and ``thesis_track_predictor``."""
        rms = pick(self.metrics["rms_cross_track_error"], ships)
        score = {"rms_cross_track_error": rms}
        for name, value in THESIS_NAVIGATOR_RMS.items():
            score[f"thesis_{name}"] = np.full_like(rms, value) if isinstance(rms, np.ndarray) else value
        return {"score": score}
