"""Fixed-step integration of the ship's equations: one ship, or a batch in one compiled call.

Each step holds the ordered rudder, the conditions and the white noise constant (zero-order hold).
The wave-spectrum excitation is likewise evaluated once per step, at mid-step.
The continuous states are integrated with classic fourth-order Runge-Kutta (default) or forward
Euler; the actual rudder is moved exactly by the steering machine's rate limiter, and the RK4
stages see the rudder where the steering machine has it at their instant. White noise of unit
intensity is the standard normal sample divided by sqrt(dt), so its effect does not depend on the
step size.

``step_ship`` and ``step_ships`` run the same compiled code per ship, so a batch of N ships gives
exactly the numbers of N single runs.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from ship_env.model import state as S
from ship_env.model.dynamics import derivatives
from ship_env.model.effects import steering_machine, wave_spectrum
from ship_env.model.kernel import kernel, parallel_kernel
from ship_env.model.noise import standard_normal_pair

RK4 = 0
EULER = 1
METHODS = {"rk4": RK4, "euler": EULER}

# Rows of the scratch space: four RK4 slopes, the stage state, the white noise.
WORK_NOISE = 5
WORK_ROWS = 6


@kernel
def new_workspace():
    """Scratch space for ``step_ship``."""
    return np.zeros((WORK_ROWS, max(S.STATE_SIZE, S.NOISE_SIZE)))


@kernel
def _rudder_at(rudder, limited_order, duration, p):
    """The actual rudder ``duration`` seconds into the step."""
    if p["steering_machine_on"]:
        return steering_machine.rudder_after(rudder, limited_order, duration, p["steering_machine_rudder_rate"])
    return limited_order


@kernel
def step_ship(state, ordered_rudder, conditions, noise_key, step_index, waves, params, dt, method, work):
    """Advance one ship's ``state`` in place by ``dt`` seconds.

    Args:
        state: (STATE_SIZE,) the ship's state.
        ordered_rudder: the ordered rudder angle, rad (clipped at the rudder limit here).
        conditions: (CONDITION_SIZE,) the conditions held over the step.
        noise_key: the ship's random key (uint64, see ``noise``).
        step_index: how many steps the ship has taken since reset (numbers its noise samples).
        waves: (3, count) wave components for the wave-spectrum effect.
        params: the model's one-element parameter record array.
        dt: the step, s.
        method: ``RK4`` or ``EULER``.
        work: (WORK_ROWS, STATE_SIZE) scratch space, overwritten.

    Returns:
        True while the model is valid: every state finite and the forward speed not negative
        (u* <= 1). False flags a ship the caller must not go on with.
    """
    p = params[0]
    order = steering_machine.limit_order(ordered_rudder, p["rudder_limit"])
    rudder = state[S.RUDDER]
    white_noise = work[WORK_NOISE]
    white_noise[:] = 0.0
    if p["wave_filter_on"] or p["gusts_on"]:
        # One Box-Muller draw gives both channels (S.NOISE_SIZE == 2) of this step.
        wave_noise, gust_noise = standard_normal_pair(noise_key, np.uint64(step_index))
        white_noise[S.NOISE_WAVE] = wave_noise / math.sqrt(dt)
        white_noise[S.NOISE_GUST] = gust_noise / math.sqrt(dt)
    wave_yaw = 0.0
    if p["wave_spectrum_on"]:
        # The sea's yaw excitation is held over the step, evaluated at mid-step.
        wave_yaw = wave_spectrum.yaw_acceleration(
            state[S.TIME] + 0.5 * dt,
            state[S.NORTH],
            state[S.EAST],
            state[S.HEADING],
            conditions[S.WAVE_DIRECTION],
            waves,
            p["wave_spectrum_yaw_coefficient"],
        )
    k1 = work[0]
    derivatives(state, _rudder_at(rudder, order, 0.0, p), conditions, white_noise, wave_yaw, p, k1)
    if method == EULER:
        for j in range(S.STATE_SIZE):
            state[j] += dt * k1[j]
    else:
        k2 = work[1]
        k3 = work[2]
        k4 = work[3]
        stage = work[4]
        half = 0.5 * dt
        rudder_half = _rudder_at(rudder, order, half, p)
        for j in range(S.STATE_SIZE):
            stage[j] = state[j] + half * k1[j]
        derivatives(stage, rudder_half, conditions, white_noise, wave_yaw, p, k2)
        for j in range(S.STATE_SIZE):
            stage[j] = state[j] + half * k2[j]
        derivatives(stage, rudder_half, conditions, white_noise, wave_yaw, p, k3)
        for j in range(S.STATE_SIZE):
            stage[j] = state[j] + dt * k3[j]
        derivatives(stage, _rudder_at(rudder, order, dt, p), conditions, white_noise, wave_yaw, p, k4)
        for j in range(S.STATE_SIZE):
            state[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
    state[S.RUDDER] = _rudder_at(rudder, order, dt, p)
    return is_valid(state)


@kernel
def is_valid(state):
    """Whether a state is inside the model's validity: finite, with forward speed u >= 0."""
    for j in range(S.STATE_SIZE):
        if not math.isfinite(state[j]):
            return False
    return state[S.SPEED_LOSS] <= 1.0


@kernel
def _step_range(first, stop, states, ordered_rudder, conditions, noise_keys, step_index, waves, params, dt, method, valid):
    """Step ships ``first`` to ``stop - 1`` of a batch with one scratch space (see ``step_ships``)."""
    work = new_workspace()
    for i in range(first, stop):
        valid[i] = step_ship(
            states[i], ordered_rudder[i], conditions[i], noise_keys[i], step_index[i], waves[i], params, dt, method, work
        )
        step_index[i] += 1


@kernel
def step_ships(states, ordered_rudder, conditions, noise_keys, step_index, waves, params, dt, method, valid):
    """Advance a batch of ships in place, in one thread: row i of each array is ship i.

    Each ship is stepped by ``step_ship``; ``valid[i]`` receives its verdict and ``step_index[i]``
    counts the step.
    """
    _step_range(0, states.shape[0], states, ordered_rudder, conditions, noise_keys, step_index, waves, params, dt, method, valid)


@parallel_kernel
def step_ships_parallel(states, ordered_rudder, conditions, noise_keys, step_index, waves, params, dt, method, valid):
    """``step_ships`` on all cores: the batch in chunks, the same numbers."""
    count = states.shape[0]
    chunks = min(count, 64)
    for chunk in prange(chunks):
        _step_range(
            chunk * count // chunks,
            (chunk + 1) * count // chunks,
            states,
            ordered_rudder,
            conditions,
            noise_keys,
            step_index,
            waves,
            params,
            dt,
            method,
            valid,
        )
