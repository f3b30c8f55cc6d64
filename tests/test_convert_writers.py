"""Writers (gcode.write.writer): IR -> text in each dialect, checked against hand-derived blocks.

Each expectation is worked out from the dialect's vocabulary (gcode/*/dialect.py, book
Appendix A Table A.2 for Fanuc, research/seed-sandia-full.md §5.3 for Sandia) and the
arc rules of NISTIR 5970 §3.6.1 (G3 = positive rotation; XZ plane = (Z, X)).
"""

from __future__ import annotations

import math

import pytest

from gcode.registry import get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon as c

MM = c.UseLengthUnits(c.Units.MM)
INCH = c.UseLengthUnits(c.Units.INCHES)


def emit(cmds, dialect, report=None, **opts):  # noqa: ANN001, ANN201
    return list(write(cmds, dialect, WriterOptions(**opts), report or ConversionReport()))


SQUARE = [
    MM,
    c.StraightTraverse(0, 0, 5),
    c.SetFeedRate(100),
    c.StraightFeed(0, 0, -1),
    c.StraightFeed(10, 0, -1),
    c.StraightFeed(10, 10, -1),
    c.StraightTraverse(10, 10, 5),
    c.ProgramEnd(),
]


def test_rs274ngc_writes_modal_minimal_blocks_in_a_percent_frame():
    assert emit(SQUARE, "rs274ngc") == [
        "%",
        "G21",
        "G90 G17",
        "G0 X0 Y0 Z5",
        "G1 Z-1 F100",
        "X10",
        "Y10",
        "G0 Z5",
        "M2",
        "%",
    ]


def test_fanuc_pads_codes_and_writes_decimal_points_in_an_o_frame():
    assert emit(SQUARE, "fanuc") == [
        "%",
        "O0001",
        "G21",
        "G90 G17",
        "G00 X0. Y0. Z5.",
        "G01 Z-1. F100.",
        "X10.",
        "Y10.",
        "G00 Z5.",
        "M30",
        "%",
    ]


def test_siemens_uses_g710_and_semicolon_comments():
    out = emit([MM, c.Comment("roughing"), *SQUARE[1:]], "siemens840d")
    assert out[:4] == ["; roughing", "G710", "G90 G17", "G0 X0 Y0 Z5"]
    assert out[-1] == "M30"


def test_sandia_generic_language_uses_seed_command_names():
    assert emit(SQUARE[:-1], "sandia") == [
        "SetUnits linear=mm angular=deg",
        "point_to_point_positioning X=0.0 Y=0.0 Z=5.0 attributes=ABSOLUTE|CS_CURRENT",
        "SetSpeed 100.0",
        "MoveTo Z=-1.0",
        "MoveTo X=10.0",
        "MoveTo Y=10.0",
        "point_to_point_positioning Z=5.0 attributes=ABSOLUTE|CS_CURRENT",
    ]


# quarter circle from (10, 0) about (0, 0) to (0, 10), counterclockwise (rotation +1)
QUARTER = [MM, c.StraightTraverse(10, 0, 0), c.SetFeedRate(50), c.ArcFeed(0, 10, 0, 0, 1, 0)]


@pytest.mark.parametrize(
    ("arc_format", "dialect", "block"),
    [
        ("ijk", "rs274ngc", "G3 X0 Y10 I-10 J0 F50"),
        ("r", "rs274ngc", "G3 X0 Y10 R10 F50"),
        ("ijk-abs", "rs274ngc", "G3 X0 Y10 I0 J0 F50"),
        ("ijk", "fanuc", "G03 X0. Y10. I-10. J0. F50."),
        ("r", "siemens840d", "G3 X0 Y10 CR=10 F50"),
        ("ijk-abs", "siemens840d", "G3 X0 Y10 I=AC(0) J=AC(0) F50"),
    ],
)
def test_arc_formats(arc_format, dialect, block):  # noqa: ANN001
    out = emit(QUARTER, dialect, arc_format=arc_format)
    assert out[-1 - len(get_dialect(dialect).footer)] == block
    if arc_format == "ijk-abs" and dialect == "rs274ngc":
        assert "G90.1" in out


