"""IR -> segment table (units, offsets, feed rules, barriers), measurements and `cnc plan`."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from cli.plan import command
from gcode.ngc.interpreter import interpret_text
from kernel.diagnostics import Diagnostic
from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, AxisLimits, Controller, Machine, with_controller
from kernel.path.build import build_path
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, DWELL, HOLD, LINE, RAPID, TOOL_CHANGE
from kernel.plan.planner import plan
from kernel.report.measure import chord_error, cycle_time, measure

MILL = Machine(
    "t",
    tuple(AxisLimits(n, velocity=200.0, acceleration=2000.0) for n in "xyz"),
    Controller(tool_change_time=4.0),
)


def test_inch_program_and_origin_offsets_become_machine_millimetres():
    cmds = [
        canon.UseLengthUnits(canon.Units.INCHES),
        canon.SetOriginOffsets(1.0, 0.0, 0.0),
        canon.SetFeedRate(60.0),  # 60 in/min = 25.4 mm/s
        canon.StraightFeed(1.0, 2.0, 0.0),
    ]
    seg = build_path(cmds, MILL).segments
    assert seg["end"][-1][:3] == pytest.approx([50.8, 50.8, 0.0])
    assert seg["feed"][-1] == pytest.approx(25.4)
    assert seg["length"][-1] == pytest.approx(math.hypot(50.8, 50.8))


def test_tool_length_offsets_move_the_machine_with_the_work_offset():
    """The tool length offset adds to the work offset (machine = program + G5x + tool, as
    LinuxCNC's canon and Grbl's gcode.c place the tool): a new offset moves the next
    move's machine end, in program units at the time, not rotated."""
    text = "G21 G90\nG0 Z5\nG43.1 Z2\nG0 Z1\nG10 L2 P1 X10\nG0 X1\n"
    text += "G20\nG43.1 Z1\nG0 Z0\nG49\nG0 Z0.5\n"
    seg = build_path(interpret_text(text + "M2\n"), MILL).segments
    moves = seg[seg["kind"] != HOLD]
    want = [[0, 0, 5], [0, 0, 3], [11, 0, 3], [11, 0, 25.4], [11, 0, 12.7]]
    assert moves["end"][:, :3] == pytest.approx(np.array(want, dtype=float))


def test_inverse_time_program_moves_last_one_over_f_minutes():
    # G1 X30 Y40 F2 in G93: 50 mm in 1/2 min; the interpreter emits 100 mm/min (as rs274)
    cmds = list(interpret_text("G21 G90 G93\nG1 X30 Y40 F2\nM2\n"))
    seg = build_path(cmds, MILL).segments
    moves = seg[seg["length"] > 0]
    assert moves["length"][0] / moves["feed"][0] == pytest.approx(30.0)  # seconds


def test_feed_per_revolution_uses_the_spindle_speed():
    cmds = [
        canon.SetSpindleSpeed(600.0),
        canon.SetFeedMode(canon.FeedMode.UNITS_PER_REVOLUTION),
        canon.SetFeedRate(0.1),
        canon.StraightFeed(10.0, 0.0, 0.0),
    ]
    assert build_path(cmds, MILL).segments["feed"][0] == pytest.approx(1.0)  # 0.1*600/60


def test_rotary_only_move_feed_is_degrees_per_minute():
    m = Machine("4ax", (*MILL.axes, AxisLimits("a", velocity=360.0, acceleration=3600.0)))
    cmds = [canon.SetFeedRate(600.0), canon.StraightFeed(0, 0, 0, 90.0)]
    seg = build_path(cmds, m).segments
    assert seg["length"][0] == pytest.approx(90.0) and seg["feed"][0] == pytest.approx(10.0)


