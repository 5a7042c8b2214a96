"""Past the library: which measured signals the model's missing yaw acceleration lines up with.

When no effect in the library explains the residual, the question becomes what kind of effect to
write. The answer is in the *equation error*: the yaw acceleration the ship showed (the smoothed
derivative of the measured rate of turn) less the yaw acceleration the fitted model gives at the
measured state, rudder, speed, propeller rate and wind. A missing effect leaves a residual that is
a function of the signals it depends on, so the residual is correlated with simple signals and
products of them (:data:`SIGNALS`): the rudder angle cubed (a rudder that stalls), the propeller
rate squared (a propeller side force), the rate of turn cubed (non-linear damping), the yaw
damping times the speed squared (shallow water), the wind's angle off the bow, the propeller
turning astern...

The fitted model already holds the linear Nomoto terms, the rudder moment u^2 delta and the hull's
damping u r (2.54); their part of each signal is projected out first, so a signal scores by what
it adds (its *partial* correlation with the residual). The signals are ranked by it, and each is
named in a naval engineer's words with the kind of effect it points to; :func:`plot_signals`
draws the residual against the strongest.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure as Drawing
from scipy.signal import savgol_filter

from ship_env.model import state as S
from ship_env.model.dynamics import derivatives
from ship_env.model.kernel import kernel
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.logs.logs import Log
from ship_env.workbench.outputs import save_drawing

#: The span the rate of turn is smoothed and differentiated over, s (Savitzky-Golay, quadratic).
SMOOTHING = 4.0


@dataclass(frozen=True)
class Measured:
    """The pooled, smoothed samples of the logs the signals are made of (SI units, radians)."""

    speed: np.ndarray
    propeller_rate: np.ndarray
    rudder: np.ndarray
    rudder_rate: np.ndarray
    rate_of_turn: np.ndarray
    normalised_rate: np.ndarray
    wind_speed: np.ndarray
    wind_angle: np.ndarray
    has_propeller: bool
    has_wind: bool


@dataclass(frozen=True)
class Signal:
    """A measured signal (or product) a missing yaw acceleration may follow.

    Attributes:
        name: a short identifier (``rudder_cubed``).
        words: what it is, in a naval engineer's words.
        points_to: the kind of effect a residual that follows it suggests.
        values: the signal from the measured samples.
        needs: ``"propeller"``, ``"wind"`` or ``""``: the channel it needs in every log.
    """

    name: str
    words: str
    points_to: str
    values: Callable[[Measured], np.ndarray]
    needs: str = ""


def _u2(m: Measured) -> np.ndarray:
    return m.speed * m.speed


#: The signals tried, each scaled as the yaw equation scales its terms ((u/L)^2 for a moment).
SIGNALS: tuple[Signal, ...] = (
    Signal(
        "speed_squared",
        "the speed squared alone (the ship turns with the rudder amidships, the more the faster)",
        "a rudder offset, or a hull that is not symmetric",
        _u2,
    ),
    Signal(
        "constant",
        "a constant yaw acceleration, whatever the speed",
        "a steady outside yaw moment (a current's or a bank's), or a rate-gyro bias",
        lambda m: np.ones_like(m.speed),
    ),
    Signal(
        "rudder_cubed",
        "the rudder angle cubed, times u^2",
        "a rudder force not proportional to the angle: stall at large angles, or a rudder partly in the hull's wake",
        lambda m: _u2(m) * m.rudder**3,
    ),
    Signal(
        "rudder_squared",
        "the rudder angle squared with its sign, times u^2",
        "a rudder force that saturates (or grows) with the angle",
        lambda m: _u2(m) * np.abs(m.rudder) * m.rudder,
    ),
    Signal(
        "rudder_speed",
        "the rudder angle times u^3",
        "a rudder moment that grows faster than the speed squared (the rudder in the propeller race, squat)",
        lambda m: _u2(m) * m.speed * m.rudder,
    ),
    Signal(
        "rudder_propeller",
        "the rudder angle times the propeller rate squared",
        "the propeller's slipstream over the rudder",
        lambda m: m.propeller_rate**2 * m.rudder,
        "propeller",
    ),
    Signal(
        "rudder_astern",
        "the rudder angle times u^2 while the propeller turns astern",
        "rudder force lost (or reversed) with the propeller astern",
        lambda m: _u2(m) * m.rudder * (m.propeller_rate < 0.0),
        "propeller",
    ),
    Signal(
        "propeller",
        "the propeller rate squared, with its sign",
        "a propeller side force (the propeller walks the stern)",
        lambda m: np.abs(m.propeller_rate) * m.propeller_rate,
        "propeller",
    ),
    Signal(
        "rate_cubed",
        "the rate of turn cubed (r*^3 u^2)",
        "yaw damping that is not linear in the rate of turn (Norrbin's cubic term)",
        lambda m: _u2(m) * m.normalised_rate**3,
    ),
    Signal(
        "rate_squared_signed",
        "the rate of turn squared with its sign (|r*| r* u^2)",
        "yaw damping that grows with the rate of turn (Norrbin's |r| r term)",
        lambda m: _u2(m) * np.abs(m.normalised_rate) * m.normalised_rate,
    ),
    Signal(
        "rate_squared",
        "the rate of turn squared, whatever the side (r*^2 u^2)",
        "a ship that turns tighter to one side (port-starboard asymmetry)",
        lambda m: _u2(m) * m.normalised_rate**2,
    ),
    Signal(
        "rate_speed",
        "the rate of turn times u^2 (the hull's damping times the speed)",
        "yaw damping that grows with speed: shallow water (depth Froude number), squat, a bank",
        lambda m: _u2(m) * m.rate_of_turn,
    ),
    Signal(
        "rudder_rate",
        "the rudder's rate of movement",
        "a steering machine slower than the model's, or a rudder log that records the order",
        lambda m: m.rudder_rate,
    ),
    Signal(
        "wind_bow",
        "the wind from the bow or the quarter (V^2 sin 2 gamma)",
        "a wind yaw moment (2.87)",
        lambda m: m.wind_speed**2 * np.sin(2.0 * m.wind_angle),
        "wind",
    ),
    Signal(
        "wind_beam",
        "a beam wind (V^2 sin gamma)",
        "a wind moment with the centre of effort off midships (accommodation aft)",
        lambda m: m.wind_speed**2 * np.sin(m.wind_angle),
        "wind",
    ),
)


@dataclass(frozen=True)
class Match:
    """How well the missing yaw acceleration follows one signal.

    Attributes:
        signal: the signal.
        correlation: its partial correlation with the residual (-1..1), the model's linear terms
            projected out of both.
        slope: the residual per unit of the signal (its least-squares coefficient).
    """

    signal: Signal
    correlation: float
    slope: float


@dataclass(frozen=True)
class ResidualSignals:
    """The missing yaw acceleration and the signals it follows, strongest first.

    Attributes:
        residual: the missing yaw acceleration at every sample, rad/s^2 (all logs).
        measured: the smoothed samples the signals are made of.
        matches: every signal tried, by the size of its partial correlation.
        held: the model's linear terms at every sample (columns), projected out before comparing.
    """

    residual: np.ndarray
    measured: Measured
    matches: tuple[Match, ...]
    held: np.ndarray

    @property
    def strongest(self) -> Match:
        return self.matches[0]

    def without_held(self, values: np.ndarray) -> np.ndarray:
        """``values`` less their least-squares fit by the model's linear terms."""
        return values - self.held @ np.linalg.lstsq(self.held, values, rcond=None)[0]

    def text(self, count: int = 3) -> str:
        """The strongest signals in words."""
        lines = [
            "the model's missing yaw acceleration (measured less modelled, rms "
            f"{math.degrees(float(np.sqrt(np.mean(self.residual**2)))):.3g} deg/s^2) lines up with:"
        ]
        for rank, match in enumerate(self.matches[:count], 1):
            side = "exceeds" if match.correlation > 0.0 else "falls short of"
            lines.append(
                f"  {rank}. {match.signal.words} (partial correlation {match.correlation:+.2f}: the ship's yaw "
                f"acceleration {side} the model's as it grows): look for {match.signal.points_to}"
            )
        return "\n".join(lines)


