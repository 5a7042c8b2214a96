"""Effects that draw random numbers where a ship starts, written outside ship_env: seeded, read, batched, refused."""

from __future__ import annotations

import math

import effect_with_draw
import numpy as np
import pytest

from ship_env.model import EFFECTS, REQUIRED_EFFECTS, Conditions, ShipModel, Simulator
from ship_env.model import state as S
from ship_env.model.dynamics import derivatives
from ship_env.model.effect_api import Contribution, Draw, Effect, Parameter, register_effect
from ship_env.model.registry import register_module

SHIP = "esso_osaka_model"
NAME = effect_with_draw.EFFECT.name
PERIODS = (6.0, 9.0, 12.0)


@pytest.fixture
def plugin():
    """The test module's effect, registered as an installed module would be, removed afterwards."""
    register_module(effect_with_draw, "module effect_with_draw")
    yield effect_with_draw
    EFFECTS.unregister(NAME)


def _swell_model(*effects: str, **parameters: float) -> ShipModel:
    values = {f"{NAME}.{key}": value for key, value in parameters.items()}
    return ShipModel(SHIP, [*REQUIRED_EFFECTS, *effects, NAME], values)


def _started(model: ShipModel, seed: int, periods: tuple[float, ...] = PERIODS) -> Simulator:
    """Ships started with ``seed``, ship i in waves of peak period ``periods[i]``."""
    sim = Simulator(model, num_ships=len(periods))
    sim.reset(seed=seed, conditions=[Conditions(wave_height=2.0, wave_period=period) for period in periods])
    return sim


def test_each_ship_draws_its_swell_from_its_seed_and_its_sea_state(plugin):
    sim = _started(_swell_model(count=4), seed=5)
    swell = sim.draws.reshape(len(PERIODS), 2, 4)
    for ship, period in enumerate(PERIODS):
        bands = 2.0 * math.pi / period * (0.8 + 0.1 * np.arange(5))  # four equal bands, 0.8 to 1.2 the peak
        assert np.all((bands[:-1] < swell[ship, 0]) & (swell[ship, 0] < bands[1:]))
        assert np.all((0.0 < swell[ship, 1]) & (swell[ship, 1] < 2.0 * math.pi))
    assert np.array_equal(_started(_swell_model(count=4), seed=5).draws, sim.draws)  # same seed, same swell
    assert not np.any(_started(_swell_model(count=4), seed=50).draws[:, 4:] == sim.draws[:, 4:])
    for ship, period in enumerate(PERIODS):  # ship i of a batch seeded s draws as a single run seeded s + i
        assert np.array_equal(_started(_swell_model(count=4), 5 + ship, (period,)).draws[0], sim.draws[ship])
    before = sim.draws.copy()
    sim.reset(seed=[40], conditions=[Conditions(wave_period=9.0)], ships=[1])  # one ship restarts: it draws anew
    assert np.array_equal(sim.draws[1], _started(_swell_model(count=4), 40, (9.0,)).draws[0])
    assert np.array_equal(sim.draws[[0, 2]], before[[0, 2]])


def test_its_contribution_reads_the_swell_drawn(plugin):
    """At any instant the added dr/dt is a / n sum sin(omega_i t + phi_i) of the ship's own swell."""
    model = _swell_model(count=3, amplitude=1e-4)
    sim = _started(model, seed=2, periods=(10.0,))
    state = sim.state[0].copy()
    state[S.TIME] = 37.0
    slopes = []
    for record in (model.record, ShipModel(SHIP, REQUIRED_EFFECTS).record):
        out = np.zeros(model.state_size)
        derivatives(state, 0.0, sim.conditions[0], np.zeros(model.state_size), sim.draws[0], 0.0, record[0], out)
        slopes.append(out[S.RATE_OF_TURN])
    frequency, phase = sim.draws[0].reshape(2, 3)
    expected = 1e-4 * np.mean(np.sin(frequency * 37.0 + phase))
    assert slopes[0] - slopes[1] == pytest.approx(expected, rel=1e-12, abs=1e-18)
    assert abs(expected) > 1e-6


