"""Where the package finds its YAML configs (ships, scenarios, agents)."""

from __future__ import annotations

from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


def config_dir() -> Path:
    """The ``configs`` folder inside the package (the repository's top-level ``configs`` links to it)."""
    return _PACKAGE_DIR / "configs"
