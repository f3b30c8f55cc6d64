"""Tool shapes of the height-field simulation (bull nose, drill, chamfer/V, shank and
holder) against closed forms, dense sampling and the tool library (issue 17).

Closed forms (R the radius, h the depth, L the straight length):
- bull nose, corner rc, h >= rc: the groove's cross-section is D h - (4 - pi) rc^2 / 2; the two
  half ends together are the profile revolved, pi a^2 h + 2 pi [(h - rc)(a rc + rc^2 / 2)
  + a pi rc^2 / 4 + rc^3 / 3] with a = R - rc;
- drill of point angle 2 alpha to tip depth h: a cylinder of depth h - R cot(alpha) and a cone
  of that height;
- V-bit of included angle 2 alpha, h <= R cot(alpha): a triangle of area h^2 tan(alpha) along
  the groove and a cone of radius h tan(alpha) and height h at the ends.
The grid's error bound is that of tests/test_stock_sim.py: perimeter x cell diagonal x depth.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from cli.main import cli
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.stock import HeightField, StockBox, ToolShape, library_from_toml, simulate_removal
from kernel.stock import parse_stock as parse_stock_text
from kernel.stock.simulate import tool_envelope
from kernel.stock.tools import make_tool, parse_tool_spec

BOX = StockBox(0.0, 0.0, -20.0, 100.0, 50.0, 0.0)


def groove(depth: float, length: float) -> list[canon.Command]:
    y = 25.03  # off the grid's symmetry
    return [
        canon.StraightTraverse(20.0, y, 5.0),
        canon.StraightFeed(20.0, y, -depth),
        canon.StraightFeed(20.0 + length, y, -depth),
        canon.StraightTraverse(20.0 + length, y, 5.0),
    ]


def check(cmds: list[canon.Command], tool: ToolShape, exact: float, bound_per_res: float) -> None:
    """Removed volume within the grid bound at 0.4 and 0.1 mm, < 0.5 % at 0.1 mm."""
    errors = {}
    for res in (0.4, 0.1):
        got = simulate_removal(cmds, HeightField(BOX, res), {0: tool}).removed_volume
        errors[res] = abs(got - exact)
        assert errors[res] <= bound_per_res * math.hypot(res, res), (res, got, exact)
    assert errors[0.1] / exact < 0.005
    assert errors[0.1] < errors[0.4]


def test_bull_nose_groove_cross_section_and_revolved_ends() -> None:
    d, rc, h, length = 10.0, 2.0, 3.0, 60.0
    r, a = d / 2, d / 2 - rc
    area = d * h - (4 - math.pi) / 2 * rc * rc
    ends = math.pi * a * a * h + 2 * math.pi * (
        (h - rc) * (a * rc + rc * rc / 2) + a * math.pi * rc * rc / 4 + rc**3 / 3
    )
    tool = make_tool("bull", d, "t", corner_radius=rc)
    check(groove(h, length), tool, area * length + ends, (2 * length + 2 * math.pi * r) * h)
    # the cross-section cell by cell in the straight part
    hf = HeightField(BOX, 0.1)
    simulate_removal(groove(h, length), hf, {0: tool})
    col = hf.h[:, np.argmin(np.abs(hf.xs - 50.0))]
    y = np.abs(hf.ys - 25.03)
    e = np.clip(y - a, 0.0, rc)
    expect = np.where(y <= r, np.minimum(-h + rc - np.sqrt(rc * rc - e * e), 0.0), 0.0)
    assert np.max(np.abs(col - expect)) < 1e-9


def test_drilled_hole_with_a_point_angle_is_a_cylinder_and_a_cone() -> None:
    d, h, angle = 8.0, 12.0, 118.0
    r = d / 2
    cone = r / math.tan(math.radians(angle / 2))
    exact = math.pi * r * r * (h - cone) + math.pi * r * r * cone / 3
    cmds = [
        canon.StraightTraverse(40.0, 20.0, 5.0),
        canon.StraightFeed(40.0, 20.0, -h),
        canon.StraightTraverse(40.0, 20.0, 5.0),
    ]
    check(cmds, make_tool("drill", d, "t", angle=angle), exact, math.pi * d * h)


def test_v_groove_is_a_triangle_along_it_and_a_cone_at_the_ends() -> None:
    d, h, angle, length = 10.0, 3.0, 90.0, 60.0
    tan = math.tan(math.radians(angle / 2))
    half = h * tan
    exact = h * half * length + math.pi * half * half * h / 3
    check(
        groove(h, length),
        make_tool("v", d, "t", angle=angle),
        exact,
        (2 * length + 2 * math.pi * half) * h,
    )


@pytest.mark.parametrize("seed", range(2))
def test_new_envelopes_agree_with_the_tool_placed_densely_along_the_move(seed: int) -> None:
    """The closed forms (and the bull nose's bisection) are never above the tool placed at
    4,001 points along a random 3-D move, and below it only by the sampling's step."""
    rng = np.random.default_rng(100 + seed)
    d = tuple(float(v) for v in rng.uniform(-6, 6, 3))
    z0 = float(rng.uniform(-2, 2))
    gx, gy = np.meshgrid(np.linspace(-10, 10, 25), np.linspace(-10, 10, 25))
    slope60, slope118 = 1 / math.tan(math.radians(30)), 1 / math.tan(math.radians(59))

    def bull(rho: np.ndarray) -> np.ndarray:
        e = np.clip(rho - 2.0, 0.0, 1.0)
        return 1.0 - np.sqrt(1.0 - e * e)

    for tool, prof in (
        (make_tool("bull", 6.0, "t", corner_radius=1.0), bull),
        (make_tool("drill", 6.0, "t"), lambda rho: slope118 * rho),
        (
            make_tool("chamfer", 6.0, "t", angle=60.0, tip_diameter=1.5),
            lambda rho: slope60 * np.maximum(rho - 0.75, 0.0),
        ),
    ):
        ref = np.full(gx.shape, np.inf)
        for chunk in np.array_split(np.linspace(0.0, 1.0, 4_001), 8):
            t = chunk[:, None, None]
            rho = np.hypot(gx - t * d[0], gy - t * d[1])
            z = np.where(rho <= 3.0, z0 + t * d[2] + prof(np.minimum(rho, 3.0)), np.inf)
            ref = np.minimum(ref, z.min(axis=0))
        got = tool_envelope(gx, gy, d, z0, tool)
        both = np.isfinite(ref)
        assert np.array_equal(np.isfinite(got) & both, both), tool.kind
        assert np.all(got[both] <= ref[both] + 1e-9), tool.kind
        assert np.allclose(got[both], ref[both], atol=5e-3), tool.kind


def test_tool_library_and_specs() -> None:
    lib = library_from_toml(
        {
            "units": "inch",
            "tools": {
                "1": {"type": "bull", "diameter": 0.5, "corner_radius": 0.0625, "flute_length": 1},
                "2": {"type": "drill", "diameter": 0.25},
                "3": {"type": "v", "diameter": 0.5, "angle": 60, "centre_cutting": True},
                "4": {
                    "type": "flat",
                    "diameter": 0.25,
                    "shank_diameter": 0.25,
                    "holder_diameter": 1.5,
                    "holder_length": 2,
                    "shank_length": 0.5,
                    "flute_length": 0.75,
                },
            },
        }
    )
    assert lib[1] == ToolShape("bull", 12.7, 25.4, corner_radius=1.5875)
    assert lib[2].kind == "drill" and lib[2].angle == 118.0
    assert lib[3].kind == "chamfer" and lib[3].angle == 60.0
    assert lib[4].holder_bottom == pytest.approx(25.4 * 1.25)
    assert lib[4].shank_bottom == pytest.approx(25.4 * 0.75)
    n, t = parse_tool_spec("5=bull:10,corner=2,flute=20,shank=10,holder=40,shank_length=5")
    assert n == 5 and t.holder_bottom == 25.0 and t.corner_radius == 2.0
    for bad in (
        {"tools": {"1": {"type": "bull", "diameter": 6}}},  # no corner radius
        {"tools": {"1": {"type": "cone", "diameter": 6}}},
        {"tools": {"x": {"type": "flat", "diameter": 6}}},
        {"tools": {"1": {"type": "flat", "diameter": 6, "colour": 3}}},
        {"tools": {"1": {"type": "drill", "diameter": 6, "angle": 190}}},
        {"units": "furlong", "tools": {"1": {"type": "flat", "diameter": 6}}},
        {},
    ):
        with pytest.raises(Diagnostic) as exc:
            library_from_toml(bad, "lib.toml")
        assert exc.value.code == "SIM-TOOL"


# ------------------------------------------------------------ holder and shank contact
STOCK = "box:0,0,-20,100,50,0"
# three step-downs of 5-6 mm with 10 mm of flutes: the flutes are never overrun, but at
# Z-16 the holder's face (15 mm above the tip) is 1 mm into the stock's top (lines 8-10)
POCKET = """G21 G90 G17
G0 X50 Y25 Z5
G1 Z-5 F100
G1 X60
G1 Z-10
G1 X50
G0 Z5
G1 Z-16
G1 X60
G0 Z5
M2
"""
HOLDER_TOOL = "0=flat:6,flute=10,shank=6,shank_length=5,holder=40"
CLEAN_TOOL = "0=flat:6,flute=10,shank=6,shank_length=20,holder=40"


def sim(tmp_path: Path, text: str, *args: str) -> tuple[int, dict[str, object]]:
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["sim", str(prog), "--stock", STOCK, "--format", "json", *args])
    assert res.exit_code in (0, 1), res.output
    return res.exit_code, json.loads(res.stdout)


