"""The README's set-up commands are the ones CI runs and the getting-started page shows, and its links
into the documentation lead to pages that exist."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def setup_commands(path: Path, heading: str) -> list[str]:
    """The shell blocks of the section under ``heading`` in the markdown file at ``path``."""
    section = path.read_text().split(heading, 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```(?:bash|sh)\n(.+?)\n```", section, flags=re.S)


def test_readme_has_exactly_two_setup_commands_and_ci_runs_them_verbatim():
    commands = setup_commands(ROOT / "README.md", "## Set-up")
    assert len(commands) == 2, commands
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    for command in commands:
        assert command in ci_lines, f"{command!r} is not in .ci/run"
    assert "torch==2.13.0" in commands[0]


def test_the_getting_started_page_shows_the_readmes_setup_commands():
    page = setup_commands(ROOT / "docs" / "getting_started.md", "## Install and run the main job")
    assert page == setup_commands(ROOT / "README.md", "## Set-up")


def test_the_readmes_links_and_pictures_lead_to_files_in_the_repository():
    targets = re.findall(r"\]\(((?!https?://)[^)#]+)\)", (ROOT / "README.md").read_text())
    assert len(targets) >= 10, targets  # the pictures and the documentation's topics
    missing = [target for target in targets if not (ROOT / target).exists()]
    assert not missing, f"README links to files that do not exist: {missing}"
