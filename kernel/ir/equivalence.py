"""Motion-level equivalence of two canonical-command streams (the rule of tests/data/README.md).

``cnc convert`` reads its own output back and compares it with the source with
:func:`first_difference`. After dropping everything else, both streams must give the same
ordered motions (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED, NURBS_FEED, ELLIPSE_FEED,
STRAIGHT_PROBE, DWELL) with the same end points and curve data within :data:`EXACT` program
units, each motion seeing the same feed rate, spindle speed and direction, tool, coolant,
length units and plane; tool changes, stops, messages and program end in the same order.

Where the output replaces a source curve by other motions (an arc as chords, a NURBS or an
ellipse as arcs or chords), the replacement is accepted when every piece ends within the
conversion's tolerance of the curve, the pieces advance along it in order, and the last one
ends on the curve's end point. Lengths are compared in millimetres so an output written in
other length units compares with its source; the units a motion sees must then map one to
one (every inch motion of the source is, say, a millimetre motion of the output).

The comparison streams: each side is read once, item by item, and nothing is kept behind.
:func:`equivalent` is its fast path for a large program: both streams as arrays of motions
(a reader's runs of plain lines come as :class:`Moves`), compared in numpy; it says True
only where :func:`first_difference` would find nothing, and leaves every other case to it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import cast

import numpy as np

from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.ir.arcsweep import TWO_PI, arc_sweep

#: equality of lengths and numbers, in the source's program units (1e-4; 1e-9 absorbs float
#: noise of printed values)
EXACT = 1e-4 + 1e-9
#: samples per curve span when a NURBS or ellipse is replaced by other motions
SAMPLES = 64

_EVENTS = (
    canon.ChangeTool,
    canon.ProgramStop,
    canon.OptionalProgramStop,
    canon.ProgramEnd,
    canon.Message,
)
_CURVES = (canon.ArcFeed, canon.NurbsFeed, canon.EllipseFeed)
#: plane -> indexes of (first, second, normal) axes in (x, y, z)
_AXES = {canon.Plane.XY: (0, 1, 2), canon.Plane.YZ: (1, 2, 0), canon.Plane.XZ: (2, 0, 1)}


@dataclass(frozen=True, slots=True)
class Difference:
    """The first place two streams differ: the source command's location and what differs."""

    source: Location | None
    message: str


@dataclass(frozen=True, slots=True)
class Seen:
    """What a motion sees; ``feed`` in mm (or inverse-time) per minute."""

    feed: float
    speed: float
    direction: canon.Direction
    tool: int | str
    mist: bool
    flood: bool
    plane: canon.Plane


@dataclass(frozen=True, slots=True)
class Item:
    """A motion (with ``seen``, its start, its end in mm) or an event (``seen`` None)."""

    command: canon.Command
    seen: Seen | None
    units: canon.Units | None
    start: tuple[float, float, float]
    end: tuple[float, float, float]


def _mm(units: canon.Units | None) -> float:
    return 1.0 if units is None else units.mm_per_unit


def items(commands: Iterable[canon.Command]) -> Iterator[Item]:
    """The motions and ordered events of a stream, with the state each motion sees."""
    feed = speed = 0.0
    direction = canon.Direction.STOPPED
    tool: int | str = 0
    mist = flood = False
    plane = canon.Plane.XY
    units: canon.Units | None = None
    pos = (0.0, 0.0, 0.0)
    seen: Seen | None = None
    for c in commands:
        if isinstance(c, canon.StraightFeed | canon.StraightTraverse | canon.StraightProbe):
            k = _mm(units)
            end = (c.x * k, c.y * k, c.z * k)
        elif isinstance(c, canon.ArcFeed | canon.EllipseFeed):
            k = _mm(units)
            i, j, n = _AXES[plane]
            point = [0.0, 0.0, 0.0]
            point[i], point[j], point[n] = c.first_end * k, c.second_end * k, c.axis_end_point * k
            end = (point[0], point[1], point[2])
        elif isinstance(c, canon.NurbsFeed):
            end = pos
            if c.points and not c.elided:
                k = _mm(units)
                i, j, _ = _AXES[plane]
                point = list(pos)
                point[i], point[j] = c.points[-1][0] * k, c.points[-1][1] * k
                end = (point[0], point[1], point[2])
        elif isinstance(c, canon.Dwell):
            end = pos
        else:
            seen = None
            if isinstance(c, canon.SetFeedRate):
                feed = c.rate
            elif isinstance(c, canon.SetSpindleSpeed):
                speed = c.speed
            elif isinstance(c, canon.StartSpindleClockwise):
                direction = canon.Direction.CLOCKWISE
            elif isinstance(c, canon.StartSpindleCounterclockwise):
                direction = canon.Direction.COUNTERCLOCKWISE
            elif isinstance(c, canon.StopSpindleTurning):
                direction = canon.Direction.STOPPED
            elif isinstance(c, canon.MistOn | canon.MistOff):
                mist = isinstance(c, canon.MistOn)
            elif isinstance(c, canon.FloodOn | canon.FloodOff):
                flood = isinstance(c, canon.FloodOn)
            elif isinstance(c, canon.UseLengthUnits):
                units = c.units
            elif isinstance(c, canon.SelectPlane):
                plane = c.plane
            elif isinstance(c, _EVENTS):
                if isinstance(c, canon.ChangeTool):
                    tool = c.name or c.slot
                yield Item(c, None, units, pos, pos)
            continue
        if seen is None:
            seen = Seen(feed * _mm(units), speed, direction, tool, mist, flood, plane)
        yield Item(c, seen, units, pos, end)
        pos = end


