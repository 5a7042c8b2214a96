"""The results pages state what the commands wrote: the dev-suite figures on docs/results/leaderboard.md
are those of the tables ``ship-env leaderboard --suite quick --out docs/results/leaderboard`` wrote."""

from __future__ import annotations

import re
from pathlib import Path

RESULTS = Path(__file__).resolve().parents[1] / "docs" / "results"
#: An estimate with its interval, as the leaderboard prints it: "0.956 [0.918, 0.976]".
ESTIMATE = re.compile(r"\d+\.\d+ \[\d+\.\d+, \d+\.\d+\]")


def test_the_dev_suite_tables_on_the_results_page_are_the_quick_leaderboards():
    page = (RESULTS / "leaderboard.md").read_text()
    written = (RESULTS / "leaderboard" / "leaderboard.md").read_text()
    dev_suite = page.split("## Dev suite", 1)[1].split("\n## ", 1)[0]
    table_rows = "\n".join(line for line in dev_suite.splitlines() if line.lstrip().startswith("|"))
    estimates = ESTIMATE.findall(table_rows)
    assert len(estimates) >= 20, estimates  # the seas' table, the 12 suites' and the tracks'
    missing = [estimate for estimate in estimates if estimate not in written]
    assert not missing, f"the results page states figures the quick leaderboard did not write: {missing}"
