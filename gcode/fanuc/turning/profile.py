"""Contour geometry for the Fanuc stock-removal cycles G71/G72 (gcode/fanuc/turning/contour.py).

The cycles work in a normalised frame (a, b): ``a`` is the axis the cycle steps along
(X for G71, Z for G72) and ``b`` the axis it cuts along, both signed so that the cycle
steps towards decreasing ``a`` and cuts towards decreasing ``b``. The four G71 patterns
(OD/ID, cutting towards -Z/+Z) and the four of G72 become one: a type I contour from A' to
B then has ``a`` non-decreasing and ``b`` non-increasing (0i-TF: "the figure must show a
monotonous change along both axes"), a type II contour only ``b`` non-increasing, so it
is a function a = h(b) with pockets. Arcs keep their centre; a reflection of the plane
reverses their direction; arcs are cut where ``a`` turns so every piece is monotone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from gcode.fanuc.turning.types import EPS, ProfileStep

TAU = 2.0 * math.pi


@dataclass(frozen=True)
class Frame:
    """Map between (x radius, z) and the normalised (a, b) of one cycle call."""

    swap: bool  # G72: a is Z, b is X
    sa: float  # +1 or -1
    sb: float

    def ab(self, x: float, z: float) -> tuple[float, float]:
        if self.swap:
            return self.sa * z, self.sb * x
        return self.sa * x, self.sb * z

    def xz(self, a: float, b: float) -> tuple[float, float]:
        if self.swap:
            return self.sb * b, self.sa * a
        return self.sa * a, self.sb * b

    @property
    def mirrors(self) -> bool:
        """Whether the map (z, x) -> (b, a) reverses the sense of rotation."""
        det = -self.sa * self.sb if self.swap else self.sa * self.sb
        return det < 0


@dataclass(frozen=True)
class Segment:
    """One contour piece in the normalised frame; ``ccw`` as seen with b right, a up."""

    kind: str  # "line" | "rapid" | "arc"
    a0: float
    b0: float
    a1: float
    b1: float
    ca: float = 0.0
    cb: float = 0.0
    ccw: bool = False
    line: int = 0

    @property
    def radius(self) -> float:
        return math.hypot(self.a0 - self.ca, self.b0 - self.cb)

    def sweep(self) -> tuple[float, float]:
        """(start angle, signed sweep) of an arc; angles measured from +b towards +a."""
        t0 = math.atan2(self.a0 - self.ca, self.b0 - self.cb)
        t1 = math.atan2(self.a1 - self.ca, self.b1 - self.cb)
        delta = (t1 - t0) % TAU if self.ccw else -((t0 - t1) % TAU)
        if abs(delta) < 1e-12:  # same end point: a full circle
            delta = TAU if self.ccw else -TAU
        return t0, delta

    def contains_angle(self, phi: float) -> bool:
        """Whether ``phi`` lies strictly inside the arc's sweep."""
        t0, delta = self.sweep()
        rel = (phi - t0) % TAU if delta > 0 else (t0 - phi) % TAU
        tol = 1e-9
        return tol < rel < abs(delta) - tol

    def turns_at(self, phi: float) -> bool:
        """Whether the arc reverses at angle ``phi`` (0 or pi: b turns; +-pi/2: a turns) by
        more than EPS beyond its end points. An arc tangent to the axis at an end, whose
        centre the program's rounded numbers put a few least increments off, passes the
        extreme by far less than one increment: the control, working in its increments,
        sees no reversal there, and neither does this check."""
        if not self.contains_angle(phi):
            return False
        r = self.radius
        if abs(math.sin(phi)) > 0.5:  # a turns
            peak, ends = self.ca + r * math.sin(phi), (self.a0, self.a1)
        else:  # b turns
            peak, ends = self.cb + r * math.cos(phi), (self.b0, self.b1)
        return min(abs(peak - e) for e in ends) > EPS

    def monotone_b(self) -> bool:
        """b never increases from start to end (type II: only the cutting axis)."""
        if self.kind == "arc" and any(self.turns_at(p) for p in (0.0, math.pi)):
            return False
        return self.b1 <= self.b0 + EPS

    def monotone(self) -> bool:
        """a never decreases and b never increases from start to end."""
        if self.kind == "arc":
            extremes = (0.0, math.pi / 2, math.pi, -math.pi / 2)
            if any(self.turns_at(phi) for phi in extremes):
                return False
        return self.a1 >= self.a0 - EPS and self.b1 <= self.b0 + EPS


def normalise(
    steps: list[ProfileStep],
    frame: Frame,
    start: tuple[float, float],
    shift: tuple[float, float],
) -> list[Segment]:
    """The contour steps after ``start`` (x, z), shifted by ``shift`` (dx, dz), as segments."""
    dx, dz = shift
    pa, pb = frame.ab(start[0] + dx, start[1] + dz)
    out: list[Segment] = []
    for st in steps:
        a1, b1 = frame.ab(st.x + dx, st.z + dz)
        if st.kind in ("cw", "ccw"):
            ca, cb = frame.ab(st.cx + dx, st.cz + dz)
            ccw = (st.kind == "ccw") != frame.mirrors
            out.append(Segment("arc", pa, pb, a1, b1, ca, cb, ccw, st.line))
        else:
            kind = "rapid" if st.kind == "rapid" else "line"
            out.append(Segment(kind, pa, pb, a1, b1, line=st.line))
        pa, pb = a1, b1
    return out


