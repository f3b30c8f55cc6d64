"""Chamfers and roundings between two programmed lines (one rule for every reader).

Fanuc and Haas mills write ``G01 X50. ,R5.`` / ``,C3.`` (Fanuc 0i-MF operator's manual,
"Chamfering and corner R"; Haas mill operator's manual, G01 "corner rounding and
chamfering"), the SINUMERIK 840D ``RND=``, ``RNDM=``, ``CHR=`` and ``CHF=`` (840D sl
programming manual, fundamentals: "Chamfer, rounding"). Either asks the control to cut the
corner between this block's move and the next one: a fillet of radius R tangent to both
moves, or a chamfer whose legs (``,C``, ``CHR``) or whose own length (``CHF``) is given.

The readers mark the move that asks (:class:`CornerRequest`) and pass their output through
:class:`CornerFilter`, which holds that move until the next move arrives, then trims both
and puts the fillet (``ARC_FEED``) or chamfer (``STRAIGHT_FEED``) between them. Both moves
must be straight feeds in the selected plane; anything else the controls alarm on, or this
reader does not cut, is a :class:`CornerError` that the reader turns into its own code.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane

#: canonical axis index (x y z a b c) of the plane's first and second axis and its normal
PLANE_AXES: dict[Plane, tuple[int, int, int]] = {
    Plane.XY: (0, 1, 2),
    Plane.XZ: (2, 0, 1),
    Plane.YZ: (1, 2, 0),
}
#: commands that may stand between the two moves (they move nothing and keep the plane)
PASSING = (canon.SetFeedRate, canon.Comment, canon.Message, canon.MachineFunction)
_EPS = 1e-9


class CornerError(ValueError):
    """A corner the control refuses (or this reader does not cut); ``location`` is the
    block that asked for it, or the block that broke the pair."""

    def __init__(self, message: str, location: Location | None) -> None:
        super().__init__(message)
        self.location = location


class OffPlane(CornerError):
    """One of the two moves leaves the plane (the 840D then cuts no corner)."""


@dataclass(frozen=True, slots=True)
class CornerRequest:
    """A block's request: ``kind`` "round" (``size`` the radius), "chamfer" (``size`` the
    leg from the virtual corner) or "chamfer_length" (``size`` the chamfer's own length);
    ``start`` the position (x y z a b c) where the block's move begins; ``shrink``: a
    corner too large for its moves is made smaller (840D) instead of refused (Fanuc);
    ``lenient``: when the next move is a rapid, leaves the plane or never comes, the move
    runs without the corner (840D) instead of an alarm (Fanuc)."""

    kind: str
    size: float
    start: tuple[float, ...]
    plane: Plane
    location: Location
    shrink: bool = False
    lenient: bool = False


def corner_leg(kind: str, size: float, turn: float) -> float:
    """Distance from the virtual corner to where the corner element meets each move, for a
    turn of ``turn`` radians between the two directions (0: straight on)."""
    if kind == "round":
        return size * math.tan(turn / 2.0)
    if kind == "chamfer":
        return size
    return size / (2.0 * math.cos(turn / 2.0))  # chamfer length: 2 d cos(turn / 2)


def cut_corner(
    req: CornerRequest, first: canon.StraightFeed, second: canon.StraightFeed
) -> list[canon.Command]:
    """``first`` ending at the corner element's start, the element (a fillet or a chamfer,
    from the request's block) and ``second`` unchanged (it starts where the element
    ends); a move the corner takes whole is left out. Raises :class:`CornerError` when the
    corner cannot be cut."""
    f, s, n = PLANE_AXES[req.plane]
    p0 = req.start
    p1 = (first.x, first.y, first.z, first.a, first.b, first.c)
    p2 = (second.x, second.y, second.z, second.a, second.b, second.c)
    for k in (n, 3, 4, 5):
        if abs(p1[k] - p0[k]) > _EPS or abs(p2[k] - p1[k]) > _EPS:
            raise OffPlane(
                "a chamfer or rounding joins two moves in the selected plane only; a move"
                " here also moves an axis off the plane",
                req.location,
            )
    d1 = (p1[f] - p0[f], p1[s] - p0[s])
    d2 = (p2[f] - p1[f], p2[s] - p1[s])
    len1, len2 = math.hypot(*d1), math.hypot(*d2)
    if len1 < _EPS or len2 < _EPS:
        raise CornerError("a chamfer or rounding needs two moves of non-zero length", req.location)
    u1 = (d1[0] / len1, d1[1] / len1)
    u2 = (d2[0] / len2, d2[1] / len2)
    cross = u1[0] * u2[1] - u1[1] * u2[0]
    dot = u1[0] * u2[0] + u1[1] * u2[1]
    turn = math.atan2(abs(cross), dot)
    if turn < 1e-9:  # straight on: no corner to cut
        return [first, second]
    if math.pi - turn < 1e-6:
        raise CornerError(
            "the next move goes straight back: there is no corner to cut", req.location
        )
    size = req.size
    leg = corner_leg(req.kind, size, turn)
    room = min(len1, len2)
    if leg > room + 1e-9:
        if not req.shrink:
            raise CornerError(
                f"the {'rounding' if req.kind == 'round' else 'chamfer'} needs {leg:.4f}"
                f" along each move but a move is only {room:.4f} long",
                req.location,
            )
        leg = room
        if req.kind == "round":
            size = leg / math.tan(turn / 2.0)
    t1 = list(p1)
    t2 = list(p1)
    t1[f], t1[s] = p1[f] - leg * u1[0], p1[s] - leg * u1[1]
    t2[f], t2[s] = p1[f] + leg * u2[0], p1[s] + leg * u2[1]
    out: list[canon.Command] = []
    if leg < len1 - 1e-9:  # a first move the corner takes whole leaves no move of its own
        out.append(canon.StraightFeed(*t1, source=first.source))
    if req.kind == "round":
        side = 1.0 if cross > 0 else -1.0  # centre to the left of a left (CCW) turn
        cf = t1[f] - side * size * u1[1]
        cs = t1[s] + side * size * u1[0]
        out.append(
            canon.ArcFeed(t2[f], t2[s], cf, cs, 1 if cross > 0 else -1, t2[n], *t2[3:],
                          source=req.location)
        )  # fmt: skip
    else:
        out.append(canon.StraightFeed(*t2, source=req.location))
    if leg < len2 - 1e-9:
        out.append(second)
    return out


Point = tuple[float, float]


@dataclass(frozen=True, slots=True)
class _Piece:
    """One move in plane coordinates: ``a`` to ``b``, a line (``centre`` None) or a
    circle turning ``turn`` (1 counterclockwise, -1 clockwise) about ``centre``."""

    a: Point
    b: Point
    centre: Point | None = None
    turn: int = 0

    def tangent(self, p: Point) -> Point:
        """Unit direction of travel at ``p`` (a point of the move)."""
        if self.centre is None:
            d = (self.b[0] - self.a[0], self.b[1] - self.a[1])
        else:
            d = (-(p[1] - self.centre[1]) * self.turn, (p[0] - self.centre[0]) * self.turn)
        n = math.hypot(*d)
        return (d[0] / n, d[1] / n)

    def offset(self, side: float, r: float) -> tuple[str, Point, Point | float]:
        """The curve ``r`` to the ``side`` (1 left of travel, -1 right): a line (a point
        and the direction) or a circle (the centre and its radius)."""
        if self.centre is None:
            u = self.tangent(self.a)
            return ("line", (self.a[0] - side * r * u[1], self.a[1] + side * r * u[0]), u)
        rho = math.dist(self.a, self.centre)
        return ("circle", self.centre, rho - side * self.turn * r)  # left of CCW is inward

    def foot(self, q: Point) -> Point:
        """The point of the move's line or circle nearest to ``q``."""
        if self.centre is None:
            u = self.tangent(self.a)
            t = (q[0] - self.a[0]) * u[0] + (q[1] - self.a[1]) * u[1]
            return (self.a[0] + t * u[0], self.a[1] + t * u[1])
        c, rho = self.centre, math.dist(self.a, self.centre)
        d = math.dist(q, c)
        return (c[0] + rho * (q[0] - c[0]) / d, c[1] + rho * (q[1] - c[1]) / d)

    def holds(self, p: Point) -> bool:
        """True when ``p`` (on the line or circle) lies on the move between its ends."""
        if self.centre is None:
            u = self.tangent(self.a)
            t = (p[0] - self.a[0]) * u[0] + (p[1] - self.a[1]) * u[1]
            return -1e-9 <= t <= math.dist(self.a, self.b) + 1e-9
        sweep = self._angle(self.b)
        return self._angle(p) <= sweep + 1e-12 or math.dist(p, self.b) < 1e-9

    def _angle(self, p: Point) -> float:
        """Angle travelled from ``a`` to ``p`` in the move's direction, in [0, 2 pi)."""
        c = self.centre
        assert c is not None
        a0 = math.atan2(self.a[1] - c[1], self.a[0] - c[0])
        a1 = math.atan2(p[1] - c[1], p[0] - c[0])
        return ((a1 - a0) * self.turn) % (2 * math.pi)


