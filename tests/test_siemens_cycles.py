"""Siemens 840D standard cycles (issue 14): CYCLE83, the position patterns HOLES1, HOLES2,
CYCLE801, the boring cycles CYCLE85-CYCLE89 and the tapping cycles CYCLE84, CYCLE840.

Each expectation is derived by hand from the "sequence of motions" and the parameter list
of each cycle in the SINUMERIK 840D sl / 828D cycles programming manual (the derivation is
in each test's docstring), not from the code under test. Motions are compared as short
strings: ``G0 x y z`` / ``G1 x y z`` (IR coordinates), ``F f``, ``DWELL s``, ``M3``,
``M4``, ``M5``, ``M0``, ``SPOS a``, ``S n``, ``SYNC k`` ... ``NOSYNC``, ``TAP x y z``.
"""

from __future__ import annotations

import pytest

from gcode.siemens.reader import interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HEAD = "G17 G90 G710 F100 S1000 M3\nG0 X10 Y10 Z20\n"


def _n(value: float) -> str:
    return f"{round(value, 4) + 0.0:g}"


def motions(text: str) -> list[str]:
    """The IR after the program's head (start-up, F, S, M3, first G0) as short strings."""
    out: list[str] = []
    for c in interpret_text(text, "p.mpf"):
        match c:
            case canon.StraightTraverse():
                out.append(f"G0 {_n(c.x)} {_n(c.y)} {_n(c.z)}")
            case canon.StraightFeed():
                out.append(f"G1 {_n(c.x)} {_n(c.y)} {_n(c.z)}")
            case canon.SetFeedRate():
                out.append(f"F {_n(c.rate)}")
            case canon.Dwell():
                out.append(f"DWELL {_n(c.seconds)}")
            case canon.StartSpindleClockwise():
                out.append("M3")
            case canon.StartSpindleCounterclockwise():
                out.append("M4")
            case canon.StopSpindleTurning():
                out.append("M5")
            case canon.ProgramStop():
                out.append("M0")
            case canon.OrientSpindle():
                out.append(f"SPOS {_n(c.orientation)}")
            case canon.SetSpindleSpeed():
                out.append(f"S {_n(c.speed)}")
            case canon.StartSpeedFeedSynch():
                out.append(f"SYNC {_n(c.feed_per_revolution)}")
            case canon.StopSpeedFeedSynch():
                out.append("NOSYNC")
            case canon.RigidTap():
                out.append(f"TAP {_n(c.x)} {_n(c.y)} {_n(c.z)}")
            case canon.ProgramEnd():
                break
    start = out.index("G0 10 10 20")
    end = len(out) - 2  # M30: F 0, M5
    return out[start + 1 : end]


def error(text: str) -> Diagnostic:
    with pytest.raises(Diagnostic) as info:
        list(interpret_text(text, "p.mpf"))
    return info.value


# ---------------------------------------------------------------------------- CYCLE83
def test_cycle83_swarf_removal_with_degression_and_automatic_anticipation() -> None:
    """CYCLE83(RTP 20, RFP 0, SDIS 2, DP -22, , FDEP -5, , DAM 2, DTB 1, DTS 0.5, FRF 0.5,
    VARI 1). Depths (manual, "FDEP, FDPR and DAM"): first -5 (stroke 5); next stroke
    5 - 2 = 3 > DAM: -8; then 3 - 2 = 1 is not above DAM, so DAM strokes while more than
    2 x DAM remains: -10, -12, -14, -16, -18; at -18 the rest 4 is not above 4: the last
    two share it, 2 + 2: -20, -22. Sequence (VARI=1): G0 to RFP + SDIS = 2; G1 at
    F x FRF = 50 to -5; F back to 100; at each depth reached: dwell DTB, G0 out to 2,
    dwell DTS, G0 in to the depth reached + the anticipation distance (_DIS1 = 0: the hole
    is 22 mm <= 30 mm deep, so 0.6 mm), G1 to the next depth; at the final depth the dwell
    _DTD (0: DTB's 1 s), G0 to RTP 20."""
    got = motions(HEAD + "CYCLE83(20, 0, 2, -22, , -5, , 2, 1, 0.5, 0.5, 1)\nM30\n")
    expected = ["G0 10 10 2", "F 50", "G1 10 10 -5", "F 100"]
    depths = [-5, -8, -10, -12, -14, -16, -18, -20, -22]
    for reached, nxt in zip(depths, depths[1:], strict=False):
        expected += ["DWELL 1", "G0 10 10 2", "DWELL 0.5", f"G0 10 10 {_n(reached + 0.6)}"]
        expected.append(f"G1 10 10 {nxt}")
    expected += ["DWELL 1", "G0 10 10 20"]
    assert got == expected


