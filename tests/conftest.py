"""Shared fixtures: simulate a ship with a rudder program and return its time series; run a script as a module."""

from __future__ import annotations

import importlib.util
import math
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from ship_env.model import Conditions, ShipModel, Simulator

CONTAINER = "container_226m"


def run(
    model: ShipModel,
    rudder: float | Callable[[float], float],
    duration: float,
    dt: float = 0.5,
    conditions: Conditions | None = None,
    seed: int = 0,
    method: str = "rk4",
    heading: float = 0.0,
) -> np.ndarray:
    """Simulate one ship and return its states, shape (steps + 1, model.state_size), plus speed column."""
    sim = Simulator(model, dt=dt, method=method)
    sim.reset(seed=seed, conditions=conditions, heading=heading)
    steps = int(round(duration / dt))
    history = np.empty((steps + 1, model.state_size + 1))
    history[0, :-1] = sim.state[0]
    history[0, -1] = sim.speed[0]
    for k in range(steps):
        order = rudder(k * dt) if callable(rudder) else rudder
        sim.step(order)
        history[k + 1, :-1] = sim.state[0]
        history[k + 1, -1] = sim.speed[0]
    return history


SPEED = -1  # column of ``run``'s history holding the forward speed


@pytest.fixture(scope="session")
def container() -> ShipModel:
    return ShipModel(CONTAINER)


def degrees(value: float) -> float:
    return math.radians(value)


@pytest.fixture
def load_script(monkeypatch: pytest.MonkeyPatch) -> Callable[[Path, str], ModuleType]:
    """Run a script (a benchmark, an example) as the module ``name``, entered in ``sys.modules`` until
    the test ends, as importlib's recipe for a source file does: its dataclasses and the compiled steps
    of the effects it registers find their module by that name."""

    def load(path: Path, name: str) -> ModuleType:
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None, path
        module = importlib.util.module_from_spec(spec)
        monkeypatch.setitem(sys.modules, name, module)
        spec.loader.exec_module(module)
        return module

    return load
