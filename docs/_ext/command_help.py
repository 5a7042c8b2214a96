"""The ``command-help`` directive: ``ship-env``'s help and each subcommand's, as the parser prints them.

Built from :func:`ship_env.command_line.build_parser` at build time, so the page cannot drift from the options.
"""

from __future__ import annotations

import argparse
import os

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

#: The width argparse wraps the help to: what the page column shows of a text block without scrolling.
COLUMNS = "90"


def help_sections() -> list[nodes.Node]:
    """``ship-env --help`` as a text block, then a section per subcommand with its ``--help``, wrapped at
    :data:`COLUMNS` (shown as plain text: help is not code to highlight)."""
    from ship_env.command_line import build_parser

    os.environ["COLUMNS"] = COLUMNS
    parser = build_parser()
    (subcommands,) = (action for action in parser._actions if isinstance(action, argparse._SubParsersAction))
    sections: list[nodes.Node] = [nodes.literal_block(text=parser.format_help(), language="text")]
    for name, command in subcommands.choices.items():
        section = nodes.section(ids=[nodes.make_id(f"ship-env {name}")])
        section += nodes.title(text=f"ship-env {name}")
        section += nodes.literal_block(text=command.format_help(), language="text")
        sections.append(section)
    return sections


class CommandHelp(SphinxDirective):
    """``.. command-help::`` (no arguments): a section per subcommand with its ``--help``."""

    def run(self) -> list[nodes.Node]:
        return help_sections()


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("command-help", CommandHelp)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
