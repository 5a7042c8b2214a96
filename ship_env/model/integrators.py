"""Fixed-step integration of the ship's equations: one ship, or a batch in one compiled call.

Each step holds the ordered rudder, the conditions and the white noise constant (zero-order hold).
The contributions declared ``held`` (the wave spectrum's excitation) are likewise evaluated once
per step, at mid-step. The continuous states are integrated with classic fourth-order Runge-Kutta
(default) or forward Euler; the actual rudder is moved exactly where an effect declares how it
follows the order (the steering machine's rate limiter, ``dynamics.actual_rudder``), and the RK4
stages see the rudder where it is at their instant. White noise of unit intensity is the standard
normal sample divided by sqrt(dt), so its effect does not depend on the step size; it is drawn
only where a state declared noise-driven needs it (``dynamics.draw_white_noise``). This module
names no effect: all of that comes from the effects' declarations.

``step_ship`` and ``step_ships`` run the same compiled code per ship, so a batch of N ships gives
exactly the numbers of N single runs.

The batch loops hand their arrays on as :func:`borrowed` views: every row view and every array
passed to a compiled function otherwise costs two atomic updates of numba's reference count, a
noticeable share of a calm ship's step (``docs/results/benchmarks.md``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba import prange, types
from numba.extending import intrinsic
from numba.np.arrayobj import make_array

from ship_env.model import state as S
from ship_env.model.dynamics import actual_rudder, derivatives, draw_white_noise, held_yaw_acceleration, state_size
from ship_env.model.kernel import inlined_kernel, kernel, parallel_kernel

RK4 = 0
EULER = 1
METHODS = {"rk4": RK4, "euler": EULER}

# Rows of the scratch space: four RK4 slopes, the stage state, the white noise (a channel per
# noise-driven state: never more than the state's size).
WORK_NOISE = 5
WORK_ROWS = 6


@intrinsic
def borrowed(typingctx, arrays):
    """The arrays of a tuple as views that numba does not reference-count (no meminfo).

    Only for a compiled function's own array arguments, which its caller keeps alive for the
    call: a borrowed view must not outlive the call nor be returned to Python. Rows and fields of
    a borrowed view are borrowed too, so a loop over ships passes them on at no cost.
    """
    if not isinstance(arrays, types.BaseTuple) or not all(isinstance(item, types.Array) for item in arrays):
        return None

    def codegen(context, builder, signature, args):
        views = []
        for index, array_type in enumerate(arrays):
            view = make_array(array_type)(context, builder, value=builder.extract_value(args[0], index))
            view.meminfo = ir.Constant(view.meminfo.type, None)
            view.parent = ir.Constant(view.parent.type, None)
            views.append(view._getvalue())
        return context.make_tuple(builder, arrays, views)

    return arrays(arrays), codegen


def _arrays_as_given(arrays):
    """:func:`borrowed` for the pure-Python model (``NUMBA_DISABLE_JIT=1``): an intrinsic does not run
    there, and Python's own reference counts are not numba's to spare, so the arrays pass as given."""
    return arrays


if numba.config.DISABLE_JIT:
    borrowed = _arrays_as_given


@kernel
def new_workspace(state_size):
    """Scratch space for ``step_ship`` on states of ``state_size`` (``ShipModel.state_size``)."""
    return np.zeros((WORK_ROWS, state_size))


@kernel
def limit_order(ordered_rudder, rudder_limit):
    """The ordered rudder clipped at +-rudder_limit (Fig. 2.9, the rudder limiter)."""
    return min(max(ordered_rudder, -rudder_limit), rudder_limit)


@kernel
def step_ship(state, ordered_rudder, conditions, noise_key, step_index, draws, params, dt, method, work):
    """Advance one ship's ``state`` in place by ``dt`` seconds, drawing its white noise.

    Args:
        state: the ship's state (layout ``ShipModel.state_names``).
        ordered_rudder: the ordered rudder angle, rad (clipped at the rudder limit here).
        conditions: (CONDITION_SIZE,) the conditions held over the step.
        noise_key: the ship's random key (uint64, see ``noise``).
        step_index: how many steps the ship has taken since reset (numbers its noise samples).
        draws: the ship's row of draws (``ShipModel.draw``): the random numbers its effects drew where it started.
        params: the model's one-element parameter record array.
        dt: the step, s.
        method: ``RK4`` or ``EULER``.
        work: ``new_workspace(state size)``, scratch space, overwritten.

    Returns:
        True while the model is valid: every state finite and the forward speed not negative
        (u* <= 1). False flags a ship the caller must not go on with.
    """
    # Borrowed: passing the arrays on to the effects' composed pieces then costs no reference counting.
    state, conditions, draws, work = borrowed((state, conditions, draws, work))
    white_noise = work[WORK_NOISE]
    draw_white_noise(state, conditions, noise_key, step_index, dt, params[0], white_noise)
    return step_ship_with_noise(state, ordered_rudder, conditions, white_noise, draws, params, dt, method, work)


@inlined_kernel
def step_ship_with_noise(state, ordered_rudder, conditions, white_noise, draws, params, dt, method, work):
    """``step_ship`` with the white noise given: ``white_noise`` holds one channel per noise-driven state
    (already divided by sqrt(dt)), held over the step. A replay of a measured run passes zeros, the
    noise's expected value: it meets no random numbers. ``work``'s rows other than ``WORK_NOISE`` are
    overwritten."""
    state, conditions, white_noise, draws, work = borrowed((state, conditions, white_noise, draws, work))
    p = params[0]
    size = state_size(p)  # == state.shape[0]; a constant, so the loops below unroll
    order = limit_order(ordered_rudder, p["rudder_limit"])
    rudder = state[S.RUDDER]
    held = held_yaw_acceleration(state, conditions, draws, dt, p)
    rudder_end = actual_rudder(state, rudder, order, dt, conditions, p)
    # One call site for the four slopes (the stages in a loop): the composed derivative is inlined
    # once, which compiles in half the time of four inlined copies, with the same numbers.
    stage = work[4]
    half = 0.5 * dt
    rudder_half = actual_rudder(state, rudder, order, half, conditions, p)
    for slope in range(1 if method == EULER else 4):
        if slope == 0:
            stage_rudder = actual_rudder(state, rudder, order, 0.0, conditions, p)
            for j in range(size):
                stage[j] = state[j]
        else:
            stage_rudder = rudder_end if slope == 3 else rudder_half
            interval = dt if slope == 3 else half
            previous = work[slope - 1]
            for j in range(size):
                stage[j] = state[j] + interval * previous[j]
        derivatives(stage, stage_rudder, conditions, white_noise, draws, held, p, work[slope])
    k1 = work[0]
    if method == EULER:
        for j in range(size):
            state[j] += dt * k1[j]
    else:
        k2 = work[1]
        k3 = work[2]
        k4 = work[3]
        for j in range(size):
            state[j] += dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
    state[S.RUDDER] = rudder_end
    return is_valid(state, size)


@kernel
def is_valid(state, size):
    """Whether a state of ``size`` variables is inside the model's validity: finite, with forward speed u >= 0."""
    for j in range(size):
        if not math.isfinite(state[j]):
            return False
    return state[S.SPEED_LOSS] <= 1.0


