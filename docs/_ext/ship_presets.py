"""The ``ship-presets`` directive: every ship preset in ``configs/ships`` with its description, read from its
YAML at build time, so the page says what the presets say."""

from __future__ import annotations

import yaml
from docutils import nodes
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective


class ShipPresets(SphinxDirective):
    """``.. ship-presets::`` (no arguments): a definition list, preset name -> its ``description``."""

    def run(self) -> list[nodes.Node]:
        from ship_env.model.ship import list_ships
        from ship_env.paths import config_dir

        entries = nodes.definition_list()
        for name in list_ships():
            path = config_dir() / "ships" / f"{name}.yaml"
            self.env.note_dependency(str(path))
            description = " ".join(str(yaml.safe_load(path.read_text()).get("description", "")).split())
            term = nodes.term()
            term += nodes.literal(text=name)
            definition = nodes.definition()
            definition += self.parse_text_to_nodes(description)
            entries += nodes.definition_list_item("", term, definition)
        return [entries]


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("ship-presets", ShipPresets)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
