"""Sphinx configuration: the guides and results pages are pages of their own (docs/*.md, docs/results/),
the API reference is built from the docstrings (docs/api/), and what the code draws or prints is generated
at build time by the extensions in docs/_ext (the effects table, the ship presets, each command's help,
each environment's episode, the workbench's walk-through, the benchmark's report, the API index)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "docs" / "_ext")]

import ship_env  # noqa: E402  (after the path set-up above)

project = "ship_env"
release = version = ship_env.__version__
extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "myst_parser",
    "effect_table",
    "ship_presets",
    "docstrings",
    "command_help",
    "episodes",
    "workbench_figures",
    "benchmark_report",
    "api_index",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# _generated holds what the build draws; results/leaderboard* what `ship-env leaderboard` wrote (included, not pages).
exclude_patterns = ["_build", "_generated", "results/leaderboard", "results/leaderboard_esso_osaka"]

html_theme = "furo"
html_title = f"ship_env {release}"
html_theme_options = {"navigation_with_keys": True}
html_show_copyright = False
html_static_path = ["_static"]
html_css_files = ["tables.css"]  # wide tables scroll inside the page column

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": True}
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True  # "Attributes:" as fields, not a second entry beside autodoc's members

myst_heading_anchors = 3
