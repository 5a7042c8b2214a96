"""How well a task was sailed: one definition for the environments and every controller.

Each task's figures are defined once, by compiled functions that the environments call once a step
(per ship) and that a ``*_metrics`` function runs along a recorded run of any controller.

**Course change.** The thesis judges its course-changing autopilot by the course error and rudder
it needs (6.4.4.1, Fig. 6.18); the design notes (section 8) name the figures kept here:

- ``integrated_heading_error`` (deg s): the integral of |e| over the run, e the heading error;
- ``overshoot`` (deg): how far the ship swung past the new heading, 0 if it never did;
- ``settling_time`` (s): the time from which |e| stays within the settling band to the end of the
  run (``inf`` if the run ends outside the band, 0 if it never left it);
- ``rudder_travel`` (deg): the total angle the actual rudder moved.

The heading error is counted *unwrapped*, relative to the ordered change: e = change - (psi - psi0)
with psi unwrapped, so a 180-deg change has no ambiguous sign and a ship that turns round the
wrong way is charged for the whole turn.

:func:`update_metrics` is the one place the figures are defined; :func:`course_change_metrics`
runs it along a recorded run.

**Track following** (:func:`update_track_metrics`, :func:`track_metrics`): the thesis's score,
the RMS perpendicular distance to the reference track (6.5) sampled every 2 s, as the mean of the
squared distances over the samples from the start (i = 0) on; the largest distance sampled; the
rudder travel.

**Course keeping** (:func:`update_course_keeping_metrics`, :func:`course_keeping_metrics`): the
classic autopilot trade-off between heading error and rudder, J = mean(e^2) + lambda mean(delta^2)
over the steps, e the true heading error (without the waves' high-frequency yaw, which no rudder
removes) and delta the actual rudder, both in deg, so J is in deg^2. This is the form of the
course-keeping criteria discussed by Van Amerongen (1982, the thesis's reference for the
autopilot), J = (1/T) int(e^2 + lambda delta^2) dt; lambda = 0.1 by default, the weight commonly
quoted after Koyama (1967) for the propulsion loss of steering (a choice, not a thesis number).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ship_env.envs.sensors import sample_due
from ship_env.envs.tracks import ReferenceTrack, signed_cross_track
from ship_env.model.kernel import kernel

#: The running metrics of one course change, in the units they are reported in.
METRICS_DTYPE = np.dtype(
    [
        ("integrated_heading_error", np.float64),  # deg s
        ("overshoot", np.float64),  # deg
        ("settling_time", np.float64),  # s, inf while outside the band
        ("rudder_travel", np.float64),  # deg
    ]
)

#: The settling band of the thesis's experiment scale: within 2 deg of the new heading.
SETTLE_BAND = math.radians(2.0)


@kernel
def start_metrics(metrics, heading_error, settle_band):
    """Set a run's metrics at its start (time 0) from the initial heading error e0 (rad)."""
    metrics["integrated_heading_error"] = 0.0
    metrics["overshoot"] = 0.0
    metrics["settling_time"] = 0.0 if abs(heading_error) <= settle_band else math.inf
    metrics["rudder_travel"] = 0.0


@kernel
def update_metrics(metrics, time, heading_error, turn_direction, rudder_move, dt, settle_band):
    """Add one sample to a run's metrics.

    Args:
        metrics: one record of ``METRICS_DTYPE``, updated in place.
        time: the sample's time since the start of the run, s.
        heading_error: e = change - (psi - psi0), unwrapped, rad.
        turn_direction: +1 for a change to starboard, -1 to port.
        rudder_move: |actual rudder now - actual rudder at the previous sample|, rad.
        dt: the time since the previous sample, s.
        settle_band: the settling band, rad.
    """
    metrics["integrated_heading_error"] += math.degrees(abs(heading_error)) * dt
    metrics["overshoot"] = max(metrics["overshoot"], -turn_direction * math.degrees(heading_error))
    if abs(heading_error) > settle_band:
        metrics["settling_time"] = math.inf
    elif metrics["settling_time"] == math.inf:
        metrics["settling_time"] = time
    metrics["rudder_travel"] += math.degrees(rudder_move)


@kernel
def _accumulate(metrics, time, heading_error, rudder, turn_direction, settle_band):
    start_metrics(metrics, heading_error[0], settle_band)
    for k in range(1, time.shape[0]):
        update_metrics(
            metrics,
            time[k] - time[0],
            heading_error[k],
            turn_direction,
            abs(rudder[k] - rudder[k - 1]),
            time[k] - time[k - 1],
            settle_band,
        )


