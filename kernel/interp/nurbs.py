"""NURBS curves and their interpolation (book §3.5; research/seed-book-interp.md §3.14-3.15).

``P(u) = sum N_ip(u) w_i P_i / sum N_ip(u) w_i`` (eq. 3.74) with Cox-de Boor basis functions
(eq. 3.75, half-open spans, the last one closed) of any degree. Knot vectors must be
clamped (``p+1`` equal knots at each end) with interior multiplicity at most ``p``: the
book's printed semicircle vector (0,0,0,.5,.5,.5,1,1) is rejected (``PLAN-NURBS``); the
corrected one is (0,0,0,.5,.5,1,1,1).

The interpolator (:func:`interpolate`, book §3.5.3) advances the parameter once per period:

* chord-error-limited feed ``F_e = (2/T) sqrt(2 eps / kappa)`` (eq. 3.83), capped by the
  programmed feed; ``kappa`` from the circle through the last three points (eq. 3.80/3.81)
  or, until three exist, analytically ``|P' x P''| / |P'|^3``;
* first-order update ``du = dL / |P'(u)|`` (eqs. 3.85/3.86, primes restored), or the
  second-order Taylor update ``du = dL/|P'| - dL^2 (P'.P'')/(2 |P'|^4)`` (not in the book;
  research note §4.9);
* the per-axis velocity-change clamp of eq. 3.87 (signs corrected, ``x dT`` restored),
  applied as one scale factor on ``dL`` so the point stays on the curve. Like the book's,
  it looks one period ahead only: it bounds acceleration from rest and along gently curved
  parts, but where the tangent turns faster than the axes can follow at the current speed
  no shortening of one step can help (the planner's curvature caps handle that; the
  kernel plans NURBS through :func:`tessellate`).

:func:`tessellate` gives chord points within a tolerance by vectorised bisection; the path
builder plans NURBS feeds as those chords.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location


@dataclass(frozen=True, slots=True)
class NurbsCurve:
    """Control points (n+1, d), weights (n+1), clamped knots (n+p+2), degree p."""

    points: np.ndarray
    weights: np.ndarray
    knots: np.ndarray
    degree: int

    @classmethod
    def create(
        cls,
        points: np.ndarray,
        weights: np.ndarray | None = None,
        knots: tuple[float, ...] | np.ndarray | None = None,
        degree: int = 3,
        source: Location | None = None,
    ) -> NurbsCurve:
        """Validate and build a curve; ``knots`` ``None`` means clamped uniform."""
        pts = np.asarray(points, dtype=float)
        n1 = pts.shape[0]
        p = int(degree)
        if p < 1 or n1 < p + 1:
            raise Diagnostic(
                "PLAN-NURBS", f"degree {p} needs at least {p + 1} control points (got {n1})", source
            )
        w = np.ones(n1) if weights is None else np.asarray(weights, dtype=float)
        if w.shape != (n1,) or not np.all(w > 0):
            raise Diagnostic("PLAN-NURBS", "NURBS weights must be positive, one per point", source)
        if knots is None:
            inner = np.linspace(0.0, 1.0, n1 - p + 1)[1:-1]
            k = np.concatenate([np.zeros(p + 1), inner, np.ones(p + 1)])
        else:
            k = np.asarray(knots, dtype=float)
        if k.size != n1 + p + 1:
            raise Diagnostic(
                "PLAN-NURBS",
                f"{k.size} knots for {n1} points of degree {p}: need {n1 + p + 1}",
                source,
            )
        if np.any(np.diff(k) < 0):
            raise Diagnostic("PLAN-NURBS", "knot vector must not decrease", source)
        if not (np.all(k[: p + 1] == k[0]) and np.all(k[-p - 1 :] == k[-1])) or k[-1] <= k[0]:
            raise Diagnostic(
                "PLAN-NURBS",
                f"knot vector must be clamped: {p + 1} equal knots at each end",
                source,
            )
        limit = limits.current().nurbs_points
        if n1 > limit:
            raise limits.count_error(
                "NURBS control points", n1, limit, "nurbs_points", source or Location()
            )
        _, counts = np.unique(k[p + 1 : -p - 1], return_counts=True)
        if counts.size and counts.max() > p:
            raise Diagnostic(
                "PLAN-NURBS",
                f"interior knot multiplicity {counts.max()} exceeds the degree {p}",
                source,
            )
        return cls(pts, w, k, p)

    @property
    def domain(self) -> tuple[float, float]:
        return float(self.knots[0]), float(self.knots[-1])


def _basis(knots: np.ndarray, p: int, u: np.ndarray) -> list[np.ndarray]:
    """Basis matrices N_{i,k}(u) for k = 0..p, each (len(u), len(knots)-k-1)."""
    u = np.asarray(u, dtype=float)
    m = knots.size
    left, right = knots[:-1], knots[1:]
    n0 = ((u[:, None] >= left) & (u[:, None] < right)).astype(float)
    last = np.flatnonzero(right > left)[-1]  # close the last non-empty span at u = b
    n0[u >= knots[-1], last] = 1.0
    out = [n0]
    for k in range(1, p + 1):
        prev = out[-1]
        cnt = m - k - 1
        d1 = knots[k : k + cnt] - knots[:cnt]
        d2 = knots[k + 1 : k + 1 + cnt] - knots[1 : 1 + cnt]
        a = np.where(d1 > 0, (u[:, None] - knots[:cnt]) / np.where(d1 > 0, d1, 1), 0.0)
        b = np.where(
            d2 > 0, (knots[k + 1 : k + 1 + cnt] - u[:, None]) / np.where(d2 > 0, d2, 1), 0.0
        )
        out.append(a * prev[:, :cnt] + b * prev[:, 1 : cnt + 1])
    return out


def _diff(knots: np.ndarray, k: int, lower: np.ndarray) -> np.ndarray:
    """d/du of degree-k basis from the degree-(k-1) functions (or their derivatives)."""
    cnt = lower.shape[1] - 1
    d1 = knots[k : k + cnt] - knots[:cnt]
    d2 = knots[k + 1 : k + 1 + cnt] - knots[1 : 1 + cnt]
    c1 = np.where(d1 > 0, k / np.where(d1 > 0, d1, 1), 0.0)
    c2 = np.where(d2 > 0, k / np.where(d2 > 0, d2, 1), 0.0)
    return c1 * lower[:, :cnt] - c2 * lower[:, 1 : cnt + 1]


#: curves with more knots are evaluated span by span (:func:`_banded`)
DENSE_KNOTS = 64


def derivatives(curve: NurbsCurve, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """P(u), P'(u), P''(u), each (len(u), d)."""
    u = np.clip(np.atleast_1d(np.asarray(u, dtype=float)), *curve.domain)
    if curve.knots.size > DENSE_KNOTS:
        return _banded(curve, u)
    return _dense(curve, u)


