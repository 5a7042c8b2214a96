"""Fit the De Keizer / Van Leeuwen coefficients of the KVLCC2 preset to shipmmg's MMG model.

The MMG ship -- shipmmg 0.0.11's KVLCC2 (Yasukawa & Yoshimura 2015), Froude-scaled to 320 m -- and its
reference are described in :mod:`ship_env.model.mmg_kvlcc2`.

Manoeuvres, as in SIMMAN 2008/2020 (simman2020.kr, case 1.2): starting at 15.5 kn with the
propeller at the constant rate that holds 15.5 kn on a straight course, rudder rate 2.32 deg/s:
35 deg turning circles to starboard and to port (SIMMAN's case 1.2.3) and 10/10 and 20/20
zig-zags starting to starboard.

shipmmg is stepped closed loop by ``ship_env.model.mmg_kvlcc2.MmgKvlcc2`` (one ``simulate_mmg_3dof``
call per step, the rudder moving linearly over the step), and the rudder it actually had is
replayed into our ``Simulator`` as the order. ``scipy.optimize.least_squares`` fits K*, tau*,
alpha2, the Norrbin cubic alpha3, K_u*, tau_u*, beta3 and gamma1* (alpha1 = 1, alpha0 = 0) to
heading, rate of turn, speed and drift angle in two stages: first 120-s prediction segments started
from the MMG state (multiple shooting: robust against the heading error that an open-loop replay
piles up), then the whole runs replayed (output error), from the first stage's result.
``--slipstream`` also fits the propeller-slipstream coefficient, with the propeller held at the
service rate as in the MMG runs.

Run:  python benchmarks/fit_kvlcc2.py [--dt 0.5] [--quick] [--slipstream]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from ship_env.model import EFFECTS, Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.external import ShipMotion
from ship_env.model.mmg_kvlcc2 import (
    INSTALL_HINT,
    LENGTH,
    PROPELLER_DIAMETER,
    RUDDER_LIMIT,
    RUDDER_RATE,
    SCALE,
    SERVICE_SPEED,
    MmgKvlcc2,
    service_propeller_rate,
)
from ship_env.model.ship import Ship

#: The effects of the fitted model: the minimal model plus Norrbin, speed loss and sway.
FIT_EFFECTS = ("yaw", "norrbin", "speed_loss", "sway", "steering_machine", "kinematics")

#: Fitted parameters: (key, start, lower bound, upper bound).
FIT_PARAMETERS = (
    ("yaw.gain", 1.5, 0.05, 10.0),
    ("yaw.time_constant", 2.0, 0.05, 30.0),
    ("asymmetry.quadratic", 0.0, -5.0, 5.0),
    ("norrbin.cubic", 0.5, 0.0, 100.0),
    ("speed_loss.gain", 0.7, 0.0, 50.0),
    ("speed_loss.time_constant", 3.0, 0.05, 200.0),
    ("speed_loss.cubic", 0.5, 0.0, 500.0),
    ("sway.linear", 0.37, -1.0, 3.0),
)
SLIPSTREAM_PARAMETER = ("propeller_slipstream.coefficient", 0.02, 0.0, 3.0)

#: Values of the model's parameters that are not fitted (and the defaults of those that are).
DEFAULT_VALUES = {
    "yaw.linear": 1.0,
    "steering_machine.rudder_rate": RUDDER_RATE,
    "propeller_slipstream.propeller_diameter": PROPELLER_DIAMETER,
    **{key: start for key, start, _, _ in (*FIT_PARAMETERS, SLIPSTREAM_PARAMETER)},
}

#: Prediction horizon of the first (multiple-shooting) stage, s.
HORIZON = 120.0

#: Residual scales: an error of this size in a channel costs as much as in any other.
SCALES = {"heading": 2.0, "rate_of_turn": 0.05, "speed": 0.1, "drift": 0.5}  # deg, deg/s, m/s, deg

#: Normalised residual given to each sample after a trial left the model's validity (u* > 1).
FAILED_RESIDUAL = 20.0


@dataclass(frozen=True)
class Manoeuvre:
    """A standard manoeuvre: a turning circle (``deviation`` None) or a zig-zag."""

    name: str
    rudder: float  # deg, positive to starboard (a zig-zag starts with it)
    deviation: float | None  # deg, zig-zag heading deviation that reverses the rudder
    duration: float  # s


MANOEUVRES = (
    Manoeuvre("turning_35", 35.0, None, 900.0),
    Manoeuvre("turning_35_port", -35.0, None, 900.0),
    Manoeuvre("zigzag_10_10", 10.0, 10.0, 1300.0),
    Manoeuvre("zigzag_20_20", 20.0, 20.0, 1000.0),
)


# -- manoeuvres ----------------------------------------------------------------------------------
def next_order(manoeuvre: Manoeuvre, heading: float, order: float | None) -> float:
    """The rudder order after a step: hold, or reverse at the zig-zag's heading deviation."""
    rudder = math.radians(manoeuvre.rudder)
    if order is None:
        return rudder
    if manoeuvre.deviation is None:
        return order
    deviation = math.radians(manoeuvre.deviation)
    if order > 0.0 and heading >= deviation:
        return -rudder
    if order < 0.0 and heading <= -deviation:
        return rudder
    return order


