"""Fanuc 0i-TF lathe cycles (gcode/fanuc_turning*.py): closed forms per cycle and properties.

References: the cycle formats of the book's Table A.1 (seed 004, Appendix A) and the 0i-TF
motion sequences stated in the module docstrings; every expected number below is derived
by hand from those sequences, not read from the implementation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from gcode.fanuc.turning.cycles import CycleSettings, LatheMove, ProfileStep, cycle_moves
from kernel.diagnostics import Diagnostic

P = ProfileStep


def pts(moves: list[LatheMove]) -> list[tuple[str, float, float]]:
    return [(m.kind, round(m.x, 9), round(m.z, 9)) for m in moves]


def ends_at(moves: list[LatheMove], x: float, z: float) -> bool:
    return math.isclose(moves[-1].x, x, abs_tol=1e-9) and math.isclose(moves[-1].z, z, abs_tol=1e-9)


# ------------------------------------------------------------------ single cycles G90 G94 G92
def test_g90_straight_cut_is_rapid_in_cut_feed_out_rapid_back() -> None:
    # start (radius 26, z 2); X40. is radius 20; cut to z -30; F0.2 on the first feed move.
    moves = cycle_moves("G90", (26.0, 2.0), {"X": 40.0, "Z": -30.0, "F": 0.2})
    assert pts(moves) == [
        ("rapid", 20.0, 2.0),
        ("feed", 20.0, -30.0),
        ("feed", 26.0, -30.0),
        ("rapid", 26.0, 2.0),
    ]
    assert moves[1].feed == 0.2 and moves[2].feed is None


def test_g90_taper_r_is_the_radius_difference_at_the_start_z() -> None:
    # the cut starts 3 (radius) below the end radius, at the start Z: a cone from
    # (17, 2) to (20, -30), whatever the diameter mode.
    for diameter, x_word in ((True, 40.0), (False, 20.0)):
        moves = cycle_moves(
            "G90", (26.0, 2.0), {"X": x_word, "Z": -30.0, "R": -3.0}, diameter=diameter
        )
        assert pts(moves)[:2] == [("rapid", 17.0, 2.0), ("feed", 20.0, -30.0)]
        slope = (moves[1].x - moves[0].x) / (moves[1].z - moves[0].z)
        assert slope == pytest.approx(-3.0 / 32.0)


def test_g90_incremental_u_w_equal_the_absolute_words() -> None:
    # U-12. is -6 in radius from x 26 -> 20; W-32. from z 2 -> -30.
    a = cycle_moves("G90", (26.0, 2.0), {"X": 40.0, "Z": -30.0})
    b = cycle_moves("G90", (26.0, 2.0), {"U": -12.0, "W": -32.0})
    assert pts(a) == pts(b)


def test_g94_face_cut_with_taper_r_in_z() -> None:
    # Face from x0 = 30 to radius 10 at z -2; R-1: the cut starts at z -3 at x0.
    moves = cycle_moves("G94", (30.0, 2.0), {"X": 20.0, "Z": -2.0, "R": -1.0, "F": 0.1})
    assert pts(moves) == [
        ("rapid", 30.0, -3.0),
        ("feed", 10.0, -2.0),
        ("feed", 10.0, 2.0),
        ("rapid", 30.0, 2.0),
    ]


def test_g92_is_one_thread_pass_with_rapid_retract() -> None:
    moves = cycle_moves("G92", (15.0, 3.0), {"X": 23.2, "Z": -20.0, "F": 1.5})
    assert pts(moves) == [
        ("rapid", 11.6, 3.0),
        ("thread", 11.6, -20.0),
        ("rapid", 15.0, -20.0),
        ("rapid", 15.0, 3.0),
    ]
    assert moves[1].lead == 1.5


def test_g92_without_lead_is_a_located_feed_error() -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G92", (15.0, 3.0), {"X": 23.2, "Z": -20.0}, line=7, path="t.nc")
    assert err.value.code == "FANUC-CYCLE-FEED"
    assert (err.value.location.file, err.value.location.line) == ("t.nc", 7)


# ---------------------------------------------------------------------------------- G71 G72
def cylinder(x_f: float, z0: float, z_end: float, x_stock: float) -> list[ProfileStep]:
    """A' at (x_f, z0) by G00 X only, the cylinder to z_end, then out to the stock radius."""
    return [
        P("rapid", x_f, z0, line=10),
        P("line", x_f, z_end, line=11),
        P("line", x_stock, z_end, line=12),
    ]


@given(
    depth_total=st.floats(0.5, 20.0),
    d=st.floats(0.2, 3.0),
    u=st.floats(0.0, 1.0),
    w=st.floats(0.0, 0.5),
)
def test_g71_cylinder_takes_ceil_depth_over_d_passes_ending_at_the_allowance(
    depth_total: float, d: float, u: float, w: float
) -> None:
    x0, z0, z_end = 30.0, 2.0, -40.0
    x_f = x0 - depth_total - u / 2.0  # finished radius; the allowance surface is x_f + u/2
    params = {"1U": d, "1R": 0.5, "U": u, "W": w, "F": 0.25, "P": 10, "Q": 12}
    moves = cycle_moves("G71", (x0, z0), params, cylinder(x_f, z0, z_end, x0))
    cuts = [m for m in moves if m.kind == "feed" and abs(m.z - (z_end + w)) < 1e-9 and m.x < x0]
    levels = [m.x for m in cuts]
    n = math.ceil(depth_total / d - 1e-9)
    expected = [x0 - k * d for k in range(1, n)] + [x_f + u / 2.0]
    assert levels == pytest.approx(expected, abs=1e-9)
    assert len(cuts) == n
    assert moves[0].kind == "rapid"  # the P block is G00: rapid infeed
    assert next(m.feed for m in moves if m.kind == "feed") == 0.25
    assert ends_at(moves, x0, z0)


