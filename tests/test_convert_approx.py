"""Approximations (gcode.write.approximate) against closed forms and dense checks.

* A rational quadratic with control points (1,0), (1,1), (0,1), weights 1, sqrt(2)/2, 1 and
  knots 0,0,0,1,1,1 is exactly the unit quarter circle (the classic conic NURBS): one arc
  about the origin must replace it.
* For any curve, the pieces must stay within the tolerance of a dense sampling of the curve
  (checked at 2,000 points, far more than the fit's own 33 per piece).
* B-spline basis functions sum to one on the knot span (partition of unity).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from gcode.write import approximate as ap
from kernel.path.ellipse import ellipse_chords


def _distance_to_pieces(points: np.ndarray, start: tuple[float, float], pieces) -> np.ndarray:  # noqa: ANN001
    best = np.full(len(points), np.inf)
    p0 = np.array(start)
    for piece in pieces:
        p1 = np.array(piece.end)
        if piece.centre is None:
            d = p1 - p0
            t = np.clip(((points - p0) @ d) / max(d @ d, 1e-300), 0, 1)
            dist = np.hypot(*(points - (p0 + t[:, None] * d)).T)
        else:
            c = np.array(piece.centre)
            r = math.dist(piece.end, piece.centre)
            sign = 1 if piece.ccw else -1
            a0 = math.atan2(*(p0 - c)[::-1])
            sweep = (sign * (math.atan2(*(p1 - c)[::-1]) - a0)) % (2 * math.pi)
            ang = (sign * (np.arctan2(points[:, 1] - c[1], points[:, 0] - c[0]) - a0)) % (
                2 * math.pi
            )
            on_arc = np.abs(np.hypot(*(points - c).T) - r)
            ends = np.minimum(np.hypot(*(points - p0).T), np.hypot(*(points - p1).T))
            dist = np.where(ang <= sweep, on_arc, ends)
        best = np.minimum(best, dist)
        p0 = p1
    return best


def test_conic_nurbs_quarter_circle_becomes_one_exact_arc():
    w = math.sqrt(2) / 2
    pts = np.array([[1.0, 0.0, 1.0], [1.0, 1.0, w], [0.0, 1.0, 1.0]])
    knots = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])

    def curve(u: np.ndarray) -> np.ndarray:
        return ap.nurbs_evaluate(3, pts, knots, u)

    pieces, worst = ap.fit_curve(curve, 0.0, 1.0, 1e-6)
    assert len(pieces) == 1
    (arc,) = pieces
    assert arc.ccw and np.allclose(arc.centre, (0, 0), atol=1e-12)
    assert np.allclose(arc.end, (0, 1), atol=1e-12) and worst < 1e-12


@settings(max_examples=60, deadline=None)
@example(  # a sharp turn on a line: overshoots the knot between two check points
    ctrl=[(-7.0, 0.0, 1.0), (1.0, 0.0, 0.25), (0.0, 0.0, 0.21875), (0.0, 0.0, 1.0)],
    order=3,
    tol=1e-3,
    arcs=False,
)
@given(
    st.lists(
        st.tuples(st.floats(-50, 50), st.floats(-50, 50), st.floats(0.2, 5)), min_size=4, max_size=8
    ),
    st.sampled_from([2, 3, 4]),
    st.sampled_from([1e-3, 1e-2]),
    st.booleans(),
)
def test_fitted_pieces_stay_within_tolerance_of_the_curve(ctrl, order, tol, arcs):  # noqa: ANN001
    pts = np.array(ctrl, dtype=float)
    n = len(pts)
    inner = list(np.linspace(0, 1, n - order + 2)[1:-1])
    knots = np.array([0.0] * order + inner + [1.0] * order)

    def curve(u: np.ndarray) -> np.ndarray:
        return ap.nurbs_evaluate(order, pts, knots, u)

    pieces, worst = ap.fit_curve(curve, 0.0, 1.0, tol, arcs, knots)
    dense = curve(np.linspace(0, 1, 2000))
    assert np.allclose(pieces[-1].end, dense[-1], atol=1e-9)
    dist = _distance_to_pieces(dense, tuple(dense[0]), pieces)
    assert worst <= tol
    assert dist.max() <= tol * 1.05 + 1e-9


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 5), st.integers(0, 4), st.data())
def test_basis_is_a_partition_of_unity(order, extra, data):  # noqa: ANN001
    n = order + extra
    inner = sorted(
        data.draw(st.lists(st.floats(0.01, 0.99), min_size=n - order, max_size=n - order))
    )
    knots = np.array([0.0] * order + inner + [1.0] * order)
    u = np.linspace(0, 1, 101)
    basis = ap.nurbs_basis(order, knots, u)
    assert basis.shape == (n, 101)
    assert np.allclose(basis.sum(axis=0), 1.0)


def test_ellipse_chords_of_a_circle_meet_the_sagitta_formula():
    # half circle of radius 10, tolerance 0.01: chord angle 2 acos(1 - tol / r)
    ch = ellipse_chords((10, 0), (-10, 0), (0, 0), 20, 20, 0, 1, 0.0, 0.01)
    pts, sag = ch.plane_points(), ch.deviation
    step = 2 * math.acos(1 - 0.01 / 10)
    assert len(pts) == math.ceil(math.pi / step)
    assert sag <= 0.01 and math.isclose(sag, 10 * (1 - math.cos(math.pi / len(pts) / 2)))
    assert np.allclose(pts[-1][:2], (-10, 0), atol=1e-9) and pts[-1][2] == 1.0


def test_ellipse_helix_fraction_follows_the_polar_angle():
    # NIST rule 2: the axis travel follows the angle about the centre, not the arc length
    pts = ellipse_chords((20, 0), (0, 5), (0, 0), 40, 10, 0, 1, 0.0, 0.05).plane_points()
    for x, y, frac in pts:
        assert math.isclose(frac, math.atan2(y, x) / (math.pi / 2), abs_tol=1e-9)
