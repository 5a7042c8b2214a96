"""The bridge's instruments on a simulator driven directly (without an environment).

Reads ship 0 of a :class:`~ship_env.model.Simulator` as :class:`~ship_env.baselines.measurement.Measurement`:
compass and rate gyro as the simulator measures them (with the high-frequency wave yaw when the
``wave_filter`` effect is on, Fig. 2.13) plus white noise, the rudder angle indicator (exact), the
log (speed through the water plus noise) and position fixes with noise every ``fix_interval``
seconds (NaN in between). The noise levels default to those of the environments' sensors
(:data:`ship_env.envs.sensors.SENSOR_NOISE`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ship_env.baselines.measurement import Measurement
from ship_env.envs.sensors import SENSOR_NOISE, ship_sensor_noise
from ship_env.envs.ship_scales import ShipScales
from ship_env.model import Simulator


@dataclass(frozen=True)
class InstrumentNoise:
    """Standard deviations of the instruments' white noise (by default the environments').

    Attributes:
        heading: compass, rad.
        rate_of_turn: rate gyro, rad/s.
        speed: log, m/s.
        position: position fix, per axis, m.
    """

    heading: float = SENSOR_NOISE["heading"]
    rate_of_turn: float = SENSOR_NOISE["rate_of_turn"]
    speed: float = SENSOR_NOISE["speed"]
    position: float = SENSOR_NOISE["position"]

    @classmethod
    def for_ship(cls, scales: ShipScales) -> InstrumentNoise:
        """The environments' noise on a ship of ``scales`` (:func:`~ship_env.envs.sensors.ship_sensor_noise`)."""
        return cls(**ship_sensor_noise(scales))


class SimulatedInstruments:
    """Instruments on ship 0 of ``simulator``.

    Args:
        simulator: the simulator (read after each step).
        noise: the instruments' noise.
        fix_interval: s between position fixes.
        seed: the noise's seed.
    """

    def __init__(
        self, simulator: Simulator, noise: InstrumentNoise | None = None, fix_interval: float = 2.0, seed: int = 0
    ) -> None:
        self.simulator = simulator
        self.noise = noise or InstrumentNoise()
        self.fix_interval = fix_interval
        self.rng = np.random.default_rng(seed)
        self._last_fix_time = -math.inf

    def read(self) -> Measurement:
        """The instruments now; a fix if one is due."""
        simulator = self.simulator
        noise = self.noise
        time = float(simulator.time[0])
        north = east = math.nan
        if time >= self._last_fix_time + self.fix_interval - 1e-6:
            self._last_fix_time = time
            north, east = simulator.position[0] + self.rng.normal(0.0, noise.position, 2)
        return Measurement(
            heading=float(simulator.measured_heading[0] + self.rng.normal(0.0, noise.heading)) % (2.0 * math.pi),
            rate_of_turn=float(simulator.measured_rate_of_turn[0] + self.rng.normal(0.0, noise.rate_of_turn)),
            rudder=float(simulator.rudder[0]),
            speed=float(simulator.speed[0] + self.rng.normal(0.0, noise.speed)),
            north=float(north),
            east=float(east),
            fix_time=time if math.isfinite(north) else math.nan,
        )