def test_cycle83_chip_breaking_default_retraction_and_final_dwell() -> None:
    """CYCLE83(20, 0, 2, , DPR 10, , FDPR 4, DAM 0, DTB 0.5, , FRF 0, VARI 0, , , _VRT 0,
    _DTD 2): depth RFP - DPR = -10, first depth RFP - FDPR = -4; DAM 0 keeps the stroke
    4: -8, then the rest 2: -10. FRF 0 is the factor 1 (no feed change). VARI=0: after
    each intermediate depth dwell DTB 0.5 and G1 back by _VRT (0: 1 mm), then G1 on; at
    the depth dwell _DTD 2 s; G0 to RTP."""
    got = motions(HEAD + "CYCLE83(20, 0, 2, , 10, , 4, 0, 0.5, , 0, 0, , , 0, 2)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "G1 10 10 -4",
        "DWELL 0.5",
        "G1 10 10 -3",
        "G1 10 10 -8",
        "DWELL 0.5",
        "G1 10 10 -7",
        "G1 10 10 -10",
        "DWELL 2",
        "G0 10 10 20",
    ]


def test_cycle83_anticipation_of_deep_holes_and_programmed() -> None:
    """Hole depth above 30 mm: anticipation depth / 50 (at most 7 mm). DP -100 from RFP 0:
    2 mm; FDEP -40, DAM 0: strokes of 40: -40, -80, -100; re-entry G0 to -38 and -78.
    DP -400: 8 mm is capped at 7; FDEP -200: -200, -400; re-entry to -193. With _DIS1 3
    programmed (DP -100): -37, -77."""
    got = motions(HEAD + "CYCLE83(20, 0, 2, -100, , -40, , 0, , , , 1)\nM30\n")
    assert [m for m in got if m.startswith("G0 10 10 -")] == ["G0 10 10 -38", "G0 10 10 -78"]
    got = motions(HEAD + "CYCLE83(20, 0, 2, -400, , -200, , 0, , , , 1)\nM30\n")
    assert [m for m in got if m.startswith("G0 10 10 -")] == ["G0 10 10 -193"]
    text = HEAD + "CYCLE83(20, 0, 2, -100, , -40, , 0, , , , 1, , , , , 3)\nM30\n"
    got = motions(text)
    assert [m for m in got if m.startswith("G0 10 10 -")] == ["G0 10 10 -37", "G0 10 10 -77"]


def test_cycle83_degression_factor_with_minimum_depth() -> None:
    """DAM -0.5 is a factor on the last stroke, not below _MDEP 1.5: first FDPR 8 -> -8;
    then 4 -> -12, 2 -> -14, max(1, 1.5) = 1.5 -> -15.5, 1.5 -> -17, rest 1 -> -18 (DP)."""
    got = motions(HEAD + "CYCLE83(20, 0, 2, -18, , , 8, -0.5, , , , 0, , 1.5, 0.5)\nM30\n")
    assert [m for m in got if m.startswith("G1")] == [
        "G1 10 10 -8",
        "G1 10 10 -7.5",
        "G1 10 10 -12",
        "G1 10 10 -11.5",
        "G1 10 10 -14",
        "G1 10 10 -13.5",
        "G1 10 10 -15.5",
        "G1 10 10 -15",
        "G1 10 10 -17",
        "G1 10 10 -16.5",
        "G1 10 10 -18",
    ]