def test_r_is_negative_beyond_a_half_circle():
    # three quarters clockwise from (10, 0) about (0, 0) to (0, 10): 270 degrees, R < 0
    cmds = [MM, c.StraightTraverse(10, 0, 0), c.SetFeedRate(50), c.ArcFeed(0, 10, 0, 0, -1, 0)]
    assert "G2 X0 Y10 R-10 F50" in emit(cmds, "rs274ngc", arc_format="r")


def test_xz_plane_arc_maps_first_axis_to_z_and_centre_to_k_i():
    # XZ plane: first = Z, second = X. From (x=10, z=0) about the origin to (x=0, z=10), CCW
    cmds = [
        MM,
        c.SelectPlane(c.Plane.XZ),
        c.StraightTraverse(10, 0, 0),
        c.SetFeedRate(5),
        c.ArcFeed(10, 0, 0, 0, 1, 0),
    ]
    out = emit(cmds, "rs274ngc")
    assert "G90 G18" in out
    assert "G3 X0 Z10 I-10 K0 F5" in out


def test_full_circle_in_r_format_falls_back_to_centres_and_is_reported():
    report = ConversionReport()
    cmds = [MM, c.StraightTraverse(10, 0, 0), c.SetFeedRate(50), c.ArcFeed(10, 0, 0, 0, 1, 0)]
    out = emit(cmds, "rs274ngc", report, arc_format="r")
    assert "G3 X10 Y0 I-10 J0 F50" in out
    assert [ch.code for ch in report.changes] == ["CONV-ARC-FORMAT"]


@pytest.mark.parametrize(
    ("end", "r_format"),
    [((-10.0, 0.0), False), ((0.0, 10.0), True), ((-8.0, 6.0), True), ((-9.6, 2.8), True)],
)
def test_r_format_keeps_clear_of_the_half_circle(end: tuple[float, float], r_format: bool):
    """At 180 degrees 4R^2 - chord^2 is 0 in decimal and may be below 0 in a reader's floating
    point (Grbl's error:33): a half circle gets centres even when R would be exact. 143.1 and
    163.7 degrees (ends exact in decimal) keep R."""
    arc = c.ArcFeed(end[0], end[1], 0, 0, 1, 0)
    report = ConversionReport()
    cmds = [MM, c.StraightTraverse(10, 0, 0), c.SetFeedRate(50), arc]
    out = emit(cmds, "grbl", report, arc_format="r", decimals=6)
    block = next(b for b in out if b.startswith("G3"))
    assert ("R10" in block) is r_format and ("I-10" in block) is not r_format
    assert [ch.code for ch in report.changes] == ([] if r_format else ["CONV-ARC-FORMAT"])


HELIX = [MM, c.StraightTraverse(5, 0, 0), c.SetFeedRate(60), c.ArcFeed(5, 0, 0, 0, 3, -3)]


def test_multi_turn_helix_uses_p_in_linuxcnc_and_turn_in_siemens():
    assert "G3 X5 Y0 Z-3 I-5 J0 P3 F60" in emit(HELIX, "rs274ngc")
    assert "G3 X5 Y0 Z-3 I-5 J0 TURN=2 F60" in emit(HELIX, "siemens840d")


def test_multi_turn_helix_is_expanded_into_full_circles_for_fanuc():
    report = ConversionReport()
    out = emit(HELIX, "fanuc", report)
    # three full turns, the helix axis shared in proportion to the angle: -1, -2, -3
    assert out[-4:-1] == [
        "G03 X5. Y0. Z-1. I-5. J0. F60.",
        "X5. Y0. Z-2. I-5. J0.",
        "X5. Y0. Z-3. I-5. J0.",
    ]
    assert [(ch.code, ch.kind, ch.pieces) for ch in report.changes] == [
        ("CONV-ARC-TURNS", "expanded", 3)
    ]