@kernel
def _yaw_accelerations(states, rudders, conditions, no_draws, params, out):
    """The model's dr/dt at each measured state (no disturbance states, no sea: ``no_draws`` are zeros)."""
    p = params[0]
    slope = np.zeros(states.shape[1])
    white_noise = np.zeros(states.shape[1])
    for i in range(states.shape[0]):
        derivatives(states[i], rudders[i], conditions[i], white_noise, no_draws, 0.0, p, slope)
        out[i] = slope[S.RATE_OF_TURN]


def _smoothed(values: np.ndarray, time: np.ndarray, derivative: int = 0) -> np.ndarray:
    step = float(np.median(np.diff(time)))
    window = max(5, int(round(SMOOTHING / step)) | 1)
    if window > len(values):
        window = len(values) if len(values) % 2 else len(values) - 1
    if window < 3:
        return np.gradient(values, time) if derivative else values.copy()
    return savgol_filter(values, window, min(2, window - 1), deriv=derivative, delta=step)


def _log_samples(setup: ReplayModel, log: Log) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """One log's missing yaw acceleration and its smoothed signals."""
    model = setup.model
    rate = log.rate_of_turn_or_smoothed
    rate_smooth = _smoothed(rate, log.time)
    measured_acceleration = _smoothed(rate, log.time, derivative=1)
    speed = np.full(log.samples, model.service_speed if log.service_speed is None else log.service_speed)
    if log.speed is not None:
        speed = _smoothed(np.maximum(log.speed, 0.0), log.time)
    propeller = np.zeros(log.samples) if log.propeller_rate is None else _smoothed(log.propeller_rate, log.time)
    rudder = _smoothed(log.rudder, log.time)
    states = np.zeros((log.samples, model.state_size))
    states[:, S.TIME] = log.time
    states[:, S.HEADING] = _smoothed(log.heading, log.time)
    states[:, S.RATE_OF_TURN] = rate_smooth
    states[:, S.RUDDER] = rudder
    conditions = np.zeros((log.samples, S.CONDITION_SIZE))
    conditions[:, S.SERVICE_SPEED] = speed
    conditions[:, S.PROPELLER_RATE] = propeller  # signed, as the replay sails it: astern is negative
    wind_speed = np.zeros(log.samples)
    wind_angle = np.zeros(log.samples)
    if log.wind_speed is not None and log.wind_direction is not None:
        wind_speed = np.maximum(log.wind_speed, 0.0)
        conditions[:, S.WIND_SPEED] = wind_speed
        conditions[:, S.WIND_DIRECTION] = log.wind_direction
        wind_angle = log.wind_direction - states[:, S.HEADING]
    S.derive_conditions(conditions)
    model.start_states(states, conditions)  # an effect's own state where its declaration starts it
    modelled = np.zeros(log.samples)
    _yaw_accelerations(states, rudder, conditions, np.zeros(model.draw_size), model.record, modelled)
    scheduling = np.maximum(speed, model.parameter("minimum_speed"))
    columns = {
        "speed": speed,
        "propeller_rate": propeller,
        "rudder": rudder,
        "rudder_rate": _smoothed(log.rudder, log.time, derivative=1),
        "rate_of_turn": rate_smooth,
        "normalised_rate": model.length * rate_smooth / scheduling,
        "wind_speed": wind_speed,
        "wind_angle": wind_angle,
    }
    return measured_acceleration - modelled, columns