def test_cycle83_in_g18_and_g19_drills_along_the_applicate() -> None:
    """G18 (Z/X plane): the applicate is Y; G19 (Y/Z): X. CYCLE83(20, 0, 2, -6, , -3, ,
    , , , , 0): G0 to 2, G1 to -3, G1 back 1 mm to -2, G1 to -6, G0 to 20, on that axis."""
    text = (
        "G17 G90 F100 S1000 M3\nG0 X10 Y10 Z20\n{}\nCYCLE83(20, 0, 2, -6, , -3, , , , , , 0)\nM30\n"
    )
    assert motions(text.format("G18")) == [
        "G0 10 2 20",
        "G1 10 -3 20",
        "G1 10 -2 20",
        "G1 10 -6 20",
        "G0 10 20 20",
    ]
    assert motions(text.format("G19")) == [
        "G0 2 10 20",
        "G1 -3 10 20",
        "G1 -2 10 20",
        "G1 -6 10 20",
        "G0 20 10 20",
    ]


def test_cycle83_under_mcall_after_each_move() -> None:
    """MCALL CYCLE83(...) runs the cycle after each following block that moves (job
    planning, modal call): at X30 and at Y30; MCALL alone ends it (the G0 X0 drills
    nothing). Each: G0 2, G1 -4, G1 -3 (1 mm back), G1 -6, G0 20."""
    text = HEAD + "MCALL CYCLE83(20, 0, 2, -6, , -4, , , , , , 0)\nX30\nY30\nMCALL\nX0\nM30\n"
    one = ["G0 {} 2", "G1 {} -4", "G1 {} -3", "G1 {} -6", "G0 {} 20"]
    assert motions(text) == [
        "G0 30 10 20",
        *(m.format("30 10") for m in one),
        "G0 30 30 20",
        *(m.format("30 30") for m in one),
        "G0 0 30 20",
    ]


def test_cycle83_in_inch_takes_the_mm_defaults_converted() -> None:
    """G700: _VRT 0 is 1 mm = 0.03937 in; the program's lengths are inches."""
    head = "G17 G90 G700 F4 S1000 M3\nG0 X10 Y10 Z20\n"
    text = head + "CYCLE83(1, 0, 0.1, -1, , -0.5, , , , , , 0)\nM30\n"
    assert motions(text) == [
        "G0 10 10 0.1",
        "G1 10 10 -0.5",
        "G1 10 10 -0.4606",
        "G1 10 10 -1",
        "G0 10 10 1",
    ]


def test_cycle83_as_fusion_360s_840d_post_writes_it() -> None:
    """The Fusion 360 840D post's chip breaking (its cycle parameters in order: FDEP =
    stock - peck, DAM 0, FRF 1, VARI 0, _MDEP = peck, _VRT = chip-break distance, _DTD,
    _DIS1 0, and with extended cycles _GMODE 0, _DMODE 0, _AMODE 1001110): with absolute
    DP and FDEP and no dwell in revolutions every _AMODE digit 0/1 reads as the
    compatible form. Strokes of 5 from -5: -10, -15, -20, then the rest 2: -22; after
    each intermediate depth G1 back _VRT 1; at the depth G0 to RTP 20."""
    call = "MCALL CYCLE83(20, 0, 2, -22, , -5, , 0, , , 1, 0, , 5, 1, 0, 0, 0, 0, 1001110)"
    got = motions(HEAD + call + "\nX10 Y10\nMCALL\nM30\n")
    assert got == [
        "G0 10 10 20",
        "G0 10 10 2",
        "G1 10 10 -5",
        "G1 10 10 -4",
        "G1 10 10 -10",
        "G1 10 10 -9",
        "G1 10 10 -15",
        "G1 10 10 -14",
        "G1 10 10 -20",
        "G1 10 10 -19",
        "G1 10 10 -22",
        "G0 10 10 20",
    ]


def test_extended_cycle81_82_85_86_calls_read_as_the_short_form() -> None:
    """The same post's extended CYCLE81/82 (``..., 0, 0, 10)``), CYCLE85 and CYCLE86
    (``..., 0, 0, 0)`` / ``10)``) give the motions of the short form."""
    for short, extended in (
        ("CYCLE81(10, 0, 2, -5, )", "CYCLE81(10, 0, 2, -5, , 0, 0, 10)"),
        ("CYCLE82(10, 0, 2, -5, , 1)", "CYCLE82(10, 0, 2, -5, , 1, 0, 0, 10)"),
        ("CYCLE85(10, 0, 2, -5, , 1, 50, 200)", "CYCLE85(10, 0, 2, -5, , 1, 50, 200, 0, 0, 0)"),
        (
            "CYCLE86(10, 0, 2, -5, , , 3, 0, 0, 0, 0)",
            "CYCLE86(10, 0, 2, -5, , , 3, 0, 0, 0, 0, 0, 0, 10)",
        ),
    ):
        assert motions(HEAD + extended + "\nM30\n") == motions(HEAD + short + "\nM30\n")


