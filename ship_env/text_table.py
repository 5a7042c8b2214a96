"""A table of text cells, rendered as aligned text for the terminal or as Markdown for reports.

A command builds each table once as a header and rows of strings (:class:`Table`), then renders
it; the workbench's tables (:mod:`ship_env.workbench.reporting.tables`), the leaderboard's
(:mod:`ship_env.leaderboard.rendering`) and the on-line estimators' bench
(:mod:`ship_env.baselines.online_estimators.bench`) print theirs this way. The text fits a terminal
of :data:`WIDTH` columns: a table wider than that wraps its header's words onto more lines, and then
prints its last column (a description) under each row, wrapped.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

#: The terminal width the text of a table fits.
WIDTH = 100
#: How far a row's last cell is indented where it is printed under its row.
NOTE_INDENT = 4


@dataclass(frozen=True)
class Table:
    """A header and rows of cells, each column left-aligned (words) or right-aligned (numbers).

    Attributes:
        header: the columns' names.
        rows: the cells, one tuple per row.
        words: without ``numbers``, the text's first ``words`` columns are left-aligned, the others right-aligned.
        numbers: per column, whether it holds numbers (right-aligned in the text and in Markdown); ``None``:
            in the text all but the first ``words``, in Markdown those whose cells all read as numbers.
    """

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    words: int = 1
    numbers: tuple[bool, ...] | None = None

    def text(self, width: int = WIDTH) -> str:
        """Aligned columns under a rule, within ``width`` columns where the cells allow: a wider table
        wraps its header's words, then prints its last cell under each row, wrapped and indented (the
        last column's name on a header line of its own)."""
        header, rows = list(self.header), [list(row) for row in self.rows]
        numbers = self.numbers if self.numbers is not None else tuple(i >= self.words for i in range(len(header)))
        for wrap_header in (False, True):
            lines = _aligned(header, rows, numbers, wrap_header)
            if max(map(len, lines)) <= width or len(header) < 2 or not rows:
                return "\n".join(lines)
        lines = _aligned(header[:-1], [row[:-1] for row in rows], numbers[:-1], wrap_header=True)
        names, rule, row_lines = lines[: -len(rows) - 1], lines[-len(rows) - 1], lines[-len(rows) :]
        indent = " " * NOTE_INDENT
        out = [*names, f"{indent}{header[-1]} (under each row)", rule]
        for line, row in zip(row_lines, rows, strict=True):
            out += [line, *textwrap.wrap(row[-1], width, initial_indent=indent, subsequent_indent=indent)]
        return "\n".join(out)

    def markdown(self) -> str:
        """A Markdown table: columns of numbers right-aligned, columns of words left-aligned (``|`` in a
        cell escaped)."""

        def line(cells: Sequence[str]) -> str:
            return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"

        def numeric(column: int) -> bool:
            if self.numbers is not None:
                return self.numbers[column]
            cells = [row[column].rstrip("%") for row in self.rows if row[column] not in ("", "-")]
            return bool(cells) and all(_is_number(cell) for cell in cells)

        rule = "|" + "|".join("---:" if numeric(i) else "---" for i in range(len(self.header))) + "|"
        return "\n".join([line(self.header), rule, *(line(row) for row in self.rows)])


def _aligned(header: list[str], rows: list[list[str]], numbers: Sequence[bool], wrap_header: bool) -> list[str]:
    """The header's lines, the rule and a line per row, each column as wide as its widest cell (and,
    with ``wrap_header``, its header wrapped at spaces to that width, or to its longest word), the
    columns of ``numbers`` right-aligned."""
    columns = range(len(header))
    cells = [max((len(row[i]) for row in rows), default=0) for i in columns]
    if wrap_header:
        widths = [max(cells[i], *(len(word) for word in header[i].split() or [""])) for i in columns]
        wrapped = [textwrap.wrap(header[i], widths[i]) or [""] for i in columns]
    else:
        widths = [max(cells[i], len(header[i])) for i in columns]
        wrapped = [[header[i]] for i in columns]
    depth = max(map(len, wrapped))
    header_lines = [[""] * (depth - len(lines)) + lines for lines in wrapped]  # names sit on the rule

    def line(row: Sequence[str]) -> str:
        return "  ".join(
            cell.rjust(widths[i]) if numbers[i] else cell.ljust(widths[i]) for i, cell in enumerate(row)
        ).rstrip()

    rule = "  ".join("-" * w for w in widths).rstrip()
    return [*(line([lines[k] for lines in header_lines]) for k in range(depth)), rule, *(line(row) for row in rows)]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