def test_g71_escape_is_45_degrees_then_rapid_back_to_start_z() -> None:
    moves = cycle_moves(
        "G71", (26.0, 2.0), {"1U": 2.0, "1R": 0.5, "P": 1, "Q": 3}, cylinder(20.0, 2.0, -30.0, 26.0)
    )
    assert pts(moves)[:5] == [
        ("rapid", 24.0, 2.0),
        ("feed", 24.0, -30.0),
        ("rapid", 24.5, -29.5),
        ("rapid", 24.5, 2.0),
        ("rapid", 22.0, 2.0),
    ]


def test_g71_cut_ends_on_the_shifted_taper_and_arc() -> None:
    # Contour: A' (10, 2) by G01 X; taper to (15, -8); quarter arc G02 to (20, -13) about
    # (15, -13)... written as G03 seen with Z right and X up: from (15,-8) about (20,-8)?
    # Use a convex fillet: centre (20, -8), radius 5, from (15, -8) to (20, -13), cw in
    # the (z right, x up) view. Allowance U1. (0.5 radius), W0.
    contour = [
        P("line", 10.0, 2.0, line=20),
        P("line", 15.0, -8.0, line=21),
        P("ccw", 20.0, -13.0, cx=15.0, cz=-13.0, line=22),
        P("line", 25.0, -13.0, line=23),
    ]
    moves = cycle_moves(
        "G71", (25.0, 2.0), {"1U": 3.0, "1R": 0.0, "U": 1.0, "P": 20, "Q": 23}, contour
    )
    cuts = [m for m in moves if m.kind == "feed" and m.x in (22.0, 19.0, 16.0, 13.0)]
    by_level = {round(m.x, 9): m.z for m in cuts}
    # level 13: on the taper shifted by 0.5: x = 10.5 + (2 - z) * 0.5 -> z = 2 - 5 = -3
    assert by_level[13.0] == pytest.approx(-3.0)
    # levels 16, 19 on the shifted arc: centre (15.5, -13), radius 5, upper-left quadrant:
    # z = -13 + sqrt(25 - (x - 15.5)^2)
    for level in (16.0, 19.0):
        assert by_level[level] == pytest.approx(-13.0 + math.sqrt(25.0 - (level - 15.5) ** 2))
    # level 22 is above the arc's end (20.5): it ends on the shoulder at z -13
    assert by_level[22.0] == pytest.approx(-13.0)
    assert moves[0].kind == "feed"  # the P block is G01: infeed at feed
    finish = [m for m in moves if m.kind == "ccw"]
    assert len(finish) == 1 and (finish[0].cx, finish[0].cz) == (15.5, -13.0)


def test_g71_pocket_is_a_located_profile_error() -> None:
    contour = [
        P("rapid", 10.0, 2.0, line=30),
        P("line", 10.0, -10.0, line=31),
        P("line", 8.0, -15.0, line=32),  # goes back down: a pocket
        P("line", 20.0, -25.0, line=33),
    ]
    with pytest.raises(Diagnostic) as err:
        cycle_moves(
            "G71", (22.0, 2.0), {"1U": 1.0, "P": 30, "Q": 33}, contour, path="p.nc", line=29
        )
    assert err.value.code == "FANUC-CYCLE-PROFILE"
    assert err.value.location.line == 32


def test_g71_arc_crossing_a_quadrant_is_not_monotone() -> None:
    contour = [
        P("rapid", 10.0, 2.0, line=1),
        P("cw", 10.0, -18.0, cx=10.0, cz=-8.0, line=2),  # half circle bulging out in X
        P("line", 25.0, -18.0, line=3),
    ]
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G71", (30.0, 2.0), {"1U": 1.0, "P": 1, "Q": 3}, contour)
    assert (err.value.code, err.value.location.line) == ("FANUC-CYCLE-PROFILE", 2)


@pytest.mark.parametrize(
    ("params", "contour", "code"),
    [
        ({"1U": 1.0}, [], "FANUC-CYCLE-CONTOUR"),
        ({"1U": 1.0, "P": 1, "Q": 2}, [], "FANUC-CYCLE-CONTOUR"),
        ({"1U": 0.0, "P": 1, "Q": 3}, cylinder(10.0, 2.0, -10.0, 20.0), "FANUC-CYCLE-DEPTH"),
        ({"1U": -1.0, "P": 1, "Q": 3}, cylinder(10.0, 2.0, -10.0, 20.0), "FANUC-CYCLE-DEPTH"),
        ({"P": 1, "Q": 3}, cylinder(10.0, 2.0, -10.0, 20.0), "FANUC-CYCLE-DEPTH"),
        (
            {"1U": 1.0, "U": 30.0, "P": 1, "Q": 3},
            cylinder(10.0, 2.0, -10.0, 20.0),
            "FANUC-CYCLE-GEOMETRY",
        ),
    ],
)
def test_g71_bad_words_are_located_errors(
    params: dict[str, float], contour: list[ProfileStep], code: str
) -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G71", (20.0, 2.0), params, contour, path="g71.nc", line=5)
    assert err.value.code == code
    assert err.value.location.file == "g71.nc"


def test_g71_omitted_first_block_uses_the_parameters() -> None:
    contour = cylinder(10.0, 2.0, -10.0, 20.0)
    a = cycle_moves("G71", (20.0, 2.0), {"1U": 2.5, "1R": 0.3, "P": 1, "Q": 3}, contour)
    b = cycle_moves(
        "G71",
        (20.0, 2.0),
        {"P": 1, "Q": 3},
        contour,
        settings=CycleSettings(depth_of_cut=2.5, escape=0.3),
    )
    assert pts(a) == pts(b)


