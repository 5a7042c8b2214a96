"""The runs the identification comparison sails, and the estimators it runs on them.

The Nomoto scenarios sail the thesis's container ship (``container_226m``, ``ShipModel.minimal``:
the linear speed-scheduled Nomoto ship with its 2.5 deg/s steering machine, so that K* = 1.6,
tau* = 1.7 is the exact truth) with the environments' instruments, sampled every 0.5 s; every
Nomoto estimator starts without prior knowledge at K*/4, tau*/4 (thesis 6.3.2). The Perera
scenarios sail Perera's own model (:mod:`ship_env.baselines.online_estimators.perera_model`), its filter
starting at half the published parameters; the zig-zag and the violent rudder each with the
steering machine's 5 deg/s and with the fast actuator separate the programme from the rudder rate.

The loaded ship (:data:`LOADED_PARAMETERS`: K* 1.3, tau* 2.2, assumed values of a ship trimmed and
loaded deeper: more inertia, less rudder effect) and the speed change (19 kn to 10 kn, which changes
K = K* u/L and T = tau* L/u, not K*, tau*) make ships that change during the run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from ship_env.baselines.instruments import InstrumentNoise
from ship_env.baselines.nomoto import NomotoParameters
from ship_env.baselines.online_estimators.adaptation import ForgettingFactor, RandomWalk
from ship_env.baselines.online_estimators.discrete_nomoto import discrete_pair
from ship_env.baselines.online_estimators.estimator import Estimator
from ship_env.baselines.online_estimators.excitation import (
    Change,
    Intermittent,
    ModelChange,
    PseudoRandomBinary,
    RudderProgramme,
    SpeedChange,
    Trial,
    Turning,
    WhiteNoise,
    ZigZag,
    sail,
)
from ship_env.baselines.online_estimators.least_squares import NguyenRLS
from ship_env.baselines.online_estimators.mras import CombinedMRAS
from ship_env.baselines.online_estimators.passenier_ekf import PassenierEKF
from ship_env.baselines.online_estimators.perera_ekf import PereraFilter, PereraFilterNoise
from ship_env.baselines.online_estimators.perera_model import (
    PUBLISHED,
    STEERING_MACHINE_RATE,
    VIOLENT_RUDDER,
    PereraSetting,
    simulate,
)
from ship_env.baselines.online_estimators.song_ekf import SongFilter, SongFilterNoise
from ship_env.manoeuvres.results import KNOT
from ship_env.model import ShipModel

SHIP = "container_226m"
#: K*, tau* of the preset (thesis 6.4.4.1) and the estimators' start: a quarter of each (6.3.2).
NOMINAL = NomotoParameters(gain=1.6, time_constant=1.7)
GUESS = NOMINAL.scaled(0.25)
SAMPLE_TIME = 0.5
#: The loaded ship's K*, tau* (assumed, illustrative).
LOADED_PARAMETERS = {"yaw.gain": 1.3, "yaw.time_constant": 2.2}
#: The spectral density of the relative parameter drift the random-walk estimators assume, 1/s
#: (about the yaw filter's default: 3e-6 / (1/1.7)^2).
PARAMETER_DRIFT = 1e-5
#: Perera's filter starts at half the published parameters.
PERERA_GUESS = PUBLISHED.scaled(0.5)


def container() -> ShipModel:
    return ShipModel.minimal(SHIP)


def zigzag_20() -> ZigZag:
    return ZigZag(math.radians(20.0), math.radians(20.0))


def least_squares_walk(drift: float, length: float, sample_time: float = SAMPLE_TIME) -> RandomWalk:
    """A random walk of the discrete pair (a, b) with relative drift density ``drift`` (1/s), scaled by the
    nominal ship's 1 - a and b at its service speed, in absolute units (for R = the gyro's variance)."""
    a, b = discrete_pair(NOMINAL, sample_time, container().service_speed, length)
    return RandomWalk.relative(drift, (1.0 - a, b), sample_time)


def ekf_walk(drift: float) -> tuple[float, float]:
    """Densities of the random walks of 1/tau* and K*/tau* for a relative drift density ``drift``
    (1/s), scaled by the nominal ship's values."""
    return drift / NOMINAL.time_constant**2, drift * (NOMINAL.gain / NOMINAL.time_constant) ** 2


def gyro_variance() -> float:
    return InstrumentNoise().rate_of_turn ** 2


def nomoto_estimators(length: float) -> list[Estimator]:
    """The Nomoto estimators as published (or as the thesis has them), each from :data:`GUESS`."""
    return [
        NguyenRLS(length, GUESS),
        CombinedMRAS(length, GUESS, least_squares_walk(PARAMETER_DRIFT, length), gyro_variance()),
        SongFilter(length, GUESS),
        PassenierEKF(length, GUESS),
    ]


def perera_estimators(setting: PereraSetting) -> list[Estimator]:
    """Perera's EKF with the calibration that knows the simulated noise, as improved and as printed."""
    noise = PereraFilterNoise.matched(setting)
    return [PereraFilter(PERERA_GUESS, noise), PereraFilter(PERERA_GUESS, noise, rudder_integrates_rate=False)]


