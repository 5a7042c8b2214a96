"""Where the package finds its YAML configs (ships, scenarios, agents)."""

from __future__ import annotations

from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


def config_dir() -> Path:
    """The ``configs`` folder: inside the installed package, or at the repository's top level."""
    for candidate in (_PACKAGE_DIR / "configs", _PACKAGE_DIR.parent / "configs"):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"no configs folder found beside {_PACKAGE_DIR}")