def first_non_monotone(segments: list[Segment], along_b_only: bool = False) -> Segment | None:
    """The first piece that breaks the type I rule (or, ``along_b_only``, type II's), or None."""
    for seg in segments:
        ok = seg.monotone_b() if along_b_only else seg.monotone()
        if not ok:
            return seg
    return None


def split_at_a_extremes(segments: list[Segment]) -> list[Segment]:
    """Arcs cut where ``a`` turns (angles +-90 degrees): every piece is then monotone in a
    (and in b, for a type II contour)."""
    out: list[Segment] = []
    for seg in segments:
        if seg.kind != "arc":
            out.append(seg)
            continue
        t0, delta = seg.sweep()
        cuts = []
        for phi in (math.pi / 2, -math.pi / 2):
            if seg.contains_angle(phi):
                rel = (phi - t0) % TAU if delta > 0 else (t0 - phi) % TAU
                cuts.append((rel, phi))
        a_prev, b_prev = seg.a0, seg.b0
        r = seg.radius
        for _, phi in sorted(cuts):
            a_mid, b_mid = seg.ca + r * math.sin(phi), seg.cb + r * math.cos(phi)
            out.append(
                Segment("arc", a_prev, b_prev, a_mid, b_mid, seg.ca, seg.cb, seg.ccw, seg.line)
            )
            a_prev, b_prev = a_mid, b_mid
        out.append(
            Segment("arc", a_prev, b_prev, seg.a1, seg.b1, seg.ca, seg.cb, seg.ccw, seg.line)
        )
    return out


def _arc_side(seg: Segment) -> tuple[float, float]:
    """Signs of sin and cos at the middle of an arc piece (constant over a split piece)."""
    t0, delta = seg.sweep()
    mid = t0 + delta / 2.0
    return (1.0 if math.sin(mid) >= 0 else -1.0), (1.0 if math.cos(mid) >= 0 else -1.0)


def crossings(pieces: list[Segment], level: float) -> list[float]:
    """b of every point where a monotone piece reaches a = level."""
    out = []
    for seg in pieces:
        lo, hi = min(seg.a0, seg.a1), max(seg.a0, seg.a1)
        if not lo - EPS <= level <= hi + EPS:
            continue
        if hi - lo <= EPS:
            out += [seg.b0, seg.b1]
        elif seg.kind != "arc":
            out.append(seg.b0 + (level - seg.a0) / (seg.a1 - seg.a0) * (seg.b1 - seg.b0))
        else:
            half = math.sqrt(max(seg.radius**2 - (level - seg.ca) ** 2, 0.0))
            out.append(seg.cb + _arc_side(seg)[1] * half)
    return out


def height(pieces: list[Segment], b: float) -> float | None:
    """a of the contour at b (a type II contour is a function of b), None outside it."""
    for seg in pieces:
        if abs(seg.b0 - seg.b1) <= EPS or not min(seg.b0, seg.b1) <= b <= max(seg.b0, seg.b1):
            continue
        if seg.kind != "arc":
            return seg.a0 + (b - seg.b0) / (seg.b1 - seg.b0) * (seg.a1 - seg.a0)
        half = math.sqrt(max(seg.radius**2 - (b - seg.cb) ** 2, 0.0))
        return seg.ca + _arc_side(seg)[0] * half
    return None


def material_intervals(
    pieces: list[Segment], level: float, b0: float, b_first: float, b_last: float
) -> list[tuple[float, float]]:
    """The (from, to) stretches, in cutting order, where a cut at a = level from b0 runs in
    stock above the contour: from b0 (before the contour's first point nothing is
    protected) down to the contour's last point, wherever the contour is at or below the
    level."""
    if b_last >= b0 - EPS:
        return []
    # every vertex too: an interval then lies on one piece, and its middle cannot fall in
    # the sliver of a wall slanted by less than EPS (where no piece gives a height)
    vertices = [b for seg in pieces for b in (seg.b0, seg.b1)]
    marks = [b0, b_last, b_first] + crossings(pieces, level) + vertices
    marks = sorted({m for m in marks if b_last - EPS <= m <= b0 + EPS}, reverse=True)
    points: list[float] = []
    for m in marks:
        if not points or points[-1] - m > EPS:
            points.append(min(max(m, b_last), b0))
    out: list[tuple[float, float]] = []
    for hi, lo in zip(points, points[1:], strict=False):
        mid = 0.5 * (hi + lo)
        h = None if mid > b_first else height(pieces, mid)
        if h is None or h <= level + EPS:
            if out and abs(out[-1][1] - hi) <= EPS:
                out[-1] = (out[-1][0], lo)
            else:
                out.append((hi, lo))
    return out