# ---------------------------------------------------------------------------- patterns
DRILL = "MCALL CYCLE81(10, 0, 2, -5)\n"


def _holes(got: list[str]) -> list[str]:
    """The plane positions drilled: the G1 to the depth -5."""
    return [" ".join(m.split()[1:3]) for m in got if m.startswith("G1") and m.endswith(" -5")]


def test_holes1_row_from_the_nearer_end() -> None:
    """HOLES1(SPCA 0, SPCO 0, STA1 0, FDIS 10, DBH 10, NUM 3): holes at 10, 20, 30 on X.
    From (10, 10) the first hole is nearer: 10, 20, 30, each G0 in the plane at the
    height of the tool, then CYCLE81 (G0 2, G1 -5, G0 RTP 10). From X40 the last is
    nearer: 30, 20, 10 (manual: the row is machined from the end nearer the tool)."""
    got = motions(HEAD + DRILL + "HOLES1(0, 0, 0, 10, 10, 3)\nMCALL\nM30\n")
    assert got[:5] == ["G0 10 0 20", "G0 10 0 2", "G1 10 0 -5", "G0 10 0 10", "G0 20 0 10"]
    assert _holes(got) == ["10 0", "20 0", "30 0"]
    got = motions(HEAD + "G0 X40\n" + DRILL + "HOLES1(0, 0, 0, 10, 10, 3)\nMCALL\nM30\n")
    assert _holes(got) == ["30 0", "20 0", "10 0"]


def test_holes1_at_an_angle() -> None:
    """STA1 90: the row runs along +Y from (5, 5): Y 5 + 2 = 7, then 7 + 3 = 10. From the
    tool at (10, 10) the last hole (5, 10) is 5 away, the first (5, 7) sqrt(34) = 5.83:
    the row starts at its last hole."""
    got = motions(HEAD + DRILL + "HOLES1(5, 5, 90, 2, 3, 2)\nMCALL\nM30\n")
    assert _holes(got) == ["5 10", "5 7"]


def test_holes2_circle_with_the_even_division() -> None:
    """HOLES2(CPA 50, CPO 50, RAD 20, STA1 0, INDA 90, NUM 4): angles 0, 90, 180, 270:
    (70, 50), (50, 70), (30, 50), (50, 30). INDA 0: 360 / NUM = 120 from STA1 30:
    (50 + 20 cos 30, 50 + 20 sin 30) = (67.3205, 60), (50 + 20 cos 150, 60) = (32.6795,
    60), (50, 30)."""
    got = motions(HEAD + DRILL + "HOLES2(50, 50, 20, 0, 90, 4)\nMCALL\nM30\n")
    assert _holes(got) == ["70 50", "50 70", "30 50", "50 30"]
    got = motions(HEAD + DRILL + "HOLES2(50, 50, 20, 30, 0, 3)\nMCALL\nM30\n")
    assert _holes(got) == ["67.3205 60", "32.6795 60", "50 30"]


def test_cycle801_grid_in_a_meander() -> None:
    """CYCLE801(_SPCA 0, _SPCO 0, _STA 0, _DIS1 10, _DIS2 5, _NUM1 3, _NUM2 2): the first
    row along X from the reference point (0 0, 10 0, 20 0), the second row 5 higher back
    (20 5, 10 5, 0 5). With _STA 90 the rows run along Y and the columns go to -X."""
    got = motions(HEAD + DRILL + "CYCLE801(0, 0, 0, 10, 5, 3, 2)\nMCALL\nM30\n")
    assert _holes(got) == ["0 0", "10 0", "20 0", "20 5", "10 5", "0 5"]
    got = motions(HEAD + DRILL + "CYCLE801(0, 0, 90, 10, 5, 2, 2)\nMCALL\nM30\n")
    assert _holes(got) == ["0 0", "0 10", "-5 10", "-5 0"]