def _meet(
    one: tuple[str, Point, Point | float], two: tuple[str, Point, Point | float]
) -> list[Point]:
    """Points common to two lines or circles (``_Piece.offset``'s form)."""
    if one[0] == "circle" and two[0] == "line":
        one, two = two, one
    if one[0] == "line" and two[0] == "line":
        (p, u), (q, v) = (one[1], one[2]), (two[1], two[2])
        assert isinstance(u, tuple) and isinstance(v, tuple)
        den = u[0] * v[1] - u[1] * v[0]
        if abs(den) < 1e-12:
            return []
        t = ((q[0] - p[0]) * v[1] - (q[1] - p[1]) * v[0]) / den
        return [(p[0] + t * u[0], p[1] + t * u[1])]
    if one[0] == "line":
        p, u = one[1], one[2]
        c, r = two[1], two[2]
        assert isinstance(u, tuple) and isinstance(r, float)
        w = (p[0] - c[0], p[1] - c[1])
        b = w[0] * u[0] + w[1] * u[1]
        disc = b * b - (w[0] ** 2 + w[1] ** 2 - r * r)
        if disc < 0 or r <= 0:
            return []
        root = math.sqrt(disc)
        return [(p[0] + t * u[0], p[1] + t * u[1]) for t in (-b - root, -b + root)]
    c1, r1, c2, r2 = one[1], one[2], two[1], two[2]
    assert isinstance(r1, float) and isinstance(r2, float)
    d = math.dist(c1, c2)
    if r1 <= 0 or r2 <= 0 or d < 1e-12 or d > r1 + r2 or d < abs(r1 - r2):
        return []
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    m = (c1[0] + a * (c2[0] - c1[0]) / d, c1[1] + a * (c2[1] - c1[1]) / d)
    off = (-(c2[1] - c1[1]) * h / d, (c2[0] - c1[0]) * h / d)
    return [(m[0] + off[0], m[1] + off[1]), (m[0] - off[0], m[1] - off[1])]


