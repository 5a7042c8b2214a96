"""A table of text cells, rendered as aligned text for the terminal or as Markdown for reports.

A command builds each table once as a header and rows of strings (:class:`Table`), then renders
it; the workbench's tables (:mod:`ship_env.workbench.tables`) and the on-line estimators' bench
(:mod:`ship_env.baselines.online_estimators.bench`) print theirs this way.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class Table:
    """A header and rows of cells; the first ``words`` columns are left-aligned, the others right-aligned."""

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    words: int = 1

    def text(self) -> str:
        widths = [max(len(row[i]) for row in (self.header, *self.rows)) for i in range(len(self.header))]

        def line(cells: Sequence[str]) -> str:
            return "  ".join(
                cell.ljust(width) if i < self.words else cell.rjust(width)
                for i, (cell, width) in enumerate(zip(cells, widths, strict=True))
            ).rstrip()

        rule = "  ".join("-" * width for width in widths).rstrip()
        return "\n".join([line(self.header), rule, *(line(row) for row in self.rows)])

    def markdown(self) -> str:
        """A Markdown table: columns of numbers right-aligned, columns of words left-aligned."""

        def line(cells: Sequence[str]) -> str:
            return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"

        def numeric(column: int) -> bool:
            cells = [row[column].rstrip("%") for row in self.rows if row[column] not in ("", "-")]
            return bool(cells) and all(_is_number(cell) for cell in cells)

        rule = "|" + "|".join("---:" if numeric(i) else "---" for i in range(len(self.header))) + "|"
        return "\n".join([line(self.header), rule, *(line(row) for row in self.rows)])


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
