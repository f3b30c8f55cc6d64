"""Curves a target dialect lacks, replaced by arcs or lines within a stated tolerance.

* NURBS (NISTIR 5970 App. A.7; book ch. 2 ``G06.2``): evaluated with the Cox-de Boor
  recursion (book ch. 3.5) and replaced by circular arcs through three curve points,
  split in parameter until the deviation at :data:`CHECKS` sample points per piece is
  within the tolerance (or by chords when the target has no arcs).
* ELLIPSE_FEED (NISTIR 5970 §3.6.3) is not here: the writers call the planner's chords,
  :func:`kernel.path.ellipse.ellipse_chords`, so a converted program and a planned one cut the
  same lines.

All functions are pure and work in the plane's (first, second) coordinates.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from kernel.interp.nurbs import DENSE_KNOTS, span_index
from kernel.ir import canon

CHECKS = 33  # sample points checked per fitted piece
MARGIN = 0.5  # a piece is kept when its sampled deviation is within MARGIN * tolerance
MAX_DEPTH = 24


#: a plane curve, vectorised: parameters (n,) -> points (n, 2)
Curve = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True, slots=True)
class Piece:
    """One replacement segment: a line, or an arc with centre and direction."""

    end: tuple[float, float]
    centre: tuple[float, float] | None = None  # None: a line
    ccw: bool = True


def nurbs_basis(order: int, knots: np.ndarray, u: np.ndarray) -> np.ndarray:
    """B-spline basis functions ``N[i, j] = N_{i,order}(u_j)`` (Cox-de Boor recursion)."""
    n = len(knots) - order
    m = len(knots) - 1
    basis = np.zeros((m, len(u)))
    for i in range(m):
        basis[i] = (knots[i] <= u) & (u < knots[i + 1])
    # u at the very end belongs to the last non-empty span (clamped curves end on a point)
    last = max(i for i in range(m) if knots[i] < knots[i + 1])
    basis[last, u >= knots[-1]] = 1.0
    for k in range(2, order + 1):
        nxt = np.zeros((m - k + 1, len(u)))
        for i in range(m - k + 1):
            d1 = knots[i + k - 1] - knots[i]
            d2 = knots[i + k] - knots[i + 1]
            if d1 > 0:
                nxt[i] += (u - knots[i]) / d1 * basis[i]
            if d2 > 0:
                nxt[i] += (knots[i + k] - u) / d2 * basis[i + 1]
        basis = nxt
    return basis[:n]


def nurbs_evaluate(order: int, points: np.ndarray, knots: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Points (len(u), 2) of the rational curve; ``points`` rows are (first, second, weight).

    A long curve is evaluated one knot span at a time on the ``order`` control points that
    span depends on: the dense basis of a 5,000-point curve would take gigabytes."""
    u = np.asarray(u, dtype=float)
    if len(knots) > DENSE_KNOTS:
        p = order - 1
        s = span_index(np.asarray(knots, dtype=float), p, len(points), u)
        out = np.empty((len(u), 2))
        order_u = np.argsort(s, kind="stable")
        spans, starts = np.unique(s[order_u], return_index=True)
        ends = np.append(starts[1:], len(order_u))
        for span, lo, hi in zip(spans.tolist(), starts.tolist(), ends.tolist(), strict=True):
            idx = order_u[lo:hi]
            out[idx] = _nurbs_dense(
                order, points[span - p : span + 1], knots[span - p : span + p + 2], u[idx]
            )
        return out
    return _nurbs_dense(order, points, knots, u)


def _nurbs_dense(order: int, points: np.ndarray, knots: np.ndarray, u: np.ndarray) -> np.ndarray:
    basis = nurbs_basis(order, knots, u) * points[:, 2:3]
    den = basis.sum(axis=0)
    return (basis.T @ points[:, :2]) / den[:, None]


def _circle(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray) -> tuple[np.ndarray, float] | None:
    """Centre and radius of the circle through three points; None when (nearly) collinear."""
    a, b = p1 - p0, p2 - p0
    cross = a[0] * b[1] - a[1] * b[0]
    chord = float(np.hypot(*(p2 - p0)))
    if abs(cross) <= 1e-12 * max(chord, 1e-12) ** 2:
        return None
    aa, bb = a @ a, b @ b
    cx = (b[1] * aa - a[1] * bb) / (2 * cross)
    cy = (a[0] * bb - b[0] * aa) / (2 * cross)
    centre = p0 + np.array([cx, cy])
    return centre, float(np.hypot(cx, cy))


def _line_deviation(p0: np.ndarray, p1: np.ndarray, pts: np.ndarray) -> float:
    d = p1 - p0
    length2 = float(d @ d)
    if length2 == 0.0:
        return float(np.max(np.hypot(*(pts - p0).T)))
    t = np.clip(((pts - p0) @ d) / length2, 0.0, 1.0)
    return float(np.max(np.hypot(*(pts - (p0 + t[:, None] * d)).T)))


def _arc_deviation(
    p0: np.ndarray, p2: np.ndarray, centre: np.ndarray, radius: float, ccw: bool, pts: np.ndarray
) -> float:
    """Distance of ``pts`` from the arc p0 -> p2 (inf when a point falls outside its sweep)."""
    sign = 1.0 if ccw else -1.0
    a0 = math.atan2(p0[1] - centre[1], p0[0] - centre[0])
    a2 = math.atan2(p2[1] - centre[1], p2[0] - centre[0])
    sweep = (sign * (a2 - a0)) % (2 * math.pi)
    ang = (sign * (np.arctan2(pts[:, 1] - centre[1], pts[:, 0] - centre[0]) - a0)) % (2 * math.pi)
    if np.any(ang > sweep + 1e-9) or np.any(np.diff(ang) < -1e-9):
        return math.inf
    return float(np.max(np.abs(np.hypot(*(pts - centre).T) - radius)))


