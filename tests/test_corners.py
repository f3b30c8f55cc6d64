"""Chamfers and roundings between two lines: Fanuc/Haas ``,C`` / ``,R`` and 840D CHF=, CHR=,
RND=, RNDM= (gcode.core.corners).

Oracles: the fillet's defining properties checked from first principles (tangent to both
lines: centre at distance R from each line, tangent points the feet of the perpendiculars,
the turn's direction), closed-form corners worked by hand from the manuals' definitions
(Fanuc 0i-MF "Chamfering and corner R": C is the distance from the virtual corner, R the
radius; 840D fundamentals "Chamfer, rounding": CHR the leg, CHF the chamfer's own length,
RND/RNDM the radius, a corner too large is made smaller, none is cut before a rapid).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gcode.core.corners import CornerError, CornerRequest, cut_corner, round_with_arcs
from gcode.fanuc.reader import interpret_text as fanuc
from gcode.haas.reader import interpret_text as haas
from gcode.siemens.reader import interpret_text as siemens
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane

HERE = Location("t", 1, 1)


def motions(cmds: list[canon.Command]) -> list[tuple]:
    """The moves as (name, rounded numbers)."""
    out = []
    for c in cmds:
        if isinstance(c, canon.StraightFeed | canon.StraightTraverse | canon.ArcFeed):
            out.append((c.NAME, *(round(float(a), 4) for a in c.args())))
    return out


def feed(*xyz: float) -> tuple:
    return ("STRAIGHT_FEED", *(float(v) for v in xyz), 0.0, 0.0, 0.0)


def arc(e1: float, e2: float, c1: float, c2: float, turn: int, n: float = 0.0) -> tuple:
    return ("ARC_FEED", e1, e2, c1, c2, float(turn), n, 0.0, 0.0, 0.0)


# ----------------------------------------------------------------------------- geometry
_coord = st.floats(-200, 200, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(_coord, _coord, _coord, _coord, _coord, _coord, st.floats(0.01, 20))
def test_a_fillet_is_tangent_to_both_lines_and_turns_their_way(x0, y0, x1, y1, x2, y2, r):
    """Any corner that has room: the arc's centre is R from both (infinite) lines, its ends
    are the feet of the perpendiculars from the centre, and it turns as the path turns."""
    d1, d2 = (x1 - x0, y1 - y0), (x2 - x1, y2 - y1)
    l1, l2 = math.hypot(*d1), math.hypot(*d2)
    cross = d1[0] * d2[1] - d1[1] * d2[0]
    if l1 < 1 or l2 < 1 or abs(cross) < 1e-3 * l1 * l2:
        return
    turn = math.atan2(abs(cross), d1[0] * d2[0] + d1[1] * d2[1])
    if r * math.tan(turn / 2) > min(l1, l2) or math.pi - turn < 1e-3:
        return
    req = CornerRequest("round", r, (x0, y0, 0, 0, 0, 0), Plane.XY, HERE)
    out = cut_corner(req, canon.StraightFeed(x1, y1, 0), canon.StraightFeed(x2, y2, 0))
    element = next(c for c in out if isinstance(c, canon.ArcFeed))
    trimmed = out[0] if isinstance(out[0], canon.StraightFeed) else None
    t1 = (trimmed.x, trimmed.y) if trimmed is not None else (x0, y0)
    t2 = (element.first_end, element.second_end)
    cx, cy = element.first_axis, element.second_axis

    def line_distance(px: float, py: float, ax: float, ay: float, d: tuple) -> float:
        return abs((px - ax) * d[1] - (py - ay) * d[0]) / math.hypot(*d)

    tol = 1e-7 * (1 + max(map(abs, (x0, y0, x1, y1, x2, y2))))
    assert line_distance(cx, cy, x0, y0, d1) == pytest.approx(r, abs=tol)
    assert line_distance(cx, cy, x1, y1, d2) == pytest.approx(r, abs=tol)
    assert math.dist((cx, cy), t1) == pytest.approx(r, abs=tol)
    assert math.dist((cx, cy), t2) == pytest.approx(r, abs=tol)
    # the radius to each tangent point is perpendicular to that line
    assert abs((t1[0] - cx) * d1[0] + (t1[1] - cy) * d1[1]) <= tol * l1
    assert abs((t2[0] - cx) * d2[0] + (t2[1] - cy) * d2[1]) <= tol * l2
    assert element.rotation == (1 if cross > 0 else -1)
    assert out[-1] == canon.StraightFeed(x2, y2, 0) or r * math.tan(turn / 2) >= l2 - 1e-9


@settings(max_examples=200, deadline=None)
@given(st.floats(5, 100), st.floats(-150, 150), st.floats(0.01, 0.4))
def test_chamfer_legs_and_length_are_the_given_sizes(length, angle, share):
    """CHR/,C: both legs from the virtual corner are the size; CHF: the chamfer is."""
    if abs(angle) < 1:
        return
    size = share * length
    a = math.radians(angle)
    end = (length + length * math.cos(a), length * math.sin(a))
    first, second = canon.StraightFeed(length, 0, 0), canon.StraightFeed(*end, 0)
    req = CornerRequest("chamfer", size, (0,) * 6, Plane.XY, HERE)
    trimmed, line, _ = cut_corner(req, first, second)
    assert math.dist((trimmed.x, trimmed.y), (length, 0)) == pytest.approx(size)
    assert math.dist((line.x, line.y), (length, 0)) == pytest.approx(size)
    req = CornerRequest("chamfer_length", size, (0,) * 6, Plane.XY, HERE)
    trimmed, line, _ = cut_corner(req, first, second)
    assert math.dist((trimmed.x, trimmed.y), (line.x, line.y)) == pytest.approx(size)


def test_a_corner_in_the_xz_plane_keeps_y_and_uses_z_as_the_first_axis():
    """G18: a 90-degree corner Z-then-X; ARC_FEED's first axis is Z (NISTIR 5970 3.6.1)."""
    req = CornerRequest("round", 2.0, (0, 5, 0, 0, 0, 0), Plane.XZ, HERE)
    out = cut_corner(req, canon.StraightFeed(0, 5, -10), canon.StraightFeed(10, 5, -10))
    assert motions(out) == [
        feed(0, 5, -8),
        # from Z-8 (X0) to Z-10 X2: centre Z-8 X2; Z then X is a right turn: clockwise
        arc(-10, 2, -8, 2, -1, 5),
        feed(10, 5, -10),
    ]


