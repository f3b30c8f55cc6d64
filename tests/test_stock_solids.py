"""Stock and fixtures as meshes, fixtures as obstacles, and ``cnc check --design``.

The meshes are written here as ASCII STL, independently of kernel.stock.mesh; the
expected values are closed forms (a box stock given as a mesh is the same grid as the box
stock, so the results must be identical; a fixture block's top against a tool at a known
height gives the contact depth exactly).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli

STOCK = "box:0,0,-20,100,50,0"
SLOT = "G21 G90 G17 M3 S8000\nG0 X20 Y25.03 Z5\nG1 Z-3 F100\nG1 X80\nG0 Z5\nM2\n"
Tri = tuple[tuple[float, float, float], ...]


def write_stl(path: Path, triangles: list[Tri]) -> Path:
    rows = ["solid t"]
    for tri in triangles:
        rows += ["facet normal 0 0 0", "outer loop"]
        rows += [f"vertex {x} {y} {z}" for x, y, z in tri]
        rows += ["endloop", "endfacet"]
    path.write_text("\n".join([*rows, "endsolid t"]) + "\n")
    return path


def box_triangles(x0: float, y0: float, z0: float, x1: float, y1: float, z1: float) -> list[Tri]:
    """The 12 triangles of a box's six faces."""
    c = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    out: list[Tri] = []
    for a, b, cc, d in quads:
        out += [(c[a], c[b], c[cc]), (c[a], c[cc], c[d])]
    return out


def sim(tmp_path: Path, text: str, *args: str) -> tuple[int, dict]:
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["sim", str(prog), "--format", "json", *args])
    assert res.exit_code in (0, 1), res.output
    return res.exit_code, json.loads(res.stdout)


def check(tmp_path: Path, text: str, *args: str) -> tuple[int, set[tuple[str, str, int]]]:
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["check", str(prog), "-f", "json", *args])
    assert res.exit_code in (0, 1), res.output
    doc = json.loads(res.stdout)
    found = {
        (f["rule"], f["code"] or "", int(f["line"] or 0))
        for r in doc["files"]
        for f in r["findings"]
        if f["rule"].startswith("CNC9")
    }
    return res.exit_code, found


def test_a_box_given_as_stl_is_the_box_stock(tmp_path: Path) -> None:
    stl = write_stl(tmp_path / "s.stl", box_triangles(0, 0, -20, 100, 50, 0))
    text = SLOT.replace("G0 Z5\nM2", "G0 Z5\nG0 X50 Y8 Z-1\nG0 Z5\nM2")
    args = ("--tool", "0=flat:10", "--resolution", "0.5")
    rc_box, box = sim(tmp_path, text, "--stock", STOCK, *args)
    rc_stl, mesh = sim(tmp_path, text, "--stock", str(stl), *args)
    assert rc_box == rc_stl == 1
    assert mesh == {**box, "program": mesh["program"]}
    assert [f["code"] for f in mesh["findings"]] == ["SIM-RAPID-IN-STOCK"]


def test_a_stepped_stl_stock_starts_at_its_top_surface(tmp_path: Path) -> None:
    """Two blocks: x 0..50 up to Z0, x 50..100 up to Z-5 (one mesh). A 10 mm end mill at
    Z-3 along Y at X25 cuts 3 x 10 x 50 (plus nothing beyond the stock); a rapid at Z-2
    over the low block hits nothing, over the high one it does."""
    tris = box_triangles(0, 0, -20, 50, 50, 0) + box_triangles(50, 0, -20, 100, 50, -5)
    stl = write_stl(tmp_path / "s.stl", tris)
    text = "G21 G90\nG0 X25 Y-10 Z5\nG1 Z-3 F100\nG1 Y60\nG0 Z5\nG0 X75 Y25\nG0 Z-2\nM2\n"
    rc, out = sim(tmp_path, text, "--stock", str(stl), "--tool", "0=flat:10")
    assert rc == 0 and out["findings"] == []
    assert out["removed_volume"] == pytest.approx(3 * 10 * 50, rel=0.02)
    rc, out = sim(tmp_path, text.replace("X75 Y25", "X40 Y25"), "--stock", str(stl))
    assert rc == 1
    assert [(f["code"], f["line"]) for f in out["findings"]] == [("SIM-RAPID-IN-STOCK", 7)]


