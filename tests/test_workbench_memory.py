"""The workbench's worker processes keep the memory a fit frees (``ship_env.workbench.fitting.memory``).

A fit allocates and frees arrays of many sizes thousands of times; under glibc's default thresholds each freed
block goes back to the system and is page-faulted in again at the next allocation. Measured in fresh processes (the
policy is process-wide): the same allocations as a worker process makes them, and as a process left alone.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from ship_env.workbench.fitting.memory import SETTINGS

#: Allocations of a fit's kind: 400 arrays of 128 kB to 16 MB, four alive at a time; prints the malloc thresholds
#: the process set ("not called" where it never asked), then the page faults taken.
ALLOCATIONS = """
import resource, sys
import numpy as np
from ship_env.workbench.fitting.memory import keep_freed_memory
from ship_env.workbench.fitting.parallel import _single_threaded
import ship_env.workbench.fitting.fit
if sys.argv[1] == "worker":
    _single_threaded()
print(",".join(keep_freed_memory()) if keep_freed_memory.cache_info().currsize else "not called")
sizes = np.random.default_rng(0).integers(2**14, 2**21, 400)
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for k in range(0, 400, 4):
    arrays = [np.ones(n) for n in sizes[k : k + 4]]
    del arrays
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def _allocate(kind: str) -> tuple[str, int]:
    """What a fresh process of ``kind`` ("worker" or "alone") printed of its thresholds, and the page faults it
    took."""
    done = subprocess.run(
        [sys.executable, "-c", ALLOCATIONS, kind], capture_output=True, text=True, check=True, timeout=120
    )
    thresholds, faults = done.stdout.splitlines()[-2:]
    return thresholds, int(faults)


def test_a_worker_process_reuses_freed_blocks_instead_of_faulting_them_in_again():
    thresholds, worker = _allocate("worker")
    assert thresholds != "not called"  # a worker's start sets the policy
    if not thresholds:
        pytest.skip("no glibc malloc here: the policy does nothing")
    assert set(thresholds.split(",")) == set(SETTINGS)
    untouched, alone = _allocate("alone")
    assert untouched == "not called"
    # Alone, most arrays are faulted in page by page (400 arrays of 8 MB on average, 2048 pages each); a worker
    # faults in only what its heap has never held.
    assert alone > 40_000
    assert worker < alone / 10
