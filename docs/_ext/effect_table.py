"""The model's effects in the documentation, generated at build time so it cannot drift from the code.

- ``effect-table``: every registered effect (:data:`ship_env.model.effects.EFFECTS`) gives a row:
  its name, what it models, the thesis equations, its parameters (unit, meaning, range) and
  whether a model needs it.
- ``effect-modules``: the API of each built-in effect's module
  (:data:`ship_env.model.effects.LIBRARY`), in the order they register; it writes reStructuredText, so a
  Markdown page calls it inside ``eval-rst``.
"""

from __future__ import annotations

import math

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

from ship_env.model.declarations import Effect, Parameter

HEADER = ("effect", "what it models", "thesis", "parameters")
WIDTHS = (16, 30, 14, 40)


def _range(parameter: Parameter) -> str:
    """The valid range as "; [a, b]", "; >= a", "; <= b", or nothing when unbounded."""
    low, high = parameter.minimum, parameter.maximum
    if math.isinf(low) and math.isinf(high):
        return ""
    if math.isinf(high):
        return f"; >= {low:g}"
    if math.isinf(low):
        return f"; <= {high:g}"
    return f"; [{low:g}, {high:g}]"


def _parameter_item(parameter: Parameter) -> nodes.list_item:
    line = nodes.paragraph()
    line += nodes.literal(text=parameter.name)
    line += nodes.Text(f" ({parameter.unit}{_range(parameter)}): {parameter.description}")
    return nodes.list_item("", line)


def _cell(*content: nodes.Node) -> nodes.entry:
    return nodes.entry("", *content)


def _row(effect: Effect) -> nodes.row:
    name = nodes.paragraph()
    name += nodes.literal(text=effect.name)
    if effect.required:
        name += nodes.Text(" (required)")
    parameters = nodes.bullet_list("", *(_parameter_item(p) for p in effect.parameters))
    return nodes.row(
        "",
        _cell(name),
        _cell(nodes.paragraph(text=effect.title)),
        _cell(nodes.paragraph(text=effect.equations)),
        _cell(parameters if effect.parameters else nodes.paragraph(text="none")),
    )


class EffectTable(SphinxDirective):
    """``.. effect-table::`` (no arguments): one row per registered effect, in the model's order."""

    def run(self) -> list[nodes.Node]:
        from ship_env.model.effects import EFFECTS

        group = nodes.tgroup(cols=len(HEADER))
        group += [nodes.colspec(colwidth=width) for width in WIDTHS]
        head = nodes.row("", *(_cell(nodes.paragraph(text=title)) for title in HEADER))
        group += nodes.thead("", head)
        group += nodes.tbody("", *(_row(effect) for effect in EFFECTS.values()))
        return [nodes.table("", group, classes=["effect-table"])]


class EffectModules(SphinxDirective):
    """``.. effect-modules::`` (no arguments): ``automodule`` of each built-in effect's module."""

    def run(self) -> list[nodes.Node]:
        from ship_env.model.effects import LIBRARY

        return self.parse_text_to_nodes("\n".join(f".. automodule:: {module.__name__}" for module in LIBRARY))


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("effect-table", EffectTable)
    app.add_directive("effect-modules", EffectModules)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