def test_holder_contact_fires_alone_and_a_longer_shank_is_clean(tmp_path: Path) -> None:
    rc, out = sim(tmp_path, POCKET, "--tool", HOLDER_TOOL)
    findings = out["findings"]
    assert isinstance(findings, list)
    assert {f["code"] for f in findings} == {"SIM-HOLDER"}
    assert sorted(f["line"] for f in findings) == [8, 9, 10]  # 10 leaves the contact
    assert rc == 1
    assert max(f["value"] for f in findings) == pytest.approx(1.0)
    rc, out = sim(tmp_path, POCKET, "--tool", CLEAN_TOOL)
    assert rc == 0 and out["findings"] == []


def test_a_shank_as_wide_as_the_cutter_rubs_when_the_flutes_are_overrun(tmp_path: Path) -> None:
    text = "G21 G90\nG0 X50 Y25 Z5\nG1 Z-12 F100\nG1 X60\nG0 Z5\nM2\n"
    rc, out = sim(tmp_path, text, "--tool", "0=flat:6,flute=10,shank=6")
    findings = out["findings"]
    assert isinstance(findings, list)
    assert {(f["code"], f["line"]) for f in findings} == {
        ("SIM-FLUTE-DEPTH", 3),
        ("SIM-FLUTE-DEPTH", 4),
        ("SIM-HOLDER", 3),
        ("SIM-HOLDER", 4),
    }
    assert rc == 1


