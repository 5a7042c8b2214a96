"""Where the workbench writes: never over a user's file, never into a folder it did not write.

A JSON file is written only where no file is; a folder for plots or a report only where none is,
where an empty one is, or where the workbench wrote before (it leaves a marker file,
``.ship-env-output``, in every folder it writes). ``force`` writes anyway.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: The file the workbench leaves in every folder it writes into.
MARKER = ".ship-env-output"


class OutputError(ValueError):
    """A place the workbench will not write to (a user's file, or a folder it did not write)."""


def claim_file(path: Path, force: bool = False, option: str = "--json") -> Path:
    """Check that ``path`` may be written: its folder exists and no file is there (unless ``force``)."""
    if not path.parent.is_dir():
        raise OutputError(f"{option}: folder {str(path.parent)!r} does not exist")
    if path.is_dir():
        raise OutputError(f"{option}: {str(path)!r} is a folder; name a file")
    if path.exists() and not force:
        raise OutputError(f"{option}: {str(path)!r} exists; choose another name or pass --force to overwrite it")
    return path


def claim_folder(path: Path, force: bool = False, option: str = "--plot") -> Path:
    """Create ``path`` (or accept an empty folder, or one the workbench wrote) and mark it as ours."""
    if path.exists() and not path.is_dir():
        raise OutputError(f"{option}: {str(path)!r} is a file; name a folder")
    if path.is_dir() and any(path.iterdir()) and not (path / MARKER).is_file() and not force:
        raise OutputError(
            f"{option}: folder {str(path)!r} holds files the workbench did not write; "
            f"choose another folder or pass --force to write into it"
        )
    try:
        path.mkdir(parents=True, exist_ok=True)
        (path / MARKER).write_text("written by ship-env's measurement workbench\n")
    except OSError as error:
        raise OutputError(f"{option}: cannot write into {str(path)!r}: {error.strerror}") from None
    return path


def save_drawing(drawing: Figure, path: Path, dpi: int) -> Path:
    """Lay the drawing out tightly and write it to ``path`` as PNG (its folder created where missing).

    The layout is fixed before saving (no layout engine left on the drawing), so that saving draws
    the drawing once, not twice.
    """
    drawing.tight_layout()
    drawing.set_layout_engine(None)
    path.parent.mkdir(parents=True, exist_ok=True)
    drawing.savefig(path, dpi=dpi)
    return path


__all__ = ["MARKER", "OutputError", "claim_file", "claim_folder", "save_drawing"]