FIXTURE = "box:30,0,-20,70,10,5"  # a clamp on the stock's front edge, 5 mm above its top


def test_a_rapid_into_a_fixture_is_an_error_at_its_line(tmp_path: Path) -> None:
    """A 10 mm tool at Y5 covers Y0..10; a rapid at Z2 along X passes over the clamp (top
    Z5): 3 mm deep, on line 3; at Z10 it is clear."""
    text = "G21 G90\nG0 X10 Y5 Z10\nG0 Z2\nG0 X90\nG0 Z10\nM2\n"
    text = text.replace("G0 Z2\nG0 X90", "G0 Z2\nG0 X90 Y5")
    clear = text.replace("G0 Z2\n", "G0 Z10\n")
    for spec in (FIXTURE, str(write_stl(tmp_path / "f.stl", box_triangles(30, 0, -20, 70, 10, 5)))):
        rc, out = sim(tmp_path, text, "--stock", STOCK, "--fixture", spec, "--tool", "0=flat:10")
        assert rc == 1
        (f,) = out["findings"]
        assert (f["code"], f["line"], f["severity"]) == ("SIM-FIXTURE", 4, "error")
        assert f["value"] == pytest.approx(3.0) and 30 - 0.5 < f["x"] < 70 + 0.5
        assert "rapid move" in f["message"]
        rc, out = sim(tmp_path, clear, "--stock", STOCK, "--fixture", spec, "--tool", "0=flat:10")
        assert rc == 0 and out["findings"] == []


def test_a_holder_over_a_fixture_and_the_profile_fixtures(tmp_path: Path) -> None:
    """Slot at Z-3 along Y25: the 10 mm cutter stays 10 mm from the clamp (Y0..10), but a
    40 mm holder 5 mm above the tip (bottom Z2) reaches Y5 over it: 3 mm into it on the
    plunge (line 3), the slot (4) and the retract (5); with a 10 mm shank out of the
    holder, its bottom is at Z12: clear."""
    tool = "0=flat:10,flute=5,holder=40"
    rc, out = sim(tmp_path, SLOT, "--stock", STOCK, "--fixture", FIXTURE, "--tool", tool)
    assert rc == 1
    assert [(f["code"], f["line"]) for f in out["findings"]] == [
        ("SIM-FIXTURE", n) for n in (3, 4, 5)
    ]
    for f in out["findings"]:
        assert f["value"] == pytest.approx(3.0) and "holder" in f["message"]
    rc, out = sim(
        tmp_path, SLOT, "--stock", STOCK, "--fixture", FIXTURE, "--tool", tool + ",shank_length=10"
    )
    assert rc == 0 and out["findings"] == []
    profile = tmp_path / "m.toml"
    write_stl(tmp_path / "clamp.stl", box_triangles(30, 0, -20, 70, 10, 5))
    here = Path(__file__).parent / "check"
    (tmp_path / "shop.tbl").write_text((here / "shop.tbl").read_text())
    profile.write_text(
        (here / "shop.toml").read_text() + "\n[stock]\nbox = [0, 0, -20, 100, 50, 0]\n"
        '[[fixture]]\nname = "clamp"\nfile = "clamp.stl"\n'
        "[[fixture]]\nbox = [30, 40, -20, 70, 50, 5]\n"
    )
    rc, out = sim(tmp_path, SLOT, "-m", str(profile), "--tool", tool)
    assert rc == 1 and [f["line"] for f in out["findings"]] == [3, 4, 5]
    assert all("clamp" in f["message"] for f in out["findings"])
    rc, found = check(tmp_path, SLOT, "-m", str(profile), "--tools", str(library(tmp_path)))
    assert rc == 1 and found == {("CNC908", "SIM-FIXTURE", n) for n in (3, 4, 5)}


def library(tmp_path: Path) -> Path:
    lib = tmp_path / "lib.toml"
    lib.write_text(
        '[tools.0]\ntype = "flat"\ndiameter = 10\nflute_length = 5\nholder_diameter = 40\n'
    )
    return lib


