"""The documentation's pages read as written: the command-line page shows help as text that reads the same on
every machine, no sentence turns into a numbered list, and the API index lists every documented module
with its summary."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path
from types import ModuleType

import pytest
from docutils import nodes

from ship_env.workbench import cli as workbench_cli

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: A line that CommonMark reads as the start of an ordered list, even in the middle of a paragraph.
LIST_START = re.compile(r"^\s*1[.)](\s|$)")
#: A line that is itself an item of a list, or a table row, a heading, a directive's option or a quote.
BLOCK_LINE = re.compile(r"^\s*([-*+>|#:]|\d+[.)](\s|$))")


def extension(name: str) -> ModuleType:
    """The documentation's extension docs/_ext/``name``.py."""
    spec = importlib.util.spec_from_file_location(name, DOCS / "_ext" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def markdown_pages() -> list[Path]:
    """The README and the documentation's Markdown pages, with what they include (not the build's)."""
    pages = [ROOT / "README.md", *DOCS.rglob("*.md")]
    return [page for page in pages if not {"_build", "_generated"} & set(page.relative_to(ROOT).parts)]


def lists_begun_mid_paragraph(text: str) -> list[str]:
    """The lines of ``text`` (outside code fences) that go on a paragraph but begin ``1.`` or ``1)``, which
    ends the paragraph and starts a numbered list there."""
    found, fenced, previous = [], False, ""
    for line in text.splitlines():
        if line.lstrip().startswith(("```", "~~~")):
            fenced, previous = not fenced, ""
            continue
        if fenced:
            continue
        if LIST_START.match(line) and previous.strip() and not BLOCK_LINE.match(previous):
            found.append(line)
        previous = line
    return found


def test_a_one_at_the_start_of_a_line_is_caught():
    assert lists_begun_mid_paragraph("the fixed PD under\n1) and settles") == ["1) and settles"]
    assert lists_begun_mid_paragraph("Steps:\n\n1. first\n2. second") == []
    assert lists_begun_mid_paragraph("```\nunder\n1) in code\n```") == []


@pytest.mark.parametrize("page", markdown_pages(), ids=lambda page: str(page.relative_to(ROOT)))
def test_no_sentence_turns_into_a_numbered_list(page):
    assert lists_begun_mid_paragraph(page.read_text()) == []


def test_the_command_line_page_shows_help_as_text_the_same_on_every_machine(monkeypatch):
    command_help = extension("command_help")
    monkeypatch.setenv("COLUMNS", command_help.COLUMNS)  # restored after the test: the directive sets it
    pages = []
    for cores in (2, 16):
        monkeypatch.setattr(workbench_cli, "usable_cores", lambda cores=cores: cores)
        sections = command_help.help_sections()
        blocks = [block for section in sections for block in section.findall(nodes.literal_block)]
        assert len(blocks) > 10  # ship-env's and each subcommand's
        assert {block["language"] for block in blocks} == {"text"}
        pages.append([block.astext() for block in blocks])
    assert pages[0] == pages[1]


def test_the_api_index_lists_every_documented_module_with_its_summary():
    api_index = extension("api_index")
    directive = (DOCS / "api" / "index.md").read_text().split(".. api-index::")[1].split("```")[0]
    pages = [line.strip() for line in directive.splitlines() if line.strip()]
    assert sorted(pages) == sorted(page.stem for page in (DOCS / "api").glob("*.md") if page.stem != "index")
    source = api_index.index_source(pages)
    for page in pages:
        title, modules = api_index.documented_modules(page)
        assert modules, page
        assert f":doc:`{title} <{page}>`" in source
        for module in modules:
            assert f":py:mod:`{module}`" in source
            assert api_index.summary(module).endswith("."), f"{module}'s docstring has no first sentence"


def test_a_summary_ends_at_the_first_full_stop_outside_parentheses(monkeypatch):
    api_index = extension("api_index")
    module = ModuleType("probe")
    module.__doc__ = "The instruments (thesis 5.3, Fig. 5.2, ch. 5). More.\n\nDetails."
    monkeypatch.setitem(sys.modules, "probe", module)
    assert api_index.summary("probe") == "The instruments (thesis 5.3, Fig. 5.2, ch. 5)."