def _channels(record: np.ndarray) -> dict[str, np.ndarray]:
    return {
        "time": record[:, 0],
        "heading": np.degrees(record[:, 1]),
        "rate_of_turn": np.degrees(record[:, 2]),
        "speed": record[:, 3],
        "drift": np.degrees(record[:, 4]),
        "north": record[:, 5],
        "east": record[:, 6],
        "rudder": record[:, 7],
    }


def run_mmg(manoeuvre: Manoeuvre, dt: float) -> dict[str, np.ndarray]:
    """shipmmg's KVLCC2 through a manoeuvre, closed loop; channels sampled after each step."""
    ship = MmgKvlcc2(rtol=1e-6, atol=1e-9)
    ship.reset(ShipMotion(0.0, 0.0, 0.0, 0.0, SERVICE_SPEED), Conditions(service_speed=SERVICE_SPEED), 0)
    steps = int(round(manoeuvre.duration / dt))
    record = np.zeros((steps, 8))
    order = next_order(manoeuvre, 0.0, None)
    for k in range(steps):
        m = ship.step(order, None, dt)
        record[k] = ((k + 1) * dt, m.heading, m.rate_of_turn, m.speed, m.drift, m.north, m.east, m.rudder)
        order = next_order(manoeuvre, m.heading, order)
    return _channels(record)


# -- our model -----------------------------------------------------------------------------------
def kvlcc2_ship(values: dict[str, float] | None = None, slipstream: bool = False) -> Ship:
    """A ``Ship`` with KVLCC2's principal particulars (independent of the YAML being fitted)."""
    chosen = {**DEFAULT_VALUES, **(values or {})}
    effects = fit_effects(slipstream)
    effect_values = {
        effect: {
            parameter.name: float(chosen.get(f"{effect}.{parameter.name}", 0.0))
            for parameter in EFFECTS[effect].parameters
        }
        for effect in effects
    }
    return Ship(
        name="kvlcc2_fit",
        description="KVLCC2 for fitting",
        principal={
            "length": LENGTH,
            "breadth": 58.0,
            "draught": 20.8,
            "service_speed": SERVICE_SPEED,
            "rudder_limit": RUDDER_LIMIT,
            "minimum_speed": 0.5,
        },
        values=effect_values,
        enabled=effects,
    )


def fit_effects(slipstream: bool) -> tuple[str, ...]:
    return FIT_EFFECTS + (("propeller_slipstream",) if slipstream else ())


def fit_parameters(slipstream: bool):
    return FIT_PARAMETERS + ((SLIPSTREAM_PARAMETER,) if slipstream else ())


def ours_conditions() -> Conditions:
    """Calm water, the propeller at the service rate (used only by the slipstream effect)."""
    return Conditions(propeller_rate=service_propeller_rate())


def run_ours(values: dict[str, float], manoeuvre: Manoeuvre, dt: float, slipstream: bool = False):
    """Our model through a manoeuvre, closed loop; None where it left the model's validity."""
    sim = Simulator(ShipModel(kvlcc2_ship(values, slipstream), fit_effects(slipstream)), dt=dt)
    sim.reset(seed=0, conditions=ours_conditions())
    steps = int(round(manoeuvre.duration / dt))
    record = np.zeros((steps, 8))
    state = sim.state[0]
    order = next_order(manoeuvre, 0.0, None)
    try:
        for k in range(steps):
            sim.step(order)
            speed = float(sim.speed[0])
            sway = float(sim.sway_velocity[0])
            record[k] = (state[0], state[3], state[4], speed, math.atan2(-sway, speed), state[1], state[2], state[6])
            order = next_order(manoeuvre, state[3], order)
    except FloatingPointError:
        return None
    return _channels(record)