def test_patterns_without_mcall_only_position_and_work_in_g19() -> None:
    """Without a modal call a pattern moves to its positions and drills nothing. In G19
    the plane's abscissa is Y and its ordinate Z: HOLES2(0, 0, 10, 0, 90, 2) goes to
    (Y 10, Z 0) and (Y 0, Z 10), X staying at 10."""
    assert motions(HEAD + "HOLES1(0, 0, 0, 10, 10, 2)\nM30\n") == ["G0 10 0 20", "G0 20 0 20"]
    got = motions(HEAD + "G19\nHOLES2(0, 0, 10, 0, 90, 2)\nM30\n")
    assert got == ["G0 10 10 0", "G0 10 0 10"]


def test_a_pattern_called_modally_only_positions() -> None:
    """MCALL CYCLE801(...): the grid runs after each block that moves; the blocks of a
    modally called program call nothing themselves (job planning, "Modal subprogram
    call"), so the grid's own moves drill nothing and do not call the grid again."""
    text = HEAD + "MCALL CYCLE801(0, 0, 0, 10, 10, 2, 1)\nX30\nMCALL\nM30\n"
    assert motions(text) == ["G0 30 10 20", "G0 0 0 20", "G0 10 0 20"]


def test_pattern_runs_the_modal_cycle82_and_cycle83() -> None:
    """The pattern runs whatever cycle MCALL selected: CYCLE82 dwells DTB at each hole;
    CYCLE83 drills its strokes at each."""
    got = motions(HEAD + "MCALL CYCLE82(10, 0, 2, -5, , 1.5)\nHOLES1(0, 0, 0, 10, 10, 2)\nM30\n")
    assert got.count("DWELL 1.5") == 2
    text = HEAD + "MCALL CYCLE83(10, 0, 2, -6, , -4, , , , , , 0)\nHOLES2(0, 0, 5, 0, 180, 2)\n"
    got = motions(text + "MCALL\nM30\n")
    assert [m for m in got if m.startswith("G1")] == [
        "G1 5 0 -4",
        "G1 5 0 -3",
        "G1 5 0 -6",
        "G1 -5 0 -4",
        "G1 -5 0 -3",
        "G1 -5 0 -6",
    ]


# ---------------------------------------------------------------------------- boring
def test_cycle85_feeds_in_and_out() -> None:
    """CYCLE85(10, 0, 2, -5, , DTB 1, FFR 50, RFF 200): G0 2; G1 to -5 at FFR; dwell 1;
    G1 out to RFP + SDIS at RFF; G0 to RTP; the feed in force (100) again."""
    got = motions(HEAD + "CYCLE85(10, 0, 2, -5, , 1, 50, 200)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "F 50",
        "G1 10 10 -5",
        "DWELL 1",
        "F 200",
        "G1 10 10 2",
        "G0 10 10 10",
        "F 100",
    ]


def test_cycle86_oriented_stop_and_lift_off() -> None:
    """CYCLE86(10, 0, 2, -5, , DTB 1, SDIR 3, RPA 1, RPO -1, RPAP 0.5, POSS 90): G0 2;
    M3; G1 -5; dwell; oriented stop at 90 (SPOS); G0 by RPA/RPO/RPAP off the wall:
    (11, 9, -4.5); G0 to RFP + SDIS; G0 back over the hole at RTP (10, 10, 10); M3."""
    got = motions(HEAD + "CYCLE86(10, 0, 2, -5, , 1, 3, 1, -1, 0.5, 90)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "M3",
        "G1 10 10 -5",
        "DWELL 1",
        "SPOS 90",
        "G0 11 9 -4.5",
        "G0 11 9 2",
        "G0 10 10 10",
        "M3",
    ]


def test_cycle86_in_g18() -> None:
    """G18: the plane's abscissa is Z and ordinate X, the applicate Y. RPA 1 moves Z,
    RPO 2 moves X, RPAP 0.5 moves Y."""
    got = motions(HEAD + "G18\nCYCLE86(10, 0, 2, -5, , 0, 4, 1, 2, 0.5, 0)\nM30\n")
    assert got == [
        "G0 10 2 20",
        "M4",
        "G1 10 -5 20",
        "SPOS 0",
        "G0 12 -4.5 21",
        "G0 12 2 21",
        "G0 10 10 20",
        "M4",
    ]


