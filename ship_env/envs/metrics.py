"""How well a course change was sailed: one definition for the environments and every controller.

The thesis judges its course-changing autopilot by the course error and rudder it needs
(6.4.4.1, Fig. 6.18); the design notes (section 8) name the figures kept here:

- ``integrated_heading_error`` (deg s): the integral of |e| over the run, e the heading error;
- ``overshoot`` (deg): how far the ship swung past the new heading, 0 if it never did;
- ``settling_time`` (s): the time from which |e| stays within the settling band to the end of the
  run (``inf`` if the run ends outside the band, 0 if it never left it);
- ``rudder_travel`` (deg): the total angle the actual rudder moved.

The heading error is counted *unwrapped*, relative to the ordered change: e = change - (psi - psi0)
with psi unwrapped, so a 180-deg change has no ambiguous sign and a ship that turns round the
wrong way is charged for the whole turn.

:func:`update_metrics` is the one place the figures are defined; the environments call it once a
step (compiled, per ship), :func:`course_change_metrics` runs it along a recorded run of any
controller.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

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
    time = np.asarray(time, dtype=np.float64)
    heading = np.unwrap(np.asarray(heading, dtype=np.float64))
    rudder = np.asarray(rudder, dtype=np.float64)
    if time.ndim != 1 or time.size < 1 or heading.shape != time.shape or rudder.shape != time.shape:
        raise ValueError(
            f"time, heading, rudder: expected three 1-D series of one length, got shapes "
            f"{time.shape}, {heading.shape}, {rudder.shape}"
        )
    if not (math.isfinite(course_change) and course_change != 0.0):
        raise ValueError(f"course_change: expected a non-zero angle in rad, got {course_change!r}")
    metrics = np.zeros(1, dtype=METRICS_DTYPE)
    heading_error = course_change - (heading - heading[0])
    _accumulate(metrics[0], time, heading_error, rudder, math.copysign(1.0, course_change), settle_band)
    return {name: float(metrics[0][name]) for name in METRICS_DTYPE.names}
