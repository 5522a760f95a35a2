#!/usr/bin/env python3
"""Screenshots of a report.html in headless Chromium: the first screen
(report-first-screen.png) and the parameter table (report-parameters.png).

    python3 scripts/report_screenshots.py results/aa2024-t3-synthetic/report.html docs/guide/

Needs Debian's Chromium (/usr/bin/chromium, or $RIGFIT_CHROMIUM) and the
`playwright` package (pip); scripts/test-python.sh installs both. The docs'
pictures are made with it from the shipped example, and the browser tests
(python/tests/test_report_in_browser.py) run it.
"""

import os
import pathlib
import sys

from playwright.sync_api import sync_playwright

CHROMIUM = os.environ.get("RIGFIT_CHROMIUM", "/usr/bin/chromium")
# No background requests of Chromium's own: the machine may have no network.
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run",
                 "--disable-quic"]


def screenshots(report, folder, browser=None):
    """Writes the two screenshots of ``report`` into ``folder`` and returns
    their paths; in ``browser`` (a Playwright browser) when given, else in
    a Chromium of its own."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    first, table = folder / "report-first-screen.png", folder / "report-parameters.png"
    if browser is None:
        with sync_playwright() as p:
            own = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            try:
                return screenshots(report, folder, own)
            finally:
                own.close()
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto(pathlib.Path(report).resolve().as_uri())
    page.wait_for_load_state("load")
    page.screenshot(path=str(first))
    page.locator("table#parameters").screenshot(path=str(table))
    page.close()
    return first, table


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    for path in screenshots(sys.argv[1], sys.argv[2]):
        print(path)
