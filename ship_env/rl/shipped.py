"""The trained policies that ship with the package: ``ship_env/policies/<Env-vN>/<algo>/``.

Each folder is a training run's output (``model.zip`` and ``metadata.json``, whose ``command``
reproduces it); the leaderboard sails them beside the classic baselines.
"""

from __future__ import annotations

from pathlib import Path

from ship_env.rl.metadata import MODEL_FILE

#: Where the shipped policies live inside the package.
POLICIES_DIR = Path(__file__).resolve().parents[1] / "policies"


def shipped_folder(env_id: str, algo: str) -> Path:
    """The folder of the shipped ``algo`` policy for ``env_id``.

    The namespace is dropped: ``ship_env/CourseChange-v0`` -> ``CourseChange-v0``.
    """
    return POLICIES_DIR / env_id.rsplit("/", 1)[-1] / algo


def shipped_policies() -> list[Path]:
    """The ``model.zip`` of every shipped policy, sorted."""
    return sorted(POLICIES_DIR.glob(f"*/*/{MODEL_FILE}"))
