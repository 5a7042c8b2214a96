"""The workbench's memory policy: the C heap keeps what a fit frees, for its next fit.

A fit allocates and frees the same large arrays (replays, residuals, Jacobians) thousands of times. glibc's
``malloc`` gives each block above its mmap threshold (128 kB, raised as such blocks are freed) straight back to the
system and trims the heap's top beyond 128 kB, so every allocation after it is page-faulted in afresh: ``ship-env
improve`` on the Esso Osaka zig-zags took 2.7 million page faults, 7.5 s of system time against 96 s of user time.
With the thresholds raised (:func:`keep_freed_memory`) in the worker processes the heap reuses the blocks: 0.34
million faults, 1.7-1.8 s, and the same results bit for bit (``docs/results/benchmarks.md``). It is called only where
the workbench owns the process, its worker processes (:mod:`.parallel`), never in the user's; without glibc's
``malloc`` (macOS, Windows, musl) it does nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools

#: ``mallopt``'s parameters (glibc's malloc.h) and the values set: blocks up to its largest mmap threshold (32 MB on
#: 64-bit) come from the heap, whose top is trimmed only beyond 256 MB, grown 16 MB at a time.
SETTINGS = {
    "M_TRIM_THRESHOLD": (-1, 256 * 2**20),
    "M_TOP_PAD": (-2, 16 * 2**20),
    "M_MMAP_THRESHOLD": (-3, 32 * 2**20),
}


@functools.cache
def keep_freed_memory() -> tuple[str, ...]:
    """Raise this process's glibc malloc thresholds (:data:`SETTINGS`), once; the names of those set (none without
    glibc)."""
    name = ctypes.util.find_library("c")
    try:
        library = ctypes.CDLL(name)
        mallopt = library.mallopt
        library.gnu_get_libc_version  # noqa: B018  (glibc's alone)
    except (OSError, AttributeError, TypeError):
        return ()
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    return tuple(key for key, (parameter, value) in SETTINGS.items() if mallopt(parameter, value) == 1)