def _close(a: float, b: float, tol: float) -> bool:
    return abs(a - b) <= tol


def _values_differ(
    name: str,
    a: Iterable[float],
    b: Iterable[float],
    lengths: int,
    scale: tuple[float, float, float],
) -> str | None:
    """The first of two argument lists that differs; the first ``lengths`` are lengths,
    ``scale`` the mm per unit of each side and the tolerance of lengths in mm."""
    k_src, k_out, tol_mm = scale
    for index, (x, y) in enumerate(zip(a, b, strict=True)):
        if index < lengths:
            x, y = x * k_src, y * k_out
            tol = tol_mm
        else:
            tol = EXACT
        if not _close(float(x), float(y), tol):
            return f"{name} argument {index + 1}: {y:g} where the source has {x:g}"
    return None


def _motion_difference(src: Item, out: Item, tol_mm: float) -> str | None:
    """What differs between two motions of the same kind (their state aside)."""
    s, o = src.command, out.command
    scale = (_mm(src.units), _mm(out.units), tol_mm)
    straight = canon.StraightFeed | canon.StraightTraverse | canon.StraightProbe
    if isinstance(s, straight) and isinstance(o, straight):
        k_src, k_out, tol = scale
        if (
            abs(s.x * k_src - o.x * k_out) <= tol
            and abs(s.y * k_src - o.y * k_out) <= tol
            and abs(s.z * k_src - o.z * k_out) <= tol
            and abs(s.a - o.a) <= EXACT
            and abs(s.b - o.b) <= EXACT
            and abs(s.c - o.c) <= EXACT
        ):
            return None  # the common case, without building the argument lists
        a = (s.x, s.y, s.z, s.a, s.b, s.c)
        b = (o.x, o.y, o.z, o.a, o.b, o.c)
        return _values_differ(s.NAME, a, b, 3, scale)
    if isinstance(s, canon.ArcFeed) and isinstance(o, canon.ArcFeed):
        if s.rotation != o.rotation:
            return f"ARC_FEED turns {o.rotation} where the source has {s.rotation}"
        a = (s.first_end, s.second_end, s.first_axis, s.second_axis, s.axis_end_point)
        b = (o.first_end, o.second_end, o.first_axis, o.second_axis, o.axis_end_point)
        return _values_differ(s.NAME, a + (s.a, s.b, s.c), b + (o.a, o.b, o.c), 5, scale)
    if isinstance(s, canon.EllipseFeed) and isinstance(o, canon.EllipseFeed):
        if s.rotation != o.rotation:
            return f"ELLIPSE_FEED turns {o.rotation} where the source has {s.rotation}"
        a = (s.major, s.minor, s.first_end, s.second_end, s.first_axis, s.second_axis)
        b = (o.major, o.minor, o.first_end, o.second_end, o.first_axis, o.second_axis)
        return _values_differ(
            s.NAME,
            a + (s.axis_end_point, s.angle_to_first),
            b + (o.axis_end_point, o.angle_to_first),
            7,
            scale,
        )
    if isinstance(s, canon.NurbsFeed) and isinstance(o, canon.NurbsFeed):
        if len(s.points) != len(o.points):
            return f"NURBS_FEED with {len(o.points)} control points, the source {len(s.points)}"
        if s.elided or o.elided:
            return None
        if s.order != o.order or len(s.knots) != len(o.knots):
            return f"NURBS_FEED of order {o.order} where the source has order {s.order}"
        for p, q in zip(s.points, o.points, strict=True):
            diff = _values_differ(s.NAME, p, q, 2, scale)
            if diff is not None:
                return diff
        return _values_differ(s.NAME, s.knots, o.knots, 0, scale)
    if isinstance(s, canon.Dwell) and isinstance(o, canon.Dwell):
        return _values_differ(s.NAME, (s.seconds,), (o.seconds,), 0, scale)
    return None


class _Units:
    """The one-to-one map of source length units to output length units."""

    def __init__(self) -> None:
        self.pairs: dict[canon.Units | None, canon.Units | None] = {}

    def differs(self, src: canon.Units | None, out: canon.Units | None) -> str | None:
        known = self.pairs.setdefault(src, out)
        if known != out or list(self.pairs.values()).count(out) > 1:
            return f"length units {_unit_name(out)} where the source has {_unit_name(src)}"
        return None


def _unit_name(units: canon.Units | None) -> str:
    return "unset" if units is None else units.value


def _state_difference(src: Item, out: Item, tol_mm: float, piece: bool = False) -> str | None:
    """What differs in the state two motions see (:func:`_seen_difference`), or None."""
    if src.seen == out.seen:
        return None  # the common case: the very same state
    return _seen_difference(src, out, tol_mm, piece)