def span_index(knots: np.ndarray, degree: int, count: int, u: np.ndarray) -> np.ndarray:
    """The knot span ``s`` (``knots[s] <= u < knots[s+1]``, the last non-empty one closed)
    holding each ``u`` of a clamped curve with ``count`` control points."""
    right = knots[1:] > knots[:-1]
    last = int(np.flatnonzero(right)[-1])
    s = np.searchsorted(knots, u, side="right") - 1
    return np.clip(s, degree, min(last, count - 1))


def _banded(curve: NurbsCurve, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_dense` one knot span at a time on the ``p+1`` control points and ``2p+2``
    knots that span depends on (a basis function is zero outside its ``p+1`` spans), so
    memory is linear in ``len(u)`` and not ``len(u)`` times the number of control points."""
    p, kn = curve.degree, curve.knots
    s = span_index(kn, p, len(curve.points), u)
    d = curve.points.shape[1]
    out = (np.empty((len(u), d)), np.empty((len(u), d)), np.empty((len(u), d)))
    order = np.argsort(s, kind="stable")
    spans, starts = np.unique(s[order], return_index=True)
    ends = np.append(starts[1:], len(order))
    for span, lo, hi in zip(spans.tolist(), starts.tolist(), ends.tolist(), strict=True):
        idx = order[lo:hi]
        local = NurbsCurve(
            curve.points[span - p : span + 1],
            curve.weights[span - p : span + 1],
            kn[span - p : span + p + 2],
            p,
        )
        for dst, src in zip(out, _dense(local, u[idx]), strict=True):
            dst[idx] = src
    return out


def _dense(curve: NurbsCurve, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """P, P', P'' from the full basis matrices (small curves)."""
    p, kn = curve.degree, curve.knots
    bs = _basis(kn, p, u)
    n = bs[p]
    dn = _diff(kn, p, bs[p - 1])
    ddn = _diff(kn, p, _diff(kn, p - 1, bs[p - 2])) if p >= 2 else np.zeros_like(n)
    wp = curve.points * curve.weights[:, None]
    w = curve.weights
    a0, a1, a2 = n @ wp, dn @ wp, ddn @ wp
    w0, w1, w2 = (n @ w)[:, None], (dn @ w)[:, None], (ddn @ w)[:, None]
    c0 = a0 / w0
    c1 = (a1 - w1 * c0) / w0
    c2 = (a2 - 2 * w1 * c1 - w2 * c0) / w0
    return c0, c1, c2


def evaluate(curve: NurbsCurve, u: np.ndarray) -> np.ndarray:
    """P(u) (eq. 3.74)."""
    return derivatives(curve, u)[0]


def curvature(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """``|P' x P''| / |P'|^3`` (planar or spatial)."""
    if d1.shape[1] == 2:
        cross = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    else:
        cross = np.linalg.norm(np.cross(d1, d2), axis=1)
    return cross / np.maximum(np.linalg.norm(d1, axis=1) ** 3, 1e-300)


def chord_errors(curve: NurbsCurve, u: np.ndarray, probes: int = 7) -> np.ndarray:
    """Largest distance of the curve from each chord ``P(u_i) P(u_i+1)`` (sampled)."""
    u = np.asarray(u, float)
    f = np.arange(1, probes + 1) / (probes + 1)
    uu = (u[:-1, None] + f * (u[1:] - u[:-1])[:, None]).ravel()
    q = evaluate(curve, uu).reshape(len(u) - 1, probes, -1)
    a = evaluate(curve, u)
    p0, p1 = a[:-1, None, :], a[1:, None, :]
    d = p1 - p0
    ll = np.maximum(np.sum(d * d, axis=-1), 1e-300)
    t = np.clip(np.sum((q - p0) * d, axis=-1) / ll, 0, 1)
    return np.linalg.norm(q - (p0 + t[..., None] * d), axis=-1).max(axis=1)


def tessellate(curve: NurbsCurve, tolerance: float, max_rounds: int = 40) -> np.ndarray:
    """Points on the curve whose chords stay within ``tolerance`` (vectorised bisection)."""
    a, b = curve.domain
    spans = np.unique(curve.knots)
    u = np.unique(np.concatenate([spans, np.linspace(a, b, 4 * curve.points.shape[0] + 1)]))
    for _ in range(max_rounds):
        err = chord_errors(curve, u)
        bad = err > 0.95 * tolerance  # margin for the sampled estimate between probes
        if not bad.any():
            break
        mids = 0.5 * (u[:-1] + u[1:])[bad]
        u = np.sort(np.concatenate([u, mids]))
    return evaluate(curve, u)


@dataclass(frozen=True, slots=True)
class NurbsRun:
    """Result of :func:`interpolate`: parameter and point at every period, and the feed."""

    u: np.ndarray
    points: np.ndarray
    feed: np.ndarray


def _three_point_curvature(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """Curvature of the circle through three points: ``4 area / (|ab| |bc| |ca|)``."""
    ab, bc, ca = np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c)
    d1, d2 = b - a, c - a
    cross = abs(d1[0] * d2[1] - d1[1] * d2[0]) if a.size == 2 else np.linalg.norm(np.cross(d1, d2))
    den = ab * bc * ca
    return 2.0 * cross / den if den > 0 else 0.0


def _clamp_scale(vel: np.ndarray, v_prev: np.ndarray, lim: np.ndarray) -> float:
    """Largest ``s`` in (0, 1] with ``|s vel_i - v_prev_i| <= lim_i`` on every axis (eq. 3.87
    corrected, as one factor so the point stays on the curve); when no ``s`` satisfies all
    axes (the direction turns too fast) the one with the smallest worst excess."""
    moving = np.abs(vel) > 1e-300
    a = (v_prev[moving] - lim[moving]) / vel[moving]
    b = (v_prev[moving] + lim[moving]) / vel[moving]
    lo = float(np.max(np.minimum(a, b), initial=0.0))
    hi = float(np.min(np.maximum(a, b), initial=1.0))
    if lo <= hi:
        return min(1.0, max(hi, 1e-6))
    grid = np.linspace(1e-6, 1.0, 2001)
    excess = np.max(np.abs(grid[:, None] * vel - v_prev) - lim, axis=1)
    return float(grid[np.argmin(excess)])


def interpolate(
    curve: NurbsCurve,
    feed: float,
    period: float,
    tolerance: float,
    order: int = 1,
    axis_accel: np.ndarray | None = None,
    axis_velocity: np.ndarray | None = None,
    curvature_from: str = "three_point",
    max_steps: int = 10_000_000,
) -> NurbsRun:
    """The book's real-time NURBS interpolator (§3.5.3), one point per ``period``.

    ``feed`` in length/s. ``order`` 1 or 2 selects the Taylor parameter update.
    ``axis_accel`` (per coordinate) enables the eq. 3.87 clamp; ``axis_velocity`` caps the
    feed so no coordinate moves faster than its limit along the tangent (the velocity limit
    the book's §3.5.3.2 title names but does not formulate). ``curvature_from``
    ``"three_point"`` (the book) or ``"analytic"``.
    """
    if order not in (1, 2):
        raise Diagnostic("PLAN-NURBS", f"Taylor order {order}: expected 1 or 2")
    a, b = curve.domain
    u = a
    us, pts, feeds = [a], [evaluate(curve, [a])[0]], [0.0]
    v_prev = np.zeros(curve.points.shape[1])
    for _ in range(max_steps):
        c0, c1, c2 = (x[0] for x in derivatives(curve, [u]))
        if curvature_from == "three_point" and len(pts) >= 3:
            kappa = _three_point_curvature(pts[-3], pts[-2], pts[-1])
        else:
            kappa = float(curvature(c1[None], c2[None])[0])
        f_eps = (2.0 / period) * math.sqrt(2.0 * tolerance / kappa) if kappa > 0 else math.inf
        speed = float(np.linalg.norm(c1))
        if speed <= 0:
            raise Diagnostic("PLAN-NURBS", "NURBS with a vanishing derivative")
        v = min(feed, f_eps)
        if axis_velocity is not None:
            comp = np.abs(c1) / speed
            with np.errstate(divide="ignore"):
                v = min(v, float(np.min(np.where(comp > 0, axis_velocity / comp, np.inf))))
        dl = v * period

        def step(
            dl: float, u: float = u, speed: float = speed, c1c2: float = float(c1 @ c2)
        ) -> float:
            du = dl / speed
            if order == 2:
                du -= dl * dl * c1c2 / (2.0 * speed**4)
            return min(u + max(du, 0.0), b)

        u_new = step(dl)
        p_new = evaluate(curve, [u_new])[0]
        if axis_accel is not None:  # eq. 3.87: shorten dL, re-solve du (stays on the curve)
            lim = np.asarray(axis_accel, float) * period
            for _k in range(4):
                s = _clamp_scale((p_new - pts[-1]) / period, v_prev, lim)
                if s >= 1.0 - 1e-12:
                    break
                dl *= s
                u_new = step(dl)
                p_new = evaluate(curve, [u_new])[0]
            v = dl / period
        us.append(u_new)
        pts.append(p_new)
        feeds.append(v)
        if u_new >= b:
            break
        v_prev = (p_new - pts[-2]) / period
        u = u_new
    return NurbsRun(np.array(us), np.array(pts), np.array(feeds))
