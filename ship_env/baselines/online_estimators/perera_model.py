"""Perera et al. (2015)'s modified non-linear second-order Nomoto model, simulated directly.

Their model (Perera 13) is not our De Keizer ship: it is third order in the heading,

    psi''' = a1 psi'^3 + a2 psi' + a3 psi'' + b1 delta + b2 delta'                        (13)

with a1 = -a_2 d_2, a2 = -a_1 d_2, a3 = -d_1, b1 = d_2, b2 = d_2 d_3 from the second-order Nomoto
model (10) with H(psi') = a_1 psi' + a_2 psi'^3 (11, 12). To reproduce their identification
result, :func:`simulate` integrates (13) itself (RK4, ``substeps`` per sample) with their
published parameters :data:`PUBLISHED`, the rudder of a programme of
:mod:`ship_env.baselines.online_estimators.excitation` through a rate-limited actuator, and measurements
(psi, psi', delta, delta') with white noise (their (18)-(20)).

Rudder: at each sample t(k) the programme orders delta_o; the rudder then moves at the constant
rate delta'(k) = clip((delta_o - delta(k)) / T_s, +-delta'_max) over the interval to t(k+1), so
delta is piecewise linear and delta' piecewise constant; the log's delta'(k) is the rate over the
interval that starts at t(k). :data:`VIOLENT_RUDDER` (a Gaussian order redrawn every 2 s) through
the fast actuator of :class:`PereraSetting` (40 deg/s) stands for their violent manoeuvres, "the
rudder angle and rudder rate ... under white Gaussian noise type motions"; a zig-zag through
:data:`STEERING_MACHINE_RATE` for the smooth manoeuvres of a ship's steering machine. A white yaw
jerk (their system noise w_w of (14)) disturbs the motion.

What the paper does not give is chosen in :class:`PereraSetting` (sample time, actuator rate,
noise levels, system noise) and :data:`VIOLENT_RUDDER`; the true parameters are held constant
(their "actual" parameters fluctuate stochastically around the values of :data:`PUBLISHED`).
"""

from __future__ import annotations

import math
from dataclasses import astuple, dataclass

import numpy as np

from ship_env.baselines.online_estimators.excitation import RudderProgramme, Trial, WhiteNoise
from ship_env.baselines.online_estimators.history import PERERA, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog


@dataclass(frozen=True)
class PereraParameters:
    """The five parameters of (13).

    Attributes:
        a1: coefficient of psi'^3, 1/rad^2.
        a2: coefficient of psi', 1/s^2.
        a3: coefficient of psi'', 1/s.
        b1: coefficient of delta, 1/s^3.
        b2: coefficient of delta', 1/s^2.
    """

    a1: float
    a2: float
    a3: float
    b1: float
    b2: float

    def as_tuple(self) -> tuple[float, float, float, float, float]:
        return astuple(self)

    def scaled(self, factor: float) -> PereraParameters:
        return PereraParameters(*(factor * value for value in self.as_tuple()))


#: The "actual" parameters of Perera et al. (2015), section "Parameter Estimation".
PUBLISHED = PereraParameters(a1=-0.3710, a2=-0.4340, a3=-3.4000, b1=0.3500, b2=0.1225)


@dataclass(frozen=True)
class PereraNoise:
    """Standard deviations of the measurement noise w_v of (18) ("accurate measurements": three
    times the environments' compass and rate gyro noise).

    Attributes:
        heading: psi, rad.
        rate_of_turn: psi', rad/s.
        rudder: delta, rad.
        rudder_rate: delta', rad/s.
    """

    heading: float = math.radians(0.3)
    rate_of_turn: float = math.radians(0.03)
    rudder: float = math.radians(0.3)
    rudder_rate: float = math.radians(0.3)


#: The violent manoeuvre: a Gaussian rudder of 30 deg standard deviation redrawn every 2 s (clipped at 35 deg).
VIOLENT_RUDDER = WhiteNoise(std=math.radians(30.0), hold=2.0, limit=math.radians(35.0))


def acceleration_rate(
    parameters: tuple[float, ...], rate: float, acceleration: float, rudder: float, rudder_rate: float
) -> float:
    """psi''' of (13) from (a1, a2, a3, b1, b2) and psi', psi'', delta, delta'."""
    a1, a2, a3, b1, b2 = parameters
    return a1 * rate**3 + a2 * rate + a3 * acceleration + b1 * rudder + b2 * rudder_rate


