"""``cnc run --design``: the cut part against a design model, coloured by the deviation in the
HTML report's 3-D view (cli.report_view.design_part, kernel.report.backplot.surface_grid and
deviation_scale, cli.formats.html_report.view_data), against closed forms.

The design is a flat plane at Z = -1 over X 10..50, Y 10..30 (two triangles) on a
60 x 40 mm stock with top Z = 0 at a 0.5 mm grid; the program cuts a 6 mm slot 2.5 deep from
X25 to X35 at Y20.1. So every cell centre within 3 mm of the slot's axis is 1.5 mm below the
design (a gouge), every other cell of the plane 1 mm above it (material left), and cells off
the plane are not compared. The browser test (tests/test_report_browser.py) draws this page.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from cli.formats.html_report import view_data
from cli.main import cli
from cli.programs import check_input
from cli.report_view import Design, design_part, program_view, read_source
from kernel.check import CheckContext, check_stream
from kernel.ir import canon
from kernel.machine import parse_machine
from kernel.path.build import build_path
from kernel.report.backplot import GOUGE_RED, LEFT_BLUE, deviation_scale, surface_grid
from kernel.stock.mesh import stl_bytes

PROFILE = """name = "mill with stock"
[axes.x]
min = -10.0
max = 200.0
[axes.y]
min = -10.0
max = 200.0
[axes.z]
min = -100.0
max = 100.0
[stock]
box = [0, 0, -10, 60, 40, 0]
"""
Y, RADIUS, DEPTH, PLANE = 20.1, 3.0, 2.5, -1.0
PROGRAM = f"""G21 G90 G94 G17
G0 X25 Y{Y} Z5
G1 Z-{DEPTH} F300
G1 X35
G0 Z5
M2
"""
PLUNGE_LINE, SLOT_LINE = 3, 4  # the moves that cut the slot's floor


def plane(z: float) -> np.ndarray:
    """The design: a rectangle X 10..50, Y 10..30 at height ``z`` as two triangles."""
    v = np.array([[10, 10, z], [50, 10, z], [50, 30, z], [10, 30, z]], float)
    return v[np.array([[0, 1, 2], [0, 2, 3]])]


def design_page(tmp_path: Path, z: float = PLANE, tol: float = 0.1) -> dict[str, object]:
    """What ``cnc run --html --design`` draws for the slot against a plane at ``z``: the
    view, the surface, the design part, the findings and the program's text."""
    prog = tmp_path / "slot.ngc"
    prog.write_text(PROGRAM)
    machine = parse_machine(PROFILE, "mill.toml")
    ctx = CheckContext(machine)
    stream, text = check_input(str(prog), None, -1, None, 1.0, machine)
    cmds: list[canon.Command] = []

    def keep(s):  # type: ignore[no-untyped-def]
        for c in s:
            cmds.append(c)
            yield c

    findings = check_stream(keep(stream), ctx, str(prog), text)
    part = design_part(cmds, ctx, str(prog), Design(plane(z), tol, 0.5))
    assert part is not None
    findings += part.findings(ctx)
    source = read_source(str(prog))
    path = build_path(cmds, machine, str(prog))
    view, surface = program_view(cmds, path, ctx, str(prog), None, source, part)
    return {
        "program": prog,
        "view": view,
        "surface": surface,
        "part": part,
        "findings": findings,
        "source": source,
    }


