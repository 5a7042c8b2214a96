"""Shared fixtures: simulate a ship with a rudder program and return its time series."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from ship_env.model import Conditions, ShipModel, Simulator

CONTAINER = "container_226m"

#: The test files that replay logs with the workbench (its compiled replay of the built-in effects): one
#: xdist group, so that one worker compiles the replay where the on-disk cache lacks it while the others
#: run the rest (pyproject's --dist loadgroup). A file that names its own group keeps it.
WORKBENCH_FILES = ("test_workbench_", "test_demo_logs", "test_esso_osaka_preset", "test_residual_signals")


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist reads the groups
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if item.path.name.startswith(WORKBENCH_FILES) and item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group("workbench"))


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
