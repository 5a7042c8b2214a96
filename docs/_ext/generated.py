"""Where the documentation's generated files go, and when they are out of date.

The figures drawn at build time (episodes, the workbench's drawings) are written under ``docs/_generated``
(not in the repository) with a stamp: a hash of the package's source and presets and of what was asked.
A build whose stamp matches reuses them; a fresh clone, or any change to the code, draws them again,
so they show what this version of the code does.
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
GENERATED = DOCS / "_generated"
STAMP_FILE = "stamp.txt"


@cache
def source_hash() -> str:
    """SHA-256 over the package's Python files and YAML presets (paths and contents, in sorted order)."""
    digest = hashlib.sha256()
    package = ROOT / "ship_env"
    for path in sorted([*package.rglob("*.py"), *package.rglob("*.yaml")]):
        digest.update(str(path.relative_to(package)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def stamp(request: object) -> str:
    """The stamp of ``request`` (anything JSON can write) drawn by this version of the code."""
    return hashlib.sha256(json.dumps([source_hash(), request], sort_keys=True).encode()).hexdigest()


def is_current(folder: Path, request: object) -> bool:
    """Whether ``folder`` holds what ``request`` draws with this version of the code."""
    path = folder / STAMP_FILE
    return path.exists() and path.read_text().strip() == stamp(request)


def mark_current(folder: Path, request: object) -> None:
    """Record that ``folder`` now holds what ``request`` draws with this version of the code."""
    (folder / STAMP_FILE).write_text(stamp(request) + "\n")