def _seen_difference(src: Item, out: Item, tol_mm: float, piece: bool) -> str | None:
    """What differs in the state two motions see. The plane is compared where it gives the
    motion its meaning (a curve on either side): a straight move is the same in any plane,
    and a language without planes (Sandia) writes every move in XY. A ``piece`` of a
    replaced curve is checked against the curve in space, whatever plane it is in."""
    a, b = src.seen, out.seen
    assert a is not None and b is not None
    if abs(a.feed - b.feed) > max(tol_mm, 1e-4 * abs(a.feed)):
        k = _mm(src.units)
        return f"feed rate {b.feed / k:g} where the source has {a.feed / k:g}"
    for name in ("speed", "direction", "tool", "mist", "flood", "plane"):
        x, y = getattr(a, name), getattr(b, name)
        if name == "speed" and abs(x - y) <= EXACT:
            continue
        curve = isinstance(src.command, _CURVES) or isinstance(out.command, _CURVES)
        if name == "plane" and (piece or not curve):
            continue
        if x != y:
            show = [v.value if hasattr(v, "value") else v for v in (x, y)]
            word = {"speed": "spindle speed", "direction": "spindle direction"}.get(name, name)
            return f"{word} {show[1]} where the source has {show[0]}"
    return None


def _event_difference(src: canon.Command, out: canon.Command) -> str | None:
    if isinstance(src, canon.Message) and isinstance(out, canon.Message):
        same = src.text.strip() == out.text.strip()
    else:
        same = src.to_text() == out.to_text()
    return None if same else f"{out.to_text()} where the source has {src.to_text()}"


class _Curve:
    """A source curve that the output replaced by pieces: where a piece end lies on it."""

    def __init__(self, item: Item) -> None:
        self.item = item
        self.progress = 0.0  # along the curve, 0..1
        cmd = item.command
        seen = item.seen
        assert seen is not None
        self.axes = _AXES[seen.plane]
        i, j, n = self.axes
        k = _mm(item.units)
        self.start = item.start
        self.end = item.end
        self.polyline: list[tuple[float, float, float]] | None = None
        if isinstance(cmd, canon.ArcFeed):
            ci, cj = cmd.first_axis * k, cmd.second_axis * k
            self.centre = (ci, cj)
            t0 = math.atan2(self.start[j] - cj, self.start[i] - ci)
            t1 = math.atan2(self.end[j] - cj, self.end[i] - ci)
            self.theta0 = t0
            self.sweep = arc_sweep(t0, t1, cmd.rotation)
            self.r0 = math.hypot(self.start[i] - ci, self.start[j] - cj)
            self.r1 = math.hypot(self.end[i] - ci, self.end[j] - cj)
            self.turns = max(1, abs(cmd.rotation))
        else:
            self.polyline = _sample(cmd, item, self.axes)
            self.turns = 1

    def locate(
        self, point: tuple[float, float, float], tol: float, advance: float = 0.0
    ) -> float | None:
        """Progress (0..1) of ``point`` along the curve past the last one, or None when it
        is farther than ``tol`` from the curve. ``advance``: on an arc, the angle (radians)
        the piece ending at ``point`` must have turned at least (a full circle's end is on
        its start: without it, the start would be found again)."""
        if self.polyline is None:
            return self._locate_arc(point, tol, advance)
        best: tuple[float, float] | None = None
        line = self.polyline
        last = len(line) - 1
        first = int(self.progress * last)
        for index in range(max(first - 1, 0), last):
            dist, frac = _segment_distance(point, line[index], line[index + 1])
            if dist <= tol:
                at = (index + frac) / last
                if at >= self.progress - 1e-9 and (best is None or at < best[0]):
                    best = (at, dist)
        return None if best is None else best[0]

    def _locate_arc(
        self, point: tuple[float, float, float], tol: float, advance: float = 0.0
    ) -> float | None:
        i, j, n = self.axes
        ci, cj = self.centre
        sweep = abs(self.sweep)
        if sweep == 0.0:
            return None
        sign = 1.0 if self.sweep > 0 else -1.0
        radius = math.hypot(point[i] - ci, point[j] - cj)
        base = (sign * (math.atan2(point[j] - cj, point[i] - ci) - self.theta0)) % TWO_PI
        slack = tol / max(min(self.r0, self.r1), tol) + 1e-9
        # the angle is known modulo a turn: take the first turn that fits past the last piece
        for turn in range(-1, int(sweep / TWO_PI) + 2):
            angle = base + turn * TWO_PI
            if angle < self.progress * sweep + advance - slack or angle > sweep + slack:
                continue
            frac = min(max(angle / sweep, 0.0), 1.0)
            expect_r = self.r0 + (self.r1 - self.r0) * frac
            expect_n = self.start[n] + (self.end[n] - self.start[n]) * frac
            if math.hypot(radius - expect_r, point[n] - expect_n) <= tol:
                return frac
        return None