def test_g72_faces_in_layers_of_w_towards_the_contour() -> None:
    # Facing: start (30, 2); P block G00 Z-6. (A' = (30, -6), Z only); contour up the face
    # to (10, -6) then (10, 0)... written as a shoulder: from A' in -X to x 10, then +Z to 0.
    contour = [
        P("rapid", 30.0, -6.0, line=1),
        P("line", 10.0, -6.0, line=2),
        P("line", 10.0, 0.0, line=3),
    ]
    moves = cycle_moves(
        "G72", (30.0, 2.0), {"1W": 2.5, "1R": 0.5, "W": 0.2, "F": 0.2, "P": 1, "Q": 3}, contour
    )
    # layers at z = -0.5, -3.0 (next -5.5 is not above the allowance surface -5.8); each
    # cut ends at the allowance surface x = 10 (U0); on the face z > 0.2 there is no part.
    cuts = [(m.x, m.z) for m in moves if m.kind == "feed" and m.x == pytest.approx(10.0)]
    assert cuts[:2] == [(10.0, -0.5), (10.0, -3.0)]
    assert pts(moves)[2] == ("rapid", 10.5, 0.0)  # escape: +X 0.5 and back in Z 0.5
    assert ends_at(moves, 30.0, 2.0)


# Property: random monotone contours in all eight G71/G72 patterns.
# (da, db, shape): a line, or a quarter arc (db = da) about (a0 + da, b0) ("arc_a") or about
# (a0, b0 - da) ("arc_b"); both change monotonically.
SEGMENTS = st.lists(
    st.tuples(
        st.floats(0.0, 6.0), st.floats(0.0, 8.0), st.sampled_from(("line", "arc_a", "arc_b"))
    ).filter(lambda t: t[0] + t[1] > 0.05 and (t[2] == "line" or t[0] > 0.05)),
    min_size=1,
    max_size=6,
).filter(lambda segs: sum(da if k != "line" else db for da, db, k in segs) > 0.05)


@settings(max_examples=150, deadline=None)
@given(
    segs=SEGMENTS,
    facing=st.booleans(),
    sa=st.sampled_from((1.0, -1.0)),
    sb=st.sampled_from((1.0, -1.0)),
    below=st.floats(0.05, 10.0),
    depth=st.floats(0.3, 4.0),
    escape=st.floats(0.0, 1.0),
    ua=st.floats(0.0, 0.8),
    ub=st.floats(0.0, 0.8),
    gap=st.floats(0.0, 2.0),
)
def test_stock_removal_stays_outside_the_allowance_contour_and_inside_the_stock(
    segs: list[tuple[float, float, str]],
    facing: bool,
    sa: float,
    sb: float,
    below: float,
    depth: float,
    escape: float,
    ua: float,
    ub: float,
    gap: float,
) -> None:
    """Normalised frame (a: stepping axis, towards -a; b: cutting axis, towards -b); the
    contour rises in a while b falls. Mapped to the real (x, z) of one of the 8 G71/G72
    patterns (OD/ID or face side, cutting towards -Z/+Z or -X/+X)."""
    a_top, b_start = 0.0, 0.0
    # the start point clears the shifted contour (as the control requires): A' lies ub + gap
    # ahead of the start in the cutting direction
    points = [(a_top - below - ua, b_start - ub - gap)]
    centres: list[tuple[float, float] | None] = [None]
    for da, db, shape in segs:
        a, b = points[-1]
        if shape == "line":
            points.append((a + da, b - db))
            centres.append(None)
        else:
            points.append((a + da, b - da))
            centres.append((a + da, b) if shape == "arc_a" else (a, b - da))
    ox, oz = 50.0, 5.0  # keep real radii positive

    def real(a: float, b: float) -> tuple[float, float]:
        return (ox + sb * b, oz + sa * a) if facing else (ox + sa * a, oz + sb * b)

    def norm(x: float, z: float) -> tuple[float, float]:
        return (sa * (z - oz), sb * (x - ox)) if facing else (sa * (x - ox), sb * (z - oz))

    start = real(a_top, b_start)
    steps = [P("rapid", *real(*points[0]), line=1)]
    for i in range(1, len(points)):
        (x0, z0), (x1, z1) = real(*points[i - 1]), real(*points[i])
        centre = centres[i]
        if centre is None:
            steps.append(P("line", x1, z1, line=i + 1))
            continue
        cx, cz = real(*centre)
        # the quarter (short) arc turns counterclockwise, seen with Z right and X up, when
        # (start - centre) x (end - centre) > 0 in (z, x) coordinates
        turn = (z0 - cz) * (x1 - cx) - (x0 - cx) * (z1 - cz)
        steps.append(P("ccw" if turn > 0 else "cw", x1, z1, cx=cx, cz=cz, line=i + 1))
    # allowance pointing out of the part in the normalised frame: (+ua, +ub)
    if facing:
        dz, dx = sa * ua, sb * ub
    else:
        dx, dz = sa * ua, sb * ub
    first = {"1W" if facing else "1U": depth, "1R": escape}
    params = {**first, "P": 1, "Q": len(steps), "U": 2.0 * dx, "W": dz, "F": 0.2}
    moves = cycle_moves("G72" if facing else "G71", start, params, steps)

    offset = np.array(points) + (ua, ub)
    t = np.linspace(0.0, 1.0, 51)
    pieces = []
    for i in range(1, len(points)):
        p0, p1 = offset[i - 1], offset[i]
        centre = centres[i]
        if centre is None:
            pieces.append(p0 + t[:, None] * (p1 - p0))
            continue
        c = np.array(centre) + (ua, ub)
        r = np.hypot(*(p0 - c))
        t0 = math.atan2(p0[0] - c[0], p0[1] - c[1])
        t1 = math.atan2(p1[0] - c[0], p1[1] - c[1])
        sweep = (t1 - t0 + math.pi) % (2 * math.pi) - math.pi  # the short way
        ang = t0 + t * sweep
        pieces.append(np.column_stack((c[0] + r * np.sin(ang), c[1] + r * np.cos(ang))))
    dense = np.vstack(pieces)
    n_finish = len(steps)  # the rough finishing pass: one move per contour block
    rough = moves[: len(moves) - n_finish - 1]
    assert all(m.kind in ("rapid", "feed") for m in rough)
    ends = np.array([norm(*start)] + [norm(m.x, m.z) for m in rough])
    s = np.linspace(0.0, 1.0, 21)[:, None, None]
    samples = (ends[:-1] + s * (ends[1:] - ends[:-1])).reshape(-1, 2)
    tol = 1e-7
    assert np.all(samples[:, 0] <= a_top + escape + tol)  # inside the stock
    assert np.all(samples[:, 1] <= b_start + tol)
    assert np.all(samples[:, 1] >= min(offset[-1, 1], b_start) - tol)  # never beyond B
    under = (samples[:, None, 0] < dense[None, :, 0] - tol) & (
        samples[:, None, 1] < dense[None, :, 1] - tol
    )
    assert not under.any(), samples[under.any(axis=1)][:3]
    # the last pass runs on the allowance contour (arcs about shifted centres), then to A
    finish = moves[-n_finish - 1 : -1]
    for m, step in zip(finish[1:], steps[1:], strict=True):
        assert m.kind == ("feed" if step.kind == "line" else step.kind)
        assert (m.x, m.z) == pytest.approx((step.x + dx, step.z + dz), abs=1e-9)
        if m.kind != "feed":
            assert (m.cx, m.cz) == pytest.approx((step.cx + dx, step.cz + dz), abs=1e-9)
    assert ends_at(moves, *start)


