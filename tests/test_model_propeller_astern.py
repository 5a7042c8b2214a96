"""Sailing astern: a negative propeller rate sails where the model has ``propeller_astern`` (with the
sign its closed form gives), is refused naming the effect where it has not, and the workbench's
residual signals take the rate with its sign, as its replay does."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from ship_env.model import REQUIRED_EFFECTS, Conditions, ShipModel, Simulator
from ship_env.workbench.deciding.signals import residual_signals
from ship_env.workbench.fitting.replay import ReplayModel
from ship_env.workbench.logs.logs import Log

SHIP = str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")
ASTERN = -8.0  # rps
WALK = 0.02  # c_w


def _astern_model() -> ShipModel:
    return ShipModel(SHIP, [*REQUIRED_EFFECTS, "propeller_astern"], {"propeller_astern.walk": WALK})


def test_a_propeller_astern_walks_the_bow_to_port_at_the_closed_forms_steady_rate():
    """Rudder amidships, n < 0: the walk's moment c_w (n D)^2 turns the bow to port, steadily at
    r = -c_w (n D)^2 / (alpha1 u L), where the hull's H(r*) = alpha1 r* balances it (yaw.py, 2.54)."""
    model = _astern_model()
    sim = Simulator(model, dt=0.5)
    sim.reset(seed=0, conditions=Conditions(propeller_rate=ASTERN))
    for _ in range(int(40 * model.parameter("yaw.time_constant") * model.length / model.service_speed / 0.5)):
        sim.step(0.0)
    induced = (ASTERN * model.parameter("propeller_slipstream.propeller_diameter")) ** 2
    speed = float(sim.speed[0])
    steady = -WALK * induced / (model.parameter("yaw.linear") * speed * model.length)
    assert steady < 0.0
    assert sim.rate_of_turn[0] == pytest.approx(steady, rel=1e-9)


def test_a_propeller_set_astern_while_sailing_sails_as_one_started_astern():
    model = _astern_model()
    started, set_later = Simulator(model, num_ships=2), Simulator(model, num_ships=2)
    started.reset(seed=1, conditions=Conditions(propeller_rate=ASTERN))
    set_later.reset(seed=1)
    set_later.set_conditions("propeller_rate", ASTERN)
    for _ in range(100):
        started.step(0.1)
        set_later.step(0.1)
    np.testing.assert_array_equal(set_later.state, started.state)
    assert started.rate_of_turn[0] != 0.0


def test_a_propeller_astern_is_refused_naming_the_effect_where_the_model_has_none():
    sim = Simulator(ShipModel(SHIP, REQUIRED_EFFECTS))
    with pytest.raises(ValueError, match=r"conditions\.propeller_rate: -8\.0 rps .*astern.*propeller_astern"):
        sim.reset(conditions=Conditions(propeller_rate=ASTERN))
    with pytest.raises(ValueError, match=r"conditions\.propeller_rate: -8\.0 rps .*astern.*propeller_astern"):
        sim.set_conditions("propeller_rate", ASTERN)
    sim.set_conditions("propeller_rate", 8.0)  # ahead it sails


def _sailed_log(model: ShipModel, propeller_rate: float) -> Log:
    """Ten minutes of a slow rudder sine (15 deg, 4 min; no reversal the log's smoothing would round
    off) with the propeller at ``propeller_rate``, logged every second."""
    sim = Simulator(model, dt=0.5)
    sim.reset(seed=0, conditions=Conditions(propeller_rate=propeller_rate))
    rows = []
    for k in range(1201):
        if k % 2 == 0:
            rows.append((sim.time[0], sim.heading[0], sim.rudder[0], sim.rate_of_turn[0], sim.speed[0]))
        sim.step(math.radians(15.0) * math.sin(2.0 * math.pi * k * 0.5 / 240.0))
    time, heading, rudder, rate, speed = (np.array(column) for column in zip(*rows, strict=True))
    rates = np.full(len(time), propeller_rate)
    return Log("astern", time, heading, rudder, rate_of_turn=rate, speed=speed, propeller_rate=rates)


def test_the_residual_signals_take_the_propeller_rate_with_its_sign():
    """The true model explains its own astern log: its missing yaw acceleration is a small part of
    what it is when the astern rate is read as a stopped propeller (what clipping the rate at 0 did)."""
    model = _astern_model()
    log = _sailed_log(model, ASTERN)
    stopped = replace(log, propeller_rate=np.zeros(log.samples))
    setup = ReplayModel(model)
    signed = residual_signals(setup, [log]).residual
    clipped = residual_signals(setup, [stopped]).residual
    assert np.sqrt(np.mean(signed**2)) < 0.1 * np.sqrt(np.mean(clipped**2))
