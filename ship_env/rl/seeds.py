"""Several training seeds of one agent config: one run folder per seed, trained one after another or as Ray tasks.

Each seed's run is the single-seed run ``ship-env train ... --seed S --out <folder>`` (its
``metadata.json`` records that command), a pure function of the config, the seed, the thread
count and the package versions: trained here or in a Ray worker, it gives the same weights, bit
for bit. A Ray task trains into a scratch folder of its worker and sends the files back, so the
workers need no shared disk.

Nothing already trained is overwritten unless asked (:func:`trained_already`).
"""

from __future__ import annotations

import dataclasses
import re
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ship_env.rl.agents import DEFAULT_TORCH_THREADS, AgentConfig
from ship_env.rl.metadata import METADATA_FILE, MODEL_FILE, PolicyMetadata

#: ``--backend`` names.
BACKENDS = ("local", "ray")
#: One item of a seed list: a seed (``3``) or an inclusive range (``0-4``).
_SEED_ITEM = re.compile(r"(\d+)(?:-(\d+))?")


def parse_seeds(text: str) -> tuple[int, ...]:
    """``"0-4"`` -> (0, 1, 2, 3, 4); ``"0,2,5"`` -> (0, 2, 5); ``"0-2,7"`` -> (0, 1, 2, 7).

    ``ValueError`` naming the text for anything else: a negative or non-numeric seed, a
    descending range, a seed listed twice.
    """
    seeds: list[int] = []
    for item in text.split(","):
        match = _SEED_ITEM.fullmatch(item.strip())
        if match is None:
            raise ValueError(f"expected seeds such as 0-4 or 0,2,5 (whole numbers >= 0), got {text!r}")
        first, last = int(match[1]), int(match[2] if match[2] is not None else match[1])
        if last < first:
            raise ValueError(
                f"expected an ascending seed range such as {last}-{first}, got {item.strip()!r} in {text!r}"
            )
        seeds += range(first, last + 1)
    repeated = sorted({seed for seed in seeds if seeds.count(seed) > 1})
    if repeated:
        raise ValueError(f"seed {repeated[0]} is listed twice in {text!r}")
    return tuple(seeds)


@dataclass(frozen=True)
class SeedRun:
    """One seed's run: where it goes, the command line that repeats it alone and the saved agent
    it continues (``None``: new weights; read where the seed trains)."""

    seed: int
    out: Path
    command: str
    trained_agent: Path | None = None


def trained_already(runs: Sequence[SeedRun]) -> list[Path]:
    """The runs' folders that already hold a model or its metadata."""
    return [run.out for run in runs if (run.out / MODEL_FILE).exists() or (run.out / METADATA_FILE).exists()]


def train_seed(
    config: AgentConfig,
    run: SeedRun,
    steps: int | None = None,
    torch_threads: int = DEFAULT_TORCH_THREADS,
    progress_bar: bool = False,
) -> PolicyMetadata:
    """Train one seed into ``run.out`` in this process; the metadata written."""
    from ship_env.rl.training import train

    return train(
        config,
        run.out,
        run.command,
        steps=steps,
        seed=run.seed,
        torch_threads=torch_threads,
        progress_bar=progress_bar,
        trained_agent=run.trained_agent,
    ).metadata


def _train_seed_files(
    config: AgentConfig, run: SeedRun, steps: int | None, torch_threads: int
) -> tuple[PolicyMetadata, dict[str, bytes]]:
    """Train one seed in a scratch folder (a Ray worker's); the metadata and every file written, by relative path."""
    with tempfile.TemporaryDirectory(prefix="ship_env_seed") as scratch:
        metadata = train_seed(config, dataclasses.replace(run, out=Path(scratch)), steps, torch_threads)
        files = {
            str(path.relative_to(scratch)): path.read_bytes() for path in Path(scratch).rglob("*") if path.is_file()
        }
    return metadata, files


def train_seeds(
    config: AgentConfig,
    runs: Sequence[SeedRun],
    steps: int | None = None,
    torch_threads: int = DEFAULT_TORCH_THREADS,
    backend: str = "local",
    ray_address: str | None = None,
    on_done: Callable[[SeedRun, PolicyMetadata], object] | None = None,
    progress_bar: bool = False,
) -> list[PolicyMetadata]:
    """Train every run, in ``runs``' order here (``local``) or as one Ray task each (``ray``: the Ray
    session of this process, or one at ``ray_address``, or a local one); their metadata in ``runs``'
    order. ``on_done(run, metadata)`` as each finishes. Does not check for earlier runs: see
    :func:`trained_already`."""
    if backend not in BACKENDS:
        raise ValueError(f"backend: expected one of {', '.join(BACKENDS)}, got {backend!r}")
    if backend == "local":
        trained = []
        for run in runs:
            trained.append(train_seed(config, run, steps, torch_threads, progress_bar))
            if on_done is not None:
                on_done(run, trained[-1])
        return trained
    from ship_env.ray_cluster import run_as_tasks

    def store(index: int, result: tuple[PolicyMetadata, dict[str, bytes]]) -> None:
        metadata, files = result
        for name, content in files.items():
            (runs[index].out / name).parent.mkdir(parents=True, exist_ok=True)
            (runs[index].out / name).write_bytes(content)
        if on_done is not None:
            on_done(runs[index], metadata)

    arguments = [(config, run, steps, torch_threads) for run in runs]
    finished = run_as_tasks(_train_seed_files, arguments, store, ray_address, num_cpus=torch_threads)
    return [metadata for metadata, _ in finished]
