"""The effect registry: the built-ins composed from it give the trajectories of the hand-written model bit for bit."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ship_env.model import Conditions, ShipModel, Simulator, list_ships

#: Trajectories recorded with the hand-written derivative (every preset with its own, every and the
#: minimal set of effects; RK4 and Euler; one ship and a batch of six in different conditions).
REFERENCE = Path(__file__).parent / "data" / "reference_trajectories.npz"
#: Effects added to the library after the reference was recorded (each checked against its closed form).
NEWER_EFFECTS = ("propeller_astern",)
#: Presets whose values changed after the reference was recorded: the file holding the values it was recorded with.
RECORDED_WITH = {"esso_osaka_model": str(Path(__file__).parent / "data" / "esso_osaka_nominal.yaml")}


def _conditions(i: int) -> Conditions:
    return Conditions(
        propeller_rate=1.0 + 0.2 * i,
        current_speed=0.3 + 0.05 * i,
        current_direction=math.radians(20 + 30 * i),
        wind_speed=[0.0, 6.0, 10.0][i % 3],
        wind_direction=math.radians(60 + 40 * i),
        wave_height=[0.0, 2.0, 3.0][(i + 1) % 3],
        wave_period=8.0,
        wave_direction=math.radians(40 + 25 * i),
    )


def _trajectory(model: ShipModel, method: str, ships: int) -> np.ndarray:
    sim = Simulator(model, num_ships=ships, dt=0.5, method=method)
    sim.reset(seed=7, conditions=[_conditions(i) for i in range(ships)])
    saved = []
    for k in range(400):
        order = math.radians(15.0) * (1 if (k // 60) % 2 == 0 else -1)
        sim.step(order if ships == 1 else np.full(ships, order) * np.linspace(0.5, 1.0, ships))
        if k % 50 == 49:
            saved.append(sim.state.copy())
    return np.stack(saved)


@pytest.mark.parametrize("ship", list_ships())
def test_built_in_effects_through_the_registry_give_the_reference_bit_for_bit(ship):
    reference = np.load(REFERENCE)
    recorded = RECORDED_WITH.get(ship, ship)
    for label, model in (
        ("preset", ShipModel(recorded)),
        ("full", ShipModel.full(recorded).without_effects(*NEWER_EFFECTS)),
        ("minimal", ShipModel.minimal(recorded)),
    ):
        for method in ("rk4", "euler"):
            for ships in (1, 6):
                key = f"{ship}/{label}/{method}/{ships}"
                # Exact equality: every number the same double (a signed zero may differ in sign).
                assert np.array_equal(_trajectory(model, method, ships), reference[key]), key