def _piece(cmd: canon.StraightFeed | canon.ArcFeed, start: Point, plane: Plane) -> _Piece:
    f, s, _ = PLANE_AXES[plane]
    if isinstance(cmd, canon.ArcFeed):
        end = (cmd.first_end, cmd.second_end)
        return _Piece(start, end, (cmd.first_axis, cmd.second_axis), 1 if cmd.rotation > 0 else -1)
    p = (cmd.x, cmd.y, cmd.z)
    return _Piece(start, (p[f], p[s]))


def _full(cmd: canon.StraightFeed | canon.ArcFeed, plane: Plane) -> tuple[float, ...]:
    """The move's end as x y z a b c."""
    if isinstance(cmd, canon.StraightFeed):
        return (cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c)
    f, s, n = PLANE_AXES[plane]
    out = [0.0] * 3
    out[f], out[s], out[n] = cmd.first_end, cmd.second_end, cmd.axis_end_point
    return (*out, cmd.a, cmd.b, cmd.c)


def round_with_arcs(
    req: CornerRequest,
    first: canon.StraightFeed | canon.ArcFeed,
    second: canon.StraightFeed | canon.ArcFeed,
) -> list[canon.Command]:
    """:func:`cut_corner` for a rounding next to a circle (line-arc, arc-line, arc-arc):
    the fillet's centre is where the curves R inside both moves meet (the one nearest the
    corner), its ends the feet of the perpendiculars on the moves (on a circle: along the
    radius through the centre). A circle keeps its centre and direction; the first move
    ends at the fillet, the second (unchanged) starts there. A corner whose fillet does not
    fit on both moves is refused, also where the 840D would shrink it."""
    f, s, n = PLANE_AXES[req.plane]
    p0 = req.start
    p1, p2 = _full(first, req.plane), _full(second, req.plane)
    for k in (n, 3, 4, 5):
        if abs(p1[k] - p0[k]) > _EPS or abs(p2[k] - p1[k]) > _EPS:
            raise OffPlane(
                "a chamfer or rounding joins two moves in the selected plane only; a move"
                " here also moves an axis off the plane",
                req.location,
            )
    for cmd in (first, second):
        if isinstance(cmd, canon.ArcFeed) and abs(cmd.rotation) != 1:
            raise CornerError(
                "a rounding next to a circle of several turns is not read", req.location
            )
    corner = (p1[f], p1[s])
    one = _piece(first, (p0[f], p0[s]), req.plane)
    two = _piece(second, corner, req.plane)
    if math.dist(one.a, one.b) < _EPS or math.dist(two.a, two.b) < _EPS:
        raise CornerError("a rounding next to a full circle is not read", req.location)
    u1, u2 = one.tangent(corner), two.tangent(corner)
    cross = u1[0] * u2[1] - u1[1] * u2[0]
    dot = u1[0] * u2[0] + u1[1] * u2[1]
    if abs(cross) < 1e-9 and dot > 0:  # tangent: no corner to cut
        return [first, second]
    if abs(cross) < 1e-9:
        raise CornerError(
            "the next move goes straight back: there is no corner to cut", req.location
        )
    side = 1.0 if cross > 0 else -1.0
    r = req.size
    found = [
        c
        for c in _meet(one.offset(side, r), two.offset(side, r))
        if one.holds(one.foot(c)) and two.holds(two.foot(c))
    ]
    if not found:
        raise CornerError(
            f"a rounding of radius {r:.4f} does not fit between this move and the next",
            req.location,
        )
    centre = min(found, key=lambda c: math.dist(c, corner))
    t1, t2 = one.foot(centre), two.foot(centre)
    out: list[canon.Command] = []
    if math.dist(t1, one.a) > 1e-9:
        if isinstance(first, canon.StraightFeed):
            e = list(p1)
            e[f], e[s] = t1
            out.append(canon.StraightFeed(*e, source=first.source))
        else:
            out.append(
                canon.ArcFeed(t1[0], t1[1], first.first_axis, first.second_axis, first.rotation,
                              first.axis_end_point, first.a, first.b, first.c, source=first.source)
            )  # fmt: skip
    out.append(
        canon.ArcFeed(t2[0], t2[1], centre[0], centre[1], 1 if cross > 0 else -1, p1[n],
                      *p1[3:], source=req.location)
    )  # fmt: skip
    if math.dist(t2, two.b) > 1e-9:
        out.append(second)
    return out


