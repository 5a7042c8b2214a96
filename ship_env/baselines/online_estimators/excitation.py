"""Rudder programmes that excite the steering dynamics, and logs sailed with them on the simulator.

Programmes (each a frozen description; :meth:`controller` gives a fresh helmsman for one run, a
function of the time since the start and the heading change from the initial course, returning
the ordered rudder in rad):

- :class:`ZigZag` a/b: rudder +-a, reversed when the heading change reaches b to that side
  (Kempf's Z-test; Nguyen's 20/20);
- :class:`Turning`: a constant rudder (the turning circle);
- :class:`PseudoRandomBinary`: +-a switched by a maximum-length binary sequence with one bit per
  ``bit_time`` (a PRBS, flat spectrum up to about 1/(2 bit_time) Hz);
- :class:`WhiteNoise`: a Gaussian rudder redrawn every ``hold`` seconds and clipped (Perera's
  "violent" manoeuvres; the steering machine turns it into a rate-limited random rudder);
- :class:`Intermittent`: another programme in bursts, with the rudder amidships between them.

:func:`sail` runs a programme on a :class:`~ship_env.model.Simulator` for any ship and records the
instruments of :class:`~ship_env.baselines.instruments.SimulatedInstruments` (compass, rate gyro, rudder
angle indicator, log, with their noise) as an :class:`~ship_env.baselines.online_estimators.log.ExcitationLog`,
with the truth K*, tau* (the sailed model's ``yaw.gain``, ``yaw.time_constant``). The ship may
change during the run: :class:`SpeedChange` ramps the service speed (K = K* u/L and T = tau* L/u
change, K*, tau* do not), :class:`ModelChange` continues the run in another model (a loading
change: K*, tau* themselves change). K*, tau* are the first-order parameters exactly where the
model's yaw is the linear Nomoto (``ShipModel.minimal``: no Norrbin term, no speed loss, no wind).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.signal import max_len_seq

from ship_env.baselines.instruments import InstrumentNoise, SimulatedInstruments
from ship_env.baselines.online_estimators.history import NOMOTO, ParameterHistory
from ship_env.baselines.online_estimators.log import ExcitationLog
from ship_env.baselines.online_estimators.zigzag_trial import zigzag_rudder
from ship_env.model import ShipModel, Simulator
from ship_env.model import state as S

#: A helmsman for one run: (time since the start s, heading change from the initial course rad) -> ordered rudder rad.
Helmsman = Callable[[float, float], float]


@dataclass(frozen=True)
class ZigZag:
    """The a/b zig-zag: ``rudder`` a (rad, negative to start to port), reversed at heading change
    b = ``heading`` (rad)."""

    rudder: float
    heading: float

    @property
    def name(self) -> str:
        return f"zig-zag {math.degrees(self.rudder):g}/{math.degrees(self.heading):g}"

    def controller(self) -> Helmsman:
        order = self.rudder

        def helmsman(time: float, heading_change: float) -> float:
            nonlocal order
            order = zigzag_rudder(order, heading_change, self.heading)
            return order

        return helmsman


@dataclass(frozen=True)
class Turning:
    """A constant ``rudder`` (rad)."""

    rudder: float

    @property
    def name(self) -> str:
        return f"turning {math.degrees(self.rudder):g}"

    def controller(self) -> Helmsman:
        return lambda time, heading_change: self.rudder


@dataclass(frozen=True)
class PseudoRandomBinary:
    """+-``amplitude`` (rad) following a maximum-length sequence of ``register_bits`` bits, one bit per ``bit_time`` s.

    ``seed`` picks the shift register's starting state (any non-zero one gives the same sequence, shifted).
    """

    amplitude: float
    bit_time: float
    register_bits: int = 9
    seed: int = 0

    @property
    def name(self) -> str:
        return f"PRBS +-{math.degrees(self.amplitude):g} deg, {self.bit_time:g} s bits"

    def controller(self) -> Helmsman:
        rng = np.random.default_rng(self.seed)
        state = rng.integers(0, 2, self.register_bits)
        state[0] = 1  # the all-zero state does not shift
        bits, _ = max_len_seq(self.register_bits, state=state)
        signs = 2.0 * bits - 1.0

        def helmsman(time: float, heading_change: float) -> float:
            return self.amplitude * signs[int(time // self.bit_time) % len(signs)]

        return helmsman


@dataclass(frozen=True)
class WhiteNoise:
    """A Gaussian rudder of standard deviation ``std`` (rad), redrawn every ``hold`` s, clipped to +-``limit`` (rad)."""

    std: float
    hold: float
    limit: float
    seed: int = 0

    @property
    def name(self) -> str:
        return f"white noise {math.degrees(self.std):g} deg, {self.hold:g} s hold"

    def controller(self) -> Helmsman:
        rng = np.random.default_rng(self.seed)
        drawn_for = -1
        order = 0.0

        def helmsman(time: float, heading_change: float) -> float:
            nonlocal drawn_for, order
            slot = int(time // self.hold)
            if slot != drawn_for:
                drawn_for = slot
                order = float(np.clip(rng.normal(0.0, self.std), -self.limit, self.limit))
            return order

        return helmsman


@dataclass(frozen=True)
class Intermittent:
    """``programme`` for ``active`` s, then the rudder amidships for ``quiet`` s, and again (the
    thesis adapts only during manoeuvres, 6.3.2: between them the data hardly inform the parameters)."""

    programme: ZigZag | Turning | PseudoRandomBinary | WhiteNoise
    active: float
    quiet: float

    @property
    def name(self) -> str:
        return f"{self.programme.name}, {self.active:g} s on, {self.quiet:g} s amidships"

    def controller(self) -> Helmsman:
        inner = self.programme.controller()
        period = self.active + self.quiet

        def helmsman(time: float, heading_change: float) -> float:
            return inner(time, heading_change) if time % period < self.active else 0.0

        return helmsman


RudderProgramme = ZigZag | Turning | PseudoRandomBinary | WhiteNoise | Intermittent


@dataclass(frozen=True)
class SpeedChange:
    """From ``time`` s on, ramp the service speed linearly to ``speed`` m/s over ``ramp`` s."""

    time: float
    speed: float
    ramp: float = 60.0


@dataclass(frozen=True)
class ModelChange:
    """From ``time`` s on, the ship is ``model`` (e.g. loaded deeper: other K*, tau*); the state carries over."""

    time: float
    model: ShipModel


Change = SpeedChange | ModelChange


@dataclass(frozen=True, eq=False)
class Trial:
    """A simulated run and the truth it was made with.

    Attributes:
        log: what the instruments read.
        truth: the true parameters at each sample (K*, tau*, or Perera's five).
        length: the ship's length L, m (``None`` for a model without one, Perera's).
        change_times: when the ship changed, s (empty for a ship that does not).
    """

    log: ExcitationLog
    truth: ParameterHistory
    length: float | None
    change_times: tuple[float, ...] = ()

    @property
    def ship_length(self) -> float:
        """L, m, for the Nomoto estimators (which scale with it); a trial without a ship has none."""
        if self.length is None:
            raise ValueError(f"trial {self.log.name!r}: length is None (a model without a ship length)")
        return self.length


def nomoto_truth(model: ShipModel) -> tuple[float, float]:
    """(K*, tau*) of a model: its ``yaw.gain`` and ``yaw.time_constant`` (thesis 2.54)."""
    return model.parameter("yaw.gain"), model.parameter("yaw.time_constant")


def sail(
    model: ShipModel,
    programme: RudderProgramme,
    duration: float,
    sample_time: float = 0.5,
    changes: Sequence[Change] = (),
    noise: InstrumentNoise | None = None,
    seed: int = 0,
    name: str | None = None,
) -> Trial:
    """Sail ``programme`` for ``duration`` s on ``model`` and log the instruments every ``sample_time`` s.

    The simulator's step is the sample time; ``changes`` happen at the first sample at or after
    their time. ``noise``: the instruments' (default: the environments').
    """
    simulator = Simulator(model, dt=sample_time)
    simulator.reset(seed=seed)
    instruments = SimulatedInstruments(simulator, noise=noise, seed=seed)
    helmsman = programme.controller()
    steps = int(round(duration / sample_time))
    columns = {key: np.empty(steps + 1) for key in ("time", "rudder", "heading", "rate_of_turn", "speed")}
    truth = np.empty((steps + 1, 2))
    pending = sorted(changes, key=lambda change: change.time)
    ramps: list[tuple[SpeedChange, float]] = []
    sailed = model
    for k in range(steps + 1):
        if k > 0:
            time = (k - 1) * sample_time
            while pending and pending[0].time <= time + 1e-9:
                change = pending.pop(0)
                if isinstance(change, ModelChange):
                    simulator = _continue_in(simulator, change.model)
                    instruments.simulator = simulator
                    sailed = change.model
                else:
                    ramps.append((change, float(simulator.conditions[0, S.SERVICE_SPEED])))
            for ramp, start_speed in ramps:
                progress = min(1.0, (time - ramp.time) / ramp.ramp) if ramp.ramp > 0.0 else 1.0
                simulator.set_conditions("service_speed", start_speed + progress * (ramp.speed - start_speed))
            simulator.step(helmsman(time, float(simulator.heading[0])))
        reading = instruments.read()
        columns["time"][k] = simulator.time[0]
        columns["rudder"][k] = reading.rudder
        columns["heading"][k] = reading.heading
        columns["rate_of_turn"][k] = reading.rate_of_turn
        columns["speed"][k] = reading.speed
        truth[k] = nomoto_truth(sailed)
    columns["heading"] = np.unwrap(columns["heading"])
    log = ExcitationLog(**columns, name=name or f"{model.ship.name}: {programme.name}")
    history = ParameterHistory(NOMOTO, log.time, truth, np.ones(len(log.time), dtype=bool))
    return Trial(log, history, model.length, tuple(sorted(change.time for change in changes)))


def _continue_in(simulator: Simulator, model: ShipModel) -> Simulator:
    """A simulator of ``model`` that carries on from ``simulator``'s state, conditions and noise streams."""
    successor = Simulator(model, num_ships=simulator.num_ships, dt=simulator.dt, method=simulator.method)
    for name in ("state", "conditions", "seeds", "noise_keys", "step_index", "draws"):
        if getattr(successor, name).shape == getattr(simulator, name).shape:
            getattr(successor, name)[...] = getattr(simulator, name)
    return successor
