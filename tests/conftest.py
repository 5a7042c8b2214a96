"""Shared fixtures: simulate a ship with a rudder program and return its time series."""

from __future__ import annotations

import math
from collections.abc import Callable

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
