"""Screenshots of the built documentation in headless Chromium: the landing page, an environment's page, the
workbench's walk-through, the leaderboard's and the workbench's results and the command line, to look at the
pages as a reader's browser draws them (a table wider than the page shows its scroll bar).

Run after building the documentation (``sphinx-build -W --keep-going -b html docs docs/_build``)::

    python docs/screenshots.py [--build docs/_build] [--out docs/_build/screenshots] [--browser chromium]

Needs a Chromium or Chrome binary (Debian: ``apt-get install chromium``); each page is drawn at 1280 pixels
wide and as tall as ``--height``, after its images have loaded.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
#: The pages shot, by the file name of their screenshot.
PAGES = {
    "landing.png": "index.html",
    "environment_course_change.png": "environments/course_change.html",
    "workbench.png": "workbench.html",
    "results_leaderboard.png": "results/leaderboard.html",
    "results_workbench.png": "results/workbench.html",
    "command_line.png": "command_line.html",
}
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "chrome")


def find_browser(name: str | None) -> str:
    """The browser binary: ``name``, or the first of BROWSERS on the path."""
    for candidate in (name,) if name else BROWSERS:
        path = shutil.which(candidate)
        if path:
            return path
    raise SystemExit(f"no browser found (tried {', '.join((name,) if name else BROWSERS)}); install chromium")


def shoot(browser: str, page: Path, picture: Path, height: int) -> None:
    """Draw ``page`` in headless ``browser`` into ``picture`` (PNG), 1280 pixels wide and ``height`` tall."""
    command = [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
        f"--window-size=1280,{height}",
        "--virtual-time-budget=5000",
        f"--screenshot={picture}",
        page.resolve().as_uri(),
    ]
    subprocess.run(command, check=True, capture_output=True, timeout=120)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("--build", type=Path, default=DOCS / "_build", help="the built HTML (default: docs/_build)")
    parser.add_argument("--out", type=Path, default=None, help="folder for the PNGs (default: BUILD/screenshots)")
    parser.add_argument("--browser", default=None, help=f"browser binary (default: the first of {', '.join(BROWSERS)})")
    parser.add_argument("--height", type=int, default=1800, help="page height drawn, pixels (default: 1800)")
    args = parser.parse_args(argv)
    out = args.out or args.build / "screenshots"
    out.mkdir(parents=True, exist_ok=True)
    browser = find_browser(args.browser)
    for name, page in PAGES.items():
        source = args.build / page
        if not source.exists():
            raise SystemExit(f"{source} does not exist: build the documentation first")
        shoot(browser, source, out / name, args.height)
        print(f"{source} -> {out / name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