def residual_signals(setup: ReplayModel, logs: Sequence[Log]) -> ResidualSignals:
    """The fitted model's missing yaw acceleration over the logs and the signals it follows.

    Args:
        setup: the fitted model (``CrossValidation.fit.setup``).
        logs: the runs it was fitted to.
    """
    pieces = [_log_samples(setup, log) for log in logs]
    residual = np.concatenate([piece[0] for piece in pieces])
    pooled = {name: np.concatenate([piece[1][name] for piece in pieces]) for name in pieces[0][1]}
    measured = Measured(
        **pooled,
        has_propeller=all(log.propeller_rate is not None for log in logs),
        has_wind=all(log.has_wind for log in logs),
    )
    # The linear Nomoto terms the fit already has: the rudder moment and the hull's damping (2.54).
    held = np.column_stack([measured.speed**2 * measured.rudder, measured.speed * measured.rate_of_turn])
    without_held = ResidualSignals(residual, measured, (), held).without_held
    target = without_held(residual)
    matches = []
    for signal in SIGNALS:
        if (signal.needs == "propeller" and not measured.has_propeller) or (
            signal.needs == "wind" and not measured.has_wind
        ):
            continue
        values = without_held(signal.values(measured))
        size = float(np.linalg.norm(values))
        if size <= 1e-12 * max(float(np.linalg.norm(signal.values(measured))), 1e-300) or not np.any(target):
            continue  # nothing left once the linear terms are out (e.g. never astern)
        correlation = float(values @ target / (size * np.linalg.norm(target)))
        matches.append(Match(signal, correlation, float(values @ target / (size * size))))
    matches.sort(key=lambda match: -abs(match.correlation))
    return ResidualSignals(residual, measured, tuple(matches), held)


def plot_signals(signals: ResidualSignals, path: Path, title: str = "") -> Path:
    """Draw the missing yaw acceleration against the strongest signal into a PNG file; returns its path.

    Both with the model's linear terms projected out (an added-variable plot), so the line's slope
    is the one the partial correlation measures.
    """
    match = signals.strongest
    values = signals.without_held(match.signal.values(signals.measured))
    residual = np.degrees(signals.without_held(signals.residual))
    drawing = Drawing(figsize=(6.4, 4.8))
    FigureCanvasAgg(drawing)
    axes = drawing.add_subplot()
    axes.plot(values, residual, ".", markersize=2, alpha=0.5, label="samples, all runs")
    ends = np.array([values.min(), values.max()])
    axes.plot(
        ends, math.degrees(match.slope) * ends, "-", color="black", label=f"partial corr. {match.correlation:+.2f}"
    )
    axes.set_xlabel(f"{match.signal.words} (less its linear-model part)")
    axes.set_ylabel("missing yaw acceleration, deg/s^2 (likewise)")
    axes.set_title(title or f"look for {match.signal.points_to}", fontsize=9, wrap=True)
    axes.legend(loc="best", fontsize=8)
    return save_drawing(drawing, Path(path), dpi=100)