def _segment_distance(
    p: tuple[float, float, float], a: tuple[float, float, float], b: tuple[float, float, float]
) -> tuple[float, float]:
    """Distance of ``p`` from segment ``ab`` and the fraction of ``ab`` at its foot."""
    d = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    length2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    t = 0.0
    if length2 > 0.0:
        t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / length2
        t = min(max(t, 0.0), 1.0)
    q = (a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2])
    return math.dist(p, q), t


def _sample(
    cmd: canon.Command, item: Item, axes: tuple[int, int, int]
) -> list[tuple[float, float, float]]:
    """A dense polyline of a NURBS or ellipse (in mm), start to end."""
    i, j, n = axes
    k = _mm(item.units)
    flat: list[tuple[float, float, float]] = []
    if isinstance(cmd, canon.NurbsFeed):
        if cmd.elided or not cmd.points:
            return [item.start, item.end]
        spans = max(len(cmd.points) - cmd.order + 1, 1)
        count = SAMPLES * spans
        lo, hi = cmd.knots[cmd.order - 1], cmd.knots[len(cmd.points)]
        for step in range(count + 1):
            u, v = _nurbs_point(cmd, lo + (hi - lo) * step / count)
            flat.append(_place(axes, u * k, v * k, item.start[n]))
        return flat
    assert isinstance(cmd, canon.EllipseFeed)
    ci, cj = cmd.first_axis * k, cmd.second_axis * k
    ca, sa = math.cos(cmd.angle_to_first), math.sin(cmd.angle_to_first)
    ra, rb = cmd.major * k / 2.0, cmd.minor * k / 2.0

    def param(p: tuple[float, float, float]) -> float:
        du, dv = p[i] - ci, p[j] - cj
        return math.atan2((-sa * du + ca * dv) / rb, (ca * du + sa * dv) / ra)

    t0, t1 = param(item.start), param(item.end)
    sweep = arc_sweep(t0, t1, cmd.rotation)
    count = SAMPLES * max(4, int(abs(sweep) * 8))
    for step in range(count + 1):
        f = step / count
        t = t0 + sweep * f
        du, dv = ra * math.cos(t), rb * math.sin(t)
        normal = item.start[n] + (item.end[n] - item.start[n]) * f
        flat.append(_place(axes, ci + ca * du - sa * dv, cj + sa * du + ca * dv, normal))
    return flat


def _place(axes: tuple[int, int, int], u: float, v: float, w: float) -> tuple[float, float, float]:
    point = [0.0, 0.0, 0.0]
    point[axes[0]], point[axes[1]], point[axes[2]] = u, v, w
    return (point[0], point[1], point[2])


def _nurbs_point(cmd: canon.NurbsFeed, u: float) -> tuple[float, float]:
    """The rational B-spline at parameter ``u`` (de Boor on homogeneous points)."""
    p = cmd.order - 1
    knots = cmd.knots
    m = len(cmd.points)
    span = p
    while span < m - 1 and knots[span + 1] <= u:
        span += 1
    d = [(pt[0] * pt[2], pt[1] * pt[2], pt[2]) for pt in cmd.points[span - p : span + 1]]
    for r in range(1, p + 1):
        for jj in range(p, r - 1, -1):
            left, right = knots[jj + span - p], knots[jj + 1 + span - r]
            a = 0.0 if right == left else (u - left) / (right - left)
            (x0, y0, w0), (x1, y1, w1) = d[jj - 1], d[jj]
            d[jj] = ((1 - a) * x0 + a * x1, (1 - a) * y0 + a * y1, (1 - a) * w0 + a * w1)
    x, y, w = d[p]
    return x / w, y / w


def first_difference(
    source: Iterable[canon.Command],
    output: Iterable[canon.Command],
    tolerance: float,
    resolution: Mapping[canon.Units | None, float] | None = None,
) -> Difference | None:
    """The first difference between a source stream and the re-reading of its conversion,
    or None when they are equivalent. ``tolerance`` (output length units) bounds how far a
    piece replacing a source curve may end from it; ``resolution`` (per output length unit:
    half the last written decimal, in that unit) widens the 1e-4 rule where the output's
    numbers are rounded more coarsely."""
    rounding = resolution or {}
    units = _Units()
    out_items = items(output)
    out = next(out_items, None)
    for src in items(source):
        where = src.command.source
        if out is None:
            return Difference(where, f"the output ends before this {src.command.NAME}")
        s, o = src.command, out.command
        if src.seen is None or out.seen is None:
            if src.seen is not None or out.seen is not None or s.NAME != o.NAME:
                return Difference(where, f"{o.NAME} where the source has {s.NAME}")
            diff = _event_difference(s, o)
            if diff is not None:
                return Difference(where, diff)
            out = next(out_items, None)
            continue
        written = rounding.get(out.units, 0.0) * _mm(out.units) * (1 + 1e-6)
        exact_mm = max(EXACT * _mm(src.units), written + 1e-9)
        split = (
            isinstance(s, canon.ArcFeed)
            and isinstance(o, canon.ArcFeed)
            and s.rotation != o.rotation
        )
        if s.NAME == o.NAME and not split:
            diff = units.differs(src.units, out.units) or _state_difference(src, out, exact_mm)
            if diff is not None:
                return Difference(where, f"{s.NAME} sees {diff}")
            diff = _motion_difference(src, out, exact_mm)
            if diff is not None:
                return Difference(where, diff)
            out = next(out_items, None)
            continue
        if not isinstance(s, _CURVES) or not isinstance(o, canon.StraightFeed | canon.ArcFeed):
            return Difference(where, f"{o.NAME} where the source has {s.NAME}")
        out, diff = _cover(
            src, out, out_items, units, tolerance * _mm(out.units) + exact_mm, exact_mm
        )
        if diff is not None:
            return Difference(where, diff)
    if out is not None:
        return Difference(out.command.source, f"the output has more: {out.command.NAME}")
    return None