@kernel
def _step_rows(
    first, stop, work, states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid
):
    """Step ships ``first`` to ``stop - 1`` of a batch with the scratch space ``work``.

    ``work`` is an argument, not allocated here, because only arguments may be borrowed: numba
    frees a local array after its last use, which a borrowed view does not count.
    """
    work, states, conditions, draws, params = borrowed((work, states, conditions, draws, params))
    for i in range(first, stop):
        valid[i] = step_ship(
            states[i],
            ordered_rudder[i],
            conditions[i],
            noise_keys[i],
            step_index[i],
            draws[i],
            params,
            dt,
            method,
            work,
        )
        step_index[i] += 1


@kernel
def _step_range(
    first, stop, states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid
):
    """Step ships ``first`` to ``stop - 1`` of a batch with a scratch space of their own (``step_ships``)."""
    work = new_workspace(states.shape[1])
    _step_rows(
        first, stop, work, states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid
    )


@kernel
def step_ships(states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid):
    """Advance a batch of ships in place, in one thread: row i of each array is ship i.

    Each ship is stepped by ``step_ship``; ``valid[i]`` receives its verdict and ``step_index[i]``
    counts the step.
    """
    first = np.int64(0)  # not the literal 0: ``_step_range`` is then compiled once, for this and the parallel step
    count = states.shape[0]
    _step_range(
        first, count, states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid
    )


@parallel_kernel
def step_ships_parallel(states, ordered_rudder, conditions, noise_keys, step_index, draws, params, dt, method, valid):
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
            draws,
            params,
            dt,
            method,
            valid,
        )
