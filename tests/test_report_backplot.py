"""The HTML report's backplot data (kernel.report.backplot, cli.formats.html_report.view_data):
rapids dashed, one colour per tool, lathe programs in ZX with X as the program gives it,
decimation that keeps every move's end, and per-point source lines that name the line whose
words put the tool there (checked against the program text, not the builder)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from cli.formats.html_report import PLOTLY_FILE, plotly_js, view_data
from cli.programs import program_commands
from cli.report_view import write_library
from kernel.diagnostics import Diagnostic
from kernel.machine import DEFAULT_MACHINE
from kernel.path.build import build_path
from kernel.report.backplot import (
    Backplot,
    Box,
    build_backplot,
    is_lathe,
    surface_grid,
    tool_changes,
)

ROOT = Path(__file__).resolve().parents[1]
FANUC_TURN = ROOT / "tests" / "dialects" / "fanuc" / "114_turn_arcs_r_ik.nc"

MILL = """G21 G17 G90 G94
T2 M6
G0 X0 Y0 Z5
G1 Z-1 F250
G1 X20 F600
G2 X30 Y10 I0 J10
G1 Y25
G0 Z5
T4 M6
G0 X50 Y50
G1 Z-2 F100
G1 X70 Y55 Z-3
G3 X60 Y65 I-10 J0
G0 Z10
M2
"""


def _plot(
    text: str,
    tmp_path: Path,
    suffix: str = ".ngc",
    dialect: str | None = None,
    lathe: bool | None = None,
    **kw: Any,
) -> Backplot:
    prog = tmp_path / f"p{suffix}"
    prog.write_text(text)
    cmds = list(program_commands(str(prog), dialect=dialect))
    path = build_path(cmds, DEFAULT_MACHINE, str(prog))
    flat = is_lathe(cmds, path) if lathe is None else lathe
    return build_backplot(path, tool_changes(cmds), lathe=flat, **kw)


def _modal_ends(text: str) -> dict[int, tuple[float, float, float]]:
    """Where each motion line of an absolute XYZ program leaves the tool, from its words."""
    pos = [0.0, 0.0, 0.0]
    out = {}
    for n, line in enumerate(text.splitlines(), 1):
        words = dict(re.findall(r"([XYZ])(-?[\d.]+)", line))
        if not words:
            continue
        for k, ax in enumerate("XYZ"):
            if ax in words:
                pos[k] = float(words[ax])
        out[n] = (pos[0], pos[1], pos[2])
    return out


def test_each_point_names_the_line_whose_words_put_the_tool_there(tmp_path: Path) -> None:
    bp = _plot(MILL, tmp_path)
    ends = _modal_ends(MILL)
    seen: dict[int, np.ndarray] = {}
    for tr in bp.traces:
        for p, n in zip(tr.points, tr.lines, strict=True):
            if n:
                seen[int(n)] = p  # the last point of the line's move: its end
    assert set(seen) == set(ends)  # every motion line is drawn, and nothing else
    for n, end in ends.items():
        assert np.allclose(seen[n], end, atol=1e-6), (n, MILL.splitlines()[n - 1])


def test_hover_feed_is_the_programmed_f_in_mm_per_min(tmp_path: Path) -> None:
    bp = _plot(MILL, tmp_path)
    lines = MILL.splitlines()
    feed = 0.0
    modal = {}
    for n, line in enumerate(lines, 1):
        m = re.search(r"F([\d.]+)", line)
        feed = float(m.group(1)) if m else feed
        modal[n] = feed
    for tr in bp.traces:
        for n, f in zip(tr.lines, tr.feeds, strict=True):
            if n and not tr.rapid:
                assert f == pytest.approx(modal[int(n)], rel=1e-6)
            if tr.rapid:
                assert f == 0.0
                assert lines[int(n) - 1].startswith("G0") or n == 0


def test_rapids_are_dashed_and_each_tool_has_its_colour(tmp_path: Path) -> None:
    bp = _plot(MILL, tmp_path)
    data = view_data(bp, None, [], "inline")
    by = {t["name"]: t for t in data["traces"]}
    assert set(by) == {"T2 feed", "T2 rapid", "T4 feed", "T4 rapid"}
    assert by["T2 rapid"]["dash"] == by["T4 rapid"]["dash"] == "dash"
    assert by["T2 feed"]["dash"] == by["T4 feed"]["dash"] == "solid"
    assert by["T2 feed"]["color"] == by["T2 rapid"]["color"]
    assert by["T4 feed"]["color"] == by["T4 rapid"]["color"] != by["T2 feed"]["color"]
    assert data["dim"] == 3


def test_arcs_are_chorded_on_their_circle(tmp_path: Path) -> None:
    bp = _plot(MILL, tmp_path, chord_tol=0.001)
    arc = np.concatenate([t.points[t.lines == 6] for t in bp.traces])  # G2 about (20, 10)
    assert len(arc) > 10
    assert np.allclose(np.hypot(arc[:, 0] - 20, arc[:, 1] - 10), 10.0, atol=1e-6)


def test_fanuc_lathe_program_is_drawn_in_zx_with_x_as_diameter(tmp_path: Path) -> None:
    text = FANUC_TURN.read_text()
    bp = _plot(text, tmp_path, ".nc", dialect="fanuc_lathe", lathe=True, diameter=True)
    assert bp.lathe and bp.labels == ("Z", "X (diameter)")
    pts = {int(n): p for t in bp.traces for p, n in zip(t.points, t.lines, strict=True) if n}
    assert all(p.shape == (2,) for p in pts.values())
    lines = text.splitlines()
    # "G01 Z-15." after "G03 X30. Z-5. R5.": the tool ends at Z-15 on diameter 30
    n = lines.index("G01 Z-15.") + 1
    assert np.allclose(pts[n], (-15.0, 30.0))
    n = lines.index("G01 X50.") + 1
    assert np.allclose(pts[n], (-20.0, 50.0))


def test_ngc_g18_program_is_a_lathe_program_in_radius(tmp_path: Path) -> None:
    text = "G21 G18 G8\nG0 X10 Z2\nG1 Z-5 F100\nG1 X12 Z-7\nM2\n"
    bp = _plot(text, tmp_path)
    assert bp.lathe and not bp.diameter and bp.labels == ("Z", "X (radius)")
    pts = {int(n): p for t in bp.traces for p, n in zip(t.points, t.lines, strict=True) if n}
    assert np.allclose(pts[4], (-7.0, 12.0))


def test_decimation_keeps_every_moves_end_within_the_budget(tmp_path: Path) -> None:
    body = [
        f"G2 X{10 * ((i + 1) % 2)} Y0 I{5 - 10 * (i % 2)} J0" for i in range(400)
    ]  # half circles
    text = "G21 G90\nG0 X0 Y0 Z0\nG1 F500\n" + "\n".join(body) + "\nM2\n"
    full = _plot(text, tmp_path)
    bp = _plot(text, tmp_path, budget=1200)
    assert not full.decimated and full.points > 1200
    assert bp.decimated and bp.points <= 1200 and bp.source_points == full.points
    drawn = {int(n) for t in bp.traces for n in t.lines if n}
    assert drawn == set(range(4, 404))  # every arc still has its end (line 2 does not move)
    ends = _modal_ends(text)
    last = {int(n): p for t in bp.traces for p, n in zip(t.points, t.lines, strict=True) if n}
    for n in (4, 200, 403):
        assert np.allclose(last[n][:2], ends[n][:2])


def test_a_tiny_budget_merges_collinear_and_short_moves(tmp_path: Path) -> None:
    body = [f"G1 X{i * 0.01:.2f}" for i in range(1, 1501)]  # one straight line in 1500 moves
    body += [f"G1 Y{(i % 2) * 0.001:.3f} X{15 + i * 0.001:.3f}" for i in range(1500)]
    text = "G21 G90\nG0 X0 Y0 Z0\nG1 F500\n" + "\n".join(body) + "\nM2\n"
    bp = _plot(text, tmp_path, budget=300)
    assert bp.decimated and bp.points <= 300
    pts = np.concatenate([t.points for t in bp.traces if not t.rapid])
    assert np.allclose(pts[0], (0, 0, 0)) and np.allclose(pts[-1][:1], 16.499, atol=1e-6)


def test_stock_and_travel_are_wire_boxes(tmp_path: Path) -> None:
    stock = Box((0.0, 0.0, -10.0), (80.0, 50.0, 0.0))
    bp = _plot(MILL, tmp_path, stock=stock)
    ((name, edges),) = bp.edges
    corners = {tuple(p) for p in edges if np.isfinite(p).all()}
    assert name == "stock" and len(corners) == 8
    assert corners == {(x, y, z) for x in (0, 80) for y in (0, 50) for z in (-10, 0)}


def test_the_cut_part_surface_keeps_narrow_cuts_when_reduced() -> None:
    h = np.zeros((500, 800))
    h[:, 401] = -5.0  # a slot one cell wide
    s = surface_grid(0.0, 0.0, 80.0, 50.0, h, cells=100)
    assert max(s.z.shape) <= 100 and s.z.min() == -5.0
    assert (s.z == -5.0).sum(axis=1).tolist() == [1] * s.z.shape[0]  # one column, every row
    assert (s.x0, s.y0, s.x1, s.y1) == (0.0, 0.0, 80.0, 50.0)
    data = view_data(_empty_plot(), s, [], "inline")
    assert (data["surface"]["nx"], data["surface"]["ny"]) == (s.z.shape[1], s.z.shape[0])


def _empty_plot() -> Backplot:
    return Backplot((), False, False, (), 0, 0, 0)


def test_a_batch_writes_plotly_once_and_keeps_a_different_file(tmp_path: Path) -> None:
    lib = tmp_path / PLOTLY_FILE
    assert write_library(str(tmp_path), False, []) == PLOTLY_FILE
    assert lib.read_text() == plotly_js() and "plotly.js v3" in plotly_js()[:200]
    stamp = lib.stat().st_mtime_ns
    write_library(str(tmp_path), False, [])  # identical: left alone
    assert lib.stat().st_mtime_ns == stamp
    lib.write_text("mine")
    with pytest.raises(Diagnostic) as err:
        write_library(str(tmp_path), False, [])
    assert err.value.code == "IO-EXISTS" and lib.read_text() == "mine"
    with pytest.raises(Diagnostic) as err:  # a program of the batch is never overwritten
        write_library(str(tmp_path), True, [str(lib)])
    assert err.value.code == "IO-SAME-FILE" and lib.read_text() == "mine"
    write_library(str(tmp_path), True, [])
    assert lib.read_text() == plotly_js()