# ---------------------------------------------------------------------------------- G70 G73
def test_g70_reproduces_the_contour_with_its_feeds() -> None:
    contour = [
        P("rapid", 10.0, 2.0, line=1),
        P("line", 10.0, -5.0, feed=0.1, line=2),
        P("cw", 15.0, -10.0, cx=15.0, cz=-5.0, line=3),
        P("line", 20.0, -10.0, feed=0.05, line=4),
    ]
    moves = cycle_moves("G70", (22.0, 3.0), {"P": 1, "Q": 4}, contour)
    assert [(m.kind, m.x, m.z, m.cx, m.cz, m.feed) for m in moves] == [
        ("rapid", 10.0, 2.0, 0.0, 0.0, None),
        ("feed", 10.0, -5.0, 0.0, 0.0, 0.1),
        ("cw", 15.0, -10.0, 15.0, -5.0, None),
        ("feed", 20.0, -10.0, 0.0, 0.0, 0.05),
        ("rapid", 22.0, 3.0, 0.0, 0.0, None),
    ]


def test_g73_passes_shrink_the_relief_evenly_to_the_allowance() -> None:
    # U3. W0 R3: shifts (3 + 0.25, 0.1), (1.5 + 0.25, 0.1), (0.25, 0.1) with U0.5 W0.1.
    contour = [
        P("line", 10.0, 1.0, line=1),
        P("line", 10.0, -10.0, line=2),
        P("line", 20.0, -15.0, line=3),
    ]
    params = {"1U": 3.0, "1W": 0.0, "1R": 3, "P": 1, "Q": 3, "U": 0.5, "W": 0.1, "F": 0.2}
    moves = cycle_moves("G73", (25.0, 3.0), params, contour)
    assert len(moves) == 3 * 4
    for j, dx in enumerate((3.25, 1.75, 0.25)):
        block = moves[4 * j : 4 * j + 4]
        assert pts(block) == [
            ("feed", 10.0 + dx, 1.1),
            ("feed", 10.0 + dx, -9.9),
            ("feed", 20.0 + dx, -14.9),
            ("rapid", 25.0, 3.0),
        ]


def test_g73_divisions_must_be_a_whole_number() -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G73", (25.0, 3.0), {"1R": 0.0, "P": 1, "Q": 1}, [P("line", 10.0, 1.0)])
    assert err.value.code == "FANUC-CYCLE-DEPTH"


# ---------------------------------------------------------------------------------- G74 G75
def test_g74_pecks_q_deep_with_return_e_and_steps_p_in_x() -> None:
    params = {"1R": 0.5, "X": 20.0, "Z": -10.0, "P": 3.0, "Q": 4.0, "R": 0.2, "F": 0.1}
    moves = cycle_moves("G74", (16.0, 2.0), params)
    pairs = zip(moves, moves[1:], strict=False)
    plunges = [m.x for p, m in pairs if m.kind == "feed" and m.z == -10.0 and m.x == p.x]
    assert plunges == [16.0, 13.0, 10.0]  # X20. is radius 10; steps of 3 from 16
    first = pts(moves)[:7]
    assert first == [
        ("feed", 16.0, -2.0),  # 4 deep
        ("rapid", 16.0, -1.5),  # back e
        ("feed", 16.0, -6.0),  # 4 + e
        ("rapid", 16.0, -5.5),
        ("feed", 16.0, -10.0),  # last peck partial
        ("rapid", 16.0, 2.0),  # no relief at the first plunge: no groove behind it
        ("rapid", 13.0, 2.0),
    ]
    # later plunges: relief R against the step direction (-X), into the groove, by rapid
    assert pts(moves)[11:14] == [
        ("feed", 13.0, -10.0),
        ("rapid", 13.2, -10.0),
        ("rapid", 13.2, 2.0),
    ]
    assert ends_at(moves, 16.0, 2.0)