def _series(names: str, *arrays: ArrayLike) -> list[np.ndarray]:
    """Equal-length 1-D float series, or ``ValueError`` naming them."""
    series = [np.asarray(array, dtype=np.float64) for array in arrays]
    if series[0].ndim != 1 or series[0].size < 1 or any(item.shape != series[0].shape for item in series):
        shapes = ", ".join(str(item.shape) for item in series)
        raise ValueError(f"{names}: expected 1-D series of one length, got shapes {shapes}")
    return series


def course_change_metrics(
    time: ArrayLike,
    heading: ArrayLike,
    rudder: ArrayLike,
    course_change: float,
    settle_band: float = SETTLE_BAND,
) -> dict[str, float]:
    """The metrics of a recorded course change, sailed by any controller.

    Args:
        time: sample times, s, increasing; the change is ordered at ``time[0]``.
        heading: the true heading at each sample, rad (wrapped or not: it is unwrapped here).
        rudder: the actual rudder angle at each sample, rad.
        course_change: the ordered change, rad, positive to starboard.
        settle_band: the settling band, rad.

    Returns:
        ``integrated_heading_error`` (deg s), ``overshoot`` (deg), ``settling_time`` (s),
        ``rudder_travel`` (deg), as defined in this module's docstring.
    """
    time, heading, rudder = _series("time, heading, rudder", time, heading, rudder)
    heading = np.unwrap(heading)
    if not (math.isfinite(course_change) and course_change != 0.0):
        raise ValueError(f"course_change: expected a non-zero angle in rad, got {course_change!r}")
    metrics = np.zeros(1, dtype=METRICS_DTYPE)
    heading_error = course_change - (heading - heading[0])
    _accumulate(metrics[0], time, heading_error, rudder, math.copysign(1.0, course_change), settle_band)
    return {name: float(metrics[0][name]) for name in METRICS_DTYPE.names or ()}


#: The running metrics of a track-following run.
TRACK_METRICS_DTYPE = np.dtype(
    [
        ("rms_cross_track_error", np.float64),  # m, the thesis's score (6.5)
        ("max_cross_track_error", np.float64),  # m, the largest |distance| sampled
        ("rudder_travel", np.float64),  # deg
        ("samples", np.int64),  # the number of samples in the RMS
        ("last_sample_time", np.float64),  # s, the time of the latest sample
    ]
)

#: The thesis's sampling interval of the track error, s (6.4.4.2: "sampled every 2 seconds").
SCORE_INTERVAL = 2.0

#: The thesis's mean RMS track errors of its twelve navigators, m (Table 6.4): the anchors a
#: track-following controller is compared with.
THESIS_NAVIGATOR_RMS = {"parallel_indexing": 117.0, "ground_speed_vector": 95.0, "track_predictor": 33.0}


@kernel
def start_track_metrics(metrics, time, cross_track):
    """Set a track run's metrics at its start from the first sample's cross-track error (m)."""
    metrics["rms_cross_track_error"] = abs(cross_track)
    metrics["max_cross_track_error"] = abs(cross_track)
    metrics["rudder_travel"] = 0.0
    metrics["samples"] = 1
    metrics["last_sample_time"] = time


@kernel
def update_track_metrics(metrics, time, cross_track, rudder_move, sample_interval):
    """Add one step to a track run's metrics: its rudder move (rad), and its cross-track error (m)
    as a sample of the RMS if one is due (every ``sample_interval`` s from the start)."""
    metrics["rudder_travel"] += math.degrees(rudder_move)
    if not sample_due(time, metrics["last_sample_time"], sample_interval):
        return
    count = metrics["samples"]
    mean_square = (metrics["rms_cross_track_error"] ** 2 * count + cross_track * cross_track) / (count + 1)
    metrics["rms_cross_track_error"] = math.sqrt(mean_square)
    metrics["max_cross_track_error"] = max(metrics["max_cross_track_error"], abs(cross_track))
    metrics["samples"] = count + 1
    metrics["last_sample_time"] = time


@kernel
def _accumulate_track(metrics, time, north, east, rudder, legs, sample_interval):
    start_track_metrics(metrics, time[0], signed_cross_track(north[0], east[0], legs))
    for k in range(1, time.shape[0]):
        cross_track = signed_cross_track(north[k], east[k], legs)
        update_track_metrics(metrics, time[k], cross_track, abs(rudder[k] - rudder[k - 1]), sample_interval)