def test_a_corner_of_lines_that_leave_the_plane_is_refused():
    req = CornerRequest("round", 1.0, (0,) * 6, Plane.XY, HERE)
    with pytest.raises(CornerError, match="off the plane"):
        cut_corner(req, canon.StraightFeed(10, 0, -1), canon.StraightFeed(10, 10, -1))


@settings(max_examples=300, deadline=None)
@given(
    st.floats(5, 60),
    st.floats(-80, 80),
    st.floats(5, 60),
    st.sampled_from([1, -1]),
    st.floats(10, 170),
    st.floats(0.05, 0.5),
    st.booleans(),
)
def test_a_fillet_beside_a_circle_touches_it_and_the_line(
    length, angle, rho, turn, sweep, share, arc_first
):
    """A line then an arc (or the arc then the line, run backwards): the fillet's centre is
    R from the line and R + or - rho from the circle's centre (tangent from outside or
    inside), its ends lie on the line and the circle, and the first move ends where the
    fillet starts."""
    a = math.radians(angle)
    corner = (length, 0.0)
    # the circle starts at the corner, its centre rho to one side of a direction `a`
    ux, uy = math.cos(a), math.sin(a)
    centre = (corner[0] - turn * rho * uy, corner[1] + turn * rho * ux)
    b0 = math.atan2(corner[1] - centre[1], corner[0] - centre[0])
    b1 = b0 + turn * math.radians(sweep)
    end = (centre[0] + rho * math.cos(b1), centre[1] + rho * math.sin(b1))
    r = share * min(length, rho)
    if arc_first:  # the same path backwards: arc from `end` to the corner, then the line
        req = CornerRequest("round", r, (*end, 0, 0, 0, 0), Plane.XY, HERE)
        one = canon.ArcFeed(*corner, *centre, -turn, 0.0)
        two = canon.StraightFeed(0, 0, 0)
    else:
        req = CornerRequest("round", r, (0,) * 6, Plane.XY, HERE)
        one = canon.StraightFeed(*corner, 0)
        two = canon.ArcFeed(*end, *centre, turn, 0.0)
    try:
        out = round_with_arcs(req, one, two)
    except CornerError as exc:
        assert "does not fit" in str(exc) or "straight back" in str(exc)
        return
    fillets = [c for c in out if isinstance(c, canon.ArcFeed) and c.source is HERE]
    if not fillets:  # tangent joint: nothing to cut
        assert out == [one, two]
        return
    (fillet,) = fillets
    f = (fillet.first_axis, fillet.second_axis)
    assert abs(f[1]) == pytest.approx(r, abs=1e-7)  # R from the line y = 0
    assert abs(math.dist(f, centre) - rho) == pytest.approx(r, abs=1e-7)
    ends = [(fillet.first_end, fillet.second_end)]
    before = out[out.index(fillet) - 1] if out.index(fillet) else None
    start = (before.x, before.y) if isinstance(before, canon.StraightFeed) else None
    if isinstance(before, canon.ArcFeed):
        start = (before.first_end, before.second_end)
    if start is not None:
        ends.append(start)
    for p in ends:  # each end on the line or on the circle
        assert min(abs(p[1]), abs(math.dist(p, centre) - rho)) < 1e-7
        assert math.dist(p, f) == pytest.approx(r, abs=1e-7)