def test_multi_turn_refused_with_location_when_asked():
    loc = Location("p.ngc", 7, 1)
    cmds = [*HELIX[:-1], c.ArcFeed(5, 0, 0, 0, 3, -3, source=loc)]
    with pytest.raises(Diagnostic) as err:
        emit(cmds, "fanuc", on_missing="refuse")
    assert err.value.code == "CONV-ARC-TURNS"
    assert err.value.location == loc


def test_units_conversion_scales_lengths_and_feed_not_angles():
    cmds = [INCH, c.StraightTraverse(1, 2, 0, 90), c.SetFeedRate(10), c.StraightFeed(2, 2, -0.5)]
    out = emit(cmds, "rs274ngc", units="mm", decimals=3)
    # the feed move returns A to 0 (the IR's a = 0): A is written, Y (unchanged) is not
    assert out[1:-1] == ["G21", "G90 G17", "G0 X25.4 Y50.8 Z0 A90", "G1 X50.8 Z-12.7 A0 F254"]


def test_line_numbers_count_blocks_not_frame_lines():
    out = emit(SQUARE, "rs274ngc", line_numbers=10)
    assert out[0] == "%" and out[-1] == "%"
    assert out[1:4] == ["N10 G21", "N20 G90 G17", "N30 G0 X0 Y0 Z5"]


def test_fanuc_sequence_numbers_wrap_after_n99999():
    cmds = [MM] + [c.StraightTraverse(i, 0, 0) for i in range(5)]
    out = emit(cmds, "fanuc", line_numbers=40000)
    assert [line.split()[0] for line in out[2:-1]] == [
        "N40000",
        "N80000",
        "N40000",
        "N80000",
        "N40000",
        "N80000",
        "N40000",
    ]


def test_grbl_rejects_a_block_longer_than_80_characters_with_its_location():
    loc = Location("long.ngc", 3, 1)
    cmds = [MM, c.Message("x" * 90, source=loc)]
    with pytest.raises(Diagnostic) as err:
        emit(cmds, "grbl")
    assert err.value.code == "CONV-LINE-LENGTH" and err.value.location == loc


def test_grbl_truncates_long_comments_to_the_line_limit():
    out = emit([MM, c.Comment("y" * 100)], "grbl")
    assert out == ["(" + "y" * 78 + ")"]


def test_grbl_tool_change_becomes_a_stop_with_a_comment():
    report = ConversionReport()
    out = emit([MM, c.SelectTool(3), c.ChangeTool(3)], "grbl", report)
    assert out == ["G21", "G90 G17", "(change to tool 3)", "M0"]
    assert report.changes[0].code == "CONV-TOOL-CHANGE"


def test_select_and_change_merge_into_one_block():
    assert emit([MM, c.SelectTool(2), c.ChangeTool(2)], "rs274ngc")[-2] == "T2 M6"


def test_mist_off_with_flood_on_writes_m9_then_m8():
    cmds = [
        MM,
        c.MistOn(),
        c.FloodOn(),
        c.StraightTraverse(0, 0, 0),
        c.MistOff(),
        c.StraightTraverse(1, 0, 0),
    ]
    out = emit(cmds, "rs274ngc")
    assert out[3:6] == ["M7", "M8", "G0 X0 Y0 Z0"]
    assert out[6:9] == ["M9", "M8", "X1"]


def test_spindle_speed_and_direction_share_a_block():
    cmds = [MM, c.SetSpindleSpeed(1200), c.StartSpindleClockwise(), c.StraightTraverse(0, 0, 0)]
    assert "S1200 M3" in emit(cmds, "rs274ngc")
    assert "S1200 M03" in emit(cmds, "fanuc")


