"""report.html opened in a real browser: Debian's Chromium, driven by
Playwright (scripts/test-python.sh installs both when missing; a missing
browser fails these tests, never skips them).

The page is the one a job writes (through ``rigfit.fit`` and through the
CLI), rebuilt by ``rigfit report`` and written by ``FitResult.report``. In the
browser: no console error, no request leaves the file, every figure drawn and
non-empty, the mouse wheel and the zoom buttons change the visible time
range, and screenshots of the first screen and of the parameter table are
taken (into ``$RIGFIT_SCREENSHOTS`` when set: the docs' pictures are made so).
"""

import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

import rigfit

from conftest import CAMPAIGNS, ROOT, cli_binary

sys.path.insert(0, str(ROOT / "scripts"))
from report_screenshots import CHROMIUM, CHROMIUM_ARGS, screenshots  # noqa: E402


@pytest.fixture(scope="module")
def tensile(tmp_path_factory):
    """The shipped tensile campaign, with a short search on the CPU."""
    folder = tmp_path_factory.mktemp("tensile")
    raw = json.loads((CAMPAIGNS / "aa2024_t3_synthetic.json").read_text())
    raw["search"].update({"population": 256, "generations": 12, "seed": 5})
    raw["solver"]["backend"] = "cpu"
    raw["output"] = "results"
    for x in raw["experiments"]:
        shutil.copy(CAMPAIGNS / x["data"]["file"], folder / x["data"]["file"])
    path = folder / "tensile.json"
    path.write_text(json.dumps(raw, indent=1))
    return path


@pytest.fixture(scope="module")
def job(tensile, tmp_path_factory):
    """A folder `rigfit run` wrote, with its report.html."""
    out = tmp_path_factory.mktemp("job") / "out"
    r = subprocess.run([cli_binary(), "--quiet", "run", str(tensile), "--out", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (out / "report.html").is_file()
    return out


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright
    assert os.path.isfile(CHROMIUM), (
        f"no Chromium at {CHROMIUM}: scripts/test-python.sh installs Debian's `chromium`")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


class Opened:
    """A page opened from a file, with everything it asked for and said."""

    def __init__(self, browser, path):
        self.url = pathlib.Path(path).resolve().as_uri()
        self.page = browser.new_page(viewport={"width": 1280, "height": 900})
        self.requests, self.console, self.errors = [], [], []
        self.page.on("console", lambda m: self.console.append((m.type, m.text)))
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))

        def route(r):
            self.requests.append(r.request.url)
            if r.request.url == self.url:
                r.continue_()
            else:
                r.abort()
        self.page.route("**/*", route)
        self.page.goto(self.url)
        self.page.wait_for_load_state("load")

    def range_of(self, figure):
        return (float(figure.get_attribute("data-t0")), float(figure.get_attribute("data-t1")))


def test_the_report_opens_offline_without_errors_and_draws_every_figure(job, browser):
    o = Opened(browser, job / "report.html")
    p = o.page
    assert o.errors == [], o.errors
    assert [c for c in o.console if c[0] in ("error", "warning")] == [], o.console
    # Nothing but the file itself was asked for.
    assert o.requests == [o.url], o.requests
    for section in ("verdict", "summary", "profiles", "validation"):
        assert p.locator(f"#{section}").count() == 1, section
    figures = p.locator("figure")
    assert figures.count() >= 4
    for i in range(figures.count()):
        f = figures.nth(i)
        svg = f.locator("svg")
        assert svg.count() >= 1, f"figure {i} has no svg"
        box = svg.first.bounding_box()
        assert box and box["width"] > 100 and box["height"] > 50, (i, box)
        marks = f.locator("svg path, svg polyline, svg rect, svg line, svg circle")
        assert marks.count() > 0, f"figure {i} is empty"
        assert f.locator("figcaption").count() == 1, f"figure {i} has no caption"
        assert svg.first.get_attribute("aria-label"), f"figure {i} has no aria-label"
    # The drawn lines hold data: some polyline or path has many points.
    longest = p.evaluate("""() => Math.max(0, ...[...document.querySelectorAll(
        'figure svg polyline, figure svg path')].map(e => (e.getAttribute('points')
        || e.getAttribute('d') || '').length))""")
    assert longest > 1000, longest
    # The parameter table: one row per free parameter, the fitted values.
    summary = json.loads((job / "result.json").read_text())
    free = [x for x in summary["parameters"] if x["free"]]
    table = p.locator("table#parameters")
    assert table.count() == 1
    text = table.inner_text()
    for x in free:
        assert x["name"] in text, x["name"]
    assert table.locator("tbody tr").count() == len(free)