def test_air_cutting_share_is_a_note_per_tool(tmp_path: Path) -> None:
    text = "G21 G90\nG0 X10 Y25 Z5\nG1 Z-1 F100\nG1 X20\nG1 Z2\nG1 X90\nG0 Z5\nM2\n"
    rc, out = sim(tmp_path, text, "--tool", "0=flat:6")
    findings = out["findings"]
    assert isinstance(findings, list)
    assert [(f["code"], f["severity"]) for f in findings] == [("SIM-AIR-CUTTING", "note")]
    tools = out["tools"]
    assert isinstance(tools, dict)
    use = tools["0"]
    assert use["feed_length"] == pytest.approx(6 + 10 + 3 + 70)
    assert use["air_length"] == pytest.approx(3 + 70)
    assert rc == 0
    _, out = sim(tmp_path, text.replace("G1 X90\n", ""), "--tool", "0=flat:6")
    assert out["findings"] == []


def test_a_tool_library_file_through_the_cli(tmp_path: Path) -> None:
    lib = tmp_path / "lib.toml"
    lib.write_text('[tools.0]\ntype = "drill"\ndiameter = 8\nangle = 118\n')
    text = "G21 G90\nG0 X40 Y20 Z5\nG1 Z-12 F100\nG0 Z5\nM2\n"
    _, out = sim(tmp_path, text, "--tools", str(lib), "--resolution", "0.1")
    cone = 4 / math.tan(math.radians(59))
    exact = math.pi * 16 * (12 - cone) + math.pi * 16 * cone / 3
    assert abs(float(out["removed_volume"]) - exact) / exact < 0.005
    lib.write_text("[tools.0]\ntype = 'flat'\n")
    prog = tmp_path / "p.ngc"
    res = CliRunner().invoke(cli, ["sim", str(prog), "--stock", STOCK, "--tools", str(lib)])
    assert res.exit_code == 1 and "SIM-TOOL" in res.output and "lib.toml" in res.output


