"""What a process pays to compile the environments' batch loops: generated per task, or shared by a closure.

    python benchmarks/bench_env_loops.py

Every environment updates its ships in two compiled loops (serial, and on all cores) around its
task's per-ship kernel. Numba caches a compiled function by its source file and bytecode; a loop
shared by the three tasks that gets the per-ship kernel from a closure is not found in the cache
(the closure's contents differ in every process), so each process would compile it afresh. The
tasks' loops are therefore generated from one template into each task module
(:func:`ship_env.envs.batch.define_update_loops`) and cached like the module's own kernels.

Each measurement runs in a fresh interpreter (the cost is a process's), after one run that fills
the disk cache: the first call of each task's two loops (no ship to update: the call is the
compilation, or the cache's load), generated and closure, in s, and their ratio measured in the same
run (the judged figure). Prints the load average: other work inflates both times.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import time

ENV_IDS = ("ship_env/CourseChange-v0", "ship_env/CourseKeeping-v0", "ship_env/TrackFollow-v0")
WAYS = ("generated", "closure")


def closure_loops(update_ship):
    """The template's two loops (:data:`~ship_env.envs.batch.UPDATE_LOOPS_SOURCE`) around ``update_ship``,
    bound through a closure instead of the task module's globals."""
    from ship_env.envs.batch import UPDATE_LOOPS_SOURCE

    source = "def make(update_ship):\n" + textwrap.indent(UPDATE_LOOPS_SOURCE, "    ")
    source += "\n    return update_ships, update_ships_parallel\n"
    namespace: dict = {}
    exec(compile(source, __file__, "exec"), namespace)
    return namespace["make"](update_ship)


def child(way: str) -> dict[str, float]:
    """In this (fresh) process: the first call of every task's two loops, s."""
    import gymnasium as gym

    import ship_env  # noqa: F401  (registers the environments)

    times = {}
    for env_id in ENV_IDS:
        batch = gym.make(env_id).unwrapped.batch  # not reset: its loops not yet called
        simulator = batch.simulator
        arrays = (
            simulator.state,
            simulator.conditions,
            simulator.noise_keys,
            simulator.step_index,
            batch.episodes,
            batch.metrics,
            *batch.task.kernel_arguments,
        )
        if way == "generated":
            loops = (batch.update_serial, batch.update_parallel)
        else:
            loops = closure_loops(sys.modules[type(batch).__module__].update_ship)
        start = time.perf_counter()
        for loop in loops:
            loop(True, batch.task.model.record, *arrays)  # no ship restarted: nothing to update
        times[env_id] = time.perf_counter() - start
    return times


def first_calls(way: str) -> dict[str, float]:
    """:func:`child` in a fresh interpreter."""
    output = subprocess.run([sys.executable, __file__, "--child", way], capture_output=True, text=True)
    if output.returncode:
        raise RuntimeError(output.stderr)
    return json.loads(output.stdout.strip().splitlines()[-1])


def main() -> None:
    if sys.argv[1:2] == ["--child"]:
        print(json.dumps(child(sys.argv[2])))
        return
    first_calls("generated")  # fill the disk cache
    times = {way: first_calls(way) for way in WAYS}
    print(
        f"load average {os.getloadavg()[0]:.2f}; first call of a task's two loops in a fresh process, s "
        "(information), and closure / generated, measured in this run (the judged figure):"
    )
    rows = {env_id: {way: times[way][env_id] for way in WAYS} for env_id in ENV_IDS}
    rows["all three"] = {way: sum(times[way].values()) for way in WAYS}
    for name, seconds in rows.items():
        print(
            f"  {name:28s}"
            + "".join(f"  {way} {seconds[way]:6.3f}" for way in WAYS)
            + f"  closure / generated {seconds['closure'] / seconds['generated']:6.1f}x"
        )


if __name__ == "__main__":
    main()
