"""The HTML report's backplot in headless Chromium (tests/browser.py, the DevTools protocol):
the page loads without console errors, the view draws (pixels of the tool colours in the
plot), hovering a move shows its source line and feed, and clicking a finding draws its move
in red and selects its line in the listing, and with a design the cut part is red where it
gouges. Lines, coordinates, feeds and deviations are checked against the program text and
closed forms. Skipped without Chromium (.ci/run installs Debian's); about 20 s idle (a
browser per module, WebGL in software)."""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from cli.formats.html_report import PLOTLY_FILE, plotly_js, render_html
from cli.programs import check_input
from cli.report_view import program_view, read_source
from kernel.check import CheckContext, check_stream
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE
from kernel.path.build import build_path

pytest.importorskip("tornado")  # the websocket client (Dask's distributed brings it)
pytest.importorskip("PIL")  # reading the screenshots

from tests.browser import Browser, find_browser  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
BRACKET = ROOT / "docs" / "examples" / "bracket.ngc"
RISKY = ROOT / "docs" / "examples" / "risky.ngc"
FANUC_TURN = ROOT / "tests" / "dialects" / "fanuc" / "114_turn_arcs_r_ik.nc"
READY = "document.querySelector('#cnc-plot .main-svg') !== null"
TOOL_BLUE = (31, 119, 180)  # the first tool's colour
RED = (228, 0, 43)  # the selected line's colour


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    exe = find_browser()
    if exe is None:
        pytest.skip("no Chromium on this machine")
    with Browser(exe) as b:
        yield b


def _page(program: Path, out: Path, library: str = "inline", dialect: str | None = None) -> Path:
    """The report page of ``program`` as ``cnc run --html`` makes it, without the servo
    stage (the findings are the real check's)."""
    ctx = CheckContext(DEFAULT_MACHINE)
    stream, text = check_input(str(program), dialect, -1, None, 1.0, DEFAULT_MACHINE)
    cmds: list[canon.Command] = []

    def recording(stream: Iterator[canon.Command]) -> Iterator[canon.Command]:
        for cmd in stream:  # the commands up to an error, as cnc run keeps them
            cmds.append(cmd)
            yield cmd

    findings = check_stream(recording(stream), ctx, str(program), text)
    path = build_path(cmds, DEFAULT_MACHINE, str(program))
    source = read_source(str(program))
    view, surface = program_view(cmds, path, ctx, str(program), dialect, source)
    doc = {
        "program": str(program),
        "machine": DEFAULT_MACHINE.name,
        "status": "ok",
        "findings": [f.to_dict() for f in findings],
        "diagnostics": [],
    }
    page = out / f"{program.stem}.report.html"
    page.write_text(render_html(doc, {}, view, source, surface, library))
    if library != "inline":
        (out / library).write_text(plotly_js())
    return page


def _rect(b: Browser, selector: str) -> list[float]:
    """``[left, top, right, bottom]`` of the first element matching ``selector``."""
    return list(
        b.eval(
            "(r => [r.left, r.top, r.right, r.bottom])"
            f"(document.querySelector({selector!r}).getBoundingClientRect())"
        )
    )


def _plot_pixels(b: Browser, colour: tuple[int, int, int], tol: int = 40) -> int:
    """Pixels of ``colour`` inside the plot, from a screenshot."""
    from PIL import Image

    rect = _rect(b, "#cnc-plot")
    img = np.asarray(Image.open(io.BytesIO(b.screenshot())).convert("RGB")).astype(int)
    x0, y0, x1, y1 = (int(v) for v in rect)
    crop = img[max(y0, 0) : y1, max(x0, 0) : x1]
    return int((np.abs(crop - np.asarray(colour)).sum(axis=2) < tol).sum())


def _modal_feed(lines: list[str], n: int) -> float:
    """The F word in force at line ``n`` (1-based), from the program text."""
    feed = 0.0
    for line in lines[:n]:
        m = re.search(r"F(\d+(?:\.\d*)?)", line)
        feed = float(m.group(1)) if m else feed
    return feed


