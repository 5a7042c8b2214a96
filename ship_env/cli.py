"""``python -m ship_env.cli``: the ``ship-env`` command (:func:`~ship_env.command_line.main`), which
parses the command line and dispatches to the chosen subcommand.

Each subcommand is declared as a :class:`~ship_env.command_line.Command` beside its code and listed
in :data:`~ship_env.command_line.SUBCOMMANDS`: ``manoeuvre`` in :mod:`ship_env.manoeuvres.cli`; the
workbench's ``fit``, ``compare``, ``diagnose`` and ``improve`` in :mod:`ship_env.workbench.cli_fit`
and its siblings, with what they share in :mod:`ship_env.workbench.cli`; ``demo-logs``, ``scale``,
``train``, ``leaderboard`` and ``identify-bench`` in their packages. Only the chosen subcommand's
module is imported before the command line is parsed. Invalid arguments end with a message naming
the argument and exit status 2, as argparse's own errors do; a simulation that leaves the model's
validity, or a log that cannot be used, ends with status 1.
"""

from __future__ import annotations

import sys

from ship_env.command_line import main  # ship-env itself, for the callers that import it from here

__all__ = ["main"]

if __name__ == "__main__":
    sys.exit(main())
