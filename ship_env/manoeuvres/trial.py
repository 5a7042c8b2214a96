"""Sailing a trial: ships on a steady straight approach, a rudder law, the recorded time series.

Every standard manoeuvre starts the way MSC.137(76) 4.2 asks: a steady straight approach with zero
yaw rate, at the test speed, in calm water (MSC/Circ.1053 2.2.1.2: deep water, no wind, waves or
current). The simulator starts each ship in that state, on heading 0 (north) at the origin, so
the first execute is at time 0. A rudder law reads the simulator and orders the rudder each
step; :func:`run_trial` records the batch and returns one table for all its runs.

Durations are given in ship lengths sailed at the approach speed, the thesis's dimensionless time
s* = (u/L) t (2.42), so that a default suits a 3 m model as well as a 226 m ship.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Protocol

import numpy as np
import pandas as pd

from ship_env.manoeuvres.results import TIME_SERIES_COLUMNS, degrees_label
from ship_env.manoeuvres.settings import TrialSettings
from ship_env.model import Conditions, ShipModel, Simulator
from ship_env.model.external import ExternalSimulator, dynamics_factory, preset_dynamics


class RudderLaw(Protocol):
    """Orders the rudder from what the simulator shows: one angle per ship, rad."""

    def __call__(self, simulator: Simulator) -> np.ndarray | float: ...


def run_trial(
    model: ShipModel,
    settings: TrialSettings,
    rudder_law: RudderLaw,
    labels: Sequence[str],
    duration: float,
    stop: Callable[[Simulator], bool] | None = None,
    initial_rate_of_turn: np.ndarray | None = None,
    initial_rudder: np.ndarray | float = 0.0,
    conditions: Conditions | None = None,
    initial_heading: float = 0.0,
    initial_speed: float | None = None,
) -> pd.DataFrame:
    """Sail one ship per label from a steady straight approach and record every step.

    Args:
        model: the ship model.
        settings: approach speed, integration step and who sails the ship (:class:`TrialSettings`).
        rudder_law: orders the rudder each step (clipped at the rudder limit, as the steering
            machine's limiter does; the recorded ``ordered_rudder`` is the clipped order).
        labels: one name per ship of the batch, the ``run`` column of the result.
        duration: the longest the trial may last, s.
        stop: ends the trial early when it returns True (checked after each recorded sample).
        initial_rate_of_turn: per-ship starting rate of turn, rad/s (``None``: straight).
        initial_rudder: per-ship starting rudder angle, rad.
        conditions: what the ships sail in besides the approach speed (propeller, wind, current);
            ``None``: calm water, as MSC/Circ.1053 asks.
        initial_heading: the starting heading, rad (0: north).
        initial_speed: the starting speed through the water, m/s (``None``: the approach speed; see
            :meth:`~ship_env.model.Simulator.reset`).

    Returns:
        The time series, columns :data:`~ship_env.manoeuvres.results.TIME_SERIES_COLUMNS`.
    """
    sailed_by = preset_dynamics(model, settings.dynamics)
    if sailed_by is None:
        simulator = Simulator(model, num_ships=len(labels), dt=settings.dt, method=settings.method)
    else:
        simulator = ExternalSimulator(model, dynamics_factory(sailed_by), len(labels), settings.dt)
    simulator.reset(
        seed=0,
        conditions=replace(Conditions() if conditions is None else conditions, service_speed=settings.speed),
        heading=initial_heading,
        rudder=initial_rudder,
        rate_of_turn=initial_rate_of_turn,
        speed=initial_speed,
    )
    limit = model.rudder_limit
    last_step = math.ceil(duration / settings.dt - 1e-9)
    samples = []
    for step in range(last_step + 1):
        orders = np.clip(np.broadcast_to(np.asarray(rudder_law(simulator), dtype=float), (len(labels),)), -limit, limit)
        samples.append(
            np.column_stack(
                (
                    simulator.time,
                    simulator.position,
                    simulator.heading,
                    simulator.rate_of_turn,
                    simulator.rudder,
                    orders,
                    simulator.speed,
                )
            )
        )
        if step == last_step or (stop is not None and stop(simulator)):
            break
        simulator.step(orders if len(labels) > 1 else float(orders[0]))
    per_ship = np.stack(samples, axis=1)  # (ships, samples, columns)
    frame = pd.DataFrame(per_ship.reshape(-1, per_ship.shape[2]), columns=TIME_SERIES_COLUMNS[1:])
    frame.insert(0, "run", np.repeat(np.asarray(labels, dtype=object), per_ship.shape[1]))
    return frame


def check_rudder_angle(model: ShipModel, angle: float, name: str = "rudder_angle") -> float:
    """``angle`` (rad) if it is a non-zero rudder angle the ship can give; ValueError otherwise."""
    if isinstance(angle, bool) or not isinstance(angle, (int, float)) or not math.isfinite(angle) or angle == 0.0:
        raise ValueError(f"{name}: expected a non-zero rudder angle in rad, got {angle!r}")
    if abs(angle) > model.rudder_limit * (1.0 + 1e-9):
        raise ValueError(
            f"{name}: {math.degrees(angle):g} deg exceeds the rudder limit of "
            f"{math.degrees(model.rudder_limit):g} deg of {model.ship.name}"
        )
    return float(angle)


def rudder_label(angle: float) -> str:
    """A rudder angle (rad) in words: "35 deg stbd" for positive, "35 deg port" for negative."""
    return f"{degrees_label(abs(angle))} deg {'stbd' if angle > 0.0 else 'port'}"
