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
(2.64, 2.65), the speed through the water from the surge equation of the speed loss (2.55, 2.39,
2.53), and optionally Norrbin's cubic and |r*| r* terms, the propeller slipstream over the rudder,
a rudder offset and a steady current:

    dr/dt = [ (u^2 + c_s (n D)^2) K* (delta + delta_0) - u^2 H(r*) ] / (tau* L^2),   r* = L r / u
    H(r*) = alpha1 r* + alpha2' |r*| r* + alpha3 r*^3
    du*/dt = (u / L) (K_u* r*^2 - u* - beta3 u*^3) / tau_u*,   u = U0 (1 - u*)
    dpsi/dt = r,   dx0/dt = u cos(psi) + c_north,   dy0/dt = u sin(psi) + c_east

Each run's service speed U0 is its manoeuvre's final speed and it starts at its start speed,
u*(0) = 1 - start / U0 (the log gives U0): the ship accelerates by its own surge equation, as a real one does. With the
``speed_loss`` effect off it loses no speed in a turn (K_u* = 0, beta3 = 0) and approaches U0 with
ship_env's generator's time constant (``NO_TURN_SPEED_LOSS``, tau_u* = 1).
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
from ship_env.workbench.synthetic.synthetic import NO_TURN_SPEED_LOSS, Manoeuvre, SensorNoise

#: Euler sub-steps per sample interval.
SUBSTEPS = 10
#: Samples by which the rate gyro lags the ship.
GYRO_DELAY = 1
#: The effects this simulator can sail besides the yaw equation and kinematics.
EFFECTS = ("norrbin", "propeller_slipstream", "rudder_offset", "current", "speed_loss")


@dataclass(frozen=True)
class Hull:
    """The coefficients the simulator sails with (SI units; an effect that is off has its null value)."""

    length: float
    gain: float
    time_constant: float
    linear: float
    rudder_rate: float
    speed_loss_gain: float = NO_TURN_SPEED_LOSS["speed_loss.gain"]
    speed_loss_time_constant: float = NO_TURN_SPEED_LOSS["speed_loss.time_constant"]
    speed_loss_cubic: float = NO_TURN_SPEED_LOSS["speed_loss.cubic"]
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

        def on(effect: str, key: str, off: float = 0.0) -> float:
            return values.parameter(key) if effect in effects else off

        def surge(key: str) -> float:
            return on("speed_loss", key, NO_TURN_SPEED_LOSS[key])

        north, east = current if "current" in effects else (0.0, 0.0)
        return cls(
            length=values.length,
            gain=values.parameter("yaw.gain"),
            time_constant=values.parameter("yaw.time_constant"),
            linear=values.parameter("yaw.linear"),
            rudder_rate=values.parameter("steering_machine.rudder_rate"),
            speed_loss_gain=surge("speed_loss.gain"),
            speed_loss_time_constant=surge("speed_loss.time_constant"),
            speed_loss_cubic=surge("speed_loss.cubic"),
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

    def speed_loss_rate(self, rate: float, speed: float, loss: float) -> float:
        """du*/dt of the surge equation in the module docstring."""
        normalised = self.length * rate / speed
        resistance = loss + self.speed_loss_cubic * loss**3
        return speed / self.length * (self.speed_loss_gain * normalised**2 - resistance) / self.speed_loss_time_constant


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
    service_speed = manoeuvre.final_speed
    loss = 1.0 - manoeuvre.start_speed / service_speed
    start_heading = heading
    true = np.empty((count, 6))  # heading, rate, north, east, actual rudder, speed
    order = 0.0
    h = dt / SUBSTEPS
    for k in range(count):
        true[k] = heading, rate, north, east, rudder, service_speed * (1.0 - loss)
        order = _order(manoeuvre, time[k], order, heading - start_heading)
        for _ in range(SUBSTEPS):
            speed = service_speed * (1.0 - loss)
            acceleration = hull.yaw_acceleration(rate, speed, rudder, manoeuvre.propeller_rate)
            loss += h * hull.speed_loss_rate(rate, speed, loss)
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
        service_speed=service_speed,
        source="second simulator",
    )


def sail_all(
    hull: Hull, manoeuvres: Sequence[Manoeuvre], seed: int = 0, dt: float = 0.2, noise: SensorNoise | None = None
) -> list[Log]:
    """Sail several manoeuvres; run ``i`` uses seed ``seed + i``."""
    sensors = SensorNoise() if noise is None else noise
    return [sail(hull, manoeuvre, seed + i, dt, sensors) for i, manoeuvre in enumerate(manoeuvres)]