def _arc_middle(item: Item) -> tuple[float, float, float]:
    """The point half way along an ARC_FEED motion (mm)."""
    arc = _Curve(item)
    i, j, n = arc.axes
    ci, cj = arc.centre
    angle = arc.theta0 + arc.sweep / 2
    radius = (arc.r0 + arc.r1) / 2
    point = [0.0, 0.0, 0.0]
    point[i] = ci + radius * math.cos(angle)
    point[j] = cj + radius * math.sin(angle)
    point[n] = (item.start[n] + item.end[n]) / 2
    return (point[0], point[1], point[2])


def _cover(
    src: Item,
    out: Item | None,
    rest: Iterator[Item],
    units: _Units,
    tol_mm: float,
    exact_mm: float,
) -> tuple[Item | None, str | None]:
    """Consume the output pieces that replace the source curve ``src``: (the next output
    item, None) when they cover it in order within ``tol_mm``, else (_, what differs)."""
    curve = _Curve(src)
    name = src.command.NAME
    pieces = 0
    while out is not None and isinstance(out.command, canon.StraightFeed | canon.ArcFeed):
        diff = units.differs(src.units, out.units) or _state_difference(
            src, out, exact_mm, piece=True
        )
        if diff is not None:
            return out, f"a piece of this {name} sees {diff}"
        # an arc piece of more than half a turn has gone past the far side of the source
        # arc's circle: its end is found on a later turn than the last piece's
        advance = 0.0
        if isinstance(out.command, canon.ArcFeed):
            advance = max(0.0, abs(_Curve(out).sweep) - math.pi)
        at = curve.locate(out.end, tol_mm, advance)
        pieces += 1
        if at is None:
            k = _mm(src.units)
            shown = ", ".join(f"{v / k:.4f}" for v in out.end)
            return out, f"piece {pieces} of this {name} ends off the curve at ({shown})"
        if isinstance(out.command, canon.ArcFeed):
            # an arc piece ending on the curve may still leave it between (the other way
            # round a circle: G02 for G03): its middle must lie on the curve too
            middle = _arc_middle(out)
            if curve.locate(middle, tol_mm) is None:
                k = _mm(src.units)
                shown = ", ".join(f"{v / k:.4f}" for v in middle)
                return out, f"piece {pieces} of this {name} leaves the curve at ({shown})"
        curve.progress = at
        end = out.end
        out = next(rest, None)
        closed = math.dist(src.start, src.end) <= tol_mm
        # a closed curve ends on its start: its end is reached in its last half turn
        last_half = 1.0 - 0.5 / curve.turns
        if math.dist(end, src.end) <= tol_mm and (at > last_half or not closed):
            return out, None
    return out, f"the output's pieces stop before the end of this {name}"


# ---------------------------------------------------------------- the array fast path

_ARC = 3  # ARC_FEED, beside the straight moves' 0 1 and SET_FEED_RATE's 2


@dataclass(frozen=True, slots=True)
class Moves:
    """A run of plain moves and feed changes as arrays (a reader's run of plain lines):
    ``kind[i]`` is 0 (STRAIGHT_TRAVERSE), 1 (STRAIGHT_FEED), 2 (SET_FEED_RATE) or 3
    (ARC_FEED), ``position[i]`` the x y z a b c after it, ``feed[i]`` the rate in force,
    ``line[i]`` its source line in ``file``; ``arc[i]`` (None when the run has no arcs) an
    arc's in-plane end, centre, turns and end on the normal axis, as ARC_FEED takes them
    (its end is its ``position``'s x y z in the plane's order: :func:`equivalent` reads an
    arc's end there)."""

    kind: np.ndarray
    position: np.ndarray
    feed: np.ndarray
    line: np.ndarray
    file: str | None
    arc: np.ndarray | None = None

    def commands(self) -> list[canon.Command]:
        """The events as IR command objects, each with its source line."""
        out: list[canon.Command] = []
        file = self.file
        arcs = self.arc.tolist() if self.arc is not None else [()] * len(self.kind)
        for k, pos, rate, ln, arc in zip(
            self.kind.tolist(),
            self.position.tolist(),
            self.feed.tolist(),
            self.line.tolist(),
            arcs,
            strict=True,
        ):
            src = Location(file, ln, 1)
            if k == 0:
                out.append(canon.StraightTraverse(*pos, source=src))
            elif k == 1:
                out.append(canon.StraightFeed(*pos, source=src))
            elif k == _ARC:
                e1, e2, c1, c2, turns, normal = arc
                out.append(canon.ArcFeed(e1, e2, c1, c2, int(turns), normal, *pos[3:], source=src))
            else:
                out.append(canon.SetFeedRate(rate, source=src))
        return out