@pytest.mark.slow
def test_the_view_draws_without_console_errors(browser: Browser, tmp_path: Path) -> None:
    page = _page(BRACKET, tmp_path)
    browser.errors.clear()
    browser.open(page.as_uri(), READY)
    browser.pump(1.0)
    assert browser.errors == []
    assert browser.eval("document.querySelectorAll('#cnc-plot canvas').length") > 0
    assert _plot_pixels(browser, TOOL_BLUE) > 500  # the first tool's moves are drawn
    # the listing shows the program's own lines, numbered
    first = browser.eval("document.querySelector('#cnc-rows .ln').textContent")
    assert first == "1" + BRACKET.read_text().splitlines()[0]


@pytest.mark.slow
def test_hovering_a_move_shows_its_line_and_feed(browser: Browser, tmp_path: Path) -> None:
    page = _page(BRACKET, tmp_path)
    browser.open(page.as_uri(), READY)
    x0, y0, x1, y1 = _rect(browser, "#cnc-plot")
    label = ""
    # sweep the mouse over the middle of the view until a move is under it
    for fy in np.linspace(0.3, 0.8, 11):
        for fx in np.linspace(0.15, 0.85, 15):
            browser.mouse("mouseMoved", x0 + fx * (x1 - x0), y0 + fy * (y1 - y0))
            label = browser.eval(
                "Array.from(document.querySelectorAll('#cnc-plot .hovertext'))"
                ".map(e => e.textContent).join('|')"
            )
            if label:
                break
        if label:
            break
    m = re.search(r"line (\d+) · (rapid|F([\d.]+))", label)
    assert m, label
    n = int(m.group(1))
    text = BRACKET.read_text().splitlines()
    assert re.search(r"[XYZ]", text[n - 1]), text[n - 1]  # a line that moves the tool
    if m.group(3):
        assert float(m.group(3)) == _modal_feed(text, n)
    # the listing follows the hover
    hov = browser.eval(
        "[...document.querySelectorAll('#cnc-rows .ln.hov')].map(e => e.dataset.line)"
    )
    assert hov == [str(n)]


def test_clicking_a_finding_draws_its_move(browser: Browser, tmp_path: Path) -> None:
    page = _page(RISKY, tmp_path)
    browser.errors.clear()
    browser.open(page.as_uri(), READY)
    text = RISKY.read_text().splitlines()
    n = text.index("G0 X1500") + 1  # CNC101: beyond the travel limit
    assert browser.eval(f"document.querySelector('tr[data-line=\"{n}\"]') !== null")
    before = _plot_pixels(browser, RED)
    browser.eval(f"document.querySelector('tr[data-line=\"{n}\"]').scrollIntoView()")
    left, top, right, bottom = _rect(browser, f'tr[data-line="{n}"]')
    browser.mouse("mousePressed", (left + right) / 2, (top + bottom) / 2)
    browser.mouse("mouseReleased", (left + right) / 2, (top + bottom) / 2)
    xs = browser.eval(
        "(d => d[d.length - 1].x.filter(v => v !== null))(document.getElementById('cnc-plot').data)"
    )
    assert xs[0] == pytest.approx(60.0) and xs[-1] == pytest.approx(1500.0)  # G1 X60, G0 X1500
    sel = browser.eval(
        "[...document.querySelectorAll('#cnc-rows .ln.sel')].map(e => e.textContent)"
    )
    assert sel == [f"{n}G0 X1500"]
    assert f"line {n}" in browser.eval("document.getElementById('cnc-selected').textContent")
    browser.eval("document.getElementById('cnc-plot').scrollIntoView()")
    browser.pump(0.5)
    assert _plot_pixels(browser, RED) > before + 50  # the move is drawn in red
    assert browser.errors == []