def test_zoom_changes_the_visible_time_range(job, browser):
    o = Opened(browser, job / "report.html")
    p = o.page
    figs = p.locator("figure[data-t0][data-t1]")
    assert figs.count() >= 2
    fig = figs.first
    t0, t1 = o.range_of(fig)
    assert t1 > t0
    # The wheel over the plot zooms in about the pointer.
    svg = fig.locator("svg").first
    svg.scroll_into_view_if_needed()
    box = svg.bounding_box()
    p.mouse.move(box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.5)
    p.mouse.wheel(0, -600)
    p.wait_for_timeout(200)
    z0, z1 = o.range_of(fig)
    assert (z1 - z0) < 0.8 * (t1 - t0), ((t0, t1), (z0, z1))
    assert t0 <= z0 < z1 <= t1
    # Dragging pans: the width stays, the range moves.
    p.mouse.move(box["x"] + box["width"] * 0.6, box["y"] + box["height"] * 0.5)
    p.mouse.down()
    p.mouse.move(box["x"] + box["width"] * 0.4, box["y"] + box["height"] * 0.5, steps=5)
    p.mouse.up()
    p.wait_for_timeout(100)
    m0, m1 = o.range_of(fig)
    assert abs((m1 - m0) - (z1 - z0)) <= 1e-9 * (t1 - t0) + 1e-12
    assert m0 != z0
    # The buttons, for the keyboard: reset gives the whole record back.
    fig.locator("button[data-zoom=reset]").click()
    assert o.range_of(fig) == (t0, t1)
    fig.locator("button[data-zoom=in]").click()
    i0, i1 = o.range_of(fig)
    assert (i1 - i0) < (t1 - t0)
    assert o.errors == [], o.errors


def test_screenshots_of_the_first_screen_and_the_parameter_table(job, browser, tmp_path):
    where = pathlib.Path(os.environ.get("RIGFIT_SCREENSHOTS", tmp_path))
    for shot in screenshots(job / "report.html", where, browser):
        # A PNG with something on it (a blank page compresses to a few KB).
        data = shot.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert len(data) > 20_000, (shot, len(data))


def test_the_report_prints_to_a4(job, browser, tmp_path):
    o = Opened(browser, job / "report.html")
    pdf = tmp_path / "report.pdf"
    o.page.pdf(path=str(pdf), format="A4")
    data = pdf.read_bytes()
    assert data[:5] == b"%PDF-"
    # Buttons are for the screen only.
    o.page.emulate_media(media="print")
    assert o.page.locator("button[data-zoom]").first.is_visible() is False


def test_python_writes_the_same_report_as_the_cli(tensile, job, tmp_path):
    r = rigfit.load_result(job)
    assert r.files["report.html"] == (job / "report.html").read_bytes()
    path = r.report(tmp_path / "mine.html")
    assert pathlib.Path(path).read_bytes() == (job / "report.html").read_bytes()
    # Never over a file it did not write, nor through a planted link.
    foreign = tmp_path / "notes.html"
    foreign.write_text("my notes")
    with pytest.raises(FileExistsError):
        r.report(foreign)
    with pytest.raises(FileExistsError):
        r.report(foreign, overwrite=True)
    assert foreign.read_text() == "my notes"
    link = tmp_path / "link.html"
    link.symlink_to(foreign)
    with pytest.raises(FileExistsError):
        r.report(link, overwrite=True)
    assert foreign.read_text() == "my notes"
    # A report it wrote may be replaced when asked.
    r.report(tmp_path / "mine.html", overwrite=True)
    # Jupyter's view: the verdict and the parameter table.
    view = r._repr_html_()
    assert "<table" in view and "verdict" in view.lower()