def test_fanuc_corner_r_between_a_clockwise_arc_and_a_line():
    """By hand: G2 from (70,20) to (90,40) about (90,20), then G1 Y80 (a left turn from +X
    to +Y): the fillet's centre is 20 + 3 from (90,20) (left of a clockwise arc is outward)
    on x = 87, so y = 20 + sqrt(23^2 - 3^2); the arc ends on its radius through that centre,
    20/23 of the way."""
    text = "O1\nG21 G90 G0 X70. Y20.\nG2 X90. Y40. R20. F500. ,R3.\nG1 Y80.\nM30\n"
    yc = 20 + math.sqrt(23**2 - 3**2)
    t1 = (90 - 3 * 20 / 23, 20 + (yc - 20) * 20 / 23)
    got = motions(list(fanuc(text, "a.nc")))[1:]
    want = [
        arc(*(round(v, 4) for v in t1), 90, 20, -1),
        arc(90, round(yc, 4), 87, round(yc, 4), 1),
        feed(90, 80, 0),
    ]
    assert got == want


# ----------------------------------------------------------------------------- Fanuc, Haas
SQUARE = """O1000
G21 G90 G17 G40 G80
G0 X0. Y0.
G1 X50. ,R5. F500.
Y50. ,C3.
F300.
X0. ,R10.
Y0.
M30
%
"""


@pytest.mark.parametrize("reader", [fanuc, haas], ids=["fanuc", "haas"])
def test_fanuc_corner_r_and_chamfer_on_a_square(reader):
    """By hand: R5 at (50,0) turning left: line to X45, arc centre (45,5) CCW to (50,5);
    C3 at (50,50): chamfer (50,47)-(47,50); F300 comes after the chamfer, before X0; R10
    at (0,50): line to X10, arc centre (10,40) CCW to (0,40), then Y0."""
    cmds = list(reader(SQUARE, "sq.nc"))
    assert motions(cmds)[1:] == [
        feed(45, 0, 0),
        arc(50, 5, 45, 5, 1),
        feed(50, 47, 0),
        feed(47, 50, 0),
        feed(10, 50, 0),
        arc(0, 40, 10, 40, 1),
        feed(0, 0, 0),
    ]
    names = [c.NAME for c in cmds]
    rate = names.index("SET_FEED_RATE", names.index("SET_FEED_RATE") + 1)
    assert cmds[rate].rate == 300.0
    assert motions(cmds[rate - 1 : rate])[0] == feed(47, 50, 0)  # the chamfer's own feed


def test_fanuc_corner_values_without_a_point_are_least_increments():
    """``,R5`` is 5 least input increments (0.005 mm), as every Fanuc length."""
    text = "O1\nG21 G90 G1 X50. ,R5000 F500.\nY50.\nM30\n"
    assert motions(list(fanuc(text, "a.nc")))[:2] == [feed(45, 0, 0), arc(50, 5, 45, 5, 1)]


def test_fanuc_incremental_corner_r_turning_right():
    """G91: X100. then Y-100. is a right turn: clockwise fillet, centre (90,-10)."""
    text = "O1\nG21 G91 G1 X100. ,R10. F500.\nY-100.\nM30\n"
    assert motions(list(fanuc(text, "a.nc"))) == [
        feed(90, 0, 0),
        arc(100, -10, 90, -10, -1),
        feed(100, -100, 0),
    ]


@pytest.mark.parametrize(
    ("text", "line", "column", "words"),
    [
        ("G1 X50. ,R5. F500.\nG0 Y50.\n", 3, 1, "STRAIGHT_TRAVERSE"),
        ("G1 X4. ,R5. F500.\nY50.\n", 2, 8, "only 4.0000 long"),
        ("G0 X50. ,R5.\nY5.\n", 2, 9, "G01, G02 or G03"),
        ("G1 X50. ,C1. ,R5. F500.\nY5.\n", 2, 9, "both"),
        ("G1 X50. ,A30. F500.\nY5.\n", 2, 9, ",A angle"),
        ("G1 X50. ,C5. F500.\nG3 X60. Y10. R10.\n", 2, 9, "circular move"),
        ("G1 X50. ,R5. F500.\nG3 X40. Y0. R5.\n", 2, 9, "does not fit"),
        ("G1 X50. ,R5. F500.\nM30\n", 3, 1, "next block"),
        ("G41 D0 G1 X50. ,R5. F500.\nY5.\n", 2, 16, "cutter compensation"),
    ],
)
def test_fanuc_corners_the_control_alarms_on_are_located_errors(text, line, column, words):
    with pytest.raises(Diagnostic) as info:
        list(fanuc("O1\n" + text + "M30\n", "e.nc"))
    assert info.value.code == "FANUC-CORNER"
    assert words in info.value.message
    assert (info.value.location.line, info.value.location.column) == (line, column)