def test_css_with_maximum_per_dialect():
    cmds = [
        MM,
        c.SetSpindleMode(2500, True),
        c.SetSpindleSpeed(200),
        c.StartSpindleClockwise(),
        c.StraightTraverse(0, 0, 0),
    ]
    assert "G96 D2500 S200" in emit(cmds, "rs274ngc")
    assert "G96 S200 LIMS=2500" in emit(cmds, "siemens840d")
    with pytest.raises(Diagnostic, match="constant surface speed"):
        emit(cmds, "grbl")


def test_inverse_time_feed_is_rate_over_length():
    # the IR carries the per-minute rate (as rs274 prints it): 20 mm/min over 10 mm = 2/min
    cmds = [
        MM,
        c.StraightTraverse(0, 0, 0),
        c.SetFeedMode(c.FeedMode.INVERSE_TIME),
        c.SetFeedRate(20),
        c.StraightFeed(10, 0, 0),
    ]
    out = emit(cmds, "rs274ngc")
    assert out[-3:-1] == ["G93", "G1 X10 F2"]


def test_tool_length_by_value():
    cmds = [
        MM,
        c.SelectTool(4),
        c.ChangeTool(4),
        c.UseToolLengthOffset(12.5),
        c.StraightTraverse(0, 0, 5),
    ]
    assert "G43.1 Z12.5" in emit(cmds, "rs274ngc")
    with pytest.raises(Diagnostic) as err:  # G10 L10 writes the machine's tool table
        emit(cmds, "fanuc")
    assert err.value.code == "CONV-TOOL-TABLE"
    fanuc = emit(cmds, "fanuc", write_tool_table=True)
    assert fanuc[fanuc.index("T4 M06") + 1 : fanuc.index("T4 M06") + 3] == [
        "G10 L10 P4 R12.5",
        "G43 H4",
    ]


def test_message_is_a_comment_where_the_dialect_has_no_message():
    report = ConversionReport()
    assert emit([MM, c.Message("check part")], "rs274ngc")[-2] == "(MSG, check part)"
    assert emit([MM, c.Message("check part")], "fanuc", report)[-2] == "(check part)"
    assert report.changes[0].kind == "substituted"


def test_rotary_motion_refused_on_three_axis_grbl():
    with pytest.raises(Diagnostic) as err:
        emit([MM, c.StraightTraverse(0, 0, 0, 45)], "grbl")
    assert err.value.code == "CONV-AXIS"


def test_threading_refused_where_there_is_no_synchronised_motion():
    cmds = [
        MM,
        c.StraightTraverse(0, 0, 0),
        c.StartSpeedFeedSynch(1.5),
        c.StraightFeed(0, 0, -10, source=Location("t.ngc", 4, 1)),
    ]
    assert emit(cmds, "rs274ngc")[-2] == "G33 Z-10 K1.5"
    with pytest.raises(Diagnostic) as err:
        emit(cmds, "haas")
    assert err.value.code == "CONV-THREAD" and err.value.location.line == 4


def test_linuxcnc_g5_2_nurbs_kept_when_knots_are_clamped_uniform():
    # G5.2 semantics: the current position is the first control point
    pts = ((0.0, 0.0, 1.0), (0.0, 1.0, 1.0), (2.0, 2.0, 1.0), (2.0, 0.0, 1.0))
    knots = (0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0)
    cmds = [MM, c.StraightTraverse(0, 0, 0), c.SetFeedRate(300), c.NurbsFeed(3, pts, knots)]
    out = emit(cmds, "rs274ngc")
    assert out[-5:-1] == ["G5.2 X0 Y1 P1 L3 F300", "X2 Y2 P1", "X2 Y0 P1", "G5.3"]