def test_bad_fixtures_are_located_diagnostics(tmp_path: Path) -> None:
    (tmp_path / "bad.stl").write_text("hello")
    prog = tmp_path / "p.ngc"
    prog.write_text(SLOT)
    for spec in ("box:1,2", str(tmp_path / "bad.stl")):
        res = CliRunner().invoke(cli, ["sim", str(prog), "--stock", STOCK, "--fixture", spec])
        assert res.exit_code == 1 and "SIM-FIXTURE-SPEC" in res.output
        assert "Traceback" not in res.output
    flat = write_stl(tmp_path / "flat.stl", [((0, 0, 0), (1, 0, 0), (1, 1, 0))])
    res = CliRunner().invoke(cli, ["sim", str(prog), "--stock", str(flat)])
    assert res.exit_code == 1 and "SIM-STOCK" in res.output


def plane(path: Path, x0: float, y0: float, x1: float, y1: float, z: tuple[float, float]) -> Path:
    """A rectangle whose Z goes linearly from z[0] at x0 to z[1] at x1."""
    a, b, c, d = (x0, y0, z[0]), (x1, y0, z[1]), (x1, y1, z[1]), (x0, y1, z[0])
    return write_stl(path, [(a, b, c), (a, c, d)])


def test_check_with_a_design_reports_gouge_and_leftover_as_rules(tmp_path: Path) -> None:
    """As ``cnc sim --design`` (tests/test_stock_tools.py): design z = -3 + 0.01 (x - 20)
    over the stock, slot to -3: gouge on the slot's line 4, material left where never cut
    (no line); a design at the slot's floor inside its straight part is clean."""
    stl = plane(tmp_path / "d.stl", 0, 0, 100, 50, (-3.2, -2.2))
    args = ("--stock", STOCK, "--tools", str(library(tmp_path)), "--design", str(stl))
    rc, found = check(tmp_path, SLOT, *args)
    assert rc == 1
    assert found == {("CNC906", "SIM-GOUGE", 4), ("CNC907", "SIM-LEFTOVER", 0)}
    rc, found = check(tmp_path, SLOT, *args, "--design-tol", "4")
    assert rc == 0 and found == set()
    plane(stl, 20, 21, 80, 29, (-3.0, -3.0))
    rc, found = check(tmp_path, SLOT, *args)
    assert rc == 0 and found == set()
    prog = tmp_path / "p.ngc"
    res = CliRunner().invoke(cli, ["check", str(prog), "--design", str(stl)])
    assert res.exit_code == 2  # a design needs a stock


@pytest.mark.slow
def test_step_stock_and_fixture_through_cadquery(tmp_path: Path) -> None:
    """A STEP box is the box stock (same grid, same result); a STEP clamp is hit as the
    box: fixture is (line 4, 3 mm)."""
    cq = pytest.importorskip("cadquery")
    stock = tmp_path / "s.step"
    block = cq.Workplane("XY").box(100, 50, 20, centered=(False, False, False))
    cq.exporters.export(block.translate((0, 0, -20)), str(stock))
    clamp = tmp_path / "c.step"
    cq.exporters.export(
        cq.Workplane("XY").box(40, 10, 25, centered=False).translate((30, 0, -20)), str(clamp)
    )
    args = ("--tool", "0=flat:10")
    _, box = sim(tmp_path, SLOT, "--stock", STOCK, *args)
    _, step = sim(tmp_path, SLOT, "--stock", str(stock), *args)
    assert step["removed_volume"] == pytest.approx(box["removed_volume"], rel=1e-9)
    text = "G21 G90\nG0 X10 Y5 Z10\nG0 Z2\nG0 X90 Y5\nG0 Z10\nM2\n"
    rc, out = sim(tmp_path, text, "--stock", str(stock), "--fixture", str(clamp), *args)
    assert rc == 1
    assert [(f["code"], f["line"]) for f in out["findings"]] == [("SIM-FIXTURE", 4)]
    assert out["findings"][0]["value"] == pytest.approx(3.0)
