"""ELLIPSE_FEED (NISTIR 5970 §3.6.3) as chords within a tolerance, for the path builder.

What controllers do with a curve their interpolator lacks: the elliptical helix is replaced
by straight chords no farther than ``tolerance`` from it, run at the programmed feed (the
feed applies along the 3-D path, NISTIR rule; the chords' length is the helix length to
within the tolerance). Conventions (research/seed-canon-rs274.md §3.5, cases 56-62):

* ``major`` / ``minor`` are full axis lengths (semi-axes ``a = major/2``, ``b = minor/2``;
  ``major >= minor`` is not required); ``angle_to_first`` is in degrees from the plane's
  first axis; ``rotation`` has ARC_FEED's meaning (sign: counter-clockwise viewed from the
  normal's + end; ``|rotation| = N``: swept angle in ``((N-1) 360, N 360]`` degrees).
* The axial coordinate follows NIST's implemented rule 2: its travel is proportional to the
  polar angle swept about the ellipse centre (so at half the swept angle, half the axial
  travel is done), not to the in-plane distance.

Chords: the ellipse is the image of the unit circle under ``M = Rot(phi) diag(a, b)``, with
the eccentric anomaly ``t`` as parameter. Affine maps keep the ratio of the distances of
points to a line, so the point of an arc ``[t0, t0 + dt]`` farthest from its chord is the
image of the circle arc's midpoint, at distance at most ``|M| (1 - cos(dt/2)) =
max(a, b) (1 - cos(dt/2))``: uniform steps ``dt <= 2 acos(1 - E / max(a, b))`` bound the
in-plane chord error by ``E`` exactly (own derivation; for ``a = b`` it is the circle's
sagitta rule, book eq. 3.83 / 4.98). The steps are then shortest where the curvature is
tightest (``|dp/dt| = b`` at the ends of the major axis, radius of curvature ``b^2/a``
for ``a >= b``): the sagitta there, ``(b dt)^2 / (8 b^2/a) = a dt^2/8``, is the bound's,
so this is the sagitta rule at the tightest curvature. ``E`` is the controller's
``chord_tolerance`` (as for NURBS); a ``G64 P`` blend of the chords adds its own tolerance.
The axial motion (rule 2) is not linear in ``t``: the chord count is doubled until the 3-D
deviation at :data:`CHECKS` points inside every chord is within ``E`` too.

A current or end point off the ellipse by more than :func:`on_ellipse_tolerance` is an error
(``PLAN-ELLIPSE``, NISTIR 5970 §3.6.3); within it, the radial scale goes linearly from the
start point's to the end point's (the ARC_FEED spiral of kernel.path.build), so the chords start
at the current position and end exactly at the programmed end point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic, Location
from kernel.ir.arcsweep import arc_sweep

CHECKS = 7  # interior check points per chord for the helical (axial) deviation
MAX_CHORDS = 2_000_000  # one ELLIPSE_FEED never becomes more lines than this


def on_ellipse_tolerance(a: float, b: float) -> float:
    """How far (mm) the current and end points may lie off the projected ellipse: 2 um,
    or 1e-6 of the major semi-axis for very large ellipses (NISTIR 5970 leaves it to the
    implementation)."""
    return max(0.002, 1e-6 * max(a, b))


@dataclass(frozen=True, slots=True)
class EllipseChords:
    """Chord end points in the plane (``first``, ``second``), excluding the start point,
    with the fraction of the axial travel done at each (NIST rule 2) and of the path
    length (for rotary axes, which move linearly along the path as on ARC_FEED)."""

    first: np.ndarray
    second: np.ndarray
    axial_fraction: np.ndarray
    length_fraction: np.ndarray
    deviation: float  # largest distance of the checked curve points from their chords

    def plane_points(self) -> list[tuple[float, float, float]]:
        """(first, second, axial fraction) of each chord end, as floats: what a writer
        emits, the last exactly on the programmed end with all of the axial travel."""
        return list(
            zip(
                self.first.tolist(),
                self.second.tolist(),
                self.axial_fraction.tolist(),
                strict=True,
            )
        )


def _polar_fraction(x: np.ndarray, y: np.ndarray, cf: float, cs: float) -> np.ndarray:
    polar = np.unwrap(np.arctan2(y - cs, x - cf))
    total = polar[-1] - polar[0]
    if total == 0.0:
        return np.linspace(0.0, 1.0, x.size)
    return (polar - polar[0]) / total


def ellipse_chords(
    start: tuple[float, float],
    end: tuple[float, float],
    centre: tuple[float, float],
    major: float,
    minor: float,
    angle_deg: float,
    rotation: int,
    axial: float,
    tolerance: float,
    location: Location | None = None,
) -> EllipseChords:
    """Chords of the elliptical helix from ``start`` to ``end`` (plane coordinates, mm)
    about ``centre``; ``axial`` is the helix' travel along the normal (mm)."""
    a, b = 0.5 * major, 0.5 * minor
    if not (a > 0 and b > 0 and math.isfinite(a) and math.isfinite(b)):
        raise Diagnostic("PLAN-ELLIPSE", "ellipse with a zero or negative axis", location)
    if rotation == 0:
        raise Diagnostic("PLAN-ELLIPSE", "ellipse with rotation 0", location)
    if not tolerance > 0:
        raise Diagnostic("PLAN-ELLIPSE", "ellipse needs a positive chord tolerance", location)
    cf, cs = centre
    phi = math.radians(angle_deg)
    cp, sp = math.cos(phi), math.sin(phi)

    def local(p: tuple[float, float]) -> tuple[float, float]:
        dx, dy = p[0] - cf, p[1] - cs
        return cp * dx + sp * dy, -sp * dx + cp * dy

    (x0, y0), (x1, y1) = local(start), local(end)
    q0, q1 = math.hypot(x0 / a, y0 / b), math.hypot(x1 / a, y1 / b)  # 1 on the ellipse
    allowed = on_ellipse_tolerance(a, b)
    for name, (x, y), q in (("current", (x0, y0), q0), ("end", (x1, y1), q1)):
        off = math.hypot(x, y) * abs(1.0 - 1.0 / q) if q > 0 else max(a, b)
        if off > allowed:
            raise Diagnostic(
                "PLAN-ELLIPSE",
                f"the {name} point is {off:.6g} mm off the ellipse (allowed {allowed:g} mm)",
                location,
            )
    t0, t1 = math.atan2(y0 / b, x0 / a), math.atan2(y1 / b, x1 / a)
    sign = 1.0 if rotation > 0 else -1.0
    sweep = abs(arc_sweep(t0, t1, rotation))
    r = max(a, b)
    step = 2 * math.acos(1 - tolerance / r) if tolerance < r else math.pi / 2
    n = max(2, math.ceil(sweep / step))
    while True:
        if n > MAX_CHORDS:
            raise Diagnostic(
                "PLAN-ELLIPSE",
                f"ellipse needs more than {MAX_CHORDS} chords for the tolerance {tolerance:g} mm",
                location,
            )
        m = n * (CHECKS + 1)  # every chord with CHECKS interior points
        lam = np.linspace(0.0, 1.0, m + 1)
        t = t0 + sign * sweep * lam
        q = q0 + (q1 - q0) * lam
        lx, ly = q * a * np.cos(t), q * b * np.sin(t)
        x = cf + cp * lx - sp * ly
        y = cs + sp * lx + cp * ly
        zf = _polar_fraction(x, y, cf, cs)
        pts = np.stack([x, y, axial * zf], axis=1)
        ends = pts[:: CHECKS + 1]
        # distance of the interior points from their chords (3-D)
        p0 = np.repeat(ends[:-1], CHECKS + 1, axis=0)
        d = np.repeat(ends[1:] - ends[:-1], CHECKS + 1, axis=0)
        rel = pts[:-1] - p0
        ll = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        u = np.clip(np.einsum("ij,ij->i", rel, d) / ll, 0.0, 1.0)
        dev = float(np.linalg.norm(rel - u[:, None] * d, axis=1).max())
        if dev <= tolerance or n >= MAX_CHORDS:
            break
        n *= 2
    first, second = ends[1:, 0].copy(), ends[1:, 1].copy()
    first[-1], second[-1] = end  # exactly the programmed end point
    chord = np.linalg.norm(np.diff(ends, axis=0), axis=1)
    cum = np.cumsum(chord)
    length_fraction = cum / cum[-1] if cum[-1] > 0 else np.linspace(0.0, 1.0, n + 1)[1:]
    axial_fraction = zf[:: CHECKS + 1][1:].copy()
    axial_fraction[-1] = length_fraction[-1] = 1.0
    return EllipseChords(first, second, axial_fraction, length_fraction, dev)


__all__ = ["EllipseChords", "ellipse_chords", "on_ellipse_tolerance"]