def test_nurbs_with_other_knots_is_approximated_and_reported():
    pts = ((0.0, 0.0, 1.0), (0.0, 1.0, 1.0), (2.0, 2.0, 1.0), (2.0, 0.0, 1.0))
    knots = (0.0, 0.0, 0.0, 0.2, 1.0, 1.0, 1.0)
    report = ConversionReport()
    cmds = [MM, c.StraightTraverse(0, 0, 0), c.SetFeedRate(300), c.NurbsFeed(3, pts, knots)]
    out = emit(cmds, "rs274ngc", report, tolerance=0.001)
    (change,) = report.changes
    assert change.code == "CONV-NURBS" and change.kind == "approximated"
    assert change.deviation is not None and change.deviation <= 0.001
    assert change.pieces == len(out) - out.index("G0 X0 Y0 Z0") - 2  # all blocks up to "%"
    assert out[-2].startswith(("X2 Y0", "G2 X2 Y0", "G3 X2 Y0", "G1 X2 Y0"))


def test_ellipse_is_approximated_by_lines_within_tolerance():
    # a circle of radius 10 as an ellipse; chords of a circle: sagitta = r (1 - cos(d/2))
    report = ConversionReport()
    cmds = [
        MM,
        c.StraightTraverse(10, 0, 0),
        c.SetFeedRate(100),
        c.EllipseFeed(20, 20, 0, -10, 0, 0, 0, 1, 0),
    ]
    out = emit(cmds, "rs274ngc", report, tolerance=0.01)
    (change,) = report.changes
    step = 2 * math.acos(1 - 0.01 / 10)
    assert change.pieces == math.ceil(math.pi / step)
    assert change.deviation <= 0.01
    assert out[-2] == "X-10 Y0"


def test_unknown_dialect_is_a_diagnostic():
    with pytest.raises(Diagnostic) as err:
        emit([MM], "heidenhain")
    assert err.value.code == "CONV-DIALECT"


def test_sandia_reports_spindle_it_cannot_state_and_refuses_feed_per_revolution():
    report = ConversionReport()
    cmds = [
        MM,
        c.SetSpindleSpeed(1000),
        c.StartSpindleClockwise(),
        c.StopSpindleTurning(),
        c.StopSpindleTurning(),
        c.StraightTraverse(1, 2, 3),
        c.ProgramEnd(),
        c.SetFeedRate(0),
    ]
    out = emit(cmds, "sandia", report)
    # three state changes have no generic command; the second stop changes nothing
    assert [ch.code for ch in report.changes] == ["CONV-SPINDLE"] * 3
    assert all(ch.loss for ch in report.changes)
    assert out[-1] == "# end of program"
    per_rev = [MM, c.SetFeedMode(c.FeedMode.UNITS_PER_REVOLUTION), c.SetFeedRate(0.2)]
    emit([*per_rev, c.StraightTraverse(1, 2, 3)], "sandia")  # no feed motion in it: fine
    feed = c.StraightFeed(1, 2, 3, source=Location("p.nc", 5, 1))
    for motion in (feed, c.ArcFeed(0, 0, 1, 0, 1, 0, source=Location("p.nc", 5, 1))):
        with pytest.raises(Diagnostic) as err:
            emit([*per_rev, motion], "sandia")
        assert err.value.code == "CONV-FEED-PER-REV" and err.value.location.line == 5


def test_sandia_arcs_become_chords_within_tolerance():
    report = ConversionReport()
    out = emit(QUARTER, "sandia", report, tolerance=0.01)
    (change,) = report.changes
    n = math.ceil((math.pi / 2) / (2 * math.acos(1 - 0.01 / 10)))
    assert change.code == "CONV-ARC-LINES" and change.pieces == n
    assert change.deviation <= 0.01
    assert out[-1] == "MoveTo X=0.0 Y=10.0"


def test_units_option_needs_units_in_the_program():
    with pytest.raises(Diagnostic) as err:
        emit([c.StraightTraverse(1, 0, 0)], "rs274ngc", units="mm")
    assert err.value.code == "CONV-OPTION"


def test_siemens_message_quotes_are_kept_inside_msg():
    out = emit([MM, c.Message('say "hi"')], "siemens840d")
    assert out[-1] == "MSG(\"say 'hi'\")"