def expanded(stream: Iterable[canon.Command | Moves]) -> Iterator[canon.Command]:
    """A stream with its :class:`Moves` as command objects."""
    for item in stream:
        if isinstance(item, Moves):
            yield from item.commands()
        else:
            yield item


#: the state a motion sees, as the fast path interns it
_State = tuple[float, canon.Direction, int | str, bool, bool, canon.Plane, canon.Units | None]


def _restated(c: object, t: type, key: _State) -> _State | None:
    """The state ``key`` (spindle speed and direction, tool, mist, flood, plane, length
    units: what the motions after it see) once the non-motion command ``c`` of type ``t``
    has run, or None when ``c`` does not set any of it. One rule for both sides of the
    comparison (:class:`_Table`, kernel.ir.chords)."""
    speed, direction, tool, mist, flood, plane, units = key
    if t is canon.SetSpindleSpeed:
        speed = cast(canon.SetSpindleSpeed, c).speed
    elif t is canon.StartSpindleClockwise:
        direction = canon.Direction.CLOCKWISE
    elif t is canon.StartSpindleCounterclockwise:
        direction = canon.Direction.COUNTERCLOCKWISE
    elif t is canon.StopSpindleTurning:
        direction = canon.Direction.STOPPED
    elif t is canon.MistOn or t is canon.MistOff:
        mist = t is canon.MistOn
    elif t is canon.FloodOn or t is canon.FloodOff:
        flood = t is canon.FloodOn
    elif t is canon.UseLengthUnits:
        units = cast(canon.UseLengthUnits, c).units
    elif t is canon.SelectPlane:
        plane = cast(canon.SelectPlane, c).plane
    elif isinstance(c, canon.ChangeTool):
        tool = c.name or c.slot
    else:
        return None
    return (speed, direction, tool, mist, flood, plane, units)


_SMALL = 256  # Moves of fewer events join the rows as Python lists
_MOTION_KINDS = (
    canon.StraightTraverse,
    canon.StraightFeed,
    canon.ArcFeed,
    canon.StraightProbe,
    canon.NurbsFeed,
    canon.EllipseFeed,
    canon.Dwell,
)


#: a block of motion rows as the fast path compares them: kind, the x y z a b c after
#: each motion, the feed rate in force, and the arcs' centre and turns (None: no arc)
_Block = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]


def _move_rows(run: Moves) -> _Block:
    """A run's motions as :class:`_Table` takes them, its feed changes left out (copied
    only where there are some): kind, position (an arc's is its end), feed rate in force,
    and the arcs' centre and turns."""
    kind, values, feed = run.kind, run.position, run.feed
    arcs = None
    if run.arc is not None:
        arc = kind == _ARC
        if arc.any():
            arcs = np.compress(arc, run.arc, axis=0)[:, 2:5]  # (boolean indexing is slower)
    motion = kind != 2
    if not motion.all():
        kind, values, feed = kind[motion], values[motion], feed[motion]
    return kind, values, feed, arcs


class _Kept:
    """The source's motion rows, kept block by block (:class:`_Table`'s sink)."""

    def __init__(self) -> None:
        self.blocks: list[_Block] = []
        self.rows = 0

    def add(self, block: _Block) -> bool:
        self.blocks.append(block)
        self.rows += len(block[0])
        return True


