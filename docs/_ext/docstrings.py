"""The docstrings' plain-text conventions, made reStructuredText before autodoc parses them.

- The environments document themselves as Gymnasium's do: Markdown sections (``## Action Space``)
  and pipe tables, readable in ``help()``. Each ``## Title`` becomes a rubric and each pipe table
  a ``list-table``.
- ``|x|`` is an absolute value (``|r*|``, ``|d delta|``), not a substitution: a ``|`` inside a line
  and outside inline literals and roles is escaped. A line that starts with ``|`` keeps its meaning.
"""

from __future__ import annotations

import re
from typing import Any

from sphinx.application import Sphinx


def _cells(line: str) -> list[str]:
    return [cell.strip() for cell in line.strip().strip("|").split("|")]


def _is_rule(line: str) -> bool:
    return set(line.strip()) <= set("|-: ") and "-" in line


def _list_table(rows: list[str], indent: str) -> list[str]:
    header, body = _cells(rows[0]), [_cells(row) for row in rows[2:]]
    lines = [f"{indent}.. list-table::", f"{indent}   :header-rows: 1", ""]
    for cells in (header, *body):
        lines += [f"{indent}   * - {cells[0]}", *(f"{indent}     - {cell}" for cell in cells[1:])]
    return [*lines, ""]


def markdown_sections_to_rst(lines: list[str]) -> list[str]:
    """``## Title`` -> ``.. rubric:: Title``; a pipe table (header, rule, rows) -> a list-table."""
    converted: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        indent = line[: len(line) - len(line.lstrip())]
        if line.lstrip().startswith("## "):
            converted += [f"{indent}.. rubric:: {line.lstrip()[3:].strip()}", ""]
            i += 1
        elif line.lstrip().startswith("|") and i + 1 < len(lines) and _is_rule(lines[i + 1]):
            end = i + 2
            while end < len(lines) and lines[end].lstrip().startswith("|"):
                end += 1
            converted += _list_table([row.strip() for row in lines[i:end]], indent)
            i = end
        else:
            converted.append(line)
            i += 1
    return converted


#: Inline literals and interpreted text (roles), whose ``|`` are left as they are.
CODE_SPANS = re.compile(r"(``.+?``|`[^`]+`)")


def escape_absolute_values(line: str) -> str:
    """``line`` with each ``|`` after its first character escaped, outside code spans and roles."""
    stripped = line.lstrip()
    indent, lead, rest = line[: len(line) - len(stripped)], stripped[:1], stripped[1:]
    parts = CODE_SPANS.split(rest)
    return indent + lead + "".join(part if i % 2 else part.replace("|", r"\|") for i, part in enumerate(parts))


def _process(app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    if any(line.lstrip().startswith("## ") for line in lines):
        lines[:] = markdown_sections_to_rst(lines)
    lines[:] = [escape_absolute_values(line) for line in lines]


def setup(app: Sphinx) -> dict[str, object]:
    app.connect("autodoc-process-docstring", _process)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
