"""Interpolator tables of book ch. 3, with the errata of research/seed-book-interp.md §6.

Reference-pulse tables 3.1, 3.5, 3.6; sampled-data circle parameters (table 3.8 corrected);
fine interpolation table 3.9; NURBS examples of fig. 3.21 (corrected knot vector).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel.diagnostics import Diagnostic
from kernel.interp import circle
from kernel.interp.fine import fine_linear, fine_moving_average, fine_positions
from kernel.interp.nurbs import NurbsCurve, chord_errors, evaluate, interpolate, tessellate
from kernel.interp.pulse import STAIRS_RULES, dda_circle, dda_line, direct_search, stairs

TABLE_3_1 = """
 0 15  0 0  0  0 0
 1 15 15 0  0  0 0
 2 15 14 1  1  1 0
 3 15 13 1  2  3 0
 4 15 12 1  3  6 0
 5 15 11 1  4 10 0
 6 15 10 1  5 15 0
 7 15  9 1  6  5 1
 8 14  7 1  7 12 0
 9 14  5 1  8  4 1
10 13  2 1  9 13 0
11 13 15 0  9  6 1
12 12 11 1 10  0 1
13 11  6 1 11 11 0
14 11  1 1 12  7 1
15 10 11 0 12  3 1
16  9  4 1 13  0 1
17  8 12 0 13 13 0
18  8  4 1 14 11 1
19  7 11 0 14  9 1
20  6  1 1 15  8 1
21  5  6 0 15  7 1
22  4 10 0 15  6 1
23  3 13 0 15  5 1
24  2 15 0 15  4 1
25  1  0 0 15  3 1
"""


def test_dda_circle_reproduces_table_3_1_row_by_row():
    want = [tuple(int(v) for v in r.split()) for r in TABLE_3_1.strip().splitlines()]
    got = [
        (r["k"], r["vx"], r["qx"], r["dsx"], r["vy"], r["qy"], r["dsy"]) for r in dda_circle(15, 4)
    ]
    assert got == want
    assert sum(r[3] for r in got) == 15 and sum(r[6] for r in got) == 15


def test_dda_line_emits_exactly_the_displacement_at_a_constant_ratio():
    p = dda_line(11, -5, 4)
    assert p.sum(axis=0).tolist() == [11, -5]
    assert len(p) == 16


# Table 3.5 with the step-6 erratum (dx printed 1, correct 11)
STAIRS_D = [0, 1, -18, -15, -10, -3, 6, -11, 0, 13, -2, 13, 0, 17, 6, -3, 16, 9, 4, 1, 0]
STAIRS_DX = [1, 3, 3, 5, 7, 9, 11, 11, 13, 15, 15, 17, 17, 19, 19, 19, 21, 21, 21, 21, 21]
STAIRS_XY = [
    (0, 10),
    (1, 10),
    (1, 9),
    (2, 9),
    (3, 9),
    (4, 9),
    (5, 9),
    (5, 8),
    (6, 8),
    (7, 8),
    (7, 7),
    (8, 7),
    (8, 6),
    (9, 6),
    (9, 5),
    (9, 4),
    (10, 4),
    (10, 3),
    (10, 2),
    (10, 1),
    (10, 0),
]


def test_stairs_reproduces_table_3_5_with_erratum():
    rows = stairs(0, 10, 10, 0, clockwise=True)
    assert len(rows) - 1 == 20  # N = 2R (eq. 3.17)
    assert [r["D"] for r in rows] == STAIRS_D
    assert [r["dx"] for r in rows] == STAIRS_DX
    assert [(r["x"], r["y"]) for r in rows] == STAIRS_XY
    assert [r["rem_x"] for r in rows][:3] == [10, 9, 9]


@pytest.mark.parametrize(("quadrant", "cw"), list(STAIRS_RULES))
def test_stairs_rules_of_table_3_4_step_outward_inside_and_inward_outside(quadrant, cw):
    inside, outside = STAIRS_RULES[(quadrant, cw)]
    # a point of the quadrant on the circle of radius 10, travelling in the given sense
    ang = math.radians(45 + 90 * (quadrant - 1))
    p = np.array([math.cos(ang), math.sin(ang)])
    tangent = np.array([p[1], -p[0]]) if cw else np.array([-p[1], p[0]])
    assert np.dot(inside, p) > 0 and np.dot(outside, p) < 0  # out when inside, in when out
    assert np.dot(inside, tangent) >= 0 and np.dot(outside, tangent) >= 0


DS_D = [0, 1, 4, 9, -3, 6, 0, -2, 0, 6, -3, 9, 4, 1, 0]  # step 4: -3 (printed 3)
DS_XY = [
    (0, 10),
    (1, 10),
    (2, 10),
    (3, 10),
    (4, 9),
    (5, 9),
    (6, 8),
    (7, 7),
    (8, 6),
    (9, 5),
    (9, 4),
    (10, 3),
    (10, 2),
    (10, 1),
    (10, 0),
]
DS_CANDIDATES = {
    1: (1, -19, -18),
    2: (4, -18, -15),
    3: (9, -15, -10),
    4: (16, -10, -3),
    5: (6, -20, -11),
    6: (17, -11, 0),
    7: (13, -15, -2),
    8: (13, -15, 0),
    9: (17, -11, 6),
    10: (25, -3, 16),
}


def test_direct_search_reproduces_table_3_6_with_erratum():
    rows = direct_search(0, 10, 10, 0, clockwise=True)
    assert len(rows) - 1 == 14
    assert [r["D"] for r in rows] == DS_D
    assert [(r["x"], r["y"]) for r in rows] == DS_XY
    for step, cands in DS_CANDIDATES.items():
        assert (rows[step]["D1"], rows[step]["D2"], rows[step]["D3"]) == cands
    radial = [abs(math.hypot(r["x"], r["y"]) - 10) for r in rows]
    assert max(radial) <= 0.5


def test_direct_search_step_count_is_about_sqrt2_r():
    assert len(direct_search(0, 100, 100, 0)) - 1 == 141


B2 = [
    0,
    0,
    0.25,
    0.75,
    1.25,
    1.75,
    2.25,
    2.75,
    3.25,
    3.75,
    4.25,
    4.75,
    5.25,
    5.75,
    6,
    6,
    6,
    6,
    5.75,
    5.25,
    4.75,
    4.25,
    3.75,
    3.25,
    2.75,
    2.25,
    1.75,
    1.25,
    0.75,
    0.25,
    0,
    0,
]
B = [
    0,
    0,
    0,
    0.5,
    1,
    1.5,
    2,
    2.5,
    3,
    3.5,
    4,
    4.5,
    5,
    5.5,
    6,
    6,
    6,
    6,
    6,
    5.5,
    5,
    4.5,
    4,
    3.5,
    3,
    2.5,
    2,
    1.5,
    1,
    0.5,
    0,
    0,
]


def test_fine_interpolation_reproduces_table_3_9():
    a = fine_linear([0, 8, 16, 24, 24, 16, 8, 0], 4)
    assert a[4:8].tolist() == [2, 2, 2, 2]
    b, bp, b2 = fine_moving_average(a, 4)
    assert b.tolist() == B
    assert b2.tolist() == B2
    assert bp[2] == 0.5 and bp[19] == 5
    assert b2.sum() == 96 == a.sum()


def test_fine_positions_keep_the_end_point():
    pos = np.cumsum(np.array([[0, 0], [8, 1], [16, 2], [24, 0], [8, 0]], float), axis=0)
    for method in ("linear", "moving_average"):
        f = fine_positions(pos, 4, method)
        assert f[-1] == pytest.approx(pos[-1])


# Table 3.8 corrected: alpha per method and quarter-circle step count (R in BLU)
@pytest.mark.parametrize(
    ("method", "r", "alpha", "n_sim"),
    [
        ("euler", 100, 0.0127324, 124),
        ("improved_euler", 100, 0.04, 40),
        ("taylor", 100, 0.282843, 6),
        ("tustin", 100, 0.284268, 6),
        ("improved_tustin", 100, 0.398675, 4),
        ("euler", 1000, 0.00127324, 1234),
        ("improved_euler", 1000, 0.004, 393),
        ("taylor", 1000, 0.0894427, 18),
        ("tustin", 1000, 0.0894875, 18),
        ("improved_tustin", 1000, 0.126449, 13),
    ],
)
def test_circle_step_parameters_table_3_8_corrected(method, r, alpha, n_sim):
    """N = ceil(90 deg / true step) (the research note's simulated 394 for improved Euler
    at R 1000 counts the uneven polar angle of its elliptic orbit; 90/0.2292 deg -> 393)."""
    a = circle.step_parameter(method, r)
    assert a == pytest.approx(alpha, rel=1e-4)
    n, _ = circle.steps_for_sweep(method, math.pi / 2, r)
    assert n == n_sim


@pytest.mark.parametrize("method", circle.METHODS)
def test_circle_closed_form_equals_the_books_recursion(method):
    alpha = circle.step_parameter(method, 100)
    it = circle.iterate(method, 100.0, 0.0, alpha, 30)
    beta = 1.0 if method == "improved_tustin" else 0.0
    cf = circle.vertices(method, 100.0, alpha, np.arange(31), beta)
    assert cf[1:] == pytest.approx(it[1:], abs=1e-9)


def test_circle_errors_within_one_blu_at_the_books_alpha():
    r = 1000.0
    for method, er_max, eh_max in (
        ("euler", 1.0008, 1e-3),
        ("improved_euler", 1.002, 1e-2),
        ("taylor", 0.15, 1.0),
        ("tustin", 1e-9, 1.0),
    ):
        n, alpha = circle.steps_for_sweep(method, math.pi / 2, r)
        pts = circle.iterate(method, r, 0.0, circle.step_parameter(method, r), n)
        assert np.abs(circle.radial_error(pts, r)).max() <= er_max
        assert circle.chord_error(pts, r).max() <= eh_max
    alpha = circle.step_parameter("improved_tustin", r)
    pts = circle.vertices("improved_tustin", r, alpha, np.arange(1, 14), 1.0)
    assert circle.radial_error(pts, r) == pytest.approx(np.ones(13))  # vertices at R + 1
    assert circle.chord_error(pts, r).max() == pytest.approx(1.0, abs=1e-9)  # chords at R - 1


def test_tustin_has_no_radial_error_and_unit_coefficients():
    a, b = circle.coefficients("tustin", 0.2)
    assert (a, b) == pytest.approx((0.980198, 0.198020), abs=1e-6)
    assert a * a + b * b == pytest.approx(1.0, abs=1e-15)


SEMI_PTS = [(0, 0), (0, 5), (5, 5), (10, 5), (10, 0)]
SEMI_W = [1, 1 / math.sqrt(2), 1, 1 / math.sqrt(2), 1]


def test_nurbs_semicircle_with_corrected_knots_is_exact():
    c = NurbsCurve.create(
        np.array(SEMI_PTS, float), np.array(SEMI_W), (0, 0, 0, 0.5, 0.5, 1, 1, 1), 2
    )
    u = np.linspace(0, 1, 401)
    p = evaluate(c, u)
    assert np.hypot(p[:, 0] - 5, p[:, 1]) == pytest.approx(np.full(401, 5.0), abs=1e-12)
    assert evaluate(c, [0.25])[0] == pytest.approx([1.464466, 3.535534], abs=1e-6)
    assert evaluate(c, [0.5])[0] == pytest.approx([5, 5])
    assert evaluate(c, [1.0])[0] == pytest.approx([10, 0])


def test_nurbs_printed_semicircle_knots_are_rejected():
    with pytest.raises(Diagnostic) as e:
        NurbsCurve.create(
            np.array(SEMI_PTS, float), np.array(SEMI_W), (0, 0, 0, 0.5, 0.5, 0.5, 1, 1), 2
        )
    assert e.value.code == "PLAN-NURBS"


LINE_PTS = np.array([(i, 1.5 * i) for i in range(7)], float)


def test_nurbs_line_example_lies_on_y_1_5x_with_the_books_points():
    c = NurbsCurve.create(LINE_PTS, None, (0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4), 3)
    p = evaluate(c, np.linspace(0, 4, 101))
    assert p[:, 1] == pytest.approx(1.5 * p[:, 0], abs=1e-12)
    want = np.array([[23 / 12, 2.875], [3, 4.5], [4.083333, 6.125]])
    assert evaluate(c, [1, 2, 3]) == pytest.approx(want, abs=1e-6)


@pytest.mark.parametrize("order", [1, 2])
def test_nurbs_line_interpolates_at_constant_feed_despite_parameter_speed(order):
    c = NurbsCurve.create(LINE_PTS, None, (0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4), 3)
    run = interpolate(c, feed=20.0, period=0.01, tolerance=0.001, order=order)
    chords = np.linalg.norm(np.diff(run.points, axis=0), axis=1)[:-1]
    tol = 0.035 if order == 1 else 0.002  # |P'| varies 3:1 along the curve
    assert chords == pytest.approx(np.full(chords.size, 0.2), rel=tol)
    assert run.points[-1] == pytest.approx([6, 9])


def test_nurbs_semicircle_feed_is_chord_error_limited_tc_i34():
    c = NurbsCurve.create(
        np.array(SEMI_PTS, float), np.array(SEMI_W), (0, 0, 0, 0.5, 0.5, 1, 1, 1), 2
    )
    run = interpolate(c, feed=100.0, period=0.002, tolerance=0.001, order=1)
    chords = np.linalg.norm(np.diff(run.points, axis=0), axis=1)[:-1]
    assert 76 <= len(run.points) - 1 <= 81  # about 79 steps
    assert chords.min() >= 0.198 and chords.max() <= 0.202
    h = 5 - np.hypot(*(0.5 * (run.points[1:] + run.points[:-1]) - [5, 0]).T)
    assert h.max() <= 1.05e-3
    slow = interpolate(c, feed=50.0, period=0.002, tolerance=0.001)
    assert len(slow.points) - 1 == pytest.approx(158, abs=2)  # not error-limited at 3 m/min


def test_nurbs_error_limited_feed_formula_tc_i33():
    # F = (2/T) sqrt(2 eps / kappa): kappa 0.2, eps 1 um, T 2 ms -> 100 mm/s
    assert (2 / 0.002) * math.sqrt(2 * 0.001 / 0.2) == pytest.approx(100.0)
    c = NurbsCurve.create(
        np.array(SEMI_PTS, float), np.array(SEMI_W), (0, 0, 0, 0.5, 0.5, 1, 1, 1), 2
    )
    run = interpolate(c, feed=1000.0, period=0.002, tolerance=0.001, curvature_from="analytic")
    assert run.feed[1:-1] == pytest.approx(np.full(len(run.feed) - 2, 100.0), rel=1e-9)


def test_nurbs_acceleration_clamp_limits_axis_velocity_steps_from_rest():
    c = NurbsCurve.create(LINE_PTS, None, (0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4), 3)
    lim = np.array([300.0, 300.0])
    run = interpolate(c, feed=50.0, period=0.002, tolerance=0.001, axis_accel=lim)
    vel = np.diff(run.points, axis=0) / 0.002
    dv = np.abs(np.diff(np.vstack([[0, 0], vel[:-1]]), axis=0)) / 0.002
    assert dv.max() <= 300 * (1 + 1e-6)
    assert run.feed.max() == pytest.approx(50.0)  # the feed is reached, then held


def test_nurbs_tessellation_chords_stay_within_tolerance():
    rng = np.random.default_rng(5)
    pts = rng.uniform(-20, 20, (9, 2))
    c = NurbsCurve.create(pts, rng.uniform(0.5, 2, 9), None, 3)
    q = tessellate(c, 0.002)
    # re-derive the parameters of the points by dense evaluation
    u = np.linspace(0, 1, 20001)
    dense = evaluate(c, u)
    idx = [int(np.argmin(np.linalg.norm(dense - p, axis=1))) for p in q]
    errs = chord_errors(c, u[idx], probes=16)
    assert errs.max() <= 0.002 * 1.05


def test_nurbs_axis_velocity_limit_caps_the_feed_along_the_tangent():
    c = NurbsCurve.create(LINE_PTS, None, (0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4), 3)
    run = interpolate(
        c, feed=50.0, period=0.002, tolerance=0.001, axis_velocity=np.array([100.0, 30.0])
    )
    vel = np.diff(run.points, axis=0)[:-1] / 0.002
    assert np.abs(vel[:, 1]).max() == pytest.approx(30.0, rel=0.02)  # y = 1.5 x binds
    assert np.abs(vel[:, 1]).max() <= 30.0 * 1.02
