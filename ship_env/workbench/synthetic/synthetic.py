"""Synthetic logs: the simulator sails zig-zags and turns with a known model, sensors add noise.

Used to check the workbench on data whose truth is known -- a log made with an effect the fitted
model lacks must lead the diagnosis to that effect. A run is sailed with
:class:`~ship_env.model.Simulator` (not the workbench's replay, so the two code paths check each
other): an approach on a straight course, then a zig-zag (rudder reversed each time the heading
passes +-the zig-zag angle, the standard test) or a turn at constant rudder. The ship sails free: its
service speed U0 is the run's ``final_speed`` (the straight-course speed at its propeller setting)
and it starts at ``start_speed``, u*(0) = 1 - start / final, accelerating by its own surge equation,
the speed loss (thesis 2.55): a true model without the ``speed_loss`` effect sails with it on at no
loss in a turn (K_u* = 0, :func:`free_running`), as every ship that accelerates has surge dynamics. The log
gives the run's service speed besides its speed channel. The true wind varies as a Gauss-Markov
process around its mean (a gusty pond or sea). The log records what sensors would: heading, rate of
turn, position, rudder (actual or ordered), speed, propeller rate and true wind (its direction in
[0, 2 pi)), each with white noise (:class:`SensorNoise`).

A truth simulated outside ship_env (``dynamics``: an adapter of :mod:`ship_env.model.external`, such as
shipmmg's MMG KVLCC2, :class:`~ship_env.model.mmg_kvlcc2.MmgKvlcc2`) sails the same runs in place of the true
model, which then gives only the particulars and the rudder limit: logs of a ship whose physics the workbench's
effects do not share, the independent check of a fit's predictions. Its own steering machine moves the rudder
(the log's actual rudder is the adapter's); it sails in calm water (a mean wind is refused).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ship_env.model import REQUIRED_EFFECTS, Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.external import DynamicsSource, ExternalSimulator, dynamics_factory
from ship_env.workbench.fitting.errors import ErrorScales, pooled, run_errors
from ship_env.workbench.fitting.replay import ReplayModel, simulate
from ship_env.workbench.logs.logs import Log


@dataclass(frozen=True)
class SensorNoise:
    """Standard deviations of the white sensor noise, SI units (defaults: a model basin's sensors)."""

    heading: float = math.radians(0.2)
    rate_of_turn: float = math.radians(0.05)
    position: float = 0.02
    rudder: float = math.radians(0.1)
    speed: float = 0.005
    wind_speed: float = 0.1
    wind_direction: float = math.radians(2.0)
    #: The rudder indicator's resolution, rad: the logged rudder is rounded to it (0: not rounded).
    rudder_resolution: float = 0.0


#: Noise-free sensors: the logs hold the simulated truth, the rudder not rounded.
NO_NOISE = SensorNoise(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

#: Sea-trial sensors: GPS of a few metres, a compass of 0.5 deg, a rate gyro, a rudder indicator read
#: to half a degree, a speed log and a ship's anemometer.
SEA_TRIAL_NOISE = SensorNoise(
    heading=math.radians(0.5),
    rate_of_turn=math.radians(0.02),
    position=3.0,
    rudder=math.radians(0.1),
    speed=0.05,
    wind_speed=0.5,
    wind_direction=math.radians(5.0),
    rudder_resolution=math.radians(0.5),
)


@dataclass(frozen=True)
class Manoeuvre:
    """One run to sail.

    Attributes:
        name: the log's name.
        kind: ``"zigzag"`` or ``"turn"``.
        rudder: rudder angle, rad; negative starts to port.
        duration: s, including the approach.
        approach: s on a straight course before the first rudder order.
        zigzag_angle: heading change that reverses the rudder, rad (zig-zags).
        start_speed, final_speed: speed through the water at the start, and the service speed U0 it
            accelerates towards on a straight course (by the true model's speed loss, 2.55), m/s.
        propeller_rate: n, rps.
        wind_speed, wind_direction: mean true wind, m/s, and where it comes from, rad.
    """

    name: str
    kind: str
    rudder: float
    duration: float
    approach: float = 10.0
    zigzag_angle: float = math.radians(20.0)
    start_speed: float = 0.3
    final_speed: float = 0.3
    propeller_rate: float = 12.0
    wind_speed: float = 1.8
    wind_direction: float = math.radians(280.0)

    def __post_init__(self) -> None:
        if self.kind not in ("zigzag", "turn"):
            raise ValueError(f"manoeuvre {self.name!r}: kind must be 'zigzag' or 'turn', got {self.kind!r}")


#: Gusts of the generated wind: relative standard deviation of the speed, of the direction (rad),
#: and their correlation time (s).
WIND_SPEED_VARIATION = 0.3
WIND_DIRECTION_VARIATION = math.radians(15.0)
WIND_CORRELATION_TIME = 5.0


@dataclass(frozen=True)
class LogSettings:
    """What the synthetic logs record.

    Attributes:
        dt: sample interval and simulation step, s.
        noise: the sensors' noise.
        rudder_kind: record the ``"actual"`` rudder or the ``"ordered"`` one.
        measure_speed: record the speed; if False the run sails at its final speed as service speed from
            u* = 0 (and the log gives only that service speed).
    """

    dt: float = 0.2
    noise: SensorNoise = field(default_factory=SensorNoise)
    rudder_kind: str = "actual"
    measure_speed: bool = True


def _gauss_markov(count: int, dt: float, deviation: float, rng: np.random.Generator) -> np.ndarray:
    """A zero-mean first-order Gauss-Markov sequence with the given stationary deviation."""
    decay = math.exp(-dt / WIND_CORRELATION_TIME)
    drive = deviation * math.sqrt(1.0 - decay**2)
    values = np.empty(count)
    values[0] = deviation * rng.standard_normal()
    for k in range(1, count):
        values[k] = decay * values[k - 1] + drive * rng.standard_normal()
    return values


#: The speed loss of a true model that lacks the effect: no loss in a turn (K_u* = 0, beta3 = 0); it accelerates
#: towards its service speed by (2.55) with tau_u* = 1: from a quarter of it to 95 % in about 12 ship lengths
#: sailed at U0 (36 s on the 3 m model), so that each run of the programme reaches its service speed, as
#: the speed ramp of 30 s its runs were written for did.
NO_TURN_SPEED_LOSS = {"speed_loss.gain": 0.0, "speed_loss.cubic": 0.0, "speed_loss.time_constant": 1.0}


def free_running(truth: ReplayModel) -> ReplayModel:
    """The true model as it sails free: with its surge equation, the speed loss (2.55), on -- where the model
    lacks it, with no loss in a turn (:data:`NO_TURN_SPEED_LOSS`)."""
    if truth.model.has("speed_loss"):
        return truth
    model = truth.model.with_effects("speed_loss").with_parameters(NO_TURN_SPEED_LOSS)
    return ReplayModel(model, truth.current_north, truth.current_east)


def sail(
    truth: ReplayModel,
    manoeuvre: Manoeuvre,
    seed: int,
    settings: LogSettings = LogSettings(),
    dynamics: DynamicsSource | None = None,
) -> Log:
    """Sail one manoeuvre with the true model sailing free (:func:`free_running`), or with ``dynamics`` (an
    external truth; module docstring), and return what the sensors logged."""
    truth = free_running(truth)
    if dynamics is not None and manoeuvre.wind_speed > 0.0:
        raise ValueError(
            f"manoeuvre {manoeuvre.name!r}: wind_speed {manoeuvre.wind_speed} m/s; a truth simulated by external "
            "dynamics sails in calm water here (give wind_speed=0)"
        )
    rng = np.random.default_rng(seed)
    dt = settings.dt
    count = round(manoeuvre.duration / dt) + 1
    time = np.arange(count) * dt
    steady = not settings.measure_speed
    wind_speed = np.maximum(manoeuvre.wind_speed * (1.0 + _gauss_markov(count, dt, WIND_SPEED_VARIATION, rng)), 0.0)
    wind_direction = manoeuvre.wind_direction + _gauss_markov(count, dt, WIND_DIRECTION_VARIATION, rng)
    north, east = truth.current
    simulator = (
        Simulator(truth.model, dt=dt)
        if dynamics is None
        else ExternalSimulator(truth.model, dynamics_factory(dynamics), dt=dt)
    )
    heading0 = rng.uniform(-math.pi, math.pi)
    simulator.reset(
        seed=seed,
        conditions=Conditions(
            service_speed=manoeuvre.final_speed,
            propeller_rate=manoeuvre.propeller_rate,
            current_speed=math.hypot(north, east),
            current_direction=math.atan2(east, north),
        ),
        heading=heading0,
    )
    if not steady:
        simulator.state[0, S.SPEED_LOSS] = 1.0 - manoeuvre.start_speed / manoeuvre.final_speed  # u*(0), (2.53)
    true = {name: np.empty(count) for name in ("heading", "rate_of_turn", "north", "east", "rudder", "speed")}
    orders = np.zeros(count)
    order = 0.0
    for k in range(count):
        if time[k] >= manoeuvre.approach:
            if order == 0.0:
                order = manoeuvre.rudder
            elif manoeuvre.kind == "zigzag":
                change = simulator.heading[0] - heading0
                if (
                    order > 0.0
                    and change >= manoeuvre.zigzag_angle
                    or order < 0.0
                    and change <= -manoeuvre.zigzag_angle
                ):
                    order = -order
        orders[k] = order
        simulator.set_conditions("wind_speed", wind_speed[k])
        simulator.set_conditions("wind_direction", wind_direction[k])
        true["heading"][k] = simulator.heading[0]
        true["rate_of_turn"][k] = simulator.rate_of_turn[0]
        true["north"][k], true["east"][k] = simulator.position[0]
        true["rudder"][k] = simulator.rudder[0]
        true["speed"][k] = simulator.speed[0]
        if k + 1 < count:
            simulator.step(order)
    noise = settings.noise

    def sensed(values: np.ndarray, deviation: float) -> np.ndarray:
        return values + deviation * rng.standard_normal(count)

    # Without a steering machine the rudder takes each order at once: over a sample interval the
    # actual rudder is that interval's order (the state sampled at its start still shows the last one).
    actual = true["rudder"] if dynamics is not None or truth.model.has("steering_machine") else orders
    rudder = actual if settings.rudder_kind == "actual" else orders

    def indicated(values: np.ndarray) -> np.ndarray:
        """The rudder indicator's reading: noisy, rounded to its resolution."""
        read = sensed(values, noise.rudder)
        step = noise.rudder_resolution
        return step * np.round(read / step) if step > 0.0 else read

    sailor = truth.model if dynamics is None else dynamics
    return Log(
        name=manoeuvre.name,
        time=time,
        heading=sensed(true["heading"], noise.heading),
        rudder=indicated(rudder),
        rudder_kind=settings.rudder_kind,
        rate_of_turn=sensed(true["rate_of_turn"], noise.rate_of_turn),
        north=sensed(true["north"], noise.position),
        east=sensed(true["east"], noise.position),
        speed=None if steady else np.maximum(sensed(true["speed"], noise.speed), 0.0),
        propeller_rate=np.full(count, manoeuvre.propeller_rate),
        wind_speed=np.maximum(sensed(wind_speed, noise.wind_speed), 0.0),
        wind_direction=np.mod(sensed(wind_direction, noise.wind_direction), 2.0 * math.pi),  # as a vane reads it
        service_speed=manoeuvre.final_speed,
        source="synthetic",
        notes=(f"sailed by {sailor!r} with current {truth.current} m/s, seed {seed}",),
    )


def sail_all(
    truth: ReplayModel,
    manoeuvres: Sequence[Manoeuvre],
    seed: int = 0,
    settings: LogSettings = LogSettings(),
    dynamics: DynamicsSource | None = None,
) -> list[Log]:
    """Sail several manoeuvres (with ``dynamics``, as :func:`sail`); run ``i`` uses seed ``seed + i``."""
    return [sail(truth, manoeuvre, seed + i, settings, dynamics) for i, manoeuvre in enumerate(manoeuvres)]


# fmt: off
#: The runs of :func:`model_test_programme`: rudder and zig-zag switch angle (deg; a turn never
#: switches), start and final speed (m/s), propeller rate (rps), mean wind (m/s) and where it comes from (deg).
_PROGRAMME = (
    # name            kind      rudder  switch  start  final     n  wind  from
    ("zigzag_20_n12",  "zigzag",   20,     20,  0.08,  0.35, 12.0,  1.8,  280),
    ("zigzag_m20_n16", "zigzag",  -20,     20,  0.15,  0.45, 16.0,  1.8,  250),
    ("zigzag_10_n10",  "zigzag",   10,     10,  0.30,  0.30, 10.0,  1.8,  320),
    ("turn_35_n10",    "turn",     35,     20,  0.30,  0.30, 10.0,  1.8,  300),
    ("turn_m35_n14",   "turn",    -35,     20,  0.40,  0.40, 14.0,  2.2,  260),
    ("turn_m25_n8",    "turn",    -25,     20,  0.12,  0.28,  8.0,  1.4,  200),
)
# fmt: on


#: The ship :data:`_PROGRAMME`'s numbers are written for: a 3 m model (L 3.0 m, U 0.35 m/s, D 0.084 m).
PROGRAMME_SHIP = "esso_osaka_model"


def model_test_programme(duration: float = 90.0, ship: str = PROGRAMME_SHIP) -> list[Manoeuvre]:
    """Six runs like a free-running model test: three zig-zags and three turns, scaled to ``ship``.

    Two of the zig-zags and one turn accelerate from low speed (so propeller rate and speed vary
    independently, as in the Esso Osaka runs); rudders, sides, propeller rates and wind directions
    differ between runs so that no effect hides behind another, and every kind of run (steady or
    accelerating, zig-zag or turn) appears twice, so a fit that leaves one run out still sees its like.

    The numbers (and ``duration``, s) are those of the 3 m model ``PROGRAMME_SHIP``; another ship sails
    the same manoeuvres in its own units: times (duration, approach) scale with its
    L / U, speeds with its service speed U, propeller rates with U / D (the same advance ratio) and
    the wind with sqrt(L) (Froude scaling: 1.8 m/s on the 3 m model is a 16 m/s breeze at 226 m).
    """
    reference, scaled = ShipModel(PROGRAMME_SHIP), ShipModel(ship)

    def diameter(model: ShipModel) -> float:
        return model.parameter("propeller_slipstream.propeller_diameter")

    speed = scaled.service_speed / reference.service_speed
    time = (scaled.length / scaled.service_speed) / (reference.length / reference.service_speed)
    propeller = speed * diameter(reference) / diameter(scaled)
    wind = math.sqrt(scaled.length / reference.length)
    return [
        Manoeuvre(
            name,
            kind,
            math.radians(rudder),
            duration * time,
            approach=Manoeuvre.approach * time,
            zigzag_angle=math.radians(switch),
            start_speed=start_speed * speed,
            final_speed=final_speed * speed,
            propeller_rate=propeller_rate * propeller,
            wind_speed=wind_speed * wind,
            wind_direction=math.radians(wind_from),
        )
        for name, kind, rudder, switch, start_speed, final_speed, propeller_rate, wind_speed, wind_from in _PROGRAMME
    ]


#: The effects the hidden-effect suite (tests/test_workbench_hidden.py) hides in the programme's logs, one at
#: a time, and the workbench finds. Not the speed loss: every true ship sails with it (:func:`free_running`)
#: and a fit to logs with a speed channel has it on from the start (:func:`~.terms.with_speed_output`).
HIDDEN_EFFECTS = (
    "wind_moment",
    "wind_drift",
    "current",
    "norrbin",
    "sway",
    "rudder_offset",
    "steering_machine",
    "propeller_slipstream",
)
#: Values the hidden-effect checks sail with where the preset's placeholder does not suit a truth
#: (the esso_osaka_model preset's speed-loss gain of 0.8 stops the ship in a 35 deg turn): the true ships'
#: speed loss.
HIDDEN_VALUES: dict[str, float] = {"speed_loss.gain": 0.3}
#: Values the hidden-effect checks give an effect whose ship preset holds the null value (an aligned
#: rudder, a slipstream inside K*): a 1 deg offset and the 3 m model's slipstream coefficient.
NULL_PRESET_VALUES: dict[str, float] = {
    "rudder_offset.angle": math.radians(1.0),
    "propeller_slipstream.coefficient": 0.08,
}
#: The steady current (north, east) the hidden-effect checks sail in, per unit of the ship's service
#: speed: 0.03 and -0.04 m/s for the 3 m model at 0.35 m/s.
HIDDEN_CURRENT = (0.03 / 0.35, -0.04 / 0.35)


def hidden_current(model: ShipModel) -> tuple[float, float]:
    """The steady current (m/s north, east) the hidden-effect checks sail ``model`` in."""
    return HIDDEN_CURRENT[0] * model.service_speed, HIDDEN_CURRENT[1] * model.service_speed


def noise_scales(noise: SensorNoise) -> ErrorScales:
    """Error scales equal to the sensors' noise: a score near 1 means errors near the noise."""
    return ErrorScales(
        heading=noise.heading,
        rate_of_turn=noise.rate_of_turn,
        position=math.sqrt(2.0) * noise.position,
        speed_error=noise.speed,
    )


def hidden_effect_logs(
    hidden: Sequence[str],
    ship: str = "esso_osaka_model",
    seed: int = 1,
    manoeuvres: Sequence[Manoeuvre] | None = None,
    noise: SensorNoise = SensorNoise(),
    values: Mapping[str, float] = HIDDEN_VALUES,
    dt: float = LogSettings.dt,
) -> tuple[ReplayModel, list[Log]]:
    """Logs sailed by the speed-scheduled Nomoto ship plus the ``hidden`` effects, sailing free
    (:func:`free_running`): (truth, logs).

    The hidden effects take the preset's values but for ``values``; the logs are
    sampled every ``dt`` seconds (default: the programme's; default manoeuvres:
    :func:`model_test_programme` scaled to ``ship``). They record what the hidden effects need to show
    and no more: the ordered rudder when the steering machine is hidden (its actual rudder would reveal
    it), no speed when the speed loss is hidden (a measured speed would show it: the fit then has it on).
    """
    model = ShipModel(ship, [*REQUIRED_EFFECTS, *hidden], values)
    truth = free_running(ReplayModel(model, *(hidden_current(model) if "current" in hidden else (0.0, 0.0))))
    settings = LogSettings(
        dt=dt,
        noise=noise,
        rudder_kind="ordered" if "steering_machine" in hidden else "actual",
        measure_speed="speed_loss" not in hidden,
    )
    return truth, sail_all(truth, model_test_programme(ship=ship) if manoeuvres is None else manoeuvres, seed, settings)


def noise_floor(truth: ReplayModel, logs: Sequence[Log], scales: ErrorScales) -> float:
    """The pooled score of the true model (as it sailed, :func:`free_running`) replayed on its own noisy logs: the
    best a fit can hope for."""
    replays = simulate(free_running(truth), logs)
    return pooled([run_errors(log, replayed) for log, replayed in zip(logs, replays, strict=True)]).score(scales)