@pytest.mark.slow
def test_a_lathe_program_is_drawn_in_zx_from_the_batch_library(
    browser: Browser, tmp_path: Path
) -> None:
    page = _page(FANUC_TURN, tmp_path, PLOTLY_FILE, "fanuc_lathe")
    assert f'<script src="{PLOTLY_FILE}">' in page.read_text()
    browser.errors.clear()
    browser.open(page.as_uri(), READY)
    browser.pump(0.5)
    assert browser.errors == []
    axes = browser.eval(
        "(l => [l.xaxis.title.text, l.yaxis.title.text])"
        "(document.getElementById('cnc-plot')._fullLayout)"
    )
    assert axes == ["Z", "X (diameter)"]
    assert _plot_pixels(browser, TOOL_BLUE) > 200
    # "G01 X50." ends on diameter 50 at Z-20 (after "G02 X40. Z-20. I5. K0.")
    n = FANUC_TURN.read_text().splitlines().index("G01 X50.") + 1
    browser.eval(f"window.cncReport.select({n})")
    xy = browser.eval(
        "(t => [t.x.filter(v => v !== null), t.y.filter(v => v !== null)])"
        "((d => d[d.length - 1])(document.getElementById('cnc-plot').data))"
    )
    assert xy[0][-1] == pytest.approx(-20.0) and xy[1][-1] == pytest.approx(50.0)


def _red_mask(b: Browser) -> tuple[np.ndarray, list[float]]:
    """Pixels of the plot that are the gouge's red (strongly red, shaded by the lighting),
    and the plot's rectangle."""
    from PIL import Image

    rect = _rect(b, "#cnc-plot")
    img = np.asarray(Image.open(io.BytesIO(b.screenshot())).convert("RGB")).astype(int)
    x0, y0, x1, y1 = (int(v) for v in rect)
    crop = img[max(y0, 0) : y1, max(x0, 0) : x1]
    r, g, bl = crop[..., 0], crop[..., 1], crop[..., 2]
    red = (r > 120) & (r - g > 70) & (r - bl > 60)
    for part in (".colorbar", ".legend"):  # the scale's and the legend's red are not the part
        if b.eval(f"document.querySelector('#cnc-plot {part}') !== null"):
            left, top, right, bottom = (int(v) for v in _rect(b, f"#cnc-plot {part}"))
            red[max(top - y0, 0) : max(bottom - y0, 0), max(left - x0, 0) : max(right - x0, 0)] = 0
    return red, rect


@pytest.mark.slow
def test_the_cut_part_is_coloured_by_its_deviation_from_the_design(
    browser: Browser, tmp_path: Path
) -> None:
    """``cnc run --html --design``: a slot cut 1.5 mm below a flat design
    (tests/test_report_design.py) is red on the part, and hovering a red pixel names that
    deviation; the deviations zeroed, no red is left (the markers' red is too small to
    count)."""
    from tests.test_report_design import design_page

    def render(z: float) -> Path:
        out = tmp_path
        page = design_page(out, z)
        doc = {
            "program": str(page["program"]),
            "machine": "mill with stock",
            "status": "findings",
            "findings": [f.to_dict() for f in page["findings"]],
            "diagnostics": [],
        }
        html = out / "slot.report.html"
        html.write_text(render_html(doc, {}, page["view"], page["source"], page["surface"]))
        return html

    browser.errors.clear()
    browser.open(render(-1.0).as_uri(), READY)
    browser.pump(1.0)
    assert browser.errors == []
    assert browser.eval("document.getElementById('cnc-plot').data.some(t => t.surfacecolor)")
    red, rect = _red_mask(browser)
    assert red.sum() > 300  # the slot's floor and walls
    # hover the middle of the red region: the surface there is 1.5 mm below the design
    ys, xs = np.nonzero(red)
    label = ""
    for q in (0.5, 0.4, 0.6, 0.3, 0.7):  # along the red region, at its middle height
        k = np.argsort(xs)[int(q * (len(xs) - 1))]
        browser.mouse("mouseMoved", rect[0] + float(xs[k]), rect[1] + float(ys[k]))
        browser.pump(0.2)
        label = browser.eval(
            "Array.from(document.querySelectorAll('#cnc-plot .hovertext'))"
            ".map(e => e.textContent).join('|')"
        )
        if "deviation" in label:
            break
    assert "deviation -1.500 mm" in label, label
    # the red is the deviation's colour: with the deviations zeroed none is left
    browser.eval(
        "(gd => { const i = gd.data.findIndex(t => t.surfacecolor);"
        " Plotly.restyle(gd, {surfacecolor: [gd.data[i].surfacecolor.map(r => r.map(() => 0))]},"
        " [i]); })(document.getElementById('cnc-plot'))"
    )
    browser.pump(0.5)
    assert browser.errors == []
    assert _red_mask(browser)[0].sum() < 20
