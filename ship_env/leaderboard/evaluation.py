"""Running the leaderboard's jobs in this process or on Ray.

A :class:`Job` is one entrant sailing one suite (:func:`~ship_env.leaderboard.sailing.sail_suite`),
a learned entrant with one of its training seeds.
The backends run the jobs and return their episodes in job order, whatever order they finish in,
so both give the same table to the last digit:

- ``local`` (the default): one job after another, in this process;
- ``ray``: one Ray task per job (:func:`run_on_ray`; the optional extra ``ray``). It joins the Ray
  session already open in this process, or the cluster at an address, or starts a local one
  (:func:`ship_env.ray_cluster.ray_session`). Policy files must be readable by the workers at
  the same path.

Learned entrants run torch with one intra-op thread (the fastest for one observation at a time).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from tqdm import tqdm

from ship_env.leaderboard.suites import Suite

if TYPE_CHECKING:  # the entrants and the episode loop bring torch and the baselines: imported when run
    from ship_env.leaderboard.entrants import Entrant
    from ship_env.leaderboard.sailing import EpisodeResult

#: ``--backend`` names.
BACKENDS = ("local", "ray")


@dataclass(frozen=True)
class Job:
    """One entrant sailing one suite (a learned entrant with its ``run``-th training seed)."""

    entrant: Entrant
    suite: Suite
    run: int = 0


def jobs_for(suites: Sequence[Suite], entrants: Sequence[Entrant]) -> list[Job]:
    """Every entrant (each of its training seeds) on every suite of its environment, suite by suite."""
    return [
        Job(entrant, suite, run)
        for suite in suites
        for entrant in entrants
        if entrant.env_id == suite.env_id
        for run in range(entrant.runs)
    ]


def run_job(job: Job, on_episode: Callable[[], object] | None = None) -> list[EpisodeResult]:
    """Sail one job (in this process or a worker's)."""
    from ship_env.leaderboard.sailing import sail_suite

    if job.entrant.kind == "learned":
        import torch

        from ship_env.rl.agents import evaluation_torch_threads

        torch.set_num_threads(evaluation_torch_threads())  # one, unless OMP_NUM_THREADS says otherwise
    return sail_suite(job.entrant, job.suite, job.run, on_episode)


def run_locally(jobs: Sequence[Job], advance: Callable[[int], object]) -> list[list[EpisodeResult]]:
    """Run the jobs one after another in this process; ``advance(n)`` after each episode."""
    return [run_job(job, lambda: advance(1)) for job in jobs]


def run_on_ray(
    jobs: Sequence[Job], advance: Callable[[int], object], address: str | None = None
) -> list[list[EpisodeResult]]:
    """Run each job as a Ray task (on the cluster at ``address``, default: this process's Ray session
    or a local one); ``advance(n)`` with a job's episodes as it finishes."""
    from ship_env.ray_cluster import run_as_tasks

    return run_as_tasks(
        run_job, [(job,) for job in jobs], lambda index, _: advance(len(jobs[index].suite.episodes)), address
    )


def evaluate(
    jobs: Sequence[Job], backend: str = "local", progress: bool = True, ray_address: str | None = None
) -> list[EpisodeResult]:
    """Run ``jobs`` on ``backend`` (Ray: at ``ray_address``) with a progress bar over episodes; their
    episodes in job order."""
    if backend not in BACKENDS:
        raise ValueError(f"backend: expected one of {', '.join(BACKENDS)}, got {backend!r}")
    total = sum(len(job.suite.episodes) for job in jobs)
    with tqdm(total=total, desc="leaderboard", unit="episode", file=sys.stderr, disable=not progress) as bar:
        if backend == "local":
            per_job = run_locally(jobs, bar.update)
        else:
            per_job = run_on_ray(jobs, bar.update, ray_address)
    return [result for results in per_job for result in results]