# -- fitting -------------------------------------------------------------------------------------
def segments(references, dt: float, horizon: float | None):
    """Cut the references into prediction segments of ``horizon`` seconds (multiple shooting).

    ``horizon`` None gives one segment per manoeuvre: the whole run replayed (output error).
    Each segment starts from the MMG state at its first instant (heading, rate of turn, speed,
    rudder) and replays the MMG rudder. Returns the start states (segments, 4), the orders
    (segments, steps), the reference channels (segments, steps; NaN past a short segment's end)
    and each sample's weight (each manoeuvre counts alike).
    """
    pieces = []
    for _, reference in references:
        count = len(reference["time"])
        length = count if horizon is None else min(count, int(round(horizon / dt)))
        firsts = range(0, count - length + 1, length)
        for k in firsts:
            if k == 0:
                start = (0.0, 0.0, SERVICE_SPEED, 0.0)
            else:
                start = (
                    math.radians(reference["heading"][k - 1]),
                    math.radians(reference["rate_of_turn"][k - 1]),
                    reference["speed"][k - 1],
                    reference["rudder"][k - 1],
                )
            pieces.append((start, k, length, reference, 1.0 / math.sqrt(len(firsts) * length)))
    steps = max(length for _, _, length, _, _ in pieces)
    starts = np.array([start for start, *_ in pieces])
    orders = np.zeros((len(pieces), steps))
    targets = {c: np.full((len(pieces), steps), np.nan) for c in SCALES}
    weights = np.zeros((len(pieces), 1))
    for i, (_, k, length, reference, weight) in enumerate(pieces):
        orders[i, :length] = reference["rudder"][k : k + length]
        orders[i, length:] = reference["rudder"][k + length - 1]
        for channel in SCALES:
            targets[channel][i, :length] = reference[channel][k : k + length]
        weights[i] = weight
    return starts, orders, targets, weights


def predict(values: dict[str, float], starts: np.ndarray, orders: np.ndarray, dt: float, slipstream: bool = False):
    """Our model from each start state through its orders, all segments as one batch.

    Returns the channels (segments, steps) and, per segment, the step at which it left the
    model's validity (u* > 1; ``steps`` where it never did). A ship that leaves is held there.
    """
    model = ShipModel(kvlcc2_ship(values, slipstream), fit_effects(slipstream))
    count, steps = orders.shape
    sim = Simulator(model, num_ships=count, dt=dt)
    sim.reset(
        seed=0, conditions=ours_conditions(), heading=starts[:, 0], rate_of_turn=starts[:, 1], rudder=starts[:, 3]
    )
    sim.state[:, S.SPEED_LOSS] = 1.0 - starts[:, 2] / SERVICE_SPEED
    out = {c: np.zeros((count, steps)) for c in (*SCALES, "north", "east")}
    failed_at = np.full(count, steps)
    gamma1 = model.parameter("sway.linear")
    for j in range(steps):
        before = sim.state.copy()
        try:
            sim.step(np.ascontiguousarray(orders[:, j]))
        except FloatingPointError:
            bad = ~np.all(np.isfinite(sim.state), axis=1) | (sim.state[:, S.SPEED_LOSS] >= 1.0)
            failed_at[bad] = np.minimum(failed_at[bad], j)
            sim.state[bad] = before[bad]
        speed = sim.speed
        normalised_rate = LENGTH * sim.rate_of_turn / np.maximum(speed, 0.5)
        out["heading"][:, j] = np.degrees(sim.heading)
        out["rate_of_turn"][:, j] = np.degrees(sim.rate_of_turn)
        out["speed"][:, j] = speed
        out["drift"][:, j] = np.degrees(np.arctan(gamma1 * normalised_rate))  # beta = atan(-v/u), v = -u gamma1 r*
        out["north"][:, j] = sim.position[:, 0]
        out["east"][:, j] = sim.position[:, 1]
    return out, failed_at