# ----------------------------------------------------------------------------- Siemens
def test_siemens_rnd_chf_chr_rndm_and_no_corner_before_a_rapid():
    """By hand (840D fundamentals): RND=5 as Fanuc's R5; CHF=4.2426 at a right angle has
    legs 4.2426 / (2 cos 45) = 3; CHR=3 legs 3; RNDM=2 rounds (20,0), not (20,20) before G0;
    RND=100 before a 5 mm move shrinks to R5 and takes that move whole."""
    text = (
        "G90 G17 G0 X0 Y0\nG1 X50 F500 RND=5\nY50 CHF=4.2426\nX0 CHR=3\nY0\nRNDM=2\n"
        "X20\nY20\nG0 X40\nRNDM=0\nG1 X60 RND=100\nY25\nM30\n"
    )
    assert motions(list(siemens(text, "r.mpf")))[1:] == [
        feed(45, 0, 0),
        arc(50, 5, 45, 5, 1),
        feed(50, 47, 0),
        feed(47, 50, 0),
        feed(3, 50, 0),
        feed(0, 47, 0),
        feed(0, 0, 0),
        feed(18, 0, 0),  # RNDM=2 is in force from here
        arc(20, 2, 18, 2, 1),
        feed(20, 20, 0),
        ("STRAIGHT_TRAVERSE", 40.0, 20.0, 0.0, 0.0, 0.0, 0.0),
        feed(55, 20, 0),
        arc(60, 25, 55, 25, 1),
    ]


def test_siemens_rounding_before_an_infeed_off_the_plane_is_not_cut():
    """The 840D cuts no corner when the next move leaves the plane (Z infeed)."""
    text = "G17 G90 G1 X10 Y0 F100 RND=2\nZ-5\nM30\n"
    assert motions(list(siemens(text, "z.mpf"))) == [feed(10, 0, 0), feed(10, 0, -5)]


@pytest.mark.parametrize(
    ("text", "column", "words"),
    [
        ("G1 X10 F100 RND=1 CHF=1\nY5\n", 19, "in one block"),
        ("RND=1\nG1 X1 F100\n", 1, "moves"),
        ("G1 X10 F100 CHR=1\nG2 X20 Y0 CR=5\n", 13, "circular"),
        ("SCALE X2 Y2\nG1 X10 F100 RND=1\nY5\n", 13, "SCALE"),
    ],
)
def test_siemens_corners_not_read_are_located_errors(text, column, words):
    with pytest.raises(Diagnostic) as info:
        list(siemens(text + "M30\n", "e.mpf"))
    assert info.value.code == "SIEM-CORNER"
    assert words in info.value.message
    assert info.value.location.column == column


def test_a_corner_in_a_lathe_cycle_contour_is_refused_not_dropped():
    """G71/G70 contour blocks are read by the cycle, not run: a ,C there would be lost."""
    text = (
        "O1\nG18 G21 G99\nT0101\nG0 X50. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0.5 W0.1 F0.2\n"
        "N10 G0 X20.\nG1 Z-10. ,C1.\nX40.\nN20 Z-30.\nG70 P10 Q20\nM30\n"
    )
    with pytest.raises(Diagnostic) as info:
        list(fanuc(text, "l.nc", lathe=True))
    assert info.value.code == "FANUC-CORNER"
    assert (info.value.location.line, info.value.location.column) == (8, 10)


def test_siemens_corners_hold_through_the_fast_lane(tmp_path, monkeypatch):
    """With the 840D fast lane taking plain blocks (as cnc convert's read-back does), a move
    waiting for its rounding and every corner under RNDM come out as the general reader's."""
    from gcode.siemens import reader as siemens_reader

    text = (
        "G90 G17 G0 X0 Y0\nG1 X50 F500 RND=5\nY50 \nX0 \nRNDM=2\nX20 \nY20 \nX40 \n"
        "RNDM=0\nY40 \nX60 \nM30\n"
    )
    path = tmp_path / "lane.mpf"
    path.write_text(text)
    monkeypatch.setattr(siemens_reader, "LANE_MIN_BYTES", 0)
    got = []
    for item in siemens_reader.interpret_chunks(path, arcs=True):
        got += [item] if isinstance(item, canon.Command) else item.commands(str(path))
    assert motions(got) == motions(list(siemens(text, str(path))))
    assert arc(50, 5, 45, 5, 1) in motions(got)
