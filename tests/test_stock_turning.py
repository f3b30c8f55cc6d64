"""The turning profile (kernel/stock/turning.py, ``cnc sim`` on a bar) against closed forms.

A straight pass to radius R1 over L removes pi (R0^2 - R1^2) L; a facing pass removes the
bar's end as a disc; a grooving plunge of a W wide insert a ring of width W. A nose radius
rn leaves at each corner the "spandrel" between the corner's square and its quarter
circle, area (1 - pi/4) rn^2 with its centroid (10 - 3 pi) / (12 - 3 pi) rn from the corner
along each axis, revolved by Pappus. The grid is aligned with the cuts, so a sharp insert
is exact to rounding; a rounded corner is within its cells' share (each cell on the
fillet is wrong by at most its width times the fillet's rise across it).
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
from kernel.stock.mesh import mesh_volume
from kernel.stock.tools import library_from_toml, make_tool
from kernel.stock.turning import (
    Bar,
    TurnedProfile,
    insert_envelope,
    parse_bar,
    revolved_mesh,
    simulate_turning,
)

SPANDREL = (10 - 3 * math.pi) / (12 - 3 * math.pi)  # centroid offset over rn


def spandrel_ring(radius: float, rn: float) -> float:
    """Volume of a corner's spandrel revolved with the corner at ``radius``."""
    return 2 * math.pi * (radius + SPANDREL * rn) * (1 - math.pi / 4) * rn * rn


def turn(cmds: list[canon.Command], bar: Bar, nose: float, width: float = 0.0) -> float:
    prof = TurnedProfile(bar, 0.1)
    kw = {"width": width} if width else {}
    tool = make_tool("insert", nose, "t", **kw)
    return simulate_turning(cmds, prof, {0: tool}).removed_volume


@pytest.mark.parametrize("nose", [0.0, 0.8])
def test_straight_turning_pass(nose: float) -> None:
    cmds: list[canon.Command] = [
        canon.StraightTraverse(26, 0, 2),
        canon.StraightFeed(20, 0, 2),
        canon.StraightFeed(20, 0, -30),
        canon.StraightTraverse(30, 0, -30),
    ]
    got = turn(cmds, Bar(25, -60, 0), nose)
    exact = math.pi * (25**2 - 20**2) * 30 - spandrel_ring(20, nose)
    if nose == 0:
        assert got == pytest.approx(exact, rel=1e-12)
    assert abs(got - exact) <= 2 * math.pi * 25 * 0.1 * nose + 1e-6


def test_facing_pass_past_the_centre() -> None:
    cmds: list[canon.Command] = [
        canon.StraightTraverse(27, 0, 0),
        canon.StraightFeed(-0.5, 0, 0),
        canon.StraightTraverse(-0.5, 0, 3),
    ]
    assert turn(cmds, Bar(25, -60, 1), 0.0) == pytest.approx(math.pi * 25**2, rel=1e-12)


def test_grooving_plunge_is_a_ring_of_the_insert_width() -> None:
    """A 3 mm insert, nose 0.2, tip corner at Z-20: the groove spans Z-20..-17, to R20."""
    cmds: list[canon.Command] = [
        canon.StraightTraverse(27, 0, -20),
        canon.StraightFeed(20, 0, -20),
        canon.StraightTraverse(27, 0, -20),
    ]
    got = turn(cmds, Bar(25, -60, 0), 0.2, width=3.0)
    exact = math.pi * (25**2 - 20**2) * 3 - 2 * spandrel_ring(20, 0.2)
    assert abs(got - exact) <= 2 * 2 * math.pi * 25 * 0.1 * 0.2


def test_insert_envelope_against_the_insert_placed_densely() -> None:
    rng = np.random.default_rng(7)
    s = np.linspace(-15, 15, 161)
    ts = np.linspace(0, 1, 2001)
    for k in range(30):
        width = rng.uniform(1, 8)
        nose = rng.uniform(0, width / 2)
        dz, dx = rng.uniform(-10, 10, 2)
        dz = 0.0 if k % 7 == 0 else dz
        env = insert_envelope(s, dz, dx, 1.0, width, nose)
        rho = np.abs(s[:, None] - ts[None, :] * dz)
        e = np.clip(rho - (width / 2 - nose), 0, nose)
        f = np.where(rho <= width / 2, nose - np.sqrt(np.maximum(nose**2 - e**2, 0)), np.inf)
        sampled = np.min(1.0 + ts[None, :] * dx + f, axis=1)
        inside = np.isfinite(sampled)
        assert np.array_equal(inside, np.isfinite(env))
        # never above the samples; below them by at most the sampling step's rise
        step = (abs(dz) + abs(dx)) / 2000
        assert np.all(env[inside] <= sampled[inside] + 1e-9)
        assert np.all(env[inside] >= sampled[inside] - step - 1e-9)