@dataclass(frozen=True)
class PereraSetting:
    """What Perera et al. leave open, as chosen for the reproduction.

    Attributes:
        sample_time: T_s, s (the fast pole of :data:`PUBLISHED` is at 3.27 rad/s: T_s well below 0.3 s).
        rudder_rate_limit: the actuator's largest rudder rate, rad/s (fast: their "violent" rudder
            has a white Gaussian rate); see :data:`STEERING_MACHINE_RATE` for a ship's steering machine.
        noise: the measurement noise.
        disturbance: standard deviation of a white yaw jerk added to psi''' (their system noise
            w_w of (14)), rad/s^3, drawn once per sample interval and held.
        substeps: RK4 steps per sample interval.
    """

    sample_time: float = 0.1
    rudder_rate_limit: float = math.radians(40.0)
    noise: PereraNoise = PereraNoise()
    disturbance: float = 0.003
    substeps: int = 2


#: A steering machine's rudder rate for a ship of Perera's size (T1 = 7.5 s), rad/s.
STEERING_MACHINE_RATE = math.radians(5.0)


def simulate(
    programme: RudderProgramme,
    duration: float,
    parameters: PereraParameters = PUBLISHED,
    setting: PereraSetting = PereraSetting(),
    seed: int = 0,
) -> Trial:
    """Sail ``programme`` for ``duration`` s on the model (13) and log (psi, psi', delta, delta') with noise.

    The programme sees the true heading (from 0). Returns the trial with the constant truth ``parameters``.
    """
    noise = setting.noise
    rng = np.random.default_rng(seed)
    helmsman = programme.controller()
    a1, a2, a3, b1, b2 = parameters.as_tuple()
    sample_time = setting.sample_time
    steps = int(round(duration / sample_time))
    h = sample_time / setting.substeps
    heading = rate = acceleration = rudder = 0.0
    time = np.arange(steps + 1) * sample_time
    true = np.empty((steps + 1, 4))  # psi, psi', delta, delta'
    jerks = setting.disturbance * rng.normal(size=steps)
    limit = setting.rudder_rate_limit

    def jerk(r: float, r_dot: float, delta: float, forcing: float) -> float:
        return a1 * r * r * r + a2 * r + a3 * r_dot + b1 * delta + forcing

    for k in range(steps + 1):
        order = helmsman(time[k], heading)
        rudder_rate = min(max((order - rudder) / sample_time, -limit), limit)
        true[k] = heading, rate, rudder, rudder_rate
        if k == steps:
            break
        forcing = b2 * rudder_rate + jerks[k]
        for i in range(setting.substeps):
            delta = rudder + rudder_rate * i * h
            k1 = (rate, acceleration, jerk(rate, acceleration, delta, forcing))
            delta += 0.5 * h * rudder_rate
            r2, r_dot2 = rate + 0.5 * h * k1[1], acceleration + 0.5 * h * k1[2]
            k2 = (r2, r_dot2, jerk(r2, r_dot2, delta, forcing))
            r3, r_dot3 = rate + 0.5 * h * k2[1], acceleration + 0.5 * h * k2[2]
            k3 = (r3, r_dot3, jerk(r3, r_dot3, delta, forcing))
            delta += 0.5 * h * rudder_rate
            r4, r_dot4 = rate + h * k3[1], acceleration + h * k3[2]
            k4 = (r4, r_dot4, jerk(r4, r_dot4, delta, forcing))
            heading += h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            rate += h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            acceleration += h / 6.0 * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2])
        rudder += rudder_rate * sample_time
        if not math.isfinite(heading + rate + acceleration):
            raise FloatingPointError(f"Perera's model left finite values at t = {time[k + 1]:.1f} s")
    measured = true + rng.normal(0.0, 1.0, true.shape) * np.array(
        [noise.heading, noise.rate_of_turn, noise.rudder, noise.rudder_rate]
    )
    log = ExcitationLog(
        time=time,
        rudder=measured[:, 2],
        heading=measured[:, 0],
        rate_of_turn=measured[:, 1],
        rudder_rate=measured[:, 3],
        name=f"Perera (13): {programme.name}",
    )
    return Trial(log, ParameterHistory.constant(PERERA, time, parameters.as_tuple()), length=None)
