"""The results pages state what the commands wrote: the dev-suite figures on docs/results/leaderboard.md
are those of the tables ``ship-env leaderboard --suite quick --out docs/results/leaderboard`` wrote, and
the shipped Esso Osaka policy's those of its test board in docs/results/leaderboard_esso_osaka."""

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
    estimates = table_estimates(dev_suite)
    assert len(estimates) >= 20, estimates  # the seas' table, the 12 suites' and the tracks'
    missing = [estimate for estimate in estimates if estimate not in written]
    assert not missing, f"the results page states figures the quick leaderboard did not write: {missing}"


def table_estimates(text: str) -> list[str]:
    """The estimates with intervals in ``text``'s table rows."""
    return ESTIMATE.findall("\n".join(line for line in text.splitlines() if line.lstrip().startswith("|")))


def test_the_esso_osaka_shipped_policys_figures_are_those_its_test_board_wrote():
    """The tables of the shipped Esso Osaka policy (README's and docs/results/esso_osaka.md's) state
    figures that ``ship-env leaderboard --ship esso_osaka_model --suite test --no-tracks`` wrote into
    docs/results/leaderboard_esso_osaka."""
    written = (RESULTS / "leaderboard_esso_osaka" / "leaderboard.md").read_text()
    page = (RESULTS / "esso_osaka.md").read_text()
    shipped = page.split("## The shipped policy", 1)[1].split("\n### ", 1)[0]
    readme = (RESULTS.parents[1] / "README.md").read_text()
    on_the_ship = readme.split("## From logs to a ship", 1)[1].split("\n## ", 1)[0]
    estimates = table_estimates(shipped) + table_estimates(on_the_ship)
    assert len(estimates) >= 16, estimates  # the page's ten suites, the README's six figures
    missing = [estimate for estimate in estimates if estimate not in written]
    assert not missing, f"figures the Esso Osaka test board did not write: {missing}"
