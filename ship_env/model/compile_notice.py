"""The line a cold compile starts with, and its progress.

numba compiles the model's equations on their first use and caches them on disk (``cache=True`` in
:mod:`ship_env.model.kernel`). A cache miss fires numba's ``numba:compile`` event before it compiles
(a load from the cache fires none), so the listener installed here knows, at no cost on a warm
cache, that a compile starts. The first one in a process prints::

    ship_env: compiling the ship model for this machine, once: about 8 to 14 s (2 idle cores; load 0.3 on 2)

and, while it lasts, a line every :data:`PROGRESS_EVERY_S` seconds with the functions compiled. The
estimate is what the last cold compile that began with the same function took on this machine
(:data:`RECORD_FILE`, in numba's cache folder), or else :data:`REFERENCE`, measured on 2 idle cores,
with the load now (a compile is single-threaded: it takes longer where more processes than cores
run). Worker processes (the workbench's) print nothing.

``NUMBA_DISABLE_JIT=1`` compiles nothing and prints nothing.
"""

from __future__ import annotations

import atexit
import json
import multiprocessing
import os
import sys
import time
from pathlib import Path
from typing import Any

import numba
from numba.core import event

#: A cold compile from the function it compiles first: (seconds, functions compiled), measured on 2
#: cores at load 0.7 with an empty cache: the Simulator's workspace first for an environment's reset
#: and step (8 s for the single environment, 14 s for the batched one with its parallel step), the
#: workbench's replay first for ``ship-env fit``.
REFERENCE: dict[str, tuple[tuple[float, float], int]] = {
    "new_workspace": ((8.0, 14.0), 75),
    "derive_conditions": ((14.0, 14.0), 58),
}
#: The figure for a compile that begins with another function.
DEFAULT_REFERENCE = ((8.0, 14.0), 70)
#: Seconds between two progress lines.
PROGRESS_EVERY_S = 5.0
#: The measured compiles, in numba's cache folder: {first function: [seconds, functions]}.
RECORD_FILE = "ship_env_compile_times.json"


def record_path() -> Path:
    """Where the measured compiles are kept: ``NUMBA_CACHE_DIR``, or the model's ``__pycache__``."""
    folder = numba.config.CACHE_DIR or str(Path(__file__).resolve().parent / "__pycache__")
    return Path(folder) / RECORD_FILE


def read_records() -> dict[str, list[float]]:
    """The measured compiles (none where the file is missing or unreadable)."""
    try:
        records = json.loads(record_path().read_text())
    except (OSError, ValueError):
        return {}
    return records if isinstance(records, dict) else {}


def estimate(first: str) -> tuple[str, int]:
    """How long a compile that begins with ``first`` takes (words) and how many functions it compiles:
    as measured on this machine where it was, else :data:`REFERENCE` with the load now."""
    measured = read_records().get(first)
    if isinstance(measured, list) and len(measured) == 2:
        return f"about {measured[0]:.0f} s (as the last compile here)", int(measured[1])
    (low, high), functions = REFERENCE.get(first, DEFAULT_REFERENCE)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    span = f"{low:.0f}" if low == high else f"{low:.0f} to {high:.0f}"
    return f"about {span} s (2 idle cores; load {os.getloadavg()[0]:.1f} on {cores})", functions


class CompileNotice(event.Listener):
    """Prints the line before the process's first compile and the progress while it compiles; records
    the compile's time at exit."""

    def __init__(self) -> None:
        self.depth = 0
        self.first: str | None = None
        self.expected = 0
        self.functions = 0
        self.seconds = 0.0
        self.started = 0.0
        self.last_line = 0.0

    def on_start(self, event: event.Event) -> None:
        self.depth += 1
        if self.depth > 1:
            return
        self.started = time.perf_counter()
        if self.first is None:
            self.first = _function_name(event.data)
            duration, self.expected = estimate(self.first)
            self.last_line = self.started
            _say(f"compiling the ship model for this machine, once: {duration}")
            atexit.register(self.record)

    def on_end(self, event: event.Event) -> None:
        self.depth -= 1
        self.functions += 1
        now = time.perf_counter()
        if self.depth == 0:
            self.seconds += now - self.started
        if now - self.last_line >= PROGRESS_EVERY_S:
            self.last_line = now
            elapsed = self.seconds + (now - self.started if self.depth else 0.0)
            of = f" of about {self.expected}" if self.functions < self.expected else ""
            _say(f"compiled {self.functions}{of} functions in {elapsed:.0f} s")

    def record(self) -> None:
        """Keep this process's compile time for the next estimate (nothing where the folder is not ours)."""
        if self.first is None or self.functions == 0:
            return
        records = read_records()
        records[self.first] = [round(self.seconds, 1), self.functions]
        try:
            record_path().parent.mkdir(parents=True, exist_ok=True)
            record_path().write_text(json.dumps(records, indent=1) + "\n")
        except OSError:
            pass


def _function_name(data: Any) -> str:
    dispatcher = data.get("dispatcher") if isinstance(data, dict) else None
    function = getattr(dispatcher, "py_func", None)
    return str(getattr(function, "__qualname__", "unknown"))


def _say(line: str) -> None:
    """A line on stderr, from the main process only (a worker started, or forked, by another stays quiet)."""
    if multiprocessing.parent_process() is None:
        print(f"ship_env: {line}", file=sys.stderr, flush=True)


def install() -> None:
    """Listen for compiles in this process."""
    event.register("numba:compile", CompileNotice())