def test_cycle87_and_cycle88_stop_for_the_operator() -> None:
    """CYCLE87(10, 0, 2, -5, , SDIR 4): G0 2, M4, G1 -5, M5, M0, G0 RTP. CYCLE88 dwells
    DTB 2 before the stop."""
    got = motions(HEAD + "CYCLE87(10, 0, 2, -5, , 4)\nM30\n")
    assert got == ["G0 10 10 2", "M4", "G1 10 10 -5", "M5", "M0", "G0 10 10 10"]
    got = motions(HEAD + "CYCLE88(10, 0, 2, -5, , 2, 3)\nM30\n")
    assert got == ["G0 10 10 2", "M3", "G1 10 10 -5", "DWELL 2", "M5", "M0", "G0 10 10 10"]


def test_cycle89_feeds_out_at_the_same_feed() -> None:
    """CYCLE89(10, 0, 2, , DPR 5, DTB 1): G0 2, G1 -5, dwell, G1 2, G0 10. A negative DTB
    is revolutions: -2 at S1000 = 0.12 s."""
    got = motions(HEAD + "CYCLE89(10, 0, 2, , 5, 1)\nM30\n")
    assert got == ["G0 10 10 2", "G1 10 10 -5", "DWELL 1", "G1 10 10 2", "G0 10 10 10"]
    assert "DWELL 0.12" in motions(HEAD + "CYCLE89(10, 0, 2, -5, , -2)\nM30\n")


def test_boring_cycles_under_mcall_and_a_pattern() -> None:
    """MCALL CYCLE89 with HOLES1: the boring cycle at each position."""
    text = HEAD + "MCALL CYCLE89(10, 0, 2, -5, , 0)\nHOLES1(0, 0, 0, 10, 10, 2)\nMCALL\nM30\n"
    got = motions(text)
    assert got == [
        "G0 10 0 20",
        "G0 10 0 2",
        "G1 10 0 -5",
        "G1 10 0 2",
        "G0 10 0 10",
        "G0 20 0 10",
        "G0 20 0 2",
        "G1 20 0 -5",
        "G1 20 0 2",
        "G0 20 0 10",
    ]


# ---------------------------------------------------------------------------- tapping
def test_cycle84_rigid_tapping_is_the_irs_rigid_tap() -> None:
    """CYCLE84(20, 0, 2, -10, , DTB 0, SDAC 3, MPIT 8, , POSS 90, SST 300, SST1 300):
    G0 2; oriented stop at 90 (the spindle becomes an axis); S 300 and right hand (MPIT
    positive: M3); M8 coarse pitch 1.25 synchronised; in to -10 and back at one speed
    without dwell: RIGID_TAP as G33.1; G0 to RTP; the speed of before (1000), SDAC M3."""
    got = motions(HEAD + "CYCLE84(20, 0, 2, -10, , 0, 3, 8, , 90, 300, 300)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "SPOS 90",
        "S 300",
        "M3",
        "SYNC 1.25",
        "TAP 10 10 -10",
        "NOSYNC",
        "G0 10 10 20",
        "S 1000",
        "M3",
    ]


def test_cycle84_with_dwell_and_retraction_speed() -> None:
    """PIT -1.5 (left hand: M4 in, M3 out), DTB 1, SST 300, SST1 600, SDAC 5: in
    synchronised to -10, dwell, S 600 reversed, out to RFP + SDIS, G0 RTP, S 1000, M5."""
    got = motions(HEAD + "CYCLE84(20, 0, 2, -10, , 1, 5, , -1.5, 0, 300, 600)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "SPOS 0",
        "S 300",
        "M4",
        "SYNC 1.5",
        "G1 10 10 -10",
        "NOSYNC",
        "DWELL 1",
        "S 600",
        "M3",
        "SYNC 1.5",
        "G1 10 10 2",
        "NOSYNC",
        "G0 10 10 20",
        "S 1000",
        "M5",
    ]