class CornerFilter:
    """Holds the move of a block that asked for a corner until the next move, and cuts the
    corner then (:func:`cut_corner`)."""

    def __init__(self) -> None:
        self.request: CornerRequest | None = None
        self.held: list[canon.Command] = []  # the asking move, then what came after it

    @property
    def pending(self) -> bool:
        return self.request is not None

    def released(
        self, out: list[canon.Command], request: CornerRequest | None, code: str
    ) -> list[canon.Command]:
        """A reader's block output ``out`` (its ``request``, if it asked for a corner)
        through :meth:`push`; a corner that cannot be cut is a Diagnostic with the reader's
        ``code``, and ``out`` is then emptied (its commands follow a move never written)."""
        if request is None and self.request is None:
            return out
        try:
            return self.push(out, request)
        except CornerError as exc:
            out.clear()
            raise Diagnostic(code, str(exc), exc.location) from None

    def push(
        self, commands: Iterable[canon.Command], request: CornerRequest | None = None
    ) -> list[canon.Command]:
        """The commands of one block (``request``: the block asked for a corner after its
        last move), with what may be released now."""
        out: list[canon.Command] = []
        cmds = list(commands)
        ask = -1
        if request is not None:
            moves = [
                i for i, c in enumerate(cmds) if isinstance(c, canon.StraightFeed | canon.ArcFeed)
            ]
            if not moves:
                raise CornerError(
                    "a chamfer or rounding belongs to a block that moves", request.location
                )
            ask = moves[-1]
        for i, cmd in enumerate(cmds):
            if self.request is not None:
                if isinstance(cmd, PASSING):
                    self.held.append(cmd)
                    continue
                released = self._cut(cmd)
                kept = bool(released) and released[-1] is cmd
                out += released[:-1] if kept else released
                if not kept:  # the corner took the whole move
                    if i == ask:
                        assert request is not None
                        raise CornerError(
                            "the corner before this block takes its whole move, which leaves"
                            " none for this block's own chamfer or rounding",
                            request.location,
                        )
                    continue
            if i == ask:
                assert request is not None
                if isinstance(cmd, canon.ArcFeed) and request.kind != "round":
                    raise CornerError(
                        "a chamfer after a circular move is not read", request.location
                    )
                self.request, self.held = request, [cmd]
            else:
                out.append(cmd)
        return out

    def _cut(self, cmd: canon.Command) -> list[canon.Command]:
        """The held move trimmed, the corner element, what came between and ``cmd`` (the
        second move, unchanged; left out when the corner takes it whole)."""
        req = self.request
        assert req is not None
        if req.lenient and not isinstance(cmd, canon.StraightFeed | canon.ArcFeed):
            return self._uncut(cmd)
        if not isinstance(cmd, canon.StraightFeed | canon.ArcFeed):
            raise CornerError(
                "a chamfer or rounding needs the next block to be a move in the plane; the"
                f" next block gives {cmd.NAME} first",
                cmd.source or req.location,
            )
        first = self.held[0]
        assert isinstance(first, canon.StraightFeed | canon.ArcFeed)
        lines = isinstance(first, canon.StraightFeed) and isinstance(cmd, canon.StraightFeed)
        if not lines and req.kind != "round":
            raise CornerError("a chamfer next to a circular move is not read", req.location)
        try:
            cut = (
                cut_corner(req, first, cmd)
                if isinstance(first, canon.StraightFeed) and isinstance(cmd, canon.StraightFeed)
                else round_with_arcs(req, first, cmd)
            )
            second = [cut.pop()] if cut and cut[-1] is cmd else []
            out = cut + self.held[1:] + second
        except OffPlane:
            if not req.lenient:
                raise
            return self._uncut(cmd)
        self.request, self.held = None, []
        return out

    def _uncut(self, then: canon.Command | None = None) -> list[canon.Command]:
        """The held move and what followed it, as programmed (no corner), and ``then``."""
        out = self.held if then is None else [*self.held, then]
        self.request, self.held = None, []
        return out

    def finish(self, code: str) -> list[canon.Command]:
        """The program ended: a corner still waiting for its second move is a Diagnostic
        with the reader's ``code``, or (``lenient``) the move runs as programmed."""
        req = self.request
        if req is not None and not req.lenient:
            raise Diagnostic(
                code, "a chamfer or rounding needs a next move to cut the corner with", req.location
            )
        return self._uncut()
