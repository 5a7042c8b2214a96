"""The bridge's instruments, shared by every environment (thesis 5.3, 5.4, Fig. 5.1).

A compass and a rate gyro that see the high-frequency wave yaw (Fig. 2.13) plus white noise, the
rudder angle indicator, a log measuring the speed through the water, and position fixes taken
every ``fix_interval`` seconds (held in between). Their noise comes from the ship's counter-based
random stream (:mod:`ship_env.model.noise`) in a domain of its own, one Box-Muller pair per
instrument pair and step (compass and gyro, log, the fix's north and east), so a seed repeats it
exactly and a ship's noise does not depend on the other ships of its batch.

:func:`measure` fills one ship's measurement vector (layout ``MEASUREMENT_NAMES``); the
environments build their observations from it and report it in ``info["measurement"]`` for
estimators such as the yaw and position filters.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ship_env.model import state as S
from ship_env.model.kernel import kernel
from ship_env.model.noise import MEASUREMENT_DOMAIN, standard_normal_pair

if TYPE_CHECKING:
    from ship_env.envs.ship_scales import ShipScales

# Measurement layout: what the bridge's instruments read.
MEASUREMENT_NAMES = ("heading", "rate_of_turn", "rudder", "speed", "north", "east", "fix_time")
MEASURED_HEADING = 0  # rad in [0, 2 pi), compass: psi + HF wave heading + noise
MEASURED_RATE_OF_TURN = 1  # rad/s, rate gyro: r + HF wave rate + noise
MEASURED_RUDDER = 2  # rad, rudder angle indicator (exact)
MEASURED_SPEED = 3  # m/s, log: speed through the water + noise
MEASURED_NORTH = 4  # m, latest position fix + noise
MEASURED_EAST = 5  # m, latest position fix + noise
MEASURED_FIX_TIME = 6  # s, the time of the latest position fix
MEASUREMENT_SIZE = 7

#: Standard deviations of the sensors' white noise at ``sensor_noise_scale = 1``. Assumed values
#: typical of modern sensors; the thesis's position-filter test used fixes of 50 m every 2 s,
#: "more than ... G.P.S." (6.3.3).
SENSOR_NOISE = {
    "heading": math.radians(0.1),  # rad
    "rate_of_turn": math.radians(0.01),  # rad/s
    "speed": 0.05,  # m/s
    "position": 5.0,  # m
}

#: The instruments' constants as the compiled code reads them.
SENSORS_DTYPE = np.dtype(
    [
        ("heading_noise", np.float64),  # rad
        ("rate_noise", np.float64),  # rad/s
        ("speed_noise", np.float64),  # m/s
        ("position_noise", np.float64),  # m
        ("fix_interval", np.float64),  # s; 0 fixes the position at every step
    ]
)

#: Sample instants closer than this to their due time count as due (the time is a sum of steps).
TIME_TOLERANCE = 1e-6  # s

# The instruments' noise draws per step, each a Box-Muller pair of channels.
_HEADING_AND_RATE = 0
_SPEED = 1  # the first of its pair
_POSITION = 2  # north and east
_NOISE_PAIRS = np.uint64(3)


def ship_sensor_noise(scales: ShipScales) -> dict[str, float]:
    """:data:`SENSOR_NOISE` on a ship of ``scales`` (it is the reference ship's): the compass's in
    rad, the position's in ship lengths, the log's in units of U and the gyro's in U / L
    (:mod:`ship_env.envs.ship_scales`)."""
    return {
        "heading": SENSOR_NOISE["heading"],
        "rate_of_turn": SENSOR_NOISE["rate_of_turn"] / scales.time,
        "speed": SENSOR_NOISE["speed"] * scales.speed,
        "position": SENSOR_NOISE["position"] * scales.length,
    }


def sensors_record(noise_scale: float, fix_interval: float, scales: ShipScales) -> np.ndarray:
    """The instruments' constants (one record) for a noise scale and a position-fix interval, s, on a
    ship of ``scales`` (:func:`ship_sensor_noise`)."""
    noise = ship_sensor_noise(scales)
    record = np.zeros(1, dtype=SENSORS_DTYPE)
    record[0]["heading_noise"] = noise_scale * noise["heading"]
    record[0]["rate_noise"] = noise_scale * noise["rate_of_turn"]
    record[0]["speed_noise"] = noise_scale * noise["speed"]
    record[0]["position_noise"] = noise_scale * noise["position"]
    record[0]["fix_interval"] = fix_interval
    return record


@kernel
def wrap(angle):
    """An angle wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@kernel
def sample_due(time, last_sample_time, interval):
    """Whether a sample taken every ``interval`` s is due at ``time``, the last one at ``last_sample_time``."""
    return time >= last_sample_time + interval - TIME_TOLERANCE


@kernel
def _sensor_noise(key, step, pair, first_deviation, second_deviation):
    """White sensor noise of two channels at one step, from one draw of the ship's random stream."""
    if first_deviation == 0.0 and second_deviation == 0.0:
        return 0.0, 0.0
    first, second = standard_normal_pair(key, MEASUREMENT_DOMAIN + np.uint64(step) * _NOISE_PAIRS + np.uint64(pair))
    return first_deviation * first, second_deviation * second


@kernel
def measure(state, service_speed, wave_yaw, key, step, sensors, restarted, measured):
    """Read one ship's instruments into ``measured`` (layout ``MEASUREMENT_NAMES``).

    Args:
        state: the ship's true state (layout :mod:`ship_env.model.state`).
        service_speed: U0, m/s.
        wave_yaw: 1 if the sea shows in the compass and gyro, else 0.
        key, step: the ship's noise key and step index (the simulator's).
        sensors: the instruments' constants (``SENSORS_DTYPE``, one record).
        restarted: a new episode: take a position fix whatever the time.
        measured: the measurement vector, written in place; its fix is kept until the next is due.
    """
    p = sensors[0]
    heading_noise, rate_noise = _sensor_noise(key, step, _HEADING_AND_RATE, p["heading_noise"], p["rate_noise"])
    heading = state[S.HEADING] + wave_yaw * state[S.WAVE_HEADING] + heading_noise
    rate = state[S.RATE_OF_TURN] + wave_yaw * state[S.WAVE_RATE] + rate_noise
    measured[MEASURED_HEADING] = heading % (2.0 * math.pi)
    measured[MEASURED_RATE_OF_TURN] = rate
    measured[MEASURED_RUDDER] = state[S.RUDDER]
    speed_noise = _sensor_noise(key, step, _SPEED, p["speed_noise"], 0.0)[0]
    measured[MEASURED_SPEED] = service_speed * (1.0 - state[S.SPEED_LOSS]) + speed_noise
    time = state[S.TIME]
    if restarted or sample_due(time, measured[MEASURED_FIX_TIME], p["fix_interval"]):
        north_noise, east_noise = _sensor_noise(key, step, _POSITION, p["position_noise"], p["position_noise"])
        measured[MEASURED_NORTH] = state[S.NORTH] + north_noise
        measured[MEASURED_EAST] = state[S.EAST] + east_noise
        measured[MEASURED_FIX_TIME] = time


#: Bounds of the normalised rate of turn and speed in every task's observation.
RATE_BOUND = 4.0
SPEED_BOUND = 2.0


@kernel
def observe_motion(
    observation, first, measured, rudder, service_speed, speed_scale, full_rudder_rate_per_speed, rudder_limit
):
    """Write the motion part every task observes into ``observation[first:first + 3]``.

    Rate of turn over the linear full-rudder steady rate K* U0 / L delta_max (clipped to
    +-RATE_BOUND), actual rudder over the rudder limit, log speed over ``speed_scale`` (the
    service speed, or the design ship's; clipped to [0, SPEED_BOUND]).
    """
    steady_rate = full_rudder_rate_per_speed * service_speed
    observation[first] = min(max(measured[MEASURED_RATE_OF_TURN] / steady_rate, -RATE_BOUND), RATE_BOUND)
    observation[first + 1] = rudder / rudder_limit
    observation[first + 2] = min(max(measured[MEASURED_SPEED] / speed_scale, 0.0), SPEED_BOUND)