def test_helix_feed_is_along_the_three_dimensional_path():
    cmds = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10, 0, 0),
        canon.ArcFeed(10, 0, 0, 0, 1, 5.0),
    ]  # full turn of R 10 rising 5
    seg = build_path(cmds, MILL).segments
    assert seg["kind"][1] == ARC
    assert seg["length"][1] == pytest.approx(math.hypot(2 * math.pi * 10, 5))
    p = plan(build_path(cmds, MILL), MILL)
    s = sample(p)
    speed = np.linalg.norm(s.velocity, axis=1)
    assert speed.max() == pytest.approx(10.0, rel=1e-9)
    assert np.array_equal(s.position[-1], [10.0, 0.0, 5.0])


def test_arcs_in_the_xz_plane_put_z_first():
    # from (x 10, z 0) CCW about +Y (Z x X = Y) around the origin to (z 10, x 0): in the
    # (Z, X) plane from 90 deg to 0 deg counter-clockwise, i.e. 270 deg through z = -10
    cmds = [
        canon.SelectPlane(canon.Plane.XZ),
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10, 0, 0),
        canon.ArcFeed(10.0, 0.0, 0.0, 0.0, 1, 0.0),
    ]
    path = build_path(cmds, MILL)
    seg = path.segments
    assert seg["kind"][1] == ARC and np.allclose(seg["normal"][1], [0, 1, 0])
    assert seg["sweep"][1] == pytest.approx(1.5 * math.pi)
    third = evaluate(seg, np.array([1]), np.array([seg["length"][1] / 3]))[0][0]
    assert third[:3] == pytest.approx([0.0, 0.0, -10.0], abs=1e-12)


def test_barriers_are_holds_with_their_durations():
    cmds = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10, 0, 0),
        canon.Dwell(0.5),
        canon.ChangeTool(2),
        canon.StraightTraverse(0, 0, 0),
        canon.ProgramEnd(),
    ]
    path = build_path(cmds, MILL)
    seg = path.segments
    assert list(seg["kind"]) == [LINE, HOLD, HOLD, LINE, HOLD]
    assert list(seg["duration"][[1, 2]]) == [0.5, 4.0]
    assert seg["category"][1] == DWELL and seg["category"][2] == TOOL_CHANGE
    assert seg["category"][3] == RAPID
    p = plan(path, MILL)
    c = cycle_time(p)
    assert c.dwell == 0.5 and c.tool_change == 4.0
    assert c.total == pytest.approx(c.cutting + c.rapid + c.dwell + c.tool_change + c.other)
    assert c.cutting == pytest.approx(10 / 10 + 10 / 2000)
    s = sample(p)
    dwelling = s.segment < 0
    assert dwelling.sum() == pytest.approx(4500, abs=2)  # 4.5 s of holds at 1 ms
    assert np.all(s.velocity[dwelling] == 0)


def test_a_move_of_a_missing_axis_is_a_diagnostic_with_its_line():
    loc = canon.Source("p.ngc", 7, 1)
    with pytest.raises(Diagnostic) as e:
        build_path(
            [canon.SetFeedRate(100), canon.StraightFeed(0, 0, 0, 5.0, source=loc)], MILL, "p.ngc"
        )
    assert e.value.code == "PLAN-AXIS" and e.value.location.line == 7


def test_a_feed_move_without_feed_rate_is_a_diagnostic():
    with pytest.raises(Diagnostic) as e:
        build_path([canon.StraightFeed(1, 0, 0)], MILL)
    assert e.value.code == "PLAN-FEED"


def test_limit_hits_name_the_axis_kind_and_source_line():
    m = Machine("small", tuple(AxisLimits(n, min=-5.0, max=5.0) for n in "xyz"), Controller())
    src = canon.Source("p.ngc", 12, 1)
    cmds = [canon.SetFeedRate(600), canon.StraightFeed(8.0, 0, 0, source=src)]
    p = plan(build_path(cmds, m, "p.ngc"), m)
    rep = measure(p, sample(p))
    assert rep.hits_total == 1
    hit = rep.hits[0]
    assert (hit.axis, hit.kind, hit.limit, hit.line) == ("x", "travel", 5.0, 12)
    assert hit.value == pytest.approx(8.0)