def test_g74_without_x_is_peck_drilling_on_the_axis() -> None:
    moves = cycle_moves("G74", (0.0, 1.0), {"1R": 1.0, "Z": -5.0, "Q": 2.0, "F": 0.05})
    assert pts(moves) == [
        ("feed", 0.0, -1.0),
        ("rapid", 0.0, 0.0),
        ("feed", 0.0, -3.0),
        ("rapid", 0.0, -2.0),
        ("feed", 0.0, -5.0),
        ("rapid", 0.0, 1.0),
    ]


def test_g75_grooves_in_x_and_steps_q_in_z() -> None:
    params = {"1R": 0.5, "X": 20.0, "Z": -10.0, "P": 3.0, "Q": 4.0, "F": 0.1}
    moves = cycle_moves("G75", (16.0, 2.0), params)
    plunges = [m.z for m in moves if m.kind == "feed" and m.x == 10.0]
    assert plunges == [2.0, -2.0, -6.0, -10.0]
    assert pts(moves)[:4] == [
        ("feed", 13.0, 2.0),
        ("rapid", 13.5, 2.0),
        ("feed", 10.0, 2.0),
        ("rapid", 16.0, 2.0),
    ]
    assert ends_at(moves, 16.0, 2.0)


def test_g75_several_plunges_need_a_shift() -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G75", (16.0, 2.0), {"X": 20.0, "Z": -10.0, "P": 3.0})
    assert err.value.code == "FANUC-CYCLE-DEPTH"


# ---------------------------------------------------------------------------------- G76
def thread_passes(moves: list[LatheMove]) -> list[LatheMove]:
    """The first thread move of every pass."""
    out = []
    prev = "rapid"
    for m in moves:
        if m.kind == "thread" and prev != "thread":
            out.append(m)
        prev = m.kind
    return out


@given(
    k=st.floats(0.5, 3.0),
    q_frac=st.floats(0.05, 0.6),
    dmin=st.floats(0.0, 0.2),
    d_frac=st.floats(0.0, 0.3),
    m=st.integers(1, 3),
    angle=st.sampled_from((0, 29, 55, 60)),
)
def test_g76_pass_depths_follow_q_sqrt_n_then_the_finishing_passes(
    k: float, q_frac: float, dmin: float, d_frac: float, m: int, angle: int
) -> None:
    q, d = k * q_frac, k * d_frac
    root = 12.0  # X24. diameter
    x0, z0, z_end, lead = root + k + 1.0, 3.0, -25.0, 1.5
    params = {
        "1P": m * 10000 + angle,
        "1Q": dmin,
        "1R": d,
        "X": 24.0,
        "Z": z_end,
        "P": k,
        "Q": q,
        "F": lead,
    }
    moves = cycle_moves("G76", (x0, z0), params)
    passes = thread_passes(moves)
    depth = [root + k - p.x for p in passes]  # depth below the crest
    # independent schedule: d_n = max(q sqrt(n), d_(n-1) + dmin) up to k - d
    expected: list[float] = []
    n = 1
    while not expected or expected[-1] < k - d - 1e-9:
        expected.append(
            min(max(q * math.sqrt(n), (expected[-1] if expected else 0.0) + dmin), k - d)
        )
        n += 1
    expected += [k] * m
    assert depth == pytest.approx(expected, abs=1e-9)
    flank = math.tan(math.radians(angle / 2))
    for p, dep in zip(passes, depth, strict=True):
        assert p.z == pytest.approx(z_end + (k - dep) * flank)  # flank infeed, shifted to +Z
        assert p.lead == lead
    assert all(m_.kind in ("rapid", "thread") for m_ in moves)
    assert ends_at(moves, x0, z0)


def test_g76_chamfer_and_taper() -> None:
    # 1P010560: m 1, r 05 (0.5 L = 1.0 with L 2), a 60; taper R-1: start radius 1 below.
    params = {"1P": 10560, "X": 20.0, "Z": -20.0, "R": -1.0, "P": 1.0, "Q": 2.0, "F": 2.0}
    moves = cycle_moves("G76", (12.0, 2.0), params)
    # first depth Q2 >= k - d = 1: one rough pass at full depth, one finishing pass: the same.
    assert (
        pts(moves)
        == [
            ("rapid", 9.0, 2.0),  # root radius 10 + taper -1
            ("thread", 10.0, -19.0),  # to 1.0 before the end
            ("thread", 11.0, -20.0),  # 45-degree chamfer out
            ("rapid", 12.0, -20.0),
            ("rapid", 12.0, 2.0),
        ]
        * 2
    )