# ------------------------------------------------------------ the same through cnc check
def check_rules(tmp_path: Path, text: str, *args: str) -> tuple[int, set[tuple[str, str, int]]]:
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["check", str(prog), "-f", "json", *args])
    assert res.exit_code in (0, 1), res.output
    doc = json.loads(res.stdout)
    found = {
        (f["rule"], f["code"] or "", int(f["line"])) for r in doc["files"] for f in r["findings"]
    }
    return res.exit_code, found


def test_cnc_check_with_stock_reports_the_simulation_as_rules(tmp_path: Path) -> None:
    spindle = POCKET.replace("G21 G90 G17", "G21 G90 G17 M3 S8000")
    lib = tmp_path / "lib.toml"
    lib.write_text(
        '[tools.0]\ntype = "flat"\ndiameter = 6\nflute_length = 10\nshank_diameter = 6\n'
        "shank_length = 5\nholder_diameter = 40\n"
    )
    rc, found = check_rules(tmp_path, spindle, "--stock", STOCK, "--tools", str(lib))
    assert found == {("CNC902", "SIM-HOLDER", n) for n in (8, 9, 10)}
    assert rc == 1
    rc, found = check_rules(tmp_path, spindle)  # no stock: no simulation
    assert rc == 0 and found == set()
    lib.write_text(lib.read_text().replace("shank_length = 5", "shank_length = 20"))
    rc, found = check_rules(tmp_path, spindle, "--stock", STOCK, "--tools", str(lib))
    assert rc == 0 and found == set()
    # the profile's [stock] and [check.rules] severities apply to the simulated rules too
    profile = tmp_path / "m.toml"
    here = Path(__file__).parent / "check"
    shop = (here / "shop.toml").read_text()
    (tmp_path / "shop.tbl").write_text((here / "shop.tbl").read_text())
    profile.write_text(shop + "\n[stock]\nbox = [0, 0, -20, 100, 50, 0]\nresolution = 1.0\n")
    text = spindle.replace("G1 X60\nG0 Z5\nM2", "G1 X60\nG0 Z5\nG0 X20 Y25 Z-1\nG0 Z5\nM2")
    _, found = check_rules(tmp_path, text, "-m", str(profile))
    assert ("CNC901", "SIM-RAPID-IN-STOCK", 11) in found
    res = CliRunner().invoke(cli, ["check", "-m", str(profile), "--list-rules"])
    assert any(line.startswith("CNC902") and " error " in line for line in res.output.splitlines())


# ------------------------------------------------------------ design comparison
SLOT = "G21 G90 G17 M3 S8000\nG0 X20 Y25.03 Z5\nG1 Z-3 F100\nG1 X80\nG0 Z5\nM2\n"


def ascii_stl(path: Path, triangles: list[tuple[tuple[float, float, float], ...]]) -> None:
    """An ASCII STL written here, independently of kernel.stock.mesh."""
    rows = ["solid design"]
    for tri in triangles:
        rows += ["facet normal 0 0 1", "outer loop"]
        rows += [f"vertex {x} {y} {z}" for x, y, z in tri]
        rows += ["endloop", "endfacet"]
    path.write_text("\n".join([*rows, "endsolid design"]) + "\n")


def plane(path: Path, x0: float, y0: float, x1: float, y1: float, z: tuple[float, float]) -> None:
    """A rectangle whose Z goes linearly from z[0] at x0 to z[1] at x1, as two triangles."""
    a, b, c, d = (x0, y0, z[0]), (x1, y0, z[1]), (x1, y1, z[1]), (x0, y1, z[0])
    ascii_stl(path, [(a, b, c), (a, c, d)])


