"""Whether an episode's ship stays inside its model's validity envelope, and where it first left it.

A preset states the conditions its model holds for (``envelope:``: ``minimum_speed``,
``minimum_froude``, ``maximum_drift``, ``maximum_rate``, ``propeller_ahead_only``; a preset written by
``ship-env fit --preset`` the ranges its logs covered), widened by the effects that are on
(:attr:`ShipModel.envelope <ship_env.model.ShipModel.envelope>`). After every simulator step each
ship is checked against it (:func:`check_envelope`, in the tasks' compiled update), in this order:

- ``speed``: the speed through the water U0 (1 - u*) below ``minimum_speed`` (m/s);
- ``froude``: that speed over sqrt(g L) below ``minimum_froude``;
- ``drift``: |atan2(-v, u)| above ``maximum_drift`` (rad), v the model's sway velocity;
- ``rate``: the rate of turn |r| above ``maximum_rate`` (rad/s);
- ``propeller``: a propeller turning astern (n < 0) where ``propeller_ahead_only``.

The first step outside is kept with the first quantity outside, its value and its limit, until the
episode ends: the episode sails on (the simulator still integrates the equations), but its numbers
past that step come from a model outside what it was made or fitted for. A limit the preset does not
state is never crossed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ship_env.model import ShipModel
from ship_env.model import state as S
from ship_env.model.dynamics import sway_velocity
from ship_env.model.kernel import kernel

GRAVITY = 9.81  # m/s^2
#: The quantities an envelope limits, in the order they are checked; a code k > 0 in the episode
#: record names ``ENVELOPE_QUANTITIES[k]`` (0: inside).
ENVELOPE_QUANTITIES = ("", "speed", "froude", "drift", "rate", "propeller")
INSIDE, SPEED, FROUDE, DRIFT, RATE, PROPELLER = range(len(ENVELOPE_QUANTITIES))
_QUANTITY_NAMES = np.asarray(ENVELOPE_QUANTITIES)

#: The envelope's fields of every task's episode record (:func:`~ship_env.envs.batch.episode_dtype`).
ENVELOPE_FIELDS = (
    ("envelope_quantity", np.int64),  # the first quantity outside (ENVELOPE_QUANTITIES), 0 while inside
    ("envelope_step", np.int64),  # the simulator step of the episode at which it first left, -1 while inside
    ("envelope_time", np.float64),  # s, the time of that step
    ("envelope_value", np.float64),  # the quantity's value there (SI: m/s, -, rad, rad/s, rps), 0 while inside
    ("envelope_limit", np.float64),  # the limit it crossed
)


def envelope_limits(model: ShipModel) -> dict[str, float | bool]:
    """``model``'s envelope (its preset's, widened by its effects') as the compiled check reads it from the
    task's parameter record (:meth:`~ship_env.envs.task.ShipTask.parameter_record`): ``minimum_speed``,
    ``minimum_froude``, ``maximum_drift``, ``maximum_rate`` (an unstated limit -inf or inf),
    ``propeller_ahead_only`` and ``froude_speed`` (m/s, sqrt(g L))."""
    envelope = model.envelope

    def given(value: float | None, unstated: float) -> float:
        return unstated if value is None else value

    return {
        "minimum_speed": given(envelope.minimum_speed, -math.inf),
        "minimum_froude": given(envelope.minimum_froude, -math.inf),
        "maximum_drift": given(envelope.maximum_drift, math.inf),
        "maximum_rate": given(envelope.maximum_rate, math.inf),
        "propeller_ahead_only": bool(envelope.propeller_ahead_only),
        "froude_speed": math.sqrt(GRAVITY * model.length),
    }


@kernel
def _leave(episode, quantity, step, time, value, limit):
    """Record the first step outside the envelope."""
    episode["envelope_quantity"] = quantity
    episode["envelope_step"] = step
    episode["envelope_time"] = time
    episode["envelope_value"] = value
    episode["envelope_limit"] = limit


@kernel
def check_envelope(state, conditions, step, episode, limits, ship):
    """Check one ship's ``state`` after a step (or its start: ``episode["restarted"]`` clears the record)
    against the ``limits`` of the task's parameter record (:func:`envelope_limits`); ``ship`` is the model's record,
    for its sway velocity. Only the first step outside is recorded."""
    if episode["restarted"]:
        episode["envelope_quantity"] = INSIDE
        episode["envelope_step"] = -1
        episode["envelope_time"] = 0.0
        episode["envelope_value"] = 0.0
        episode["envelope_limit"] = 0.0
    elif episode["envelope_quantity"] != INSIDE:
        return
    speed = conditions[S.SERVICE_SPEED] * (1.0 - state[S.SPEED_LOSS])
    time = state[S.TIME]
    if speed < limits["minimum_speed"]:
        _leave(episode, SPEED, step, time, speed, limits["minimum_speed"])
        return
    froude = speed / limits["froude_speed"]
    if froude < limits["minimum_froude"]:
        _leave(episode, FROUDE, step, time, froude, limits["minimum_froude"])
        return
    if limits["maximum_drift"] < math.inf:
        drift = abs(math.atan2(-sway_velocity(state, conditions, ship), speed))
        if drift > limits["maximum_drift"]:
            _leave(episode, DRIFT, step, time, drift, limits["maximum_drift"])
            return
    rate = abs(state[S.RATE_OF_TURN])
    if rate > limits["maximum_rate"]:
        _leave(episode, RATE, step, time, rate, limits["maximum_rate"])
        return
    propeller_rate = conditions[S.PROPELLER_RATE]
    if limits["propeller_ahead_only"] and propeller_rate < 0.0:
        _leave(episode, PROPELLER, step, time, propeller_rate, 0.0)


def envelope_info(episodes: np.ndarray | Mapping[str, np.ndarray], ships: int | slice) -> dict[str, Any]:
    """``info["envelope"]`` of one ship (an index: scalars) or all (``slice(None)``: arrays), read from
    the episode records (or their field views by name): ``inside`` (bool: never left this episode),
    and of the first step outside ``quantity`` (:data:`ENVELOPE_QUANTITIES`), ``step`` (the
    simulator step of the episode), ``time`` (s), ``value`` and ``limit`` (SI units); while inside
    ``""``, -1 and 0 (not NaN: an info must equal itself, as Gymnasium's checker asks)."""
    codes = episodes["envelope_quantity"][ships]
    if isinstance(ships, slice):
        inside = codes == INSIDE
        quantity = np.zeros(codes.shape, dtype=_QUANTITY_NAMES.dtype)  # "", the name inside, for each ship
        left = np.flatnonzero(~inside)  # the others' names looked up alone (a lookup for each costs 12 ns)
        quantity[left] = _QUANTITY_NAMES[codes[left]]
        return {
            "inside": inside,
            "quantity": quantity,
            **{key: episodes[f"envelope_{key}"][ships] for key in ("step", "time", "value", "limit")},
        }
    if codes == INSIDE:  # the common case, without reading the record's other fields
        return {"inside": True, "quantity": "", "step": -1, "time": 0.0, "value": 0.0, "limit": 0.0}
    return {
        "inside": False,
        "quantity": ENVELOPE_QUANTITIES[codes],
        "step": int(episodes["envelope_step"][ships]),
        "time": float(episodes["envelope_time"][ships]),
        "value": float(episodes["envelope_value"][ships]),
        "limit": float(episodes["envelope_limit"][ships]),
    }