def residuals(vector, keys, starts, orders, targets, weights, dt: float, slipstream: bool) -> np.ndarray:
    values = dict(zip(keys, (float(v) for v in vector), strict=True))
    ours, failed_at = predict(values, starts, orders, dt, slipstream)
    failed = np.arange(orders.shape[1])[None, :] >= failed_at[:, None]
    parts = []
    for channel, scale in SCALES.items():
        error = (ours[channel] - targets[channel]) / scale
        error[failed] = FAILED_RESIDUAL
        error[np.isnan(targets[channel])] = 0.0
        parts.append((weights * error).ravel())
    return np.concatenate(parts)


def segment_errors(values, references, dt: float, horizon: float | None, slipstream: bool):
    """Per manoeuvre: RMS error of each channel over ``horizon``-s predictions, and validity."""
    result = []
    for manoeuvre, reference in references:
        starts, orders, targets, _ = segments([(manoeuvre, reference)], dt, horizon)
        ours, failed_at = predict(values, starts, orders, dt, slipstream)
        errors = {c: float(np.sqrt(np.nanmean((ours[c] - targets[c]) ** 2))) for c in SCALES}
        errors["valid"] = bool(np.all(failed_at == orders.shape[1]))
        result.append(errors)
    return result


def fit(
    dt: float = 0.5, manoeuvres=MANOEUVRES, slipstream: bool = False, horizon: float = HORIZON, verbose: bool = True
):
    """Generate the MMG references and fit our coefficients; returns (values, references)."""
    from scipy.optimize import least_squares

    started = time.perf_counter()
    references = [(m, run_mmg(m, dt)) for m in manoeuvres]
    if verbose:
        steps = sum(len(r["time"]) for _, r in references)
        print(f"shipmmg references: {steps} closed-loop steps in {time.perf_counter() - started:.1f} s")
    parameters = fit_parameters(slipstream)
    keys = [p[0] for p in parameters]
    vector = np.array([p[1] for p in parameters])
    bounds = (np.array([p[2] for p in parameters]), np.array([p[3] for p in parameters]))
    for stage, stage_horizon in (("prediction segments", horizon), ("whole runs", None)):
        started = time.perf_counter()
        data = segments(references, dt, stage_horizon)
        result = least_squares(residuals, vector, bounds=bounds, args=(keys, *data, dt, slipstream), x_scale="jac")
        vector = result.x
        if verbose:
            label = f"{stage} ({stage_horizon:.0f} s)" if stage_horizon else stage
            print(
                f"least_squares on {label}: {result.nfev} evaluations, {time.perf_counter() - started:.1f} s, "
                f"cost {result.cost:.4g}"
            )
    return dict(zip(keys, (float(v) for v in vector), strict=True)), references


def rms(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((a - b) ** 2)))


def overshoots(channels: dict[str, np.ndarray], manoeuvre: Manoeuvre, count: int = 2) -> list[float]:
    """Zig-zag overshoot angles (deg): the heading's excursions beyond the deviation, in order."""
    heading = channels["heading"]
    rudder = channels["rudder"]
    negative = rudder < 0.0
    # Segments of one rudder sign after the first reversal; the heading peaks within each.
    edges = np.flatnonzero(negative[1:] != negative[:-1]) + 1
    result = []
    for start, stop in zip(edges, list(edges[1:]) + [len(heading)], strict=True):
        segment = heading[start:stop]
        extreme = segment.max() if negative[start] else -segment.min()
        result.append(float(extreme - manoeuvre.deviation))
    return result[:count]


def turning_figures(channels: dict[str, np.ndarray]) -> tuple[float, float]:
    """(advance, tactical diameter) in ship lengths from a turning circle (NaN if not reached)."""
    heading = np.abs(channels["heading"])
    figures = []
    for angle, axis in ((90.0, "north"), (180.0, "east")):
        reached = np.flatnonzero(heading >= angle)
        figures.append(abs(channels[axis][reached[0]]) / LENGTH if reached.size else math.nan)
    return figures[0], figures[1]


