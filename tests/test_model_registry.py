"""The effect registry: the built-ins composed from it give the trajectories of the hand-written model.

Bit for bit on the CPU that recorded them; on another within the rounding of its elementary functions
(:func:`assert_matches_reference`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ship_env.model import Conditions, ShipModel, Simulator, list_ships

#: Trajectories recorded with the hand-written derivative (every preset with its own, every and the
#: minimal set of effects; RK4 and Euler; one ship and a batch of six in different conditions).
REFERENCE = Path(__file__).parent / "data" / "reference_trajectories.npz"
#: Samples of each recorded trajectory, and steps between them (``_trajectory``).
SNAPSHOTS, STEPS_BETWEEN = 8, 50
#: A few ULP: the error of one elementary function. numpy evaluates exp and power per CPU (its SIMD
#: routines on AVX-512, others elsewhere), and the sea's components are drawn with them
#: (``wave_spectrum.components``), so another CPU draws them a few ULP apart.
ELEMENTARY_ULP = 4
#: Each step can add at most one such error per state, relative to the state's scale, where the
#: trajectory amplifies none: after all the steps, at most this far from the recorded doubles.
CROSS_CPU_TOLERANCE = SNAPSHOTS * STEPS_BETWEEN * ELEMENTARY_ULP * float(np.finfo(float).eps)  # 3.6e-13
#: Effects added to the library after the reference was recorded (each checked against its closed form).
NEWER_EFFECTS = ("propeller_astern", "sway_lag", "drift_resistance")
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
    for k in range(SNAPSHOTS * STEPS_BETWEEN):
        order = math.radians(15.0) * (1 if (k // 60) % 2 == 0 else -1)
        sim.step(order if ships == 1 else np.full(ships, order) * np.linspace(0.5, 1.0, ships))
        if k % STEPS_BETWEEN == STEPS_BETWEEN - 1:
            saved.append(sim.state.copy())
    return np.stack(saved)


def reference_mismatch(trajectory: np.ndarray, recorded: np.ndarray) -> float:
    """The largest difference of a trajectory from the recorded one, relative to each state's scale (its
    largest magnitude in the recording), in units of :data:`CROSS_CPU_TOLERANCE`; the states of effects newer
    than the recording, which follow the recorded ones, left out."""
    trajectory = trajectory[..., : recorded.shape[-1]]
    scale = np.max(np.abs(recorded), axis=(0, 1))
    difference = np.abs(trajectory - recorded) / np.where(scale > 0.0, scale, 1.0)
    return float(np.max(difference)) / CROSS_CPU_TOLERANCE


def assert_matches_reference(trajectory: np.ndarray, recorded: np.ndarray, key: str) -> None:
    """The same doubles where this CPU rounds as the recording one did; else no farther than its rounding. The
    states of effects newer than the recording follow the recorded ones; with their effects off they stay put."""
    newer = trajectory[..., recorded.shape[-1] :]
    assert np.array_equal(newer, np.broadcast_to(newer[:1], newer.shape)), key
    if not np.array_equal(trajectory[..., : recorded.shape[-1]], recorded):
        assert reference_mismatch(trajectory, recorded) <= 1.0, key


@pytest.mark.parametrize("ship", list_ships())
def test_built_in_effects_through_the_registry_give_the_reference(ship):
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
                assert_matches_reference(_trajectory(model, method, ships), reference[key], key)


def test_a_change_in_a_term_s_tenth_digit_is_past_the_cross_cpu_tolerance():
    """The tolerance lets rounding through, not physics: the yaw gain moved by one part in 1e10 fails it."""
    model = ShipModel.full("container_226m").without_effects(*NEWER_EFFECTS)
    moved = model.with_parameters({"yaw.gain": model.parameter("yaw.gain") * (1.0 + 1e-10)})
    assert reference_mismatch(_trajectory(moved, "rk4", 6), np.load(REFERENCE)["container_226m/full/rk4/6"]) > 1.0
