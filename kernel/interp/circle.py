"""Sampled-data (reference-word) circle interpolation: book §3.3.2.2-3.3.2.8.

Every method advances the point relative to the centre by a 2x2 matrix per period
(book eq. 3.33, CCW; CW mirrors it):

    X(i+1) = A X(i) - B Y(i),   Y(i+1) = A Y(i) + B X(i)

* Euler (eq. 3.41): ``A = 1, B = alpha``, ``alpha = 4/(pi R)`` (eq. 3.44);
* improved Euler (eq. 3.46): ``X(i+1) = X - alpha Y``, ``Y(i+1) = Y + alpha X(i+1)``,
  ``alpha = 4/R`` (eq. 3.49);
* Taylor (eq. 3.51): ``A = 1 - alpha^2/2, B = alpha``, ``alpha = sqrt(8/R)`` (eq. 3.56;
  Table 3.8 misprints it as sqrt(8)/R, research/seed-book-interp.md §3.12);
* Tustin (eq. 3.59): ``A = (1-(alpha/2)^2)/(1+(alpha/2)^2)``, ``B = alpha/(1+(alpha/2)^2)``,
  ``alpha = sqrt(8/(R-1))`` (eq. 3.65); the true step is ``2 atan(alpha/2)``;
* improved Tustin (eq. 3.71): exact rotation by ``alpha = 2 acos((R-beta)/(R+beta))`` on a
  circle of radius ``R + beta`` (vertices outside by ``beta``, chord midpoints inside by
  ``beta``).

Radii are in BLU (the tolerance unit): ``R = radius / tolerance``. Radial error
``ER = |P| - R`` (eq. 3.36) and chord-height error ``EH = R - |midpoint|`` (eq. 3.38).
:func:`vertices` gives the k-th point in closed form (matrix powers), so a whole arc is
computed without a per-step loop; :func:`iterate` is the book's recursion, step by step.
"""

from __future__ import annotations

import math

import numpy as np

from kernel.diagnostics import Diagnostic

METHODS: tuple[str, ...] = ("euler", "improved_euler", "taylor", "tustin", "improved_tustin")


def step_parameter(method: str, radius_blu: float, beta: float = 1.0) -> float:
    """The book's ``alpha`` for a radius in BLU and a tolerance of ``beta`` BLU (Table 3.8)."""
    r = float(radius_blu)
    if method == "euler":
        return 4.0 / (math.pi * r)
    if method == "improved_euler":
        return 4.0 / r
    if method == "taylor":
        return math.sqrt(8.0 / r)
    if method == "tustin":
        return math.sqrt(8.0 / max(r - 1.0, 1e-12))
    if method == "improved_tustin":
        return 2.0 * math.acos(max(-1.0, (r - beta) / (r + beta)))
    raise Diagnostic("PLAN-CIRCLE", f"unknown circle method {method!r}")


def coefficients(method: str, alpha: float) -> tuple[float, float]:
    """(A, B) of eq. 3.33 for the scaled-rotation methods (not improved Euler)."""
    if method == "euler":
        return 1.0, alpha
    if method == "taylor":
        return 1.0 - alpha * alpha / 2.0, alpha
    if method == "tustin":
        q = 1.0 + (alpha / 2.0) ** 2
        return (1.0 - (alpha / 2.0) ** 2) / q, alpha / q
    if method == "improved_tustin":
        return math.cos(alpha), math.sin(alpha)
    raise Diagnostic("PLAN-CIRCLE", f"{method!r} is not a scaled rotation")


def true_step(method: str, alpha: float) -> float:
    """The rotation per step the method really makes, rad."""
    if method == "improved_euler":
        return math.acos(1.0 - alpha * alpha / 2.0)
    a, b = coefficients(method, alpha)
    return math.atan2(b, a)


def parameter_for_step(method: str, phi: float) -> float:
    """Inverse of :func:`true_step`: the ``alpha`` whose real rotation is ``phi``."""
    t = math.tan(phi)
    if method == "euler":
        return t
    if method == "taylor":
        return (math.sqrt(1.0 + 2.0 * t * t) - 1.0) / t if t else 0.0
    if method == "tustin":
        return 2.0 * math.tan(phi / 2.0)
    if method == "improved_euler":
        return math.sqrt(2.0 * (1.0 - math.cos(phi)))
    if method == "improved_tustin":
        return phi
    raise Diagnostic("PLAN-CIRCLE", f"unknown circle method {method!r}")


def steps_for_sweep(method: str, sweep: float, radius_blu: float) -> tuple[int, float]:
    """Number of steps ``N = ceil(sweep/step)`` and the reduced parameter (book §6.2.2,
    corrected: ``ceil``, so the tolerance is kept; research/seed-book-motion.md §5.3)."""
    alpha = step_parameter(method, radius_blu)
    n = max(1, math.ceil(abs(sweep) / true_step(method, alpha) - 1e-9))
    return n, parameter_for_step(method, abs(sweep) / n)


