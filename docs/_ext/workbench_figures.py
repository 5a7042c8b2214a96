"""The workbench's walk-through, run at build time on simulated logs so the page shows what the commands do.

At ``builder-inited`` the commands of :data:`STEPS` run one after another in ``docs/_generated/workbench``
(``ship-env demo-logs``, then ``compare --plot``, ``diagnose --plot`` and ``improve --report`` on its logs),
each one's printout kept in ``<step>.txt``; they run again when the code changes (:mod:`generated`).

- ``workbench-step STEP``: the step's command line and what it printed.
- The drawings are plain files under ``/_generated/workbench/`` that a page shows with ``{figure}``, and
  the improve report is ``/_generated/workbench/report/report.md``, which a page includes.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
import time

from docutils import nodes
from generated import GENERATED, ROOT, is_current, mark_current
from sphinx.application import Sphinx
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

FOLDER = GENERATED / "workbench"
#: The walk-through: each step's name and the ``ship-env`` arguments it runs with, in order.
STEPS: dict[str, tuple[str, ...]] = {
    "demo-logs": ("demo-logs", "demo", "--hidden", "propeller_slipstream,rudder_offset"),
    "compare": ("compare", "demo/zigzag", "--plot", "plots/"),
    "diagnose": ("diagnose", "demo/zigzag", "--plot", "signals.png"),
    "improve": ("improve", "demo/zigzag", "--validate-on", "demo/turning", "--report", "report/"),
}

logger = logging.getLogger(__name__)


def command_line(step: str) -> str:
    """The step as a reader types it."""
    return shlex.join(("ship-env", *STEPS[step]))


def run_steps(app: Sphinx) -> None:
    """Run the walk-through's commands where their outputs are missing or older than the code."""
    if is_current(FOLDER, STEPS):
        return
    if FOLDER.exists():
        for path in sorted(FOLDER.rglob("*"), reverse=True):  # the workbench does not overwrite: start empty
            path.rmdir() if path.is_dir() else path.unlink()
    FOLDER.mkdir(parents=True, exist_ok=True)
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    for step, arguments in STEPS.items():
        start = time.perf_counter()
        result = subprocess.run(
            [sys.executable, "-m", "ship_env.cli", *arguments],
            cwd=FOLDER,
            env=environment,
            capture_output=True,
            text=True,
        )
        if result.returncode != 0:
            raise RuntimeError(f"{command_line(step)} failed ({result.returncode}):\n{result.stderr}")
        (FOLDER / f"{step}.txt").write_text(result.stdout)
        logger.info(f"workbench walk-through: {command_line(step)} ({time.perf_counter() - start:.0f} s)")
    mark_current(FOLDER, STEPS)


class WorkbenchStep(SphinxDirective):
    """``.. workbench-step:: STEP``: ``$ ship-env ...`` and the printout, as a console block."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        step = self.arguments[0]
        if step not in STEPS:
            raise self.error(f"workbench-step: unknown step {step!r}; expected one of {', '.join(STEPS)}")
        printout = (FOLDER / f"{step}.txt").read_text().rstrip()
        block = nodes.literal_block(text=f"$ {command_line(step)}\n{printout}", language="text")
        return [block]


def setup(app: Sphinx) -> dict[str, object]:
    app.connect("builder-inited", run_steps)
    app.add_directive("workbench-step", WorkbenchStep)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
