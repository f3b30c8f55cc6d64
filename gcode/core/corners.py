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

from kernel.diagnostics import Location
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


class CornerFilter:
    """Holds the move of a block that asked for a corner until the next move, and cuts the
    corner then (:func:`cut_corner`)."""

    def __init__(self) -> None:
        self.request: CornerRequest | None = None
        self.held: list[canon.Command] = []  # the asking move, then what came after it

    @property
    def pending(self) -> bool:
        return self.request is not None

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
                if not isinstance(cmd, canon.StraightFeed):
                    raise CornerError(
                        "a chamfer or rounding after a circular move is not read",
                        request.location,
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
        if not isinstance(cmd, canon.StraightFeed):
            what = "a circular move" if isinstance(cmd, canon.ArcFeed) else cmd.NAME
            raise CornerError(
                "a chamfer or rounding needs the next block to be a straight feed in the"
                f" plane; the next block gives {what} first",
                cmd.source or req.location,
            )
        first = self.held[0]
        assert isinstance(first, canon.StraightFeed)
        try:
            cut = cut_corner(req, first, cmd)
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

    def finish(self) -> list[canon.Command]:
        """The program ended: a corner still waiting for its second move is an error, or
        (``lenient``) the move runs as programmed."""
        req = self.request
        if req is not None and not req.lenient:
            raise CornerError(
                "a chamfer or rounding needs a next move to cut the corner with", req.location
            )
        return self._uncut()
