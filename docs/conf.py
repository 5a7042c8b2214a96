"""Sphinx configuration: the API pages are built from the docstrings, the walk-throughs include the
README's sections (one text for both), the effects table is generated from the declarations."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "docs" / "_ext")]

import ship_env  # noqa: E402  (after the path set-up above)

project = "ship_env"
release = version = ship_env.__version__
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "myst_parser", "effect_table", "docstrings", "command_help"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build"]
html_theme = "alabaster"

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": True}
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True  # "Attributes:" as fields, not a second entry beside autodoc's members

# The included README sections start at "##": their anchors are not cross-referenced.
myst_heading_anchors = 0
suppress_warnings = ["myst.header"]