def _axis_distance(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Distance of points from the slot's axis, the segment X25..X35 at Y20.1."""
    return np.hypot(x - np.clip(x, 25.0, 35.0), y - Y)


def test_the_colour_array_is_the_deviation_from_a_flat_design(tmp_path: Path) -> None:
    page = design_page(tmp_path)
    surface = page["surface"]
    assert surface is not None and surface.dev is not None
    data = view_data(page["view"], surface, [], "inline")
    s = data["surface"]
    dev = s["deviation"]
    values = np.frombuffer(base64.b64decode(dev["values"]), "<f4").reshape(s["ny"], s["nx"])
    assert (s["nx"], s["ny"]) == (120, 80)  # 60 x 40 mm at 0.5 mm, not reduced
    xs = 0.25 + 0.5 * np.arange(120)
    ys = 0.25 + 0.5 * np.arange(80)
    x, y = np.meshgrid(xs, ys)
    on_plane = (x > 10) & (x < 50) & (y > 10) & (y < 30)
    d = _axis_distance(x, y)
    gouge = on_plane & (d < RADIUS - 1e-6)
    left = on_plane & (d > RADIUS + 1e-6)
    assert gouge.sum() > 100 and left.sum() > 2000
    assert np.allclose(values[gouge], -DEPTH - PLANE)  # -1.5: below the design
    assert np.allclose(values[left], 0.0 - PLANE)  # +1.0: material left
    assert np.all(values[~on_plane] == 0.0)  # not compared: neutral
    assert np.all(np.isnan(surface.dev[~on_plane]))
    # the diverging scale: ±1.5 mm, red below -tol, neutral within ±tol, blue above +tol
    assert dev["span"] == 1.5 and dev["tol"] == 0.1
    stops = dev["colorscale"]
    assert stops[0] == [0.0, GOUGE_RED] and stops[-1] == [1.0, LEFT_BLUE]
    band = [p for p, c in stops if c == "#d9dee5"]
    assert np.allclose(band, [0.5 - 0.05 / 1.5, 0.5 + 0.05 / 1.5])
    # the worst values marked: the gouge in the slot, at the move that last cut there (the
    # plunge within its radius of X25, the feed move beyond); the leftover
    marks = {m["label"].split(" ")[1]: m for m in dev["marks"]}
    gx, gy = marks["gouge"]["x"], marks["gouge"]["y"]
    assert marks["gouge"]["value"] == -1.5
    assert _axis_distance(np.array(gx), np.array(gy)) < RADIUS
    line = PLUNGE_LINE if np.hypot(gx - 25.0, gy - Y) < RADIUS else SLOT_LINE
    assert marks["gouge"]["line"] == line
    assert marks["gouge"]["z"] == -DEPTH
    assert marks["material"]["value"] == 1.0 and marks["material"]["z"] == 0.0
    rules = {f.rule: f for f in page["findings"]}
    assert rules["CNC906"].location.line == line and rules["CNC906"].code == "SIM-GOUGE"
    assert "CNC907" in rules


def test_a_design_at_the_slot_floor_has_no_gouge(tmp_path: Path) -> None:
    page = design_page(tmp_path, z=-DEPTH)
    dev = page["surface"].dev
    assert np.nanmin(dev) == 0.0 and np.nanmax(dev) == DEPTH
    assert [f.rule for f in page["findings"] if f.rule.startswith("CNC9")] == ["CNC907"]
    assert [m.label.split(" ")[1] for m in page["surface"].marks] == ["material"]


def test_reducing_the_grid_keeps_the_largest_deviation() -> None:
    h = np.zeros((4, 4))
    dev = np.full((4, 4), np.nan)
    dev[0, 0], dev[0, 1], dev[1, 0] = 0.2, -0.7, 0.5  # one 2 x 2 block
    dev[2:, 2:] = 0.05
    s = surface_grid(0.0, 0.0, 4.0, 4.0, h, cells=2, deviation=dev, tol=0.1)
    assert s.dev is not None and s.dev.shape == (2, 2)
    assert s.dev[0, 0] == -0.7 and s.dev[1, 1] == 0.05
    assert np.isnan(s.dev[0, 1]) and np.isnan(s.dev[1, 0])
    span, _ = deviation_scale(s)
    assert span == 0.7


def test_cnc_run_design_lists_the_findings_and_colours_the_page(tmp_path: Path) -> None:
    prog = tmp_path / "slot.ngc"
    prog.write_text(PROGRAM)
    profile = tmp_path / "mill.toml"
    profile.write_text(PROFILE)
    stl = tmp_path / "design.stl"
    tri = plane(PLANE)
    verts = tri.reshape(-1, 3)
    stl.write_bytes(stl_bytes(verts, np.arange(len(verts)).reshape(-1, 3)))
    out = tmp_path / "out"
    args = ["run", str(prog), "-m", str(profile), "--design", str(stl), "-o", str(out)]
    res = CliRunner().invoke(cli, [*args, "--html"])
    assert res.exit_code == 1, res.output  # the gouge is an error
    doc = json.loads((out / "slot.report.json").read_text())
    found = {f["rule"]: f for f in doc["findings"]}
    assert found["CNC906"]["line"] in (PLUNGE_LINE, SLOT_LINE)
    assert doc["design"]["gouge"] == 1.5 and doc["design"]["leftover"] == 1.0
    assert "stock - design (mm)" in (out / "slot.report.html").read_text()
    # no [stock] in the profile: a usage error
    bare = tmp_path / "bare.toml"
    bare.write_text(PROFILE.split("[stock]")[0])
    res = CliRunner().invoke(cli, ["run", str(prog), "-m", str(bare), "--design", str(stl)])
    assert res.exit_code == 2 and "[stock]" in res.output