def track_metrics(
    time: ArrayLike,
    north: ArrayLike,
    east: ArrayLike,
    rudder: ArrayLike,
    track: ReferenceTrack,
    sample_interval: float = SCORE_INTERVAL,
) -> dict[str, float]:
    """The metrics of a recorded track-following run, sailed by any controller.

    Args:
        time: sample times, s, increasing, from the start of the run.
        north, east: the ship's true position at each sample, m.
        rudder: the actual rudder angle at each sample, rad.
        track: the reference track (:func:`ship_env.envs.tracks.reference_track`).
        sample_interval: the score's sampling interval, s (the thesis's 2 s).

    Returns:
        ``rms_cross_track_error`` (m, eq. 6.5), ``max_cross_track_error`` (m), ``rudder_travel``
        (deg), ``samples`` and ``last_sample_time`` (s), as the environment reports them.
    """
    time, north, east, rudder = _series("time, north, east, rudder", time, north, east, rudder)
    metrics = np.zeros(1, dtype=TRACK_METRICS_DTYPE)
    _accumulate_track(metrics[0], time, north, east, rudder, track.legs, float(sample_interval))
    return {name: metrics[0][name].item() for name in TRACK_METRICS_DTYPE.names or ()}


#: The running metrics of a course-keeping run.
COURSE_KEEPING_METRICS_DTYPE = np.dtype(
    [
        ("cost", np.float64),  # deg^2, J = mean(e^2) + lambda mean(delta^2)
        ("mean_squared_heading_error", np.float64),  # deg^2
        ("mean_squared_rudder", np.float64),  # deg^2
        ("rudder_travel", np.float64),  # deg
        ("samples", np.int64),  # the steps averaged
    ]
)

#: lambda, the default rudder weight of the course-keeping criterion (see the module docstring).
RUDDER_WEIGHT = 0.1


@kernel
def start_course_keeping_metrics(metrics):
    """Set a course-keeping run's metrics at its start (no step averaged yet)."""
    metrics["cost"] = 0.0
    metrics["mean_squared_heading_error"] = 0.0
    metrics["mean_squared_rudder"] = 0.0
    metrics["rudder_travel"] = 0.0
    metrics["samples"] = 0


@kernel
def update_course_keeping_metrics(metrics, heading_error, rudder, rudder_move, rudder_weight):
    """Add one step: the true heading error and the actual rudder at its end, and its rudder move (rad)."""
    count = metrics["samples"]
    error = math.degrees(heading_error)
    angle = math.degrees(rudder)
    metrics["mean_squared_heading_error"] += (error * error - metrics["mean_squared_heading_error"]) / (count + 1)
    metrics["mean_squared_rudder"] += (angle * angle - metrics["mean_squared_rudder"]) / (count + 1)
    metrics["cost"] = metrics["mean_squared_heading_error"] + rudder_weight * metrics["mean_squared_rudder"]
    metrics["rudder_travel"] += math.degrees(rudder_move)
    metrics["samples"] = count + 1


@kernel
def _accumulate_course_keeping(metrics, heading_error, rudder, rudder_weight):
    start_course_keeping_metrics(metrics)
    for k in range(1, heading_error.shape[0]):
        update_course_keeping_metrics(
            metrics, heading_error[k], rudder[k], abs(rudder[k] - rudder[k - 1]), rudder_weight
        )


def course_keeping_metrics(
    heading: ArrayLike, rudder: ArrayLike, course: float, rudder_weight: float = RUDDER_WEIGHT
) -> dict[str, float]:
    """The metrics of a recorded course-keeping run, sailed by any controller.

    Args:
        heading: the true heading at the start and after each step (equal steps), rad.
        rudder: the actual rudder angle at the same instants, rad.
        course: the ordered course, rad.
        rudder_weight: lambda of J = mean(e^2) + lambda mean(delta^2).

    Returns:
        ``cost`` J (deg^2), ``mean_squared_heading_error`` (deg^2), ``mean_squared_rudder``
        (deg^2), ``rudder_travel`` (deg), ``samples``; the means are over the steps (the samples
        after the first), e = wrap(course - heading).
    """
    heading, rudder = _series("heading, rudder", heading, rudder)
    heading_error = (course - heading + math.pi) % (2.0 * math.pi) - math.pi
    metrics = np.zeros(1, dtype=COURSE_KEEPING_METRICS_DTYPE)
    _accumulate_course_keeping(metrics[0], heading_error, rudder, float(rudder_weight))
    return {name: metrics[0][name].item() for name in COURSE_KEEPING_METRICS_DTYPE.names or ()}
