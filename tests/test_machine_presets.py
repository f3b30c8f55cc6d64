"""``cnc machine init --kind``: presets whose rules fit the machine, so ``cnc check`` does
not cry wolf on real programs.

The programs in ``tests/presets/`` are written as the common posts of each kind write them
(README there). Each runs correctly on its machine, so with its kind's preset it must give
no finding at all; with the built-in mill the same program is reported, which shows what
the preset changes. What each kind means comes from how the machines are programmed: a
laser's M3/M4 switch the beam and S is its power (Grbl 1.1 laser mode: G1 with S0 or M5
moves without burning), a plasma torch is switched by M3/M5 (Mach3/LinuxCNC posts) or
M07/M08 (EIA plasma controls), a router's spindle speed is often set by hand (M3 without
S), a lathe's T0101 applies the tool's offsets (no G43).
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from kernel.machine import DEFAULT_MACHINE, KINDS, parse_machine
from kernel.machine_presets import PRESETS

PROGRAMS = Path(__file__).resolve().parent / "presets"


def cnc(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.fixture(scope="module")
def profiles(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = {}
    root = tmp_path_factory.mktemp("profiles")
    for kind in KINDS:
        path = root / f"{kind}.toml"
        assert cnc("machine", "init", "--kind", kind, "-o", str(path)).exit_code == 0
        out[kind] = path
    return out


def findings(res) -> list[dict]:
    return [f for file in json.loads(res.stdout)["files"] for f in file["findings"]]


def test_every_kind_has_a_preset_that_validates_and_says_its_kind(profiles) -> None:
    assert set(PRESETS) == set(KINDS) == {"mill", "router", "laser", "plasma", "lathe"}
    for kind, path in profiles.items():
        res = cnc("machine", "validate", str(path))
        assert res.exit_code == 0, res.output
        machine = parse_machine(path.read_text(), str(path))
        assert machine.kind == kind
        assert machine == PRESETS[kind].machine()
        shown = cnc("machine", "show", str(path)).stdout
        assert parse_machine(shown).kind == kind


def test_the_lathe_preset_has_x_and_z_only(profiles) -> None:
    machine = parse_machine(profiles["lathe"].read_text())
    assert machine.axis_names == ("x", "z")
    text = profiles["lathe"].read_text()
    assert "G18" in text and "diameter" in text and "G96" in text


@pytest.mark.parametrize(
    ("program", "kind", "on_the_mill"),
    [
        ("laser_lightburn.gc", "laser", "CNC505"),  # G1 ... S0 moves with the beam off
        ("laser_m3_m5.nc", "laser", "CNC504"),  # G1 after M5 is a travel move
        ("plasma_sheetcam.tap", "plasma", "CNC505"),  # M03 without S lights the torch
        ("plasma_m07_m08.nc", "plasma", "CNC504"),  # M07/M08 switch the torch
        ("router_manual_spindle.nc", "router", "CNC505"),  # M3 without S: the dial
        ("lathe_fanuc.nc", "lathe", "CNC203"),  # T0101 applies the offsets
        ("lathe_linuxcnc.ngc", "lathe", "CNC203"),
    ],
)
def test_a_correct_program_is_clean_with_its_preset(
    profiles, program: str, kind: str, on_the_mill: str
) -> None:
    path = str(PROGRAMS / program)
    res = cnc("-q", "check", "-f", "json", "-m", str(profiles[kind]), path)
    assert res.exit_code == 0, res.output
    assert findings(res) == []
    mill = cnc("-q", "check", "-f", "json", path)
    assert on_the_mill in {f["rule"] for f in findings(mill)}


def test_a_mill_program_is_clean_on_the_mill_preset_and_the_default(profiles) -> None:
    path = str(PROGRAMS / "mill_fusion.ngc")
    for extra in (("-m", str(profiles["mill"])), ()):
        res = cnc("-q", "check", "-f", "json", *extra, path)
        assert res.exit_code == 0 and findings(res) == [], res.output
    laser = cnc("-q", "check", "-f", "json", "-m", str(profiles["laser"]), path)
    assert [f["rule"] for f in findings(laser)] == ["CNC501"]  # S9000 is no laser power


def test_the_beam_and_turret_kinds_still_catch_what_is_wrong(profiles, tmp_path: Path) -> None:
    laser = tmp_path / "hot.nc"
    laser.write_text("G21 G90\nG0 X10 Y10\nM3 S1200\nG1 X20 F1000\nM5\nM2\n")
    res = cnc("check", "-f", "json", "-m", str(profiles["laser"]), str(laser))
    (found,) = findings(res)
    assert found["rule"] == "CNC501" and found["message"].startswith("power S1200 exceeds")
    lathe = tmp_path / "y.ngc"
    lathe.write_text("G18 G21 G90\nT1 M6\nS500 M3\nG0 X10 Z2\nG1 Y5 F100\nM5\nM2\n")
    res = cnc("check", "-f", "json", "-m", str(profiles["lathe"]), str(lathe))
    assert findings(res)[0]["rule"] == "CNC102"  # (and CNC103: an axis it lacks has no speed)
    router = tmp_path / "stopped.nc"
    router.write_text("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG0 Z5\nM2\n")
    res = cnc("check", "-f", "json", "-m", str(profiles["router"]), str(router))
    assert {f["rule"] for f in findings(res)} == {"CNC504"}  # never switched on


def test_a_mistaken_kind_is_refused(tmp_path: Path) -> None:
    prof = tmp_path / "m.toml"
    prof.write_text('kind = "waterjet"\n[axes.x]\nmin = 0.0\nmax = 1.0\n')
    res = cnc("machine", "validate", str(prof))
    assert res.exit_code == 1 and "MACH-KIND" in res.stderr


# --------------------------------------------------------------------------- the default
def test_the_default_machine_has_the_starter_spindle_range() -> None:
    shown = tomllib.loads(cnc("machine", "show").stdout)
    assert shown["spindle"] == {"min_speed": 0.0, "max_speed": 12000.0}
    assert shown["kind"] == "mill"
    assert DEFAULT_MACHINE.extra["spindle"] == PRESETS["mill"].machine().extra["spindle"]


def test_default_machine_limits_say_where_they_come_from(tmp_path: Path, profiles) -> None:
    prog = tmp_path / "big.nc"
    prog.write_text("G21 G90\nG0 X0 Y0 Z5\nS40000 M3\nG1 Z-1 F100\nG0 Z250\nM5\nM2\n")
    res = cnc("check", "-f", "json", str(prog))
    by_rule = {f["rule"]: f["message"] for f in findings(res)}
    assert by_rule["CNC501"] == (
        "spindle speed S40000 exceeds the maximum 12000 rpm of the built-in default machine; "
        "give -m PROFILE"
    )
    assert by_rule["CNC101"].endswith(
        "beyond the travel limit 200 mm of the built-in default machine; give -m PROFILE"
    )
    own = cnc("check", "-f", "json", "-m", str(profiles["mill"]), str(prog))
    mine = {f["rule"]: f["message"] for f in findings(own)}
    assert mine["CNC501"] == "spindle speed S40000 exceeds the maximum 12000 rpm"
    assert mine["CNC101"].endswith("beyond the travel limit 200 mm")
