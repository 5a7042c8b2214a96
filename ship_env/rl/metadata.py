"""What a training run records beside its model: ``metadata.json``.

A run's folder holds ``model.zip`` (stable-baselines3's file) and ``metadata.json``: the
environment id and keyword arguments trained on, the agent config entry, the seed, the steps,
the wall time, the versions of the packages that made it and the command that reproduces it.
The leaderboard reads the environment id from it to know which suite a policy sails.
"""

from __future__ import annotations

import json
import platform
from dataclasses import MISSING, asdict, dataclass, fields
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ship_env

if TYPE_CHECKING:
    from ship_env.rl.agents import AgentConfig

#: The file names of a run's folder.
MODEL_FILE = "model.zip"
METADATA_FILE = "metadata.json"

#: The distributions whose installed versions a run records beside ship-env's.
RECORDED_PACKAGES = ("stable-baselines3", "torch", "numpy", "gymnasium", "numba")


def package_versions() -> dict[str, str]:
    """Python's version, ship-env's (``ship_env.__version__``: the code that ran, installed or not)
    and the installed versions of :data:`RECORDED_PACKAGES`."""
    versions = {"python": platform.python_version(), "ship-env": ship_env.__version__}
    for package in RECORDED_PACKAGES:
        try:
            versions[package] = version(package)
        except PackageNotFoundError:
            versions[package] = "not installed"
    return versions


def machine_description() -> dict[str, str]:
    """The machine a run trains on: its architecture, CPU model and the instruction set torch's CPU
    kernels use (``AVX512``, ``AVX2``, ...). The same command gives the same weights only on the same
    kind of machine: the CPU's instruction set changes the rounding of the linear algebra."""
    import torch

    cpu = platform.processor()
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            cpu = next((line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith("model name")), cpu)
    except OSError:
        pass
    return {
        "architecture": platform.machine(),
        "cpu": cpu,
        "torch_cpu_capability": str(torch.backends.cpu.get_cpu_capability()),
    }


@dataclass(frozen=True)
class PolicyMetadata:
    """A training run as ``metadata.json`` records it.

    Attributes:
        env_id: the Gymnasium id trained on.
        env_kwargs: the environment's keyword arguments (``ship``: the ship trained on, when not
            the environments' default; the leaderboard names a policy sailing another ship by it).
        algo: the algorithm's name (``ppo``, ``sac``).
        config: the agent config entry used (:meth:`~ship_env.rl.agents.AgentConfig.entry`).
        config_file: where the entry was read from.
        seed: the run's seed.
        steps: the environment steps asked for.
        timesteps: the environment steps taken (a whole number of rollouts, so at least ``steps``).
        wall_time_s: the training's wall-clock time, s.
        torch_threads: torch's intra-op threads during training.
        versions: package versions (:func:`package_versions`).
        command: the ``ship-env train`` command line that reproduces the run.
        trained_agent: for a run that continued a saved agent (``--trained-agent``), that agent's
            ``model.zip`` path, its SHA-256 and the command that trained it; ``None`` for a run
            from new weights.
        machine: the machine trained on (:func:`machine_description`); ``None`` in runs recorded
            before it was.
    """

    env_id: str
    env_kwargs: dict[str, Any]
    algo: str
    config: dict[str, Any]
    config_file: str
    seed: int
    steps: int
    timesteps: int
    wall_time_s: float
    torch_threads: int
    versions: dict[str, str]
    command: str
    trained_agent: dict[str, Any] | None = None
    machine: dict[str, str] | None = None

    @classmethod
    def of_run(
        cls,
        config: AgentConfig,
        *,
        seed: int,
        steps: int,
        timesteps: int,
        wall_time_s: float,
        torch_threads: int,
        command: str,
        trained_agent: dict[str, Any] | None = None,
    ) -> PolicyMetadata:
        """The metadata of a run of ``config``: its environment, algorithm and entry, with the
        packages installed now (:func:`package_versions`) and the run's own figures."""
        return cls(
            env_id=config.env_id,
            env_kwargs=dict(config.env_kwargs),
            algo=config.algo,
            config=dict(config.entry),
            config_file=str(config.source),
            seed=seed,
            steps=steps,
            timesteps=timesteps,
            wall_time_s=round(wall_time_s, 3),
            torch_threads=torch_threads,
            versions=package_versions(),
            command=command,
            trained_agent=trained_agent,
            machine=machine_description(),
        )

    def write(self, folder: Path) -> Path:
        """Write ``folder/metadata.json``; returns its path."""
        path = Path(folder) / METADATA_FILE
        path.write_text(json.dumps(asdict(self), indent=2) + "\n")
        return path

    @classmethod
    def read(cls, path: Path) -> PolicyMetadata:
        """Read a ``metadata.json``; ``ValueError`` naming the file if it is not one."""
        try:
            document = json.loads(Path(path).read_text())
        except (OSError, json.JSONDecodeError) as error:
            raise ValueError(f"{path}: cannot read the policy's metadata: {error}") from None
        names = [item.name for item in fields(cls)]
        required = [item.name for item in fields(cls) if item.default is MISSING]
        missing = [name for name in required if name not in document] if isinstance(document, dict) else required
        if missing:
            raise ValueError(f"{path}: not a training run's metadata, missing {', '.join(missing)}")
        return cls(**{name: document[name] for name in names if name in document})
