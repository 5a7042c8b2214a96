"""Torch's threads for sailing learned policies: one by default, the user's where OMP_NUM_THREADS sets them."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

torch = pytest.importorskip("torch")

from ship_env.leaderboard import evaluation  # noqa: E402  (after the skip: it needs torch to run a job)


@pytest.mark.parametrize(("variable", "threads"), [(None, 1), ("3", 3), ("", 1), ("many", 1), ("0", 1)])
def test_learned_policies_sail_on_one_torch_thread_unless_omp_num_threads_says(monkeypatch, variable, threads):
    if variable is None:
        monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    else:
        monkeypatch.setenv("OMP_NUM_THREADS", variable)
    seen = []
    monkeypatch.setattr(
        "ship_env.leaderboard.sailing.sail_suite", lambda *arguments: seen.append(torch.get_num_threads()) or []
    )
    before = torch.get_num_threads()
    torch.set_num_threads(2)
    try:
        job = SimpleNamespace(entrant=SimpleNamespace(kind="learned"), suite=None, run=0)
        assert evaluation.run_job(job) == []  # type: ignore[arg-type]
    finally:
        torch.set_num_threads(before)
    assert seen == [threads]