@dataclass(frozen=True)
class Scenario:
    """A run of the comparison.

    Attributes:
        name: short name (command line, file names).
        make_trial: (seed, duration scale) -> the trial.
        make_estimators: the trial -> the estimators to run on it.
    """

    name: str
    make_trial: Callable[[int, float], Trial]
    make_estimators: Callable[[Trial], list[Estimator]]


def _nomoto(trial: Trial) -> list[Estimator]:
    return nomoto_estimators(trial.ship_length)


def _container(
    programme: RudderProgramme, duration: float, changes: Sequence[Change] = (), name: str | None = None
) -> Callable[[int, float], Trial]:
    def make(seed: int, scale: float) -> Trial:
        scaled = [replace(change, time=change.time * scale) for change in changes]
        return sail(container(), programme, duration * scale, SAMPLE_TIME, changes=scaled, seed=seed, name=name)

    return make


def _perera(programme: RudderProgramme, setting: PereraSetting, duration: float) -> Callable[[int, float], Trial]:
    def make(seed: int, scale: float) -> Trial:
        seeded = replace(programme, seed=seed) if isinstance(programme, WhiteNoise) else programme
        return simulate(seeded, duration * scale, setting=setting, seed=seed)

    return make


_PERERA_SETTING = PereraSetting()
_PERERA_STEERING_MACHINE = PereraSetting(rudder_rate_limit=STEERING_MACHINE_RATE)

SCENARIOS: dict[str, Scenario] = {
    scenario.name: scenario
    for scenario in (
        Scenario("zigzag", _container(zigzag_20(), 1200.0), _nomoto),
        Scenario("prbs", _container(PseudoRandomBinary(math.radians(10.0), 30.0), 1200.0), _nomoto),
        Scenario(
            "white-noise",
            _container(WhiteNoise(math.radians(10.0), 20.0, math.radians(35.0)), 1200.0),
            _nomoto,
        ),
        Scenario("turning", _container(Turning(math.radians(20.0)), 1200.0), _nomoto),
        Scenario(
            "intermittent",
            _container(Intermittent(zigzag_20(), 300.0, 300.0), 2400.0),
            _nomoto,
        ),
        Scenario(
            "loading-change",
            _container(
                zigzag_20(),
                2400.0,
                [ModelChange(1200.0, container().with_parameters(LOADED_PARAMETERS))],
                "container_226m: zig-zag 20/20, loaded deeper at 1200 s",
            ),
            _nomoto,
        ),
        Scenario(
            "speed-change",
            _container(
                zigzag_20(),
                2400.0,
                [SpeedChange(1200.0, 10.0 * KNOT, 60.0)],
                "container_226m: zig-zag 20/20, 19 -> 10 kn at 1200 s",
            ),
            _nomoto,
        ),
        Scenario(
            "perera-violent",
            _perera(VIOLENT_RUDDER, _PERERA_SETTING, 3500.0),
            lambda trial: perera_estimators(_PERERA_SETTING),
        ),
        Scenario(
            "perera-zigzag",
            _perera(zigzag_20(), _PERERA_STEERING_MACHINE, 3500.0),
            lambda trial: perera_estimators(_PERERA_STEERING_MACHINE)[:1],
        ),
        Scenario(
            "perera-zigzag-fast",
            _perera(zigzag_20(), _PERERA_SETTING, 3500.0),
            lambda trial: perera_estimators(_PERERA_SETTING)[:1],
        ),
        Scenario(
            "perera-violent-slow",
            _perera(VIOLENT_RUDDER, _PERERA_STEERING_MACHINE, 3500.0),
            lambda trial: perera_estimators(_PERERA_STEERING_MACHINE)[:1],
        ),
    )
}


def adaptation_trials(seed: int = 0, scale: float = 1.0) -> tuple[Trial, Trial]:
    """The stelling-5 comparison's runs: a calibration run of the unchanging ship (another seed) and the
    loading change, both on the 20/20 zig-zag, ``scale`` times 2400 s long."""
    calibration = sail(container(), zigzag_20(), 2400.0 * scale, SAMPLE_TIME, seed=seed + 1000)
    return calibration, SCENARIOS["loading-change"].make_trial(seed, scale)


def forgetting_least_squares(length: float) -> Callable[[float], Estimator]:
    """The thesis's first-order least squares (r on r, delta) with forgetting factor lambda
    (R = the gyro's variance)."""
    return lambda factor: NguyenRLS(
        length, GUESS, ForgettingFactor(factor), 1.0, include_heading=False, noise_variance=gyro_variance()
    )


def random_walk_least_squares(length: float, drift: float) -> Estimator:
    """The same least squares with random-walk parameters of relative drift density ``drift``."""
    return NguyenRLS(
        length, GUESS, least_squares_walk(drift, length), 1.0, include_heading=False, noise_variance=gyro_variance()
    )


def forgetting_ekf(length: float) -> Callable[[float], Estimator]:
    """The EKF on the yaw model (Song's filter without tanh and guard) with forgetting factor lambda."""
    return lambda factor: SongFilter(length, GUESS, factor, innovation_scale=math.inf, guard=False)


def random_walk_ekf(length: float, drift: float) -> Estimator:
    """The same EKF without forgetting, with random-walk parameters of relative drift density ``drift``."""
    noise = SongFilterNoise(parameter_walk=ekf_walk(drift))
    return SongFilter(length, GUESS, 1.0, noise, innovation_scale=math.inf, guard=False)