def test_it_sails_single_and_batched_bit_for_bit_and_leaves_the_sea_as_it_was(plugin):
    """Beside the library's sea (the first draw), the swell (a second) changes none of the sea's numbers."""
    model = _swell_model("wave_spectrum", amplitude=2e-4)
    batch = _started(model, seed=8)
    singles = [_started(model, 8 + ship, (period,)) for ship, period in enumerate(PERIODS)]
    sea_only = _started(ShipModel(SHIP, [*REQUIRED_EFFECTS, "wave_spectrum"]), seed=8)
    assert np.array_equal(batch.draws[:, : sea_only.draws.shape[1]], sea_only.draws)
    for k in range(200):
        order = math.radians(10.0) * (1 if k < 100 else -1)
        batch.step(np.full(len(PERIODS), order))
        for single in singles:
            single.step(order)
        sea_only.step(np.full(len(PERIODS), order))
    assert all(np.array_equal(batch.state[i], single.state[0]) for i, single in enumerate(singles))
    assert np.all(np.abs(batch.heading - sea_only.heading) > 1e-4)  # the swell yaws each ship


# -- errors ---------------------------------------------------------------------------------------
def _effect() -> Effect:
    return Effect(
        "bad_draw",
        "a test effect",
        "none",
        Parameter("count", "-", "a count", 1.0, 8.0, integer=True, default=2.0, source="assumed"),
        Parameter("size", "-", "a size", 0.0, 2.0, default=1.0, source="assumed"),
    )


def _phases(uniforms):
    return 2.0 * math.pi * uniforms


def _reads(time, phases):
    return 0.0 * phases[0] * time


@pytest.mark.parametrize(
    ("draw", "message"),
    [
        (
            Draw("phases", "rad", "phases", ("size",), _phases),
            r"draw 'phases': shape: 'size' is not a positive whole number nor one of the effect's whole-number "
            r"parameters \(count\)",
        ),
        (Draw("phases", "rad", "phases", (0,), _phases), r"draw 'phases': shape: 0 is not a positive whole number"),
        (Draw("phases", "rad", "phases", [3], _phases), r"draw 'phases': shape: expected a tuple of sizes, got \[3\]"),
        (Draw("phases", "rad", "phases", (3,), _phases, (-1,)), r"draw 'phases': uniforms: -1 is not a positive"),
        (Draw("phases", "", "phases", (3,), _phases), r"draw 'phases': unit: every draw needs its SI unit"),
        (Draw("heading", "rad", "phases", (3,), _phases), r"draw 'heading': name: 'heading' is already an input"),
        (
            Draw("phases", "rad", "phases", (3,), lambda count: count),
            r"draw 'phases': function: it must read its argument 'uniforms'",
        ),
        (
            Draw("phases", "rad", "phases", (3,), lambda uniforms, depth: uniforms),
            r"draw 'phases': function: argument 'depth' names nothing known where a ship starts",
        ),
    ],
)
def test_a_malformed_draw_is_refused_naming_the_plugin_and_the_field(draw, message):
    with pytest.raises(
        (ValueError, TypeError), match=rf"effect 'bad_draw' from module test_model_effect_draws: {message}"
    ):
        register_effect(_effect(), [Contribution("yaw_acceleration", _reads)], draws=[draw])
    assert "bad_draw" not in EFFECTS


@pytest.mark.parametrize(
    ("function", "message"),
    [
        (lambda uniforms: uniforms[:, :2], r"its function gave numbers of shape \(1, 2\), expected \(1, 3\)"),
        (
            lambda uniforms, size: np.where(uniforms > size, uniforms, np.nan),
            r"its function gave numbers that are not finite",
        ),
    ],
)
def test_a_draw_giving_other_numbers_than_declared_is_refused_where_the_model_is_built(function, message):
    register_effect(
        _effect(), [Contribution("yaw_acceleration", _reads)], draws=[Draw("phases", "rad", "phases", (3,), function)]
    )
    try:
        with pytest.raises(
            ValueError, match=rf"effect 'bad_draw' from module test_model_effect_draws: draw 'phases': {message}"
        ):
            ShipModel(SHIP, [*REQUIRED_EFFECTS, "bad_draw"])
    finally:
        EFFECTS.unregister("bad_draw")