def _turning_point(curve: Curve, a: float, b: float, chord: np.ndarray) -> float | None:
    """Where the curve turns back along ``chord`` inside (a, b), if it leaves or arrives
    backwards; None when it runs forwards at both ends.

    Sampled deviations cannot see a curve that overshoots an end of its piece and returns
    between two samples (a sharp NURBS turn at a knot); its velocity at that end, projected
    on the chord, is negative. The piece is split where that projection changes sign
    (bisection), so each part runs one way along its chord.
    """
    h = (b - a) * 1e-7
    if h <= 0.0 or not chord.any():
        return None
    us = np.linspace(a, b, CHECKS)
    lo, hi = np.maximum(us - h, a), np.minimum(us + h, b)
    speed = (curve(hi) - curve(lo)) @ chord
    # backwards means faster than 1e-3 of the mean forward speed (not round-off at a stop)
    speed[np.abs(speed) <= 1e-3 * float(chord @ chord) * 2e-7] = 0.0
    if speed[0] >= 0.0 and speed[-1] >= 0.0:
        return None
    moving = np.flatnonzero(speed)
    signs = np.sign(speed[moving])
    change = np.flatnonzero(signs[1:] != signs[:-1])
    if change.size == 0:
        return None
    k = int(change[0] if speed[0] < 0.0 else change[-1])
    left, right, sign = float(us[moving[k]]), float(us[moving[k + 1]]), signs[k]
    for _ in range(40):
        mid = 0.5 * (left + right)
        pair = curve(np.array([max(mid - h, a), min(mid + h, b)]))
        if np.sign((pair[1] - pair[0]) @ chord) == sign:
            left = mid
        else:
            right = mid
    turn = 0.5 * (left + right)
    return turn if a + 1e-6 * (b - a) < turn < b - 1e-6 * (b - a) else None


def fit_curve(
    curve: Curve,
    u0: float,
    u1: float,
    tolerance: float,
    arcs: bool = True,
    breaks: Iterable[float] | None = None,
) -> tuple[list[Piece], float]:
    """Replace ``curve(u)`` (vectorised, returns (n, 2)) on [u0, u1] by :class:`Piece` s.

    ``breaks`` (the knots) start the fit on each knot span, where the curve is one smooth
    rational polynomial.

    Returns (pieces, largest deviation found at the check points). Each piece is the arc
    through the curve at both ends and the middle parameter, or the chord when that fits
    better (collinear points, a corner of a degree-1 curve, or ``arcs`` false); a piece
    whose deviation exceeds ``tolerance`` is halved in parameter, down to
    :data:`MAX_DEPTH` levels; a chord the curve runs past and back along (unseen between
    check points) is split at the turn.
    """
    pieces: list[Piece] = []
    worst = 0.0
    inner = () if breaks is None else (float(k) for k in breaks if u0 < k < u1)
    bounds = sorted({u0, u1, *inner})
    stack = [(a, b, 0) for a, b in reversed(list(zip(bounds[:-1], bounds[1:], strict=True)))]
    while stack:
        a, b, depth = stack.pop()
        us = np.linspace(a, b, CHECKS)
        pts = curve(us)
        p0, pm, p2 = pts[0], pts[CHECKS // 2], pts[-1]
        fit = _circle(p0, pm, p2) if arcs else None
        dev = _line_deviation(p0, p2, pts)
        piece = Piece((float(p2[0]), float(p2[1])))
        if fit is not None and fit[1] < 1e6 * max(float(np.hypot(*(p2 - p0))), 1e-9):
            centre, radius = fit
            u, v = pm - p0, p2 - pm
            ccw = float(u[0] * v[1] - u[1] * v[0]) > 0
            arc_dev = _arc_deviation(p0, p2, centre, radius, ccw, pts)
            if arc_dev < dev:  # a line wins only where it fits better (corners, flats)
                dev = arc_dev
                piece = Piece(piece.end, (float(centre[0]), float(centre[1])), ccw)
        if depth < MAX_DEPTH:
            split = 0.5 * (a + b) if dev > MARGIN * tolerance else None
            if split is None and piece.centre is None:  # runs past an end and back?
                split = _turning_point(curve, a, b, p2 - p0)
            if split is not None:
                stack.append((split, b, depth + 1))  # popped second: keeps pieces in order
                stack.append((a, split, depth + 1))
                continue
        pieces.append(piece)
        worst = max(worst, dev)
    return pieces, worst


def nurbs_problem(c: canon.NurbsFeed) -> str | None:
    """Why a NURBS_FEED cannot be written at all, or None.

    LinuxCNC prints ``NURBS_FEED(n, ...)`` without its data; kernel.ir.canon reads that as an
    order-0 curve of NaN points.
    """
    pts = np.array(c.points, dtype=float).reshape(-1, 3)
    if c.order < 2 or len(pts) < c.order or not np.all(np.isfinite(pts)):
        return "NURBS_FEED without usable control points (LinuxCNC prints none)"
    if np.any(pts[:, 2] <= 0):
        return "NURBS_FEED with a weight that is not positive"
    return None
