"""Independent fits in worker processes: the workbench's parallel map.

A step of the error ladder fits many models that do not depend on each other -- each candidate
effect, each start of a refit, each fold refitted in full -- so they run in a pool of worker
processes (``FitOptions.workers``), one BLAS and one numba thread each (as in the parent, see
:func:`~.fit.one_thread`). Every item is computed by the same code on the same inputs whichever
process takes it, and the results come back in the items' order: the outcome is the same, bit for
bit, with one worker or many.

The pool is started once (``spawn``: the compiled replay's OpenMP threads do not survive a
``fork``) and kept for the next calls with the same number of workers.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor
from typing import TypeVar

Item = TypeVar("Item")
Result = TypeVar("Result")

_pool: tuple[int, ProcessPoolExecutor] | None = None


def usable_cores() -> int:
    """The CPU cores this process may run on (its affinity), at least 1."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _single_threaded() -> None:
    """A worker's start: one BLAS thread and one numba thread for its whole life."""
    import numba
    from threadpoolctl import threadpool_limits

    import ship_env.workbench.fit  # noqa: F401  (loads scipy's BLAS before limiting it)

    numba.set_num_threads(1)
    threadpool_limits(limits=1, user_api="blas")


def _workers(count: int) -> ProcessPoolExecutor:
    global _pool
    if _pool is None or _pool[0] != count:
        if _pool is not None:
            _pool[1].shutdown()
        context = multiprocessing.get_context("spawn")
        _pool = (count, ProcessPoolExecutor(count, mp_context=context, initializer=_single_threaded))
    return _pool[1]


def run_each(function: Callable[[Item], Result], items: Iterable[Item], workers: int) -> list[Result]:
    """``[function(item) for item in items]``, over ``workers`` processes where more than one.

    ``function`` must be a module-level function and the items picklable.
    """
    items = list(items)
    if workers <= 1 or len(items) <= 1:
        return [function(item) for item in items]
    return list(_workers(workers).map(function, items))