def iterate(
    method: str, x0: float, y0: float, alpha: float, n: int, clockwise: bool = False
) -> np.ndarray:
    """The book's recursion run ``n`` steps from (x0, y0) (centre-relative): (n+1, 2)."""
    sgn = -1.0 if clockwise else 1.0
    out = np.empty((n + 1, 2))
    x, y = float(x0), float(y0)
    if method == "improved_tustin":
        r = math.hypot(x, y)
        x, y = x * (r + 1.0) / r, y * (r + 1.0) / r  # the circle of radius R + beta
    out[0] = x0, y0
    if method == "improved_euler":
        for i in range(1, n + 1):
            x = x - sgn * alpha * y
            y = y + sgn * alpha * x
            out[i] = x, y
        return out
    a, b = coefficients(method, alpha)
    b *= sgn
    for i in range(1, n + 1):
        x, y = a * x - b * y, a * y + b * x
        out[i] = x, y
    return out


def vertices(
    method: str, radius: float, alpha: float, k: np.ndarray, beta: float = 0.0
) -> np.ndarray:
    """Closed form of :func:`iterate` from (radius, 0), CCW: points ``k`` (array), (len, 2).

    Scaled rotations: ``M^k = C^k Rot(k phi)``; improved Euler (det 1):
    ``M^k = (sin(k phi) M - sin((k-1) phi) I) / sin(phi)``. ``beta`` is the improved-Tustin
    offset in the same length unit as ``radius``. Point 0 is the start itself.
    """
    k = np.asarray(k, dtype=float)
    if method == "improved_euler":
        phi = true_step(method, alpha)
        if phi == 0:
            return np.stack([np.full_like(k, radius), np.zeros_like(k)], axis=-1)
        sk, sk1 = np.sin(k * phi), np.sin((k - 1) * phi)
        sp = math.sin(phi)
        x = radius * (sk * 1.0 - sk1) / sp
        y = radius * (sk * alpha) / sp
        return np.stack([x, y], axis=-1)
    a, b = coefficients(method, alpha)
    c, phi = math.hypot(a, b), math.atan2(b, a)
    r = radius + beta if method == "improved_tustin" else radius
    rk = r * c**k
    out = np.stack([rk * np.cos(k * phi), rk * np.sin(k * phi)], axis=-1)
    out[k == 0] = radius, 0.0
    return out


def tustin_band(radius: float, sweep: float, beta: float) -> np.ndarray:
    """Improved-Tustin vertices for an arc whose ends must be the programmed points.

    Inner vertices lie on ``R + beta`` at most ``alpha`` (eq. 3.71) apart; the first and
    last chords start from radius ``R``, so their step is the ``phi`` with
    ``(R + beta/2) cos(phi/2) = R - beta`` to keep their midpoints in the band as well.
    Returns (n+1, 2) points CCW from (R, 0) over ``|sweep|``.
    """
    r, sw = float(radius), abs(float(sweep))
    alpha = 2.0 * math.acos(max(-1.0, (r - beta) / (r + beta)))
    q = r + beta

    def nearest(ph: float) -> float:  # distance of the centre from the first chord
        p1 = np.array([q * math.cos(ph), q * math.sin(ph)])
        d = p1 - np.array([r, 0.0])
        t = min(1.0, max(0.0, float(-np.dot([r, 0.0], d) / np.dot(d, d))))
        return float(np.hypot(r + t * d[0], t * d[1]))

    lo, hi = 0.0, alpha
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if nearest(mid) >= r - beta else (lo, mid)
    phi = lo
    if sw <= 2.0 * phi:
        ang = np.array([0.0, sw / 2.0, sw])
    else:
        inner = max(1, math.ceil((sw - 2.0 * phi) / alpha - 1e-12))
        ang = np.concatenate([[0.0], phi + np.linspace(0.0, sw - 2.0 * phi, inner + 1), [sw]])
    rad = np.full(ang.size, r + beta)
    rad[0] = rad[-1] = r
    return np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)


def radial_error(points: np.ndarray, radius: float) -> np.ndarray:
    """ER = |P| - R at every point (eq. 3.36)."""
    return np.hypot(points[:, 0], points[:, 1]) - radius


def chord_error(points: np.ndarray, radius: float) -> np.ndarray:
    """EH = R - |chord midpoint| for every consecutive pair (eq. 3.38)."""
    mid = 0.5 * (points[1:] + points[:-1])
    return radius - np.hypot(mid[:, 0], mid[:, 1])