class _Compared:
    """The output's motion rows compared with the source's (:class:`_Kept`) as they come,
    nothing kept: each must be of the same kind (an arc of the same turns), its lengths and
    centre within the source row's ``tol`` (mm; ``mm`` its mm per unit), its A B C within
    :data:`EXACT`, its feed rate within ``tol`` or 1e-4 of it. ``mm`` and ``tol`` are
    numbers, or arrays over the source's rows where its length units change. ``add`` says
    False at the first block that differs (:class:`_Table`'s sink)."""

    def __init__(self, src: _Kept, mm: float | np.ndarray, tol: float | np.ndarray) -> None:
        self.src = src.blocks
        self.mm, self.tol = mm, tol
        self.rows = 0  # rows compared
        self.block = 0  # the source block holding the next row
        self.offset = 0  # the next row's place in it
        self.arcs = 0  # the arcs of that block before it
        if isinstance(mm, float) and isinstance(tol, float):
            # a position's x y z in mm and a b c; an arc's centre in mm and its turns
            self.flat = (
                _Bounds((mm, mm, mm, 1.0, 1.0, 1.0), (tol, tol, tol, EXACT, EXACT, EXACT)),
                _Bounds((mm, mm, 1.0), (tol, tol, 0.0)),
            )

    def add(self, block: _Block) -> bool:
        kind, values, feed, arcs = block
        done = arcs_done = 0
        while done < len(kind):
            if self.block == len(self.src):
                return False  # the output has more motions
            s_kind, s_values, s_feed, s_arcs = self.src[self.block]
            lo = self.offset
            m = min(len(kind) - done, len(s_kind) - lo)
            part = kind[done : done + m]
            if not np.array_equal(s_kind[lo : lo + m], part):
                return False
            n_arcs = int(np.count_nonzero(part == _ARC))
            a_arcs = b_arcs = None
            if n_arcs:
                if s_arcs is None or arcs is None:
                    return False  # arcs without their centres: not this path's to compare
                a_arcs = s_arcs[self.arcs : self.arcs + n_arcs]
                b_arcs = arcs[arcs_done : arcs_done + n_arcs]
            if not self._same(
                part,
                (s_values[lo : lo + m], values[done : done + m]),
                (s_feed[lo : lo + m], feed[done : done + m]),
                (a_arcs, b_arcs),
            ):
                return False
            done += m
            arcs_done += n_arcs
            self.rows += m
            self.offset += m
            self.arcs += n_arcs
            if self.offset == len(s_kind):
                self.block, self.offset, self.arcs = self.block + 1, 0, 0
        return True

    def _same(
        self,
        kind: np.ndarray,
        values: tuple[np.ndarray, np.ndarray],
        feeds: tuple[np.ndarray, np.ndarray],
        arcs: tuple[np.ndarray | None, np.ndarray | None],
    ) -> bool:
        """The next rows (source, output) the same: positions, feed rates, arcs."""
        mm, tol = self.mm, self.tol
        if isinstance(mm, np.ndarray) and isinstance(tol, np.ndarray):
            mm = mm[self.rows : self.rows + len(kind)]
            tol = tol[self.rows : self.rows + len(kind)]
            if not _within_rows(np.abs(values[0] - values[1]), 3, mm, tol, EXACT):
                return False
            if arcs[0] is not None and arcs[1] is not None:
                on = kind == _ARC
                if not _within_rows(np.abs(arcs[0] - arcs[1]), 2, mm[on], tol[on], 0.0):
                    return False
        else:
            if not self.flat[0].within(np.abs(values[0] - values[1])):
                return False
            if (
                arcs[0] is not None
                and arcs[1] is not None
                and not self.flat[1].within(np.abs(arcs[0] - arcs[1]))
            ):
                return False
        a, b = feeds
        if np.array_equal(a, b):
            return True  # the very same rates (NaN aside: array_equal says they differ)
        rate_a, rate_b = a * mm, b * mm
        return bool((np.abs(rate_a - rate_b) <= np.maximum(tol, 1e-4 * np.abs(rate_a))).all())


def _within_rows(
    diff: np.ndarray, lengths: int, mm: np.ndarray, tol: np.ndarray, limit: float
) -> bool:
    """``diff``'s first ``lengths`` columns times each row's ``mm`` within its ``tol``, the
    other columns within ``limit``."""
    if not (diff[:, :lengths] * mm[:, None] <= tol[:, None]).all():
        return False
    return bool((diff[:, lengths:] <= limit).all())


