"""The workbench's thread policy: one BLAS thread and one numba thread for its fits and replays.

Their linear algebra is on tall, thin matrices (samples x terms) and their replay batches are small
and many: more threads spend more time waiting for each other than working (the figures:
``docs/results/benchmarks.md``). :func:`one_thread` holds the policy for an entry point's call in
this process; :mod:`.parallel`'s worker processes hold it for their whole life.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import ParamSpec, TypeVar

import numba
from threadpoolctl import threadpool_limits

Arguments = ParamSpec("Arguments")
Returned = TypeVar("Returned")


def one_thread(function: Callable[Arguments, Returned]) -> Callable[Arguments, Returned]:
    """Decorator for the workbench's entry points: one BLAS thread, one thread for the compiled replays."""

    @functools.wraps(function)
    def single_threaded(*args: Arguments.args, **kwargs: Arguments.kwargs) -> Returned:
        threads = numba.get_num_threads()
        numba.set_num_threads(1)
        try:
            with threadpool_limits(limits=1, user_api="blas"):
                return function(*args, **kwargs)
        finally:
            numba.set_num_threads(threads)

    return single_threaded
