"""A second ship simulator, written apart from ship_env's integrators and kernels, to sail test logs.

The workbench fits models that ship_env's own compiled step integrates (RK4, inputs held from the
start of each sample interval). Logs sailed by that same code share its numerical conventions, which
no real log does. This simulator sails the same physical model family in plain numpy, deliberately
differently:

- **explicit Euler** with ``SUBSTEPS`` sub-steps per sample interval, the speed and rudder changing
  within the interval (not held);
- a **steering gear** that moves the actual rudder towards the order at its rate limit, and the
  **actual rudder sampled at the end** of each interval (ship_env holds a sample from the interval's
  start);
- a **sensor delay**: the rate gyro reports the value of one sample earlier. (A compass as late
  would look to the track replay, which sails the measured heading, exactly like a drift angle of
  r dt: Van Leeuwen's sway with gamma1* = u dt / L, 0.023 on the 3 m model at 5 Hz -- a real
  mismatch of a size that also means something physically, so no materiality can tell them apart.)

The model: De Keizer's speed-scheduled first-order Nomoto yaw (thesis 2.54, 2.27) with kinematics
(2.64, 2.65), and optionally Norrbin's cubic and |r*| r* terms, the propeller slipstream over the
rudder, a rudder offset and a steady current:

    dr/dt = [ (u^2 + c_s (n D)^2) K* (delta + delta_0) - u^2 H(r*) ] / (tau* L^2),   r* = L r / u
    H(r*) = alpha1 r* + alpha2' |r*| r* + alpha3 r*^3
    dpsi/dt = r,   dx0/dt = u cos(psi) + c_north,   dy0/dt = u sin(psi) + c_east

The speed through the water follows the manoeuvre's acceleration from its start to its final speed.
The coefficients are read from a ship preset (a :class:`~ship_env.model.ShipModel`'s values): only
the numbers are shared, never the code that integrates them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ship_env.model import ShipModel
from ship_env.workbench import Log
from ship_env.workbench.synthetic import Manoeuvre, SensorNoise

#: Euler sub-steps per sample interval.
SUBSTEPS = 10
#: Samples by which the rate gyro lags the ship.
GYRO_DELAY = 1
#: The effects this simulator can sail besides the yaw equation and kinematics.
EFFECTS = ("norrbin", "propeller_slipstream", "rudder_offset", "current")


@dataclass(frozen=True)
class Hull:
    """The coefficients the simulator sails with (SI units; an effect that is off has its null value)."""

    length: float
    gain: float
    time_constant: float
    linear: float
    rudder_rate: float
    cubic: float = 0.0
    odd_quadratic: float = 0.0
    slipstream: float = 0.0
    propeller_diameter: float = 0.0
    rudder_offset: float = 0.0
    current_north: float = 0.0
    current_east: float = 0.0

    @classmethod
    def from_preset(cls, ship: str, effects: Sequence[str] = (), current: tuple[float, float] = (0.0, 0.0)) -> Hull:
        """The preset's coefficients, with the named ``EFFECTS`` on at the preset's values (and ``current``)."""
        unknown = set(effects) - set(EFFECTS)
        if unknown:
            raise ValueError(f"second simulator: cannot sail {sorted(unknown)}; it sails {EFFECTS}")
        values = ShipModel(ship)

        def on(effect: str, key: str) -> float:
            return values.parameter(key) if effect in effects else 0.0

        north, east = current if "current" in effects else (0.0, 0.0)
        return cls(
            length=values.length,
            gain=values.parameter("yaw.gain"),
            time_constant=values.parameter("yaw.time_constant"),
            linear=values.parameter("yaw.linear"),
            rudder_rate=values.parameter("steering_machine.rudder_rate"),
            cubic=on("norrbin", "norrbin.cubic"),
            odd_quadratic=on("norrbin", "norrbin.odd_quadratic"),
            slipstream=on("propeller_slipstream", "propeller_slipstream.coefficient"),
            propeller_diameter=values.parameter("propeller_slipstream.propeller_diameter"),
            rudder_offset=on("rudder_offset", "rudder_offset.angle"),
            current_north=north,
            current_east=east,
        )

    def yaw_acceleration(self, rate: float, speed: float, rudder: float, propeller_rate: float) -> float:
        """dr/dt of the model in the module docstring."""
        normalised = self.length * rate / speed
        restoring = (
            self.linear * normalised + self.odd_quadratic * abs(normalised) * normalised + self.cubic * normalised**3
        )
        inflow = speed * speed + self.slipstream * (max(propeller_rate, 0.0) * self.propeller_diameter) ** 2
        moment = inflow * self.gain * (rudder + self.rudder_offset) - speed * speed * restoring
        return moment / (self.time_constant * self.length**2)


def _speed(manoeuvre: Manoeuvre, time: float) -> float:
    final, start = manoeuvre.final_speed, manoeuvre.start_speed
    return final + (start - final) * math.exp(-time / manoeuvre.acceleration_time)


def _order(manoeuvre: Manoeuvre, time: float, order: float, heading_change: float) -> float:
    """The rudder order after a sample: the first order at the approach's end, a zig-zag's reversals."""
    if time < manoeuvre.approach:
        return 0.0
    if order == 0.0:
        return manoeuvre.rudder
    if manoeuvre.kind == "zigzag" and (
        (order > 0.0 and heading_change >= manoeuvre.zigzag_angle)
        or (order < 0.0 and heading_change <= -manoeuvre.zigzag_angle)
    ):
        return -order
    return order


def sail(hull: Hull, manoeuvre: Manoeuvre, seed: int, dt: float, noise: SensorNoise) -> Log:
    """Sail one manoeuvre and return the logged run (see the module docstring)."""
    rng = np.random.default_rng(seed)
    count = round(manoeuvre.duration / dt) + 1
    time = np.arange(count) * dt
    heading, rate, north, east, rudder = rng.uniform(-math.pi, math.pi), 0.0, 0.0, 0.0, 0.0
    start_heading = heading
    true = np.empty((count, 6))  # heading, rate, north, east, actual rudder, speed
    order = 0.0
    h = dt / SUBSTEPS
    for k in range(count):
        true[k] = heading, rate, north, east, rudder, _speed(manoeuvre, time[k])
        order = _order(manoeuvre, time[k], order, heading - start_heading)
        for j in range(SUBSTEPS):
            t = time[k] + j * h
            speed = _speed(manoeuvre, t)
            acceleration = hull.yaw_acceleration(rate, speed, rudder, manoeuvre.propeller_rate)
            north += h * (speed * math.cos(heading) + hull.current_north)
            east += h * (speed * math.sin(heading) + hull.current_east)
            heading += h * rate
            rate += h * acceleration
            rudder += float(np.clip(order - rudder, -hull.rudder_rate * h, hull.rudder_rate * h))

    def sensed(values: np.ndarray, deviation: float) -> np.ndarray:
        return values + deviation * rng.standard_normal(count)

    def delayed(values: np.ndarray) -> np.ndarray:
        return np.concatenate([np.full(GYRO_DELAY, values[0]), values[:-GYRO_DELAY]])

    # The actual rudder at the end of each interval: the value reached when the next sample starts.
    rudder_at_end = np.append(true[1:, 4], true[-1, 4])
    return Log(
        name=manoeuvre.name,
        time=time,
        heading=sensed(true[:, 0], noise.heading),
        rudder=sensed(rudder_at_end, noise.rudder),
        rudder_kind="actual",
        rate_of_turn=sensed(delayed(true[:, 1]), noise.rate_of_turn),
        north=sensed(true[:, 2], noise.position),
        east=sensed(true[:, 3], noise.position),
        speed=np.maximum(sensed(true[:, 5], noise.speed), 0.0),
        propeller_rate=np.full(count, manoeuvre.propeller_rate),
        source="second simulator",
    )


def sail_all(
    hull: Hull, manoeuvres: Sequence[Manoeuvre], seed: int = 0, dt: float = 0.2, noise: SensorNoise | None = None
) -> list[Log]:
    """Sail several manoeuvres; run ``i`` uses seed ``seed + i``."""
    sensors = SensorNoise() if noise is None else noise
    return [sail(hull, manoeuvre, seed + i, dt, sensors) for i, manoeuvre in enumerate(manoeuvres)]