def test_the_revolved_mesh_is_closed_and_holds_the_profile() -> None:
    prof = TurnedProfile(Bar(25, -60, 0), 0.5)
    prof.r[prof.zs > -30] = 20.0
    verts, faces = revolved_mesh(prof, 96)
    polygon = 96 / (2 * math.pi) * math.sin(2 * math.pi / 96)  # inscribed polygon's share
    # frustums between the rings through the cell centres (the end rings at the faces)
    z = np.concatenate([[-60.0], prof.zs[1:-1], [0.0]])
    ra, rb, h = prof.r[:-1], prof.r[1:], np.diff(z)
    frustums = float(np.sum(math.pi * h / 3 * (ra * ra + ra * rb + rb * rb)))
    assert mesh_volume(verts, faces) == pytest.approx(frustums * polygon, rel=1e-9)
    assert frustums == pytest.approx(prof.volume(), abs=math.pi * (25**2 - 20**2) * 0.5)


def test_bars_and_inserts_are_checked() -> None:
    assert parse_bar("bar:25,-60,0") == Bar(25, -60, 0)
    for bad in ("bar:25,0", "bar:-1,0,1", "bar:5,1,0", "box:0,0,0,1,1,1"):
        with pytest.raises(Diagnostic) as exc:
            parse_bar(bad)
        assert exc.value.code == "SIM-STOCK"
    lib = library_from_toml({"tools": {"1": {"type": "insert", "nose_radius": 0.4, "width": 4}}})
    assert (lib[1].kind, lib[1].corner_radius, lib[1].width) == ("insert", 0.4, 4.0)
    with pytest.raises(Diagnostic):
        make_tool("insert", 3.0, "t", width=4.0)  # wider nose than the insert


# ------------------------------------------------------------------ cnc sim on a bar
NGC = "G21 G18 G7 G90\nT1 M6\nG0 X52 Z2\nG1 X40 F100\nG1 Z-30\nG0 X60\nM2\n"
FANUC = "G21 G18 G40\nT0101\nG97 S1000 M3\nG0 X52. Z2.\nG1 X40. F0.2\nG1 Z-30.\nG0 X60.\nM30\n"
BAR = "bar:25,-60,0"
PASS = math.pi * (25**2 - 20**2) * 30


def sim(tmp_path: Path, text: str, name: str, *args: str) -> tuple[int, dict, str]:
    prog = tmp_path / name
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["sim", str(prog), "--format", "json", *args])
    assert res.exit_code in (0, 1), res.output
    return res.exit_code, (json.loads(res.stdout) if res.stdout.startswith("{") else {}), res.output


def test_diameter_mode_programs_of_two_dialects_turn_the_same(tmp_path: Path) -> None:
    args = ("--tool", "1=insert:0", "--resolution", "0.1")
    rc, out, _ = sim(tmp_path, NGC, "p.ngc", "--stock", BAR, *args)
    assert rc == 0 and out["turning"] and out["findings"] == []
    assert out["removed_volume"] == pytest.approx(PASS, rel=1e-9)
    rc, fanuc, _ = sim(tmp_path, FANUC, "p.nc", "--stock", BAR, "--dialect", "fanuc_lathe", *args)
    assert rc == 0 and fanuc["removed_volume"] == pytest.approx(PASS, rel=1e-9)
    # a lathe dialect with a box stock is refused with a located error
    rc, _, text = sim(
        tmp_path, FANUC, "p.nc", "--stock", "box:0,0,0,1,1,1", "--dialect", "fanuc_lathe"
    )
    assert rc == 1 and "SIM-STOCK" in text


