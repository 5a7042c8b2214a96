"""The ``benchmark-report`` directive: a benchmark's results file, printed as the benchmark prints it.

``.. benchmark-report:: results/bench_simulator.json`` (relative to ``docs/``) reads the JSON that
``python benchmarks/bench_simulator.py --json FILE`` wrote and formats it with the benchmark's own
``format_report``, so the page shows the measured figures, the machine and its load, and the command.
"""

from __future__ import annotations

import importlib.util
import json

from docutils import nodes
from generated import DOCS, ROOT
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

BENCHMARK = ROOT / "benchmarks" / "bench_simulator.py"


def format_report(results: dict) -> str:
    """The benchmark's printout of ``results``."""
    spec = importlib.util.spec_from_file_location("bench_simulator", BENCHMARK)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.format_report(results, results["command"])


class BenchmarkReport(SphinxDirective):
    """``.. benchmark-report:: FILE``: the results in ``FILE`` as the benchmark printed them."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        path = DOCS / self.arguments[0]
        self.env.note_dependency(str(path))
        return [nodes.literal_block(text=format_report(json.loads(path.read_text())), language="text")]


def setup(app: Sphinx) -> dict[str, object]:
    app.add_directive("benchmark-report", BenchmarkReport)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