def test_sampled_circle_methods_keep_their_chord_error():
    cmds = [
        canon.SetFeedRate(1200.0),
        canon.StraightFeed(20, 0, 0),
        canon.ArcFeed(-20, 0, 0, 0, 1, 0),
    ]
    errs = {}
    for method in ("exact", "improved_tustin", "taylor"):
        m = with_controller(MILL, circle_method=method, chord_tolerance=0.01)
        p = plan(build_path(cmds, m), m)
        s = sample(p)
        errs[method] = chord_error(p, s)
        assert np.array_equal(s.position[-1], [-20.0, 0.0, 0.0])
    assert errs["exact"] < 1e-4
    assert 0.009 < errs["improved_tustin"] <= 0.0101  # vertices at R + E, chords to R - E
    assert errs["taylor"] <= 0.0101


def test_plan_command_prints_the_breakdown_and_json(tmp_path):
    prog = tmp_path / "p.canon"
    text = "\n".join(
        c.to_text()
        for c in [
            canon.SetFeedRate(600.0),
            canon.StraightFeed(10, 0, 0),
            canon.Dwell(1.0),
            canon.StraightTraverse(0, 0, 0),
            canon.ProgramEnd(),
        ]
    )
    prog.write_text(text + "\n")
    r = CliRunner().invoke(command, [str(prog)])
    assert r.exit_code == 0, r.output
    assert "cutting" in r.output and "dwell" in r.output and "no limit hits" in r.output
    r = CliRunner().invoke(command, [str(prog), "--format", "json"])
    data = json.loads(r.output)
    assert data["cycle"]["dwell"] == 1.0
    assert data["cycle"]["cutting"] == pytest.approx(1.0 + 10 / 2000)


def test_plan_command_reports_program_errors_with_exit_1(tmp_path):
    prog = tmp_path / "bad.canon"
    prog.write_text("STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n")
    r = CliRunner().invoke(command, [str(prog)])
    assert r.exit_code == 1
    assert "PLAN-FEED" in r.output


def test_plan_command_reads_a_machine_profile(tmp_path):
    prog = tmp_path / "p.canon"
    prog.write_text(
        "SET_FEED_RATE(600.0000)\nSTRAIGHT_FEED(20.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
    )
    mach = tmp_path / "m.toml"
    mach.write_text("[axes.x]\nmax = 10.0\n[axes.y]\n[axes.z]\n")
    r = CliRunner().invoke(command, [str(prog), "--machine", str(mach), "--format", "json"])
    assert r.exit_code == 0, r.output
    hits = json.loads(r.output)["hits"]
    assert hits and hits[0]["kind"] == "travel" and hits[0]["line"] == 2
    assert DEFAULT_MACHINE.controller.interpolation_period == 0.001


def test_nurbs_feed_is_planned_within_the_chord_tolerance_of_the_curve():
    from kernel.interp.nurbs import NurbsCurve
    from kernel.interp.nurbs import evaluate as nurbs_at

    w = 1 / math.sqrt(2)
    pts = ((0.0, 0.0, 1.0), (0.0, 5.0, w), (5.0, 5.0, 1.0), (10.0, 5.0, w), (10.0, 0.0, 1.0))
    knots = (0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0)
    cmds = [canon.SetFeedRate(1200.0), canon.NurbsFeed(3, pts, knots)]
    m = with_controller(MILL, chord_tolerance=0.001)
    p = plan(build_path(cmds, m), m)
    s = sample(p)
    on_arc = s.segment >= 0
    r = np.hypot(s.position[on_arc, 0] - 5.0, s.position[on_arc, 1])
    assert np.all(r <= 5.0 + 1e-9) and np.all(r >= 5.0 - 0.001 * 1.01)
    assert np.array_equal(s.position[-1], [10.0, 0.0, 0.0])
    curve = NurbsCurve.create(
        np.array([q[:2] for q in pts]), np.array([q[2] for q in pts]), knots, 2
    )
    assert nurbs_at(curve, [0.5])[0] == pytest.approx([5, 5])
    assert np.linalg.norm(s.velocity, axis=1).max() <= 20.0 * (1 + 1e-9)


