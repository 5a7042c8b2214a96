"""The ``api-index`` directive: every module the API pages document, page by page, each with the first
sentence of its docstring (a table linking to the module's entry on its page).

The modules are read from the pages' ``automodule`` directives, so the index lists what the pages document
and cannot drift from them.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

#: The folder of the API pages.
API = Path(__file__).resolve().parents[1] / "api"
AUTOMODULE = re.compile(r"^\.\. automodule:: (\S+)", re.MULTILINE)
TITLE = re.compile(r"^# (.+)$", re.MULTILINE)
#: A full stop followed by a space or the end: where a sentence may end.
FULL_STOP = re.compile(r"\.(\s|$)")


def summary(module: str) -> str:
    """The first sentence of ``module``'s docstring: up to the first full stop outside parentheses, so that
    "(thesis ch. 5)" or "Fig. 5.2" inside them does not end it."""
    docstring = importlib.import_module(module).__doc__ or ""
    paragraph = " ".join(docstring.strip().split("\n\n")[0].split())
    for stop in FULL_STOP.finditer(paragraph):
        head = paragraph[: stop.start() + 1]
        if head.count("(") == head.count(")"):
            return head
    return paragraph


def documented_modules(page: str) -> tuple[str, list[str]]:
    """The title of the API page ``page`` (its name in docs/api, without ``.md``) and the modules it
    documents, in its order."""
    text = (API / f"{page}.md").read_text()
    title = TITLE.search(text)
    if title is None:
        raise ValueError(f"docs/api/{page}.md has no '# ' title")
    return title.group(1), AUTOMODULE.findall(text)


def index_source(pages: list[str]) -> str:
    """The reStructuredText of the index: per page a heading that links to it and a table of its modules
    with their summaries, and the pages' (hidden) table of contents."""
    parts = [".. toctree::\n   :hidden:\n\n" + "".join(f"   {page}\n" for page in pages) + "\n"]
    for page in pages:
        title, modules = documented_modules(page)
        parts.append(f".. rubric:: :doc:`{title} <{page}>`\n\n.. list-table::\n   :widths: 2 3\n\n")
        parts.append("".join(f"   * - :py:mod:`{module}`\n     - {summary(module)}\n" for module in modules) + "\n")
    return "".join(parts)


class ApiIndex(SphinxDirective):
    """``.. api-index::`` with the API pages' names as content, one a line: the index, and the pages in the
    table of contents in that order. Its content is parsed as reStructuredText: in a Markdown page, write it
    in an ``eval-rst`` block."""

    has_content = True

    def run(self) -> list[nodes.Node]:
        for page in self.content:
            self.env.note_dependency(str(API / f"{page.strip()}.md"))
        return self.parse_text_to_nodes(index_source([page.strip() for page in self.content if page.strip()]))


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("api-index", ApiIndex)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