def test_cycle84_in_strokes_chip_breaking_and_swarf_removal() -> None:
    """Fusion 360's "tapping with chip breaking": CYCLE84(20, 0, 2, -10, , 0, 3, , PIT 1,
    0, 300, 300, 0, 0, 0, _VARI 1, _DAM 5, _VRT 0.5). From RFP + SDIS = 2 strokes of 5:
    -3, -8, then the depth -10. After each intermediate depth M4 and synchronised back by
    0.5 (-2.5, -7.5), M3 and on; at the depth M4, out to 2, G0 RTP, S and SDAC. _VARI 2
    comes back to 2 each time instead."""
    call = "CYCLE84(20, 0, 2, -10, , 0, 3, , 1, 0, 1000, 1000, 0, 0, 0, {}, 5, 0.5)"
    got = [m for m in motions(HEAD + call.format(1) + "\nM30\n") if m[0] in "GM"]
    assert got == [
        "G0 10 10 2",
        "M3",
        "G1 10 10 -3",
        "M4",
        "G1 10 10 -2.5",
        "M3",
        "G1 10 10 -8",
        "M4",
        "G1 10 10 -7.5",
        "M3",
        "G1 10 10 -10",
        "M4",
        "G1 10 10 2",
        "G0 10 10 20",
        "M3",
    ]
    got = [m for m in motions(HEAD + call.format(2) + "\nM30\n") if m.startswith("G1")]
    assert got == ["G1 10 10 -3", "G1 10 10 2", "G1 10 10 -8", "G1 10 10 2", "G1 10 10 -10"] + [
        "G1 10 10 2"
    ]


def test_cycle840_with_and_without_encoder() -> None:
    """CYCLE840(20, 0, 2, -10, , DTB 0.5, SDR 0, SDAC 3, ENC 0, , PIT 1.25): with the
    encoder in synchronised (G33) at 1.25, dwell, reversed automatically (M3 -> M4), out,
    G0 RTP, SDAC M3. ENC 1 (compensating chuck, no encoder): G1 (G63) in and out at the
    feed in force, SDR 4 reversal."""
    got = motions(HEAD + "CYCLE840(20, 0, 2, -10, , 0.5, 0, 3, 0, , 1.25)\nM30\n")
    assert got == [
        "G0 10 10 2",
        "SYNC 1.25",
        "G1 10 10 -10",
        "NOSYNC",
        "DWELL 0.5",
        "M4",
        "SYNC 1.25",
        "G1 10 10 2",
        "NOSYNC",
        "G0 10 10 20",
        "M3",
    ]
    got = motions(HEAD + "CYCLE840(20, 0, 2, -10, , 0, 4, 3, 1)\nM30\n")
    assert got == ["G0 10 10 2", "G1 10 10 -10", "M4", "G1 10 10 2", "G0 10 10 20", "M3"]


