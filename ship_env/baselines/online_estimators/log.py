"""What the on-line estimators read: one run's samples as plain numpy arrays in SI units and radians.

:class:`ExcitationLog` holds time, rudder, heading, rate of turn and speed (and, where known, the
rudder rate Perera's filter measures). It checks its arrays when made, so that an estimator never
sees NaN, time that stands still or goes back, or degrees where radians belong; each problem raises
:class:`ExcitationLogError` naming the field, the sample and the value:

- a field that is not a 1-D array of the time's length, or holds NaN or infinity;
- time not strictly increasing;
- a rudder beyond pi/2 rad or a rate of turn beyond 1 rad/s (no ship steers or turns that far:
  the numbers are degrees);
- a heading that changes about 57 times faster, or slower, than the rate of turn says (one of the
  two in degrees).

:func:`from_workbench_log` converts the measurement workbench's :class:`ship_env.workbench.logs.logs.Log`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ship_env.workbench.logs.logs import Log

#: No rudder turns further than this, rad: a larger value is in degrees.
MAX_PLAUSIBLE_RUDDER = math.pi / 2.0
#: No ship turns faster than this, rad/s (the workbench's limit too).
MAX_PLAUSIBLE_RATE = 1.0
#: Heading and rate of turn disagree in scale when d(psi)/dt is this many times r, or 1/this.
UNIT_MISMATCH_RATIO = 10.0
#: Below this RMS rate of turn, rad/s, the heading-rate comparison is left out (nothing to compare).
MIN_RATE_FOR_UNIT_CHECK = 1e-3
#: Sample intervals may differ from their median by this fraction and still count as uniform.
UNIFORM_SAMPLING_TOLERANCE = 0.01

_SIGNALS = ("rudder", "heading", "rate_of_turn", "speed", "rudder_rate")


class ExcitationLogError(ValueError):
    """A log an estimator cannot use; the message names the field, the sample and the value."""


@dataclass(frozen=True, eq=False)
class ExcitationLog:
    """One run for the on-line estimators.

    Attributes:
        time: sample times t(k), s, strictly increasing.
        rudder: actual rudder angle delta(k), rad, positive to starboard.
        heading: heading psi(k), rad, unwrapped (continuous through whole turns).
        rate_of_turn: rate of turn r(k) = psi'(k), rad/s.
        speed: forward speed through the water u(k), m/s; ``None`` for a model without speed
            (Perera's), which the speed-scheduled Nomoto estimators refuse.
        rudder_rate: delta'(k), rad/s, where measured (Perera's fourth measurement); ``None``
            derives it from ``rudder`` (:meth:`rudder_rate_or_difference`).
        name: what the run was.
    """

    time: np.ndarray
    rudder: np.ndarray
    heading: np.ndarray
    rate_of_turn: np.ndarray
    speed: np.ndarray | None = None
    rudder_rate: np.ndarray | None = None
    name: str = "log"

    def __post_init__(self) -> None:
        time = _as_array(self.time, "time", None, self.name)
        object.__setattr__(self, "time", time)
        if len(time) < 2:
            raise ExcitationLogError(f"log {self.name!r}: time holds {len(time)} samples; at least 2 are needed")
        steps = np.diff(time)
        if np.any(steps <= 0.0):
            k = int(np.flatnonzero(steps <= 0.0)[0])
            raise ExcitationLogError(
                f"log {self.name!r}: time must increase, but time[{k + 1}] = {time[k + 1]:.6g} s follows "
                f"time[{k}] = {time[k]:.6g} s"
            )
        for name in _SIGNALS:
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _as_array(value, name, len(time), self.name))
        _check_magnitude(self.rudder, "rudder", MAX_PLAUSIBLE_RUDDER, "rad", self.name)
        _check_magnitude(self.rate_of_turn, "rate_of_turn", MAX_PLAUSIBLE_RATE, "rad/s", self.name)
        if self.speed is not None and np.any(self.speed < 0.0):
            k = int(np.flatnonzero(self.speed < 0.0)[0])
            raise ExcitationLogError(f"log {self.name!r}: speed[{k}] = {self.speed[k]:.6g} m/s is negative")
        _check_heading_against_rate(time, self.heading, self.rate_of_turn, self.name)

    @property
    def samples(self) -> int:
        return len(self.time)

    def sample_time(self) -> float:
        """T_s, s, for the discrete-time estimators; an :class:`ExcitationLogError` if sampling is not uniform."""
        steps = np.diff(self.time)
        median = float(np.median(steps))
        worst = int(np.argmax(np.abs(steps - median)))
        if abs(steps[worst] - median) > UNIFORM_SAMPLING_TOLERANCE * median:
            raise ExcitationLogError(
                f"log {self.name!r}: time is not uniformly sampled (step {steps[worst]:.6g} s at time[{worst + 1}] = "
                f"{self.time[worst + 1]:.6g} s, median {median:.6g} s); resample it for a discrete-time estimator"
            )
        return median

    def speed_or_error(self, user: str) -> np.ndarray:
        """u(k), m/s; an :class:`ExcitationLogError` naming ``user`` (an estimator) if the log has no speed."""
        if self.speed is None:
            raise ExcitationLogError(
                f"log {self.name!r}: speed is absent, and {user} needs it (its model is speed-scheduled)"
            )
        return self.speed

    def rudder_rate_or_difference(self) -> np.ndarray:
        """delta'(k), rad/s: the measured rudder rate, or the forward difference of the rudder
        (delta(k+1) - delta(k)) / (t(k+1) - t(k)), the rate over the interval that starts at t(k)
        (the last sample repeats the one before)."""
        if self.rudder_rate is not None:
            return self.rudder_rate
        rate = np.empty_like(self.rudder)
        rate[:-1] = np.diff(self.rudder) / np.diff(self.time)
        rate[-1] = rate[-2]
        return rate

    def interval_rudder(self) -> np.ndarray:
        """The rudder over each sample interval (t(k-1), t(k)], k = 1..n-1: the mean of its two ends
        (exact for the steering machine's linear ramp; Song's "sampling mean of the input", (9))."""
        return 0.5 * (self.rudder[1:] + self.rudder[:-1])


def _as_array(value: object, name: str, length: int | None, log_name: str) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ExcitationLogError(f"log {log_name!r}: {name} must be numbers, got {value!r:.80}") from None
    if array.ndim != 1 or (length is not None and len(array) != length):
        expected = f"{length} samples (as time)" if length is not None else "a 1-D array"
        raise ExcitationLogError(f"log {log_name!r}: {name} has shape {array.shape}; expected {expected}")
    bad = ~np.isfinite(array)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ExcitationLogError(
            f"log {log_name!r}: {name}[{k}] = {array[k]:.6g} is not a finite number ({int(bad.sum())} such samples)"
        )
    array.setflags(write=False)
    return array


def _check_magnitude(values: np.ndarray, name: str, limit: float, unit: str, log_name: str) -> None:
    k = int(np.argmax(np.abs(values)))
    if abs(values[k]) > limit:
        raise ExcitationLogError(
            f"log {log_name!r}: {name}[{k}] = {values[k]:.6g} {unit} is beyond {limit:.3g} {unit}; "
            f"degrees where radians are expected?"
        )


def _check_heading_against_rate(time: np.ndarray, heading: np.ndarray, rate: np.ndarray, log_name: str) -> None:
    """The least-squares ratio of d(psi)/dt to r must be near 1, not near 57 or 1/57."""
    if math.sqrt(float(np.mean(rate**2))) < MIN_RATE_FOR_UNIT_CHECK:
        return
    heading_rate = np.diff(heading) / np.diff(time)
    mean_rate = 0.5 * (rate[1:] + rate[:-1])
    ratio = float(heading_rate @ mean_rate / (mean_rate @ mean_rate))
    if ratio > UNIT_MISMATCH_RATIO:
        raise ExcitationLogError(
            f"log {log_name!r}: heading changes {ratio:.3g} times faster than rate_of_turn says "
            f"(heading up to {float(np.max(np.abs(heading))):.4g}); heading in degrees where radians are expected?"
        )
    if ratio < 1.0 / UNIT_MISMATCH_RATIO:
        raise ExcitationLogError(
            f"log {log_name!r}: heading changes {ratio:.3g} times as fast as rate_of_turn says "
            f"(rate_of_turn up to {float(np.max(np.abs(rate))):.4g}); rate_of_turn in deg/s where rad/s is expected?"
        )


def from_workbench_log(log: Log, service_speed: float | None = None) -> ExcitationLog:
    """The measurement workbench's :class:`ship_env.workbench.logs.logs.Log` as an :class:`ExcitationLog`.

    The workbench's log is already in SI units and radians with an unwrapped heading. A log without
    a rate-of-turn channel gets r = d(psi)/dt by central differences (``numpy.gradient``); one
    without a speed channel sails at its ``service_speed``, else at ``service_speed`` given here.
    Raises :class:`ExcitationLogError` for an ordered (not actual) rudder, which the estimators
    cannot use as their input, and for a log with neither speed nor service speed.
    """
    if log.rudder_kind != "actual":
        raise ExcitationLogError(
            f"log {log.name!r}: rudder is the {log.rudder_kind} rudder; the estimators need the actual rudder angle"
        )
    rate = log.rate_of_turn_or_smoothed
    if log.speed is not None:
        speed = log.speed
    else:
        constant = log.service_speed if log.service_speed is not None else service_speed
        if constant is None:
            raise ExcitationLogError(f"log {log.name!r}: speed has no channel and no service speed; give service_speed")
        speed = np.full(len(log.time), float(constant))
    return ExcitationLog(log.time, log.rudder, log.heading, rate, speed, name=log.name)
