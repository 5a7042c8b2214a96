"""The compiler used for the model's equations.

Every equation of the model is a plain Python function of floats, compiled with numba so that one
ship steps at C speed from Python and a batch of ships steps in one compiled call over numpy arrays.
Set the environment variable ``NUMBA_DISABLE_JIT=1`` to run the same code as pure Python (slow, but
debuggable with pdb; the same numbers: ``tests/test_model_simulator.py``). numpy then warns of the
integer overflow that the random stream's hashing wraps on purpose (:mod:`ship_env.model.noise`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numba

from ship_env.model import compile_notice

compile_notice.install()  # a line before the first compile, progress while it lasts

#: Decorator for every model equation: compiled, cached on disk, IEEE-exact (no fast-math).
kernel = numba.njit(cache=True, fastmath=False, error_model="numpy")

#: Decorator for the batched step: the same, looping over ships on all cores.
parallel_kernel = numba.njit(cache=True, fastmath=False, error_model="numpy", parallel=True)

#: Decorator for a compiled piece its compiled callers take in whole (numba's IR inlining): no call, and
#: nothing passed to it is reference-counted.
inlined_kernel = numba.njit(cache=True, fastmath=False, error_model="numpy", inline="always")


def entry_point(function: Callable[..., Any], *args: Any) -> Callable[..., Any]:
    """The compiled ``function``'s entry point for arguments of the types of ``args`` (compiled, or read
    from the cache, where it is not yet): a call without numba's dispatch, which types every argument
    afresh (about 0.3 us a call and 0.05 to 0.2 us an argument, the most for a record array; figures
    in ``docs/results/benchmarks.md``). It checks no types: call it only with arguments of the types
    of ``args``, best those very objects. With ``NUMBA_DISABLE_JIT=1``, the function itself."""
    if numba.config.DISABLE_JIT:
        return function
    return function.compile(tuple(function.typeof_pyval(arg) for arg in args))  # type: ignore[attr-defined]