class _Bounds:
    """A row's scale and limit per column, repeated over flat rows (kept between calls,
    grown when needed): ``diff * scale <= limit`` over the flat contiguous values is the
    per-column rule without strided columns."""

    def __init__(self, scale: tuple[float, ...], limit: tuple[float, ...]) -> None:
        self.row_scale = np.array(scale, dtype=np.float64)
        self.row_limit = np.array(limit, dtype=np.float64)
        self.scale = self.limit = np.zeros(0)

    def within(self, diff: np.ndarray) -> bool:
        """Every row of ``diff`` (absolute differences, a new array) within the bounds."""
        flat = diff.reshape(-1)
        if len(self.scale) < len(flat):
            rows = max(len(diff), 2 * len(self.scale) // len(self.row_scale))
            self.scale = np.tile(self.row_scale, rows)
            self.limit = np.tile(self.row_limit, rows)
        flat *= self.scale[: len(flat)]
        return bool((flat <= self.limit[: len(flat)]).all())


class _Table:
    """One stream's motions, handed to ``sink`` in blocks of rows (:data:`_Block`: kind,
    the six values (ends, or an arc's end and normal end with A B C), the feed rate in
    force, an arc's centre and turns apart); ``runs``, the id of the rest of the state the
    motions see (interned in ``states``, shared by both sides) as (id, motions) runs; and
    the ordered events with the number of motions before each. ``ok`` is False where the
    stream holds what only :func:`first_difference` compares, or where ``sink`` refused a
    block (the output differs from the source)."""

    def __init__(
        self,
        stream: Iterable[canon.Command | Moves],
        states: dict[_State, int],
        sink: _Kept | _Compared,
    ):
        self.ok = True
        state_runs: list[tuple[int, int]] = []  # (state id, motions)
        self.events: list[tuple[int, str]] = []
        moves = 0  # motions so far
        pk: list[int] = []
        pv: list[tuple[float, ...]] = []
        pf: list[float] = []
        pa: list[tuple[float, ...]] = []  # the arcs' centre and turns of the rows in pk
        feed = 0.0
        key: _State = (0.0, canon.Direction.STOPPED, 0, False, False, canon.Plane.XY, None)
        plane = key[5]
        state = states.setdefault(key, len(states))
        run_start = 0  # first motion seeing ``state``

        def flush() -> bool:
            if not pk:
                return True
            block = (
                np.array(pk, dtype=np.int8),
                np.array(pv, dtype=np.float64).reshape(len(pk), 6),
                np.array(pf, dtype=np.float64),
                np.array(pa, dtype=np.float64).reshape(len(pa), 3) if pa else None,
            )
            pk.clear()
            pv.clear()
            pf.clear()
            pa.clear()
            return sink.add(block)

        def restate() -> int:
            nonlocal run_start
            state_runs.append((state, moves - run_start))
            run_start = moves
            return states.setdefault(key, len(states))

        traverse, straight, arc = canon.StraightTraverse, canon.StraightFeed, canon.ArcFeed
        for c in stream:
            t = type(c)
            if t is straight or t is traverse:
                assert isinstance(c, straight | traverse)
                pk.append(1 if t is straight else 0)
                pv.append((c.x, c.y, c.z, c.a, c.b, c.c))
                pf.append(feed)
                moves += 1
            elif t is arc:
                assert isinstance(c, canon.ArcFeed)
                pk.append(_ARC)
                i, j, k = _AXES[plane]  # its end as x y z, as a run's position holds it
                end = [0.0, 0.0, 0.0]
                end[i], end[j], end[k] = c.first_end, c.second_end, c.axis_end_point
                pv.append((end[0], end[1], end[2], c.a, c.b, c.c))
                pf.append(feed)
                pa.append((c.first_axis, c.second_axis, c.rotation))
                moves += 1
            elif t is Moves:
                assert isinstance(c, Moves)
                n = len(c.kind)
                if not n:
                    continue
                block = _move_rows(c)
                count = len(block[0])
                if n < _SMALL:  # as rows: a few list items cost less than three arrays
                    pk.extend(block[0].tolist())
                    pv.extend(map(tuple, block[1].tolist()))
                    pf.extend(block[2].tolist())
                    if block[3] is not None:
                        pa.extend(map(tuple, block[3].tolist()))
                elif count and not (flush() and sink.add(block)):
                    self.ok = False
                    return
                moves += count
                feed = float(c.feed[-1])
            elif isinstance(c, _MOTION_KINDS):
                self.ok = False  # probes, curves, dwells: first_difference's rules
                return
            elif t is canon.SetFeedRate:
                assert isinstance(c, canon.SetFeedRate)
                feed = c.rate
            else:
                new = _restated(c, t, key)
                if new is not None:
                    key, plane = new, new[5]
                    state = restate()
                if isinstance(c, _EVENTS):
                    text = c.text.strip() if isinstance(c, canon.Message) else c.to_text()
                    self.events.append((moves, c.NAME + " " + text))
        if not flush():
            self.ok = False
            return
        state_runs.append((state, moves - run_start))
        self.moves = moves
        self.runs: list[tuple[int, int]] = []  # state_runs, empty ones out, equal ones joined
        for sid, count in state_runs:
            if not count:
                continue
            if self.runs and self.runs[-1][0] == sid:
                self.runs[-1] = (sid, self.runs[-1][1] + count)
            else:
                self.runs.append((sid, count))


def _scales(
    table: _Table, states: dict[_State, int], rounding: Mapping[canon.Units | None, float]
) -> tuple[float | np.ndarray, float | np.ndarray]:
    """The mm per unit and the length tolerance (mm: :data:`EXACT`, or the output's
    rounding where coarser) of the source's motions: numbers where all see the same length
    units, else arrays over them."""
    keys = sorted(states, key=states.__getitem__)
    k = np.array([_mm(key[6]) for key in keys])
    written = np.array([rounding.get(key[6], 0.0) * _mm(key[6]) * (1 + 1e-6) for key in keys])
    exact = np.maximum(EXACT * k, written + 1e-9)
    ids = np.array([sid for sid, _ in table.runs], dtype=np.int64)
    counts = [count for _, count in table.runs]
    if len(set(zip(k[ids].tolist(), exact[ids].tolist(), strict=True))) <= 1:
        first = int(ids[0]) if len(ids) else 0
        return float(k[first]), float(exact[first])
    return np.repeat(k[ids], counts), np.repeat(exact[ids], counts)


def equivalent(
    source: Iterable[canon.Command | Moves],
    output: Iterable[canon.Command | Moves],
    resolution: Mapping[canon.Units | None, float] | None = None,
) -> bool:
    """True when the two streams are equivalent by :func:`first_difference`'s rule, found
    by comparing their motion tables as arrays; False means only that this fast path
    cannot tell (a curve replaced by pieces, a probe, a difference anywhere), and
    :func:`first_difference` must compare and say what differs. Each motion must be of
    the same kind (arcs of the same turns) and see exactly the same state, feed aside;
    that is stricter than the rule, never looser. The source's rows are kept; the
    output's are compared with them block by block as they are read, and the reading
    stops at the first block that differs."""
    states: dict[_State, int] = {}
    kept = _Kept()
    src = _Table(source, states, kept)
    if not src.ok:
        return False
    mm, tol = _scales(src, states, resolution or {})
    compared = _Compared(kept, mm, tol)
    out = _Table(output, states, compared)
    return (
        out.ok and compared.rows == kept.rows and src.events == out.events and src.runs == out.runs
    )
