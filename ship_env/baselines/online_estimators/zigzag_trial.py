"""The preliminary identification trial: K*, tau* and gamma from a zig-zag (thesis 6.4.4.1, Figs. 6.17, 6.20).

Before the tracking experiment the thesis identified the ship with the yaw filter on a 15/15 deg
zig-zag (converged after about 5 minutes: the reference model's K*, tau*) and fixed the sway
constant from the position filter's estimate on a zig-zag. This sails that trial on the
simulator: the ship's model, a zig-zag a/a deg on the true heading, the yaw filter started
without prior knowledge (K*/4, tau*/4 of the given guess: 6.3.2), the position filter fed by
it, instruments with the environments' noise (:class:`~ship_env.baselines.instruments.InstrumentNoise`,
fixes every 2 s). The trial's times are the reference ship's (10 minutes, samples every 0.5 s, fixes
every 2 s), and on another ship the same in units of its L / U, its noise and the filters'
calibration in its scales (:mod:`ship_env.envs.ship_scales`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ship_env.baselines.instruments import InstrumentNoise, SimulatedInstruments
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.position_filter import PositionFilter, PositionFilterNoise
from ship_env.baselines.yaw_filter import ship_yaw_filter
from ship_env.envs.ship_scales import ship_scales
from ship_env.model import ShipModel, Simulator


@dataclass(frozen=True)
class IdentifiedShip:
    """What the trial found.

    Attributes:
        parameters: K*, tau* (the reference and prediction model).
        sway_constant: gamma, m (v = -gamma r).
    """

    parameters: NomotoParameters
    sway_constant: float


def zigzag_rudder(order: float, heading_change: float, angle: float) -> float:
    """The zig-zag helmsman: the rudder ``order`` (rad, +-a), reversed once the heading change from
    the initial course has reached ``angle`` (rad; a for the a/a zig-zag) to the side the rudder is over to."""
    return -order if order * heading_change >= abs(order) * angle else order


#: The trial's duration and sample time on the reference ship, s (:mod:`ship_env.envs.ship_scales`).
REFERENCE_DURATION = 600.0
REFERENCE_SAMPLE_TIME = 0.5
#: The reference ship's position fixes, s between them.
REFERENCE_FIX_INTERVAL = 2.0


def identify_by_zigzag(
    model: ShipModel,
    guess: NomotoParameters,
    rudder: float = math.radians(15.0),
    duration: float | None = None,
    sample_time: float | None = None,
    seed: int = 0,
) -> IdentifiedShip:
    """Sail a zig-zag ``rudder``/``rudder`` (rad) for ``duration`` s and return the filters' final estimates.

    ``guess``: the K*, tau* the yaw filter starts from, divided by four (no prior knowledge).
    ``duration`` and ``sample_time``, s: by default the reference ship's in units of ``model``'s L / U.
    Raises ``ValueError`` if the yaw filter ends without a stable ship.
    """
    scales = ship_scales(model)
    duration = REFERENCE_DURATION * scales.time if duration is None else duration
    sample_time = REFERENCE_SAMPLE_TIME * scales.time if sample_time is None else sample_time
    simulator = Simulator(model, dt=sample_time)
    simulator.reset(seed=seed)
    instruments = SimulatedInstruments(
        simulator, InstrumentNoise.for_ship(scales), REFERENCE_FIX_INTERVAL * scales.time, seed=seed
    )
    yaw_filter = ship_yaw_filter(model, sample_time, guess.scaled(0.25))
    noise = dataclasses.replace(PositionFilterNoise().for_ship(scales), position_fix=instruments.noise.position)
    position_filter = PositionFilter(sample_time, noise=noise)
    first = instruments.read()
    yaw_filter.reset(first)
    position_filter.reset(first, yaw_filter.rate_of_turn, yaw_filter.heading)
    order = rudder
    for _ in range(int(round(duration / sample_time))):
        order = zigzag_rudder(order, simulator.heading[0], rudder)
        simulator.step(order)
        reading = instruments.read()
        yaw_filter.step(reading, speed=position_filter.speed)
        position_filter.step(reading, yaw_filter.rate_of_turn, yaw_filter.heading)
    parameters = yaw_filter.parameters
    if parameters is None:
        raise ValueError("the yaw filter ended the zig-zag without a stable ship; sail it longer")
    return IdentifiedShip(parameters, position_filter.sway_constant)