def test_design_gouge_is_located_at_the_move_that_cut_the_worst_cell(tmp_path: Path) -> None:
    """Design z = -3 + 0.01 (x - 20) over the whole stock, slot cut to -3: the stock is below
    the design by 0.01 (x - 20) in the slot, worst at its far end (x < 85, line 4); material
    left everywhere else (up to 3.2 mm at x = 0)."""
    stl = tmp_path / "d.stl"
    plane(stl, 0, 0, 100, 50, (-3.2, -2.2))
    rc, out = sim(
        tmp_path, SLOT, "--tool", "0=flat:10", "--design", str(stl), "--resolution", "0.25"
    )
    findings = {f["code"]: f for f in out["findings"]}
    assert set(findings) == {"SIM-GOUGE", "SIM-LEFTOVER"} and rc == 1
    g = findings["SIM-GOUGE"]
    assert g["line"] == 4 and g["severity"] == "error"
    assert 84.5 < g["x"] < 85 and (g["x"] - 80) ** 2 + (g["y"] - 25.03) ** 2 <= 25
    assert g["value"] == pytest.approx(0.01 * (g["x"] - 20), abs=1e-9)
    left = findings["SIM-LEFTOVER"]
    # the worst is at the lowest x, a cell never cut: no line
    assert not left["line"] and left["value"] == pytest.approx(3.2 - 0.01 * 0.125, abs=1e-9)


def test_design_clean_and_leftover_alone(tmp_path: Path) -> None:
    stl = tmp_path / "d.stl"
    plane(stl, 20, 21, 80, 29, (-3.0, -3.0))  # inside the slot's straight part: exact
    rc, out = sim(tmp_path, SLOT, "--tool", "0=flat:10", "--design", str(stl))
    assert rc == 0 and out["findings"] == []
    design = out["design"]
    assert isinstance(design, dict) and design["gouge"] == 0 and design["leftover"] == 0
    plane(stl, 10, 21, 90, 29, (-3.0, -3.0))  # beyond the slot's round ends: material left
    rc, out = sim(tmp_path, SLOT, "--tool", "0=flat:10", "--design", str(stl))
    assert rc == 0
    assert [(f["code"], f["value"]) for f in out["findings"]] == [("SIM-LEFTOVER", 3.0)]


def test_design_outputs_and_a_binary_stl(tmp_path: Path) -> None:
    from kernel.stock.mesh import read_stl, stl_bytes

    tri = np.array(
        [[[0, 0, -1], [100, 0, -1], [100, 50, -1]], [[0, 0, -1], [100, 50, -1], [0, 50, -1]]]
    )
    verts, faces = tri.reshape(-1, 3), np.arange(6).reshape(2, 3)
    data = stl_bytes(verts.astype(float), faces)
    assert np.array_equal(read_stl(data), tri)
    stl = tmp_path / "d.stl"
    stl.write_bytes(data)
    out_dir = tmp_path / "out"
    rc, out = sim(
        tmp_path,
        SLOT,
        "--design",
        str(stl),
        "--tool",
        "0=flat:10",
        "-o",
        str(out_dir),
        "--resolution",
        "1",
    )
    assert rc == 1  # the slot is 2 mm below the design
    dev = np.load(out_dir / "p_deviation.npy")
    assert (
        dev.shape == (50, 100) and np.nanmin(dev) == pytest.approx(-2.0) and np.nanmax(dev) == 1.0
    )
    assert (out_dir / "p_deviation.png").read_bytes()[:4] == b"\x89PNG"
    summary = json.loads((out_dir / "p_sim.json").read_text())
    assert summary["grid"] == {"x0": 0.0, "y0": 0.0, "z0": -20.0, "dx": 1.0, "dy": 1.0}
    assert summary["files"] == {"height": "p_height.npy", "deviation": "p_deviation.npy"}
    (tmp_path / "bad.stl").write_text("hello")
    prog = tmp_path / "p.ngc"
    res = CliRunner().invoke(
        cli, ["sim", str(prog), "--stock", STOCK, "--design", str(tmp_path / "bad.stl")]
    )
    assert res.exit_code == 1 and "SIM-DESIGN" in res.output


