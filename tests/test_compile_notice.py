"""The line a cold compile starts with: printed before numba compiles, never where its cache holds the
code, and with the time the last compile took on this machine once one was measured."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

#: Two cached kernels, one calling the other: a cold cache compiles both, a warm one loads them.
KERNELS = """
from ship_env.model.kernel import kernel


@kernel
def square(x):
    return x * x


@kernel
def sum_of_squares(x, y):
    return square(x) + square(y)
"""

#: Compiles the kernels (a progress line after each function) and prints their result on stdout.
RUN = """
import sys
from ship_env.model import compile_notice
compile_notice.PROGRESS_EVERY_S = 0.0
sys.path.insert(0, sys.argv[1])
from kernels import sum_of_squares
print("result", sum_of_squares(3.0, 4.0), file=sys.stderr)
"""


def _run(folder: Path, cache: Path) -> list[str]:
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    environment.pop("NUMBA_DISABLE_JIT", None)
    done = subprocess.run(
        [sys.executable, "-c", RUN, str(folder)], env=environment, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return [line for line in done.stderr.splitlines() if line.startswith(("ship_env:", "result"))]


def test_a_cold_compile_is_announced_before_it_starts_and_a_warm_cache_says_nothing(tmp_path):
    (tmp_path / "kernels.py").write_text(KERNELS)
    cache = tmp_path / "cache"
    cold = _run(tmp_path, cache)
    assert cold[0].startswith("ship_env: compiling the ship model for this machine, once: about ")
    assert "s (2 idle cores; load " in cold[0]
    # square is compiled inside sum_of_squares's compile; a progress line after each (every 0 s here)
    assert [re.sub(r"in \d+ s$", "in T s", line) for line in cold[1:]] == [
        "ship_env: compiled 1 of about 70 functions in T s",
        "ship_env: compiled 2 of about 70 functions in T s",
        "result 25.0",
    ]
    (first, (seconds, functions)), *_ = json.loads((cache / "ship_env_compile_times.json").read_text()).items()
    assert (first, functions) == ("sum_of_squares", 2) and seconds > 0.0

    assert _run(tmp_path, cache) == ["result 25.0"]  # loaded from the cache: no compile, no line


def test_the_next_cold_compile_is_estimated_from_the_one_measured_here(tmp_path):
    (tmp_path / "kernels.py").write_text(KERNELS)
    cache = tmp_path / "cache"
    cache.mkdir()
    (cache / "ship_env_compile_times.json").write_text(json.dumps({"sum_of_squares": [42.0, 2]}))
    lines = _run(tmp_path, cache)
    assert (
        lines[0]
        == "ship_env: compiling the ship model for this machine, once: " + "about 42 s (as the last compile here)"
    )