def validity_check(values, dt: float, slipstream: bool) -> list[str]:
    """Hard-over turns both ways and long zig-zags: does the fitted model stay valid (u* < 1)?"""
    lines = []
    for manoeuvre in (
        Manoeuvre("turning_35_starboard_1h", 35.0, None, 3600.0),
        Manoeuvre("turning_35_port_1h", -35.0, None, 3600.0),
        Manoeuvre("zigzag_35_35_1h", 35.0, 35.0, 3600.0),
    ):
        run = run_ours(values, manoeuvre, dt, slipstream)
        if run is None:
            lines.append(f"{manoeuvre.name}: INVALID (u* > 1)")
        else:
            lowest = run["speed"].min()
            lines.append(f"{manoeuvre.name}: valid, lowest speed {lowest:.2f} m/s ({lowest / SERVICE_SPEED:.0%} of U0)")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("--dt", type=float, default=0.5, help="step for both models, s (default 0.5)")
    parser.add_argument("--quick", action="store_true", help="only the first 300 s of each manoeuvre")
    parser.add_argument("--slipstream", action="store_true", help="also fit the propeller-slipstream coefficient")
    args = parser.parse_args(argv)
    try:
        import shipmmg  # noqa: F401
    except ImportError:
        print(INSTALL_HINT)
        return 1
    manoeuvres = MANOEUVRES
    if args.quick:
        manoeuvres = tuple(Manoeuvre(m.name, m.rudder, m.deviation, min(m.duration, 300.0)) for m in MANOEUVRES)
    print(
        "command: python "
        + " ".join(
            [sys.argv[0] if argv is None else "benchmarks/fit_kvlcc2.py", *(sys.argv[1:] if argv is None else argv)]
        )
    )
    mmg = MmgKvlcc2()
    print(
        f"KVLCC2 full scale (lambda = {SCALE:.3f}): L_pp {mmg.basic.L_pp:.1f} m, B {mmg.basic.B:.2f} m, "
        f"d {mmg.basic.d:.2f} m, U0 {mmg.service_speed:.3f} m/s, propeller {mmg.propeller_rate * 60:.2f} rpm "
        f"(equilibrium at U0), rudder rate {math.degrees(RUDDER_RATE):.2f} deg/s, dt {args.dt} s"
    )
    values, references = fit(args.dt, manoeuvres, args.slipstream)
    print("\nfitted values (yaw.linear = 1, asymmetry.constant = 0, sway.cubic = 0 held):")
    for key, value in values.items():
        print(f"  {key:34s} {value:.4g}")

    whole = segment_errors(values, references, args.dt, None, args.slipstream)
    short = segment_errors(values, references, args.dt, HORIZON, args.slipstream)
    print("\nRMS error of our model against shipmmg (replaying shipmmg's rudder):")
    print(
        f"  {'manoeuvre':14s} {'heading deg':>11s} {'r deg/s':>8s} {'u m/s':>6s} {'drift deg':>9s} "
        f"{'heading deg, 120-s predictions':>31s}"
    )
    for (manoeuvre, _), run, pieces in zip(references, whole, short, strict=True):
        flag = "" if run["valid"] else "  INVALID (u* > 1)"
        print(
            f"  {manoeuvre.name:14s} {run['heading']:11.2f} {run['rate_of_turn']:8.4f} {run['speed']:6.3f} "
            f"{run['drift']:9.2f} {pieces['heading']:31.2f}{flag}"
        )

    print("\nclosed-loop checks (shipmmg | ours):")
    for manoeuvre, reference in references:
        ours = run_ours(values, manoeuvre, args.dt, args.slipstream)
        if ours is None:
            print(f"  {manoeuvre.name}: ours left the model's validity")
            continue
        heading_rms = rms(ours["heading"], reference["heading"])
        if manoeuvre.deviation is None:
            a, b = turning_figures(reference), turning_figures(ours)
            print(
                f"  {manoeuvre.name}: advance {a[0]:.2f} | {b[0]:.2f} L, tactical diameter {a[1]:.2f} | {b[1]:.2f} L, "
                f"steady speed {reference['speed'][-1]:.2f} | {ours['speed'][-1]:.2f} m/s"
            )
        else:
            a, b = overshoots(reference, manoeuvre), overshoots(ours, manoeuvre)
            print(
                f"  {manoeuvre.name}: overshoots {', '.join(f'{v:.1f}' for v in a)} | "
                f"{', '.join(f'{v:.1f}' for v in b)} deg, RMS heading difference {heading_rms:.2f} deg"
            )
    print("\nvalidity of the fitted model:")
    for line in validity_check(values, args.dt, args.slipstream):
        print("  " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