@pytest.mark.slow
def test_step_design_through_cadquery(tmp_path: Path) -> None:
    """A STEP block whose top (Z-3) covers the slot's straight part, and one 1 mm higher."""
    cq = pytest.importorskip("cadquery")
    for top, codes in ((-3.0, []), (-2.0, ["SIM-GOUGE"])):
        step = tmp_path / "d.step"
        block = cq.Workplane("XY").box(60, 8, 2, centered=(False, False, False))
        cq.exporters.export(block.translate((20, 21, top - 2)), str(step))
        rc, out = sim(tmp_path, SLOT, "--tool", "0=flat:10", "--design", str(step))
        assert [f["code"] for f in out["findings"]] == codes
        assert rc == (1 if codes else 0)


def test_cylinder_stock(tmp_path: Path) -> None:
    """cyl:50,25,20,-10,0: a disc of material; a 50 mm face mill plunged 1 mm at its centre
    takes pi r^2 x 1; a rapid down in the bounding box's corner (outside the disc) hits
    nothing and one across the disc does (line 6)."""
    prog = tmp_path / "p.ngc"
    args = ["sim", str(prog), "--stock", "cyl:50,25,20,-10,0", "--format", "json"]
    prog.write_text("G21 G90\nG0 X50 Y25 Z5\nG1 Z-1 F100\nG0 Z5\nM2\n")
    res = CliRunner().invoke(cli, [*args, "--tool", "0=flat:50", "--resolution", "0.1"])
    out = json.loads(res.stdout)
    exact = math.pi * 20 * 20 * 1
    assert abs(out["removed_volume"] - exact) <= 2 * math.pi * 20 * math.hypot(0.1, 0.1) * 1
    prog.write_text("G21 G90\nG0 X31 Y6 Z5\nG0 Z-5\nG0 X32 Y7\nG0 Z5\nG0 X50 Y25 Z-1\nM2\n")
    res = CliRunner().invoke(cli, [*args, "--tool", "0=flat:2"])
    out = json.loads(res.stdout)
    assert [(f["code"], f["line"]) for f in out["findings"]] == [("SIM-RAPID-IN-STOCK", 6)]
    hf = HeightField(parse_stock_text("cyl:50,25,20,-10,0"), 0.1)
    assert abs(hf.volume() - hf.box.volume) <= 2 * math.pi * 20 * math.hypot(0.1, 0.1) * 10


def test_bull_nose_with_the_material_ceiling_against_dense_placement() -> None:
    """The compiled bull-nose sweep (Newton's method in a bracket) over random moves, many
    nearly level (the stationary point near the flat end's edge, where g'' jumps) and some
    steep: never above the tool placed at 2,001 points along the move, below it only by
    the sampling's step; with a random material top, a cell it leaves is never cut below
    that top (the pruning bounds hold)."""
    rng = np.random.default_rng(5)
    gx, gy = np.meshgrid(np.linspace(-8, 8, 21), np.linspace(-8, 8, 21))
    tool = make_tool("bull", 6.0, "t", corner_radius=1.0)

    def bull(rho: np.ndarray) -> np.ndarray:
        e = np.clip(rho - 2.0, 0.0, 1.0)
        return 1.0 - np.sqrt(1.0 - e * e)

    ts = np.linspace(0.0, 1.0, 1_001)[:, None, None]
    for k in range(12):
        d = rng.uniform(-5, 5, 3) * ((1, 1, 0.01), (1, 1, 1), (0.2, 0.2, 1))[k % 3]
        z0 = float(rng.uniform(-2, 2))
        rho = np.hypot(gx - ts * d[0], gy - ts * d[1])
        z = np.where(rho <= 3.0, z0 + ts * d[2] + bull(np.minimum(rho, 3.0)), np.inf)
        ref = z.min(axis=0)
        ceiling = ref + rng.uniform(-0.3, 0.3, ref.shape)
        step = float(np.abs(d).sum()) / 1_000 + 1e-9
        for top in (None, ceiling):
            got = tool_envelope(gx, gy, tuple(float(v) for v in d), z0, tool, top)
            cut = np.isfinite(ref) if top is None else ref < ceiling - step
            assert np.all(got[cut] <= ref[cut] + 1e-9)
            assert np.all(got[cut] >= ref[cut] - step)
            if top is not None:
                kept = np.isfinite(ref) & (ref >= ceiling)
                assert np.all(got[kept] >= ceiling[kept] - 1e-9)
