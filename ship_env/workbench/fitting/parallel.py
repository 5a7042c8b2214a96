"""Independent fits in worker processes: the workbench's parallel map.

A step of the error ladder fits many models that do not depend on each other -- each candidate
effect, each start of a refit, each fold refitted in full -- so they run in a pool of worker
processes (``FitOptions.workers``), one BLAS and one numba thread each (as in the parent, see
:func:`~.threads.one_thread`). Every item is computed by the same code on the same inputs whichever
process takes it, and the results come back in the items' order: the outcome is the same, bit for
bit, with one worker or many.

The pool is started once (``spawn``: the compiled replay's OpenMP threads do not survive a
``fork``) and kept for the next calls with the same number of workers. A spawned worker knows the
built-in effects and those of installed entry points; while this process has registered others (a
notebook's, a script's), the fits run here, one after another.

A spawned worker imports the main script again. A script that does its work without the
``if __name__ == "__main__":`` guard would start it again in every worker, and the workers die
while starting; such a worker says so (it never starts workers of its own), and so does this
process (:class:`WorkerStartError`, naming the script and the fix), not a bare ``BrokenProcessPool``.
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
import signal
import sys
from collections.abc import Callable, Iterable
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

Result = TypeVar("Result")

#: The pool: its number of workers, the workers, and their effect registry's fingerprint (to come).
_pool: tuple[int, ProcessPoolExecutor, Future[str]] | None = None


class WorkerStartError(RuntimeError):
    """The worker processes could not start (most often: a script without the ``__main__`` guard)."""


def _guard_advice() -> str:
    """What to do where the main script runs its work again in every spawned worker."""
    script = getattr(sys.modules.get("__mp_main__", sys.modules.get("__main__")), "__file__", None)
    which = f"the script {script}" if script else "the main script"
    return (
        f"{which} seems to do its work without the guard, so every worker process, which imports it, runs it "
        'again: put the script\'s work under `if __name__ == "__main__":`, or use workers=1 (--workers 1)'
    )


def _importing_parents_script() -> bool:
    """Whether this is a spawned process running its parent's main script: ``multiprocessing`` imports it as
    ``__mp_main__``, which is the ``__main__`` module everywhere but while that import runs."""
    return sys.modules.get("__mp_main__", sys.modules.get("__main__")) is not sys.modules.get("__main__")


def usable_cores() -> int:
    """The CPU cores this process may run on (its affinity), at least 1."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _single_threaded() -> None:
    """A worker's start: one BLAS thread and one numba thread for its whole life, which ends with
    this process's (on Linux, even where this process is killed)."""
    import numba
    from threadpoolctl import threadpool_limits

    import ship_env.workbench.fitting.fit  # noqa: F401  (loads scipy's BLAS before limiting it)
    from ship_env.workbench.fitting.memory import keep_freed_memory

    keep_freed_memory()
    numba.set_num_threads(1)
    threadpool_limits(limits=1, user_api="blas")
    if sys.platform == "linux":
        set_parent_death_signal = 1  # prctl(PR_SET_PDEATHSIG, signal)
        ctypes.CDLL(None).prctl(set_parent_death_signal, signal.SIGTERM)


def _registry() -> str:
    """A fingerprint of the registered effects (names, order and equations)."""
    from ship_env.model import EFFECTS

    return EFFECTS.fingerprint(list(EFFECTS))


def start(workers: int) -> None:
    """Start ``workers`` worker processes (for more than one) without waiting for them: they start
    while this process goes on (fits the starting model)."""
    if workers > 1:
        _workers(workers)


def _workers(count: int) -> ProcessPoolExecutor:
    global _pool
    if _importing_parents_script():
        raise WorkerStartError(f"a worker process was asked to start worker processes: {_guard_advice()}")
    if _pool is None or _pool[0] != count:
        if _pool is not None:
            _pool[1].shutdown()
        context = multiprocessing.get_context("spawn")
        executor = ProcessPoolExecutor(count, mp_context=context, initializer=_single_threaded)
        # One call per worker: each submission starts a process.
        _pool = (count, executor, [executor.submit(_registry) for _ in range(count)][0])
    return _pool[1]


class _InProcess:
    """The pool's ``submit`` for one worker: the call made at once, in this process."""

    def submit(self, function: Callable[..., Result], *arguments: Any) -> Future[Result]:
        done: Future[Result] = Future()
        done.set_result(function(*arguments))
        return done


def pool(workers: int, tasks: int = 2) -> ProcessPoolExecutor | _InProcess:
    """Something to ``submit(function, *arguments)`` to: the worker processes, or this process for one
    worker, for fewer than two ``tasks`` or where the workers would not know this process's effects."""
    if workers > 1 and tasks > 1:
        executor = _workers(workers)
        if _pool is not None and _started(_pool[2]) == _registry():
            return executor
    return _InProcess()


def _started(fingerprint: Future[str]) -> str:
    """The workers' effect registry's fingerprint, once they have started; a WorkerStartError if they died."""
    global _pool
    try:
        return fingerprint.result()
    except BrokenProcessPool:
        if _pool is not None:
            _pool[1].shutdown(wait=False)
        _pool = None
        raise WorkerStartError(f"the worker processes stopped while starting: {_guard_advice()}") from None


def run_each(function: Callable[..., Result], arguments: Iterable[tuple[Any, ...]], workers: int) -> list[Result]:
    """``[function(*item) for item in arguments]``, over ``workers`` processes where more than one.

    ``function`` must be a module-level function and the arguments picklable.
    """
    items = list(arguments)
    runner = pool(workers, len(items))
    if isinstance(runner, _InProcess):
        return [function(*item) for item in items]
    return list(runner.map(function, *zip(*items, strict=True)))