def test_cutter_compensation_by_value_register_or_refused():
    """LinuxCNC states the radius by value (G41.1 D diameter); Fanuc and Haas put it in the
    offset register of the tool in the spindle (G10 L12 P R, then G41 D); Grbl has none."""
    cmds = [
        MM,
        c.SetFeedRate(10),
        c.ChangeTool(4),
        c.SetCutterRadiusCompensation(2.5),
        c.StartCutterRadiusCompensation(c.CompSide.LEFT),
        c.StraightFeed(1, 0, 0),
        c.StopCutterRadiusCompensation(),
    ]
    out = emit(cmds, "rs274ngc")
    assert out[-5:] == ["T4 M6", "G41.1 D5", "G1 X1 Y0 Z0 F10", "G40", "%"]
    report = ConversionReport()
    fanuc = emit(cmds, "fanuc", report)
    i = fanuc.index("G10 L12 P4 R2.5")
    assert fanuc[i + 1 : i + 4] == ["G41 D4", "G01 X1. Y0. Z0. F10.", "G40"]
    assert [ch.code for ch in report.changes] == ["CONV-CUTTER-COMP"]
    with pytest.raises(Diagnostic) as err:
        emit(cmds, "grbl")
    assert err.value.code == "CONV-CUTTER-COMP" and "--cutter-comp apply" in err.value.message


def test_nurbs_without_data_is_refused_with_its_location():
    # LinuxCNC prints NURBS_FEED(5, ...) without control points
    tc = next(c.read_text(["NURBS_FEED(5, ...)"]))
    cmd = c.parse_command(tc, "x.canon")
    for dialect in ("rs274ngc", "haas", "sandia"):
        with pytest.raises(Diagnostic) as err:
            emit([MM, c.StraightTraverse(0, 0, 0), cmd], dialect)
        assert err.value.code == "CONV-NURBS" and err.value.location.line == 1


def test_an_ellipse_that_does_not_start_on_its_curve_is_refused_at_its_line():
    """The writer cuts the planner's chords (kernel.path.ellipse): an ELLIPSE_FEED whose current
    point is off the ellipse is an error there too, not a silent approximation."""
    bad = c.EllipseFeed(20, 10, 0, -10, 0, 0, 0, 1, 0, source=Location("e.ngc", 4, 1))
    for dialect in ("fanuc", "sandia"):
        with pytest.raises(Diagnostic) as err:
            emit([MM, c.StraightTraverse(0, 0, 0), c.SetFeedRate(100), bad], dialect)
        assert err.value.code == "PLAN-ELLIPSE" and err.value.location.line == 4
    ok = emit([MM, c.StraightTraverse(10, 0, 0), c.SetFeedRate(100), bad], "fanuc")
    assert ok[-2:] == ["X-10. Y0.", "%"]  # the chords end exactly at the programmed end


@pytest.mark.parametrize("dialect", ["rs274ngc", "fanuc", "sandia"])
def test_text_chunks_are_the_lines_with_newlines(dialect: str):
    """``write_text`` (what ``cnc convert`` writes) is exactly ``write``'s lines, each with
    a newline, in chunks of whole lines, also across the batch size."""
    from gcode.write.writer import write_text

    cmds = [MM, c.StraightTraverse(0, 0, 5), c.SetFeedRate(100)]
    cmds += [
        c.ArcFeed(10.0 * (k % 2), 5.0 * k, 5.0 * (k % 2), 5.0 * k, 1, -1) for k in range(1, 40)
    ]
    cmds += [c.ProgramEnd()]
    lines = emit(cmds, dialect)
    chunks = list(write_text(cmds, dialect, WriterOptions(), ConversionReport(), batch=7))
    assert "".join(chunks) == "".join(f"{line}\n" for line in lines)
    assert len(chunks) > 1 and all(chunk.endswith("\n") for chunk in chunks)