def test_a_rapid_into_the_bar_is_an_error_at_its_line(tmp_path: Path) -> None:
    text = NGC.replace("G0 X60\nM2", "G0 X60\nG0 Z-40\nG0 X44\nM2")  # line 8: to R22 < 25
    rc, out, _ = sim(tmp_path, text, "p.ngc", "--stock", BAR)
    assert rc == 1
    (f,) = out["findings"]
    assert (f["code"], f["line"], f["severity"]) == ("SIM-RAPID-IN-STOCK", 8, "error")
    assert f["value"] == pytest.approx(3.0) and -40 <= f["z"] <= -34
    res = CliRunner().invoke(cli, ["check", str(tmp_path / "p.ngc"), "--stock", BAR, "-f", "json"])
    doc = json.loads(res.stdout)
    rules = {(x["rule"], x["line"]) for r in doc["files"] for x in r["findings"]}
    assert ("CNC901", 8) in rules and res.exit_code == 1


def test_turning_outputs_and_refusals(tmp_path: Path) -> None:
    out_dir = tmp_path / "out"
    rc, _, _ = sim(tmp_path, NGC, "p.ngc", "--stock", BAR, "-o", str(out_dir))
    assert rc == 0
    rows = (out_dir / "p_profile.csv").read_text().splitlines()
    assert rows[0] == "z,radius,diameter" and len(rows) == 121
    z, r, d = (float(v) for v in rows[-1].split(","))
    assert (z, r, d) == (-0.25, 20.0, 40.0)
    stl = (out_dir / "p_stock.stl").read_bytes()
    assert len(stl) == 84 + 50 * int.from_bytes(stl[80:84], "little")
    assert json.loads((out_dir / "p_sim.json").read_text())["files"] == {"profile": "p_profile.csv"}
    rc, _, text = sim(tmp_path, NGC, "p.ngc", "--stock", BAR, "--tool", "1=flat:10")
    assert rc == 1 and "SIM-UNSUPPORTED" in text and "p.ngc:4" in text
    rc, _, text = sim(tmp_path, NGC.replace("G1 Z-30", "G1 Y3 Z-30"), "p.ngc", "--stock", BAR)
    assert rc == 1 and "SIM-UNSUPPORTED" in text
    mill = "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM2\n"
    rc, _, text = sim(
        tmp_path, mill, "m.ngc", "--stock", "box:-10,-10,-10,10,10,0", "--tool", "1=insert:0.4"
    )
    assert rc == 1 and "SIM-UNSUPPORTED" in text


G71 = (
    "G21 G18 G40\nT0101\nG97 S1000 M3\nG0 X54. Z2.\nG71 U2. R0.5\n"
    "G71 P10 Q20 U{u}. W0. F0.2\nN10 G0 X40.\nG1 Z-30.\nN20 X54.\nG0 X60. Z5.\nM30\n"
)


@pytest.mark.parametrize("allowance", [0, 1])
def test_a_fanuc_g71_roughing_cycle_turns_its_contour(tmp_path: Path, allowance: int) -> None:
    """G71 roughs the bar down to the contour (diameter 40 over Z0..-30) plus the finishing
    allowance U (on the diameter), in 2 mm passes that retract at 45°, then follows the
    contour offset by U: a sharp insert leaves exactly the cylinder of radius 20 + U/2, and
    no rapid of the cycle enters material."""
    rc, out, _ = sim(
        tmp_path,
        G71.format(u=allowance),
        "p.nc",
        "--stock",
        BAR,
        "--dialect",
        "fanuc_lathe",
        "--tool",
        "1=insert:0",
        "--resolution",
        "0.1",
    )
    r1 = 20 + allowance / 2
    assert rc == 0 and out["findings"] == []
    assert out["removed_volume"] == pytest.approx(math.pi * (25**2 - r1**2) * 30, rel=1e-9)


def test_a_lathe_profile_picks_the_turning_profile(tmp_path: Path) -> None:
    axes = "".join(
        f"[axes.{a}]\nmin = -200.0\nmax = 200.0\nvelocity = 100.0\n" for a in ("x", "y", "z")
    )
    profile = tmp_path / "lathe.toml"
    profile.write_text(f'name = "lathe"\nkind = "lathe"\n{axes}[stock]\nbar = [25, -60, 0]\n')
    args = ("-m", str(profile), "--tool", "1=insert:0", "--resolution", "0.1")
    rc, out, _ = sim(tmp_path, NGC, "p.ngc", *args)
    assert rc == 0 and out["turning"]
    assert out["removed_volume"] == pytest.approx(PASS, rel=1e-9)
    profile.write_text(
        profile.read_text().replace("bar = [25, -60, 0]", "box = [0, 0, 0, 1, 1, 1]")
    )
    rc, _, text = sim(tmp_path, NGC, "p.ngc", *args)
    assert rc == 1 and "SIM-STOCK" in text