def test_linuxcnc_work_offsets_and_xy_rotation_map_program_to_machine():
    # G92 first, then the XY rotation, then the G5x offset (rs274's order)
    cmds = [
        canon.SetG5xOffset(1, 100.0, 0.0, -50.0),
        canon.SetG92Offset(1.0, 0.0, 0.0),
        canon.SetXYRotation(90.0),
        canon.SetFeedRate(600.0),
        canon.StraightFeed(9.0, 0.0, 0.0),
        canon.ArcFeed(9.0, 2.0, 9.0, 1.0, 1, 0.0),  # half circle about (9, 1)
    ]
    seg = build_path(cmds, MILL).segments
    assert seg["end"][0][:3] == pytest.approx([100.0, 10.0, -50.0])  # R90 (10, 0) + g5x
    assert seg["kind"][1] == ARC
    assert seg["centre"][1][:2] == pytest.approx([99.0, 10.0])
    assert seg["end"][1][:3] == pytest.approx([98.0, 10.0, -50.0])
    mid = evaluate(seg, np.array([1]), np.array([seg["length"][1] / 2]))[0][0]
    assert mid[:3] == pytest.approx([99.0, 11.0, -50.0])  # CCW still CCW after rotation


def test_rigid_tap_runs_down_and_back_synchronised_with_stops():
    cmds = [
        canon.SetSpindleSpeed(200.0),
        canon.StraightTraverse(0, 0, 5.0),
        canon.StartSpeedFeedSynch(1.5),
        canon.RigidTap(0, 0, -10.0),
        canon.StopSpeedFeedSynch(),
    ]
    p = plan(build_path(cmds, MILL), MILL)
    seg = p.path.segments
    assert list(seg["kind"]) == [LINE, LINE, LINE]
    assert seg["feed"][1:] == pytest.approx([5.0, 5.0])  # 1.5 mm/rev x 200 rpm
    assert seg["end"][1][2] == -10.0 and seg["end"][2][2] == 5.0
    assert p.v_junction[2] == 0.0  # the spindle reverses at the bottom


SIX_AXES = Machine(
    "6ax",
    (
        *DEFAULT_MACHINE.axes,
        *(AxisLimits(n, velocity=3600.0, acceleration=36000.0, jerk=1e6) for n in "abc"),
    ),
    DEFAULT_MACHINE.controller,
)


def test_golden_programs_plan_within_every_axis_limit():
    """Every golden rs274 output (tests/golden/ngc) plans, samples and ends where it should,
    with no velocity or acceleration limit hit; the only diagnostics are the NURBS feeds
    whose control data rs274 elides."""
    from pathlib import Path

    planned = 0
    for f in sorted(str(q) for q in (Path(__file__).parent / "golden" / "ngc").glob("*.canon")):
        with open(f) as fh:
            cmds = list(canon.read_commands(fh, f, keep_linuxcnc=True))
        try:
            path = build_path(cmds, SIX_AXES, f)
        except Diagnostic as d:
            assert d.code == "PLAN-NURBS", str(d)
            continue
        p = plan(path, SIX_AXES)
        if p.total_time > 600:  # feed-per-rev programs with a slow spindle: hours of samples
            continue
        s = sample(p)
        rep = measure(p, s)
        assert not [h for h in rep.hits if h.kind != "travel"], f
        if len(path):
            assert np.array_equal(s.position[-1], path.end_position[: len(s.axes)])
        planned += 1
    assert planned >= 150


def test_plan_command_runs_g_code_through_the_interpreter(tmp_path):
    pytest.importorskip("gcode.ngc.interpreter")
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 G17 G90 G54\nF600\nG1 X10 Y0\nG2 X20 Y0 I5 J0\nG4 P0.5\nM2\n")
    r = CliRunner().invoke(command, [str(prog), "--format", "json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert data["cycle"]["dwell"] == 0.5
    assert data["feed_length"] == pytest.approx(10 + 5 * math.pi)
    assert data["hits"] == []