# ---------------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    ("call", "code", "word"),
    [
        ("CYCLE83(20, 0, 2, -22, , 5, , 2, , , , 1)", "SIEM-CYCLE-ARGS", "61107"),
        ("CYCLE83(20, 0, 2, -22, , -5, , 2, , , , 2)", "SIEM-CYCLE-ARGS", "VARI"),
        ("CYCLE83(20, 0, 2, -22, , -5, , 2, , , 2, 1)", "SIEM-CYCLE-ARGS", "FRF"),
        ("CYCLE83(20, 0, 2, -22, , -5, , -0.5, , , , 1)", "SIEM-CYCLE-ARGS", "_MDEP"),
        ("CYCLE83(20, 0, 2, -22, , -5, , , , , , 1, 5)", "SIEM-CYCLE-UNSUPPORTED", "_AXN"),
        (
            "CYCLE83(10,0,5,,20,,4,100,0,0.5,100,1,0,1.2,1.4,0,1.6,0,1,11211111)",
            "SIEM-CYCLE-UNSUPPORTED",
            "_DMODE",
        ),
        ("CYCLE83(20, 0, 2, -900, , -0.01, , 0, , , , 0)", "SIEM-CYCLE-ARGS", "strokes"),
        (
            "CYCLE83(20, 0, 2, -22, , -5, , 0, , , 1, 0, , 5, 1, 0, 0, 0, 0, 1002110)",
            "SIEM-CYCLE-UNSUPPORTED",
            "_AMODE",
        ),
        ("CYCLE81(10, 0, 2, , 5, 0, 0, 10)", "SIEM-CYCLE-UNSUPPORTED", "_AMODE"),
        ("CYCLE82(10, 0, 2, -5, , 1, 1, 0, 0)", "SIEM-CYCLE-UNSUPPORTED", "_GMODE"),
        ("CYCLE83(20, 0, 2, 5, , -5)", "SIEM-CYCLE-ARGS", "depth"),
        ("HOLES2(50, 50, 20, 0, 90, 0)", "SIEM-CYCLE-ARGS", "NUM"),
        ("HOLES2(50, 50, 0, 0, 90, 4)", "SIEM-CYCLE-ARGS", "RAD"),
        ("HOLES1(0, 0, 0, 10, 10, 2.5)", "SIEM-CYCLE-ARGS", "NUM"),
        ("CYCLE801(0, 0, 0, 10, 10, 2, 0)", "SIEM-CYCLE-ARGS", "_NUM2"),
        ("CYCLE85(10, 0, 2, -5, , 1, 0, 200)", "SIEM-CYCLE-ARGS", "FFR"),
        ("CYCLE86(10, 0, 2, -5, , 1, 5, 1, 1, 1, 0)", "SIEM-CYCLE-ARGS", "SDIR"),
        ("CYCLE86(10, 0, 2, -5, , 1, 3, 1, 1, 1, 400)", "SIEM-CYCLE-ARGS", "POSS"),
        ("CYCLE87(10, 0, 2, -5)", "SIEM-CYCLE-ARGS", "SDIR"),
        ("CYCLE84(20, 0, 2, -10, , 0, 3, , , 0, 300)", "SIEM-CYCLE-ARGS", "pitch"),
        ("CYCLE84(20, 0, 2, -10, , 0, 3, 7, , 0, 300)", "SIEM-CYCLE-ARGS", "MPIT"),
        ("CYCLE84(20, 0, 2, -10, , 0, 3, 8, 1.5, 0, 300)", "SIEM-CYCLE-ARGS", "61001"),
        ("CYCLE84(20, 0, 2, -10, , 0, 7, 8, , 0, 300)", "SIEM-CYCLE-ARGS", "SDAC"),
        (
            "CYCLE84(20, 0, 2, -10, , 0, 3, 8, , 0, 300, , , , , 3, 2, 1)",
            "SIEM-CYCLE-ARGS",
            "_VARI",
        ),
        ("CYCLE84(20, 0, 2, -10, , 0, 3, 8, , 0, 300, , , , , 1, 0, 1)", "SIEM-CYCLE-ARGS", "_DAM"),
        ("CYCLE840(20, 0, 2, -10, , 0, 0, 3, 2, 8)", "SIEM-CYCLE-UNSUPPORTED", "ENC"),
        ("M5\nCYCLE840(20, 0, 2, -10, , 0, 0, 3, 0, 8)", "SIEM-CYCLE-ARGS", "spindle"),
        ("CYCLE89(10, 0, 2, -5, , 1, 2)", "SIEM-CYCLE-ARGS", "at most 6"),
        (
            "CYCLE90(10, 0, 2, -10, , 20, 0, 2, 100, 2, 0, 50, 50)",
            "SIEM-CYCLE-UNSUPPORTED",
            "CYCLE90",
        ),
    ],
)
def test_bad_cycle_calls_are_located_and_named(call: str, code: str, word: str) -> None:
    """Each bad call stops at its own line and column with the code and names the
    parameter (or the cycle) at fault."""
    lines = (HEAD + call).count("\n")
    err = error(HEAD + call + "\nM30\n")
    assert err.code == code, err.message
    assert word in err.message
    assert (err.location.file, err.location.line, err.location.column) == ("p.mpf", lines + 1, 1)


def test_a_pattern_under_a_modal_subprogram_call_is_refused() -> None:
    """MCALL of a program file, then HOLES1: the reader repeats only expanded cycles in a
    pattern and names the pattern and the program."""
    err = error(HEAD + "MCALL L10\nHOLES1(0, 0, 0, 10, 10, 2)\nM30\n")
    assert err.code == "SIEM-CYCLE-UNSUPPORTED"
    assert "HOLES1" in err.message and "L10" in err.message and err.location.line == 4


def test_cycle83_without_feed_is_refused_at_its_line() -> None:
    """The strokes are G1 at the feed in force: none programmed is SIEM-FEED at the call."""
    err = error("G0 X0 Y0 Z20\nCYCLE83(20, 0, 2, -10, , -5, , , , , , 0)\nM30\n")
    assert (err.code, err.location.line) == ("SIEM-FEED", 2)