@pytest.mark.parametrize(
    ("params", "code"),
    [
        ({"X": 20.0, "Z": -20.0, "P": 1.0, "Q": 0.3}, "FANUC-CYCLE-FEED"),
        ({"X": 20.0, "Z": -20.0, "P": 0.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-DEPTH"),
        ({"X": 20.0, "Z": -20.0, "P": 1.0, "Q": 0.0, "F": 1.0}, "FANUC-CYCLE-DEPTH"),
        ({"X": 20.0, "Z": -20.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-WORD"),
        ({"1R": 1.0, "X": 20.0, "Z": -20.0, "P": 1.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-DEPTH"),
        ({"1P": 2.106, "X": 20.0, "Z": -20.0, "P": 1.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-WORD"),
        ({"X": 20.0, "Z": 2.0, "P": 1.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-GEOMETRY"),
        ({"X": 23.0, "Z": -20.0, "P": 1.0, "Q": 0.3, "F": 1.0}, "FANUC-CYCLE-GEOMETRY"),
    ],
)
def test_g76_bad_words_are_located_errors(params: dict[str, float], code: str) -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G76", (12.0, 2.0), params, line=40)
    assert (err.value.code, err.value.location.line) == (code, 40)


# ---------------------------------------------------------------------------------- all
@pytest.mark.parametrize(
    ("cycle", "params", "contour"),
    [
        ("G90", {"X": 40.0, "Z": -30.0}, []),
        ("G94", {"X": 10.0, "Z": -1.0}, []),
        ("G92", {"X": 40.0, "Z": -30.0, "F": 1.0}, []),
        ("G70", {}, cylinder(15.0, 2.0, -20.0, 25.0)),
        ("G71", {"1U": 1.5, "1R": 0.5}, cylinder(15.0, 2.0, -20.0, 25.0)),
        (
            "G72",
            {"1W": 1.5, "1R": 0.5},
            [P("rapid", 26.0, -5.0), P("line", 15.0, -5.0), P("line", 15.0, 0.0)],
        ),
        ("G73", {"1U": 2.0, "1R": 2}, cylinder(15.0, 2.0, -20.0, 25.0)),
        ("G74", {"Z": -10.0, "Q": 3.0}, []),
        ("G75", {"X": 30.0, "P": 2.0}, []),
        ("G76", {"X": 40.0, "Z": -30.0, "P": 1.0, "Q": 0.3, "F": 1.5}, []),
    ],
)
def test_every_cycle_ends_at_its_start_point(
    cycle: str, params: dict[str, float], contour: list[ProfileStep]
) -> None:
    moves = cycle_moves(cycle, (26.0, 2.0), params, contour)
    assert moves and ends_at(moves, 26.0, 2.0)


def test_unknown_cycle_is_a_located_error() -> None:
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G77", (0.0, 0.0), {}, line=3, path="x.nc")
    assert err.value.code == "FANUC-CYCLE-UNKNOWN"
    assert str(err.value.location) == "x.nc:3:1"


WORDS = ("1U", "1W", "1R", "1P", "1Q", "X", "Z", "U", "W", "R", "P", "Q", "F")
NUMBERS = st.one_of(
    st.sampled_from((0.0, -1.0, 1.0, 0.5, 10060.0, 1e-7, 1e9, -1e9)),
    st.floats(-100.0, 100.0, allow_nan=False),
    st.floats(allow_nan=True, allow_infinity=True),
)
STEPS = st.lists(
    st.builds(
        ProfileStep,
        kind=st.sampled_from(("rapid", "line", "cw", "ccw")),
        x=st.floats(-50.0, 50.0),
        z=st.floats(-50.0, 50.0),
        cx=st.floats(-50.0, 50.0),
        cz=st.floats(-50.0, 50.0),
    ),
    max_size=5,
)


@settings(max_examples=300, deadline=None)
@given(
    cycle=st.sampled_from(("G70", "G71", "G72", "G73", "G74", "G75", "G76", "G90", "G92", "G94")),
    params=st.dictionaries(st.sampled_from(WORDS), NUMBERS, max_size=8),
    contour=STEPS,
    diameter=st.booleans(),
)
def test_any_words_give_moves_or_a_located_diagnostic(
    cycle: str, params: dict[str, float], contour: list[ProfileStep], diameter: bool
) -> None:
    try:
        moves = cycle_moves(cycle, (20.0, 2.0), params, contour, diameter, line=9, path="f.nc")
    except Diagnostic as exc:
        assert exc.code.startswith("FANUC-CYCLE-")
        assert exc.location.file == "f.nc" and exc.location.line > 0
        return
    assert all(math.isfinite(m.x) and math.isfinite(m.z) for m in moves)


def test_g71_allowance_u_is_a_diameter_but_the_depth_u_a_radius() -> None:
    # Diameter mode: second-block U1. leaves 0.5 on the radius; first-block U2. steps 2 on
    # the radius. Radius mode: U1. leaves 1. The depth does not change with the mode.
    contour = cylinder(10.0, 2.0, -10.0, 20.0)
    for diameter, left in ((True, 0.5), (False, 1.0)):
        params = {"1U": 2.0, "U": 1.0, "P": 1, "Q": 3}
        moves = cycle_moves("G71", (20.0, 2.0), params, contour, diameter=diameter)
        levels = [m.x for m in moves if m.kind == "feed" and m.z == -10.0 and m.x < 20.0]
        expected = [x for x in (18.0, 16.0, 14.0, 12.0) if x > 10.0 + left] + [10.0 + left]
        assert levels == pytest.approx(expected)


def test_g76_x_is_a_diameter_only_in_diameter_mode() -> None:
    params = {"X": 20.0, "Z": -10.0, "P": 1.0, "Q": 2.0, "F": 1.0}
    dia = cycle_moves("G76", (12.0, 2.0), {**params, "1P": 10000})
    rad = cycle_moves("G76", (22.0, 2.0), {**params, "1P": 10000}, diameter=False)
    assert [m.x for m in dia if m.kind == "thread"] == [10.0, 10.0]
    assert [m.x for m in rad if m.kind == "thread"] == [20.0, 20.0]


# ---------------------------------------------------------------------------------- type II
POCKET = [
    P("rapid", 10.0, 1.0, line=1),  # X and Z in the P block: type II
    P("line", 10.0, -5.0, line=2),
    P("line", 6.0, -5.0, line=3),  # down into a pocket
    P("line", 6.0, -10.0, line=4),
    P("line", 14.0, -10.0, line=5),
    P("line", 14.0, -15.0, line=6),
    P("line", 20.0, -15.0, line=7),
]


def test_g71_type_ii_cuts_the_pocket_from_above_after_the_outer_stretch() -> None:
    # A = (20, 2), depth 3, escape 0.5, no allowance. Levels 17, 14, 11, 8 (above the pocket
    # bottom 6). 17: stock down to the last shoulder z -15; 14: along the flat at 14 to -15;
    # 11: down to the pocket's far wall at z -10; 8: the stretch in front of the contour
    # (z 2 to 1) and the pocket (z -5 to -10), reached over the top at x 20, down by rapid to
    # the cut level above (11) and fed to 8.
    params = {"1U": 3.0, "1R": 0.5, "P": 1, "Q": 7, "F": 0.2}
    moves = cycle_moves("G71", (20.0, 2.0), params, POCKET)
    assert pts(moves) == [
        ("rapid", 17.0, 2.0),
        ("feed", 17.0, -15.0),
        ("rapid", 17.5, -14.5),
        ("rapid", 17.5, 2.0),
        ("rapid", 14.0, 2.0),
        ("feed", 14.0, -15.0),
        ("rapid", 14.5, -14.5),
        ("rapid", 14.5, 2.0),
        ("rapid", 11.0, 2.0),
        ("feed", 11.0, -10.0),
        ("rapid", 11.5, -9.5),
        ("rapid", 11.5, 2.0),
        ("rapid", 8.0, 2.0),
        ("feed", 8.0, 1.0),
        ("rapid", 8.5, 1.5),
        ("rapid", 20.0, 1.5),
        ("rapid", 20.0, -5.0),
        ("rapid", 11.0, -5.0),
        ("feed", 8.0, -5.0),
        ("feed", 8.0, -10.0),
        ("rapid", 8.5, -9.5),
        ("rapid", 20.0, -9.5),
        ("rapid", 20.0, 2.0),
        ("rapid", 10.0, 1.0),  # rough finishing along the contour
        ("feed", 10.0, -5.0),
        ("feed", 6.0, -5.0),
        ("feed", 6.0, -10.0),
        ("feed", 14.0, -10.0),
        ("feed", 14.0, -15.0),
        ("feed", 20.0, -15.0),
        ("rapid", 20.0, 2.0),
    ]


def test_the_same_pocket_with_an_x_only_p_block_is_a_type_i_profile_error() -> None:
    contour = [P("rapid", 10.0, 2.0, line=1), *POCKET[1:]]
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G71", (20.0, 2.0), {"1U": 3.0, "P": 1, "Q": 7}, contour)
    assert (err.value.code, err.value.location.line) == ("FANUC-CYCLE-PROFILE", 3)


def test_type_ii_still_needs_a_monotone_cutting_axis() -> None:
    contour = [*POCKET[:3], P("line", 6.0, -3.0, line=4), *POCKET[4:]]  # z goes back up
    with pytest.raises(Diagnostic) as err:
        cycle_moves("G71", (20.0, 2.0), {"1U": 3.0, "P": 1, "Q": 7}, contour)
    assert (err.value.code, err.value.location.line) == ("FANUC-CYCLE-PROFILE", 4)


@settings(max_examples=150, deadline=None)
@given(
    segs=st.lists(
        st.tuples(st.floats(-5.0, 5.0), st.floats(0.0, 6.0)).filter(
            lambda t: abs(t[0]) + t[1] > 0.05
        ),
        min_size=2,
        max_size=7,
    ),
    facing=st.booleans(),
    sa=st.sampled_from((1.0, -1.0)),
    sb=st.sampled_from((1.0, -1.0)),
    margin=st.floats(0.05, 5.0),
    depth=st.floats(0.3, 4.0),
    escape=st.floats(0.0, 1.0),
    ua=st.floats(0.0, 0.8),
    ub=st.floats(0.0, 0.8),
)
@example(  # walls slanted by 1e-9: a span's middle fell in a wall's sliver, cut through
    segs=[(-2.5, 1.0), (1.0, 1e-09), (0.0, 1.0), (1.0, 1e-09), (0.0, 1.0)],
    facing=True,
    sa=1.0,
    sb=1.0,
    margin=1.0,
    depth=1.0,
    escape=0.0,
    ua=0.0,
    ub=0.0,
)
def test_type_ii_roughing_never_enters_the_allowance_contour(
    segs: list[tuple[float, float]],
    facing: bool,
    sa: float,
    sb: float,
    margin: float,
    depth: float,
    escape: float,
    ua: float,
    ub: float,
) -> None:
    """Random pocketed contours (monotone along the cutting axis only) in all 8 patterns:
    every roughing move stays on or above the allowance contour and inside the stock box
    (touching the plane of a wall or of A' is allowed)."""
    pts_ab = [(0.0, -1.0 - ub)]  # A' one unit ahead of the start in the cutting direction
    for da, db in segs:
        a, b = pts_ab[-1]
        pts_ab.append((a + da, b - db))
    if pts_ab[-1][1] > pts_ab[0][1] - 0.05:
        return  # no length along the cutting axis: a geometry error, tested elsewhere
    top = max(a for a, _ in pts_ab)
    pts_ab = [(a - top - ua - margin, b) for a, b in pts_ab]  # the start (0, 0) is above all
    ox, oz = 50.0, 5.0

    def real(a: float, b: float) -> tuple[float, float]:
        return (ox + sb * b, oz + sa * a) if facing else (ox + sa * a, oz + sb * b)

    def norm(x: float, z: float) -> tuple[float, float]:
        return (sa * (z - oz), sb * (x - ox)) if facing else (sa * (x - ox), sb * (z - oz))

    steps = [P("rapid", *real(*pts_ab[0]), line=1)]
    steps += [P("line", *real(a, b), line=i + 2) for i, (a, b) in enumerate(pts_ab[1:])]
    if facing:
        dz, dx = sa * ua, sb * ub
    else:
        dx, dz = sa * ua, sb * ub
    first = {"1W" if facing else "1U": depth, "1R": escape}
    params = {**first, "P": 1, "Q": len(steps), "U": 2.0 * dx, "W": dz}
    start = real(0.0, 0.0)
    moves = cycle_moves("G72" if facing else "G71", start, params, steps)
    off = np.array(pts_ab) + (ua, ub)
    n_finish = len(steps)
    rough = moves[: len(moves) - n_finish - 1]
    ends = np.array([(0.0, 0.0)] + [norm(m.x, m.z) for m in rough])
    s = np.linspace(0.0, 1.0, 41)[:, None, None]
    smp = (ends[:-1] + s * (ends[1:] - ends[:-1])).reshape(-1, 2)
    tol = 1e-7
    assert np.all(smp[:, 0] <= escape + tol) and np.all(smp[:, 1] <= tol)
    assert np.all(smp[:, 1] >= min(off[-1, 1], 0.0) - tol)
    # lowest contour a at each sample's b, over every contour segment spanning that b
    a0, b0, a1, b1 = off[:-1, 0], off[:-1, 1], off[1:, 0], off[1:, 1]
    sb_ = smp[:, 1:2]
    inside = (sb_ > b1 + tol) & (sb_ < b0 - tol)  # touching a face or wall is allowed
    span = np.where(np.abs(b0 - b1) > 1e-12, b0 - b1, 1.0)
    t = np.clip((b0 - sb_) / span, 0.0, 1.0)
    on_seg = np.where(np.abs(b0 - b1) > 1e-12, a0 + t * (a1 - a0), np.minimum(a0, a1))
    low = np.where(inside, on_seg, np.inf).min(axis=1)
    low[np.isinf(low)] = -np.inf  # no contour at that b: in front of A' or beyond B
    bad = smp[:, 0] < low - 1e-6
    assert not bad.any(), smp[bad][:3]
    assert ends_at(moves, *start)


def test_type_ii_arc_pocket_is_cut_between_its_crossings_with_the_level() -> None:
    # A half-circle groove G02 from (10, -4) to (10, -12) about (10, -8), radius 4, bottom
    # x 6 at z -8. At level 8 the arc is at or below 8 where 10 + 4 sin(t) <= 8, i.e. for
    # t in [-150, -30] degrees: z = -8 + 4 cos(t) from -8 + 2 sqrt(3) to -8 - 2 sqrt(3).
    contour = [
        P("rapid", 10.0, 1.0, line=1),
        P("line", 10.0, -4.0, line=2),
        P("cw", 10.0, -12.0, cx=10.0, cz=-8.0, line=3),
        P("line", 10.0, -15.0, line=4),
        P("line", 20.0, -15.0, line=5),
    ]
    moves = cycle_moves("G71", (20.0, 2.0), {"1U": 3.0, "1R": 0.5, "P": 1, "Q": 5}, contour)
    at8 = [(m.kind, m.z) for m in moves if m.x == 8.0]
    hi, lo = -8.0 + 2.0 * math.sqrt(3.0), -8.0 - 2.0 * math.sqrt(3.0)
    assert at8 == [
        ("rapid", 2.0),
        ("feed", 1.0),  # in front of A'
        ("feed", pytest.approx(hi)),  # fed down into the groove at its entry
        ("feed", pytest.approx(lo)),  # across to the far side of the groove
    ]
    arcs = [m for m in moves if m.kind == "cw"]
    assert [(m.x, m.z, m.cx, m.cz) for m in arcs] == [(10.0, -12.0, 10.0, -8.0)]
    assert ends_at(moves, 20.0, 2.0)


def test_g71_without_rough_finishing_cuts_a_last_level_on_the_allowance() -> None:
    # Parameter 5105#1 (RF1) = 1: no cut along the contour; the last level is the allowance
    # surface itself (x 10.5 here), then rapid back to A.
    params = {"1U": 2.0, "1R": 0.5, "U": 1.0, "P": 1, "Q": 3}
    moves = cycle_moves(
        "G71",
        (16.0, 2.0),
        params,
        cylinder(10.0, 2.0, -10.0, 16.0),
        settings=CycleSettings(rough_finish=False),
    )
    cuts = [m.x for m in moves if m.kind == "feed"]
    assert cuts == [14.0, 12.0, 10.5]
    assert ends_at(moves, 16.0, 2.0)


def test_g76_inside_thread_feeds_outwards_in_x() -> None:
    # Internal thread: start x 9 inside, root (major) radius 12 at X24.; height 1, first
    # depth 1 (one pass) and one finishing pass; passes at 12 - (1 - 1) = 12, radial (a 0).
    params = {"1P": 10000, "X": 24.0, "Z": -15.0, "P": 1.0, "Q": 1.0, "F": 1.5}
    moves = cycle_moves("G76", (9.0, 2.0), params)
    assert (
        pts(moves)
        == [
            ("rapid", 12.0, 2.0),
            ("thread", 12.0, -15.0),
            ("rapid", 9.0, -15.0),
            ("rapid", 9.0, 2.0),
        ]
        * 2
    )
    # Q0.5: depths 0.5 sqrt(n) = 0.5, 0.7071, 0.8660, 1.0, then the finishing pass at 1.0;
    # pass radius 12 - (1 - depth)
    half = cycle_moves("G76", (9.0, 2.0), {**params, "Q": 0.5})
    depths = [0.5, 0.5 * math.sqrt(2.0), 0.5 * math.sqrt(3.0), 1.0, 1.0]
    assert [m.x for m in half if m.kind == "thread"] == pytest.approx([11.0 + d for d in depths])
