"""The trained policies that ship with the package: ``ship_env/policies/<Env-vN>/<algo>/``.

Each such folder is one leaderboard entrant: either one training run (``model.zip`` and
``metadata.json``, whose ``command`` reproduces it) or one run per training seed in
``seed<S>/`` sub-folders (as ``ship-env train --seeds`` writes them). The leaderboard sails them
beside the classic baselines.
"""

from __future__ import annotations

from pathlib import Path

from ship_env.rl.policy_file import seed_models

#: Where the shipped policies live inside the package.
POLICIES_DIR = Path(__file__).resolve().parents[1] / "policies"


def shipped_folder(env_id: str, algo: str) -> Path:
    """The shipped ``algo`` entrant's folder for ``env_id`` (``ship_env/CourseChange-v0`` -> ``CourseChange-v0``)."""
    return POLICIES_DIR / env_id.rsplit("/", 1)[-1] / algo


def shipped_entrants() -> list[Path]:
    """The folder of every shipped entrant (``<Env-vN>/<algo>``), sorted."""
    return sorted(folder for folder in POLICIES_DIR.glob("*/*") if seed_models(folder)[0].is_file())


def shipped_policies() -> list[Path]:
    """The ``model.zip`` of every shipped policy, every training seed, sorted."""
    return sorted(path for folder in shipped_entrants() for path in seed_models(folder))
