"""Plane geometry of LinuxCNC 2.9's lathe cycles G70, G71 and G72 (no interpreter state).

A profile is a list of segments in the XZ plane, each point a complex number ``z + x*1j``
(real part Z, imaginary part X). The first segment is the lead-in from the cycle's start
point to the profile's first point; the others are the profile subroutine's moves, with
fillets (``A``) and chamfers (``C``) as corner segments. The cycles turn the profile so that
X and Z both decrease along it (mirroring, and for G72 a quarter turn), offset it by the
finishing allowance, and then either follow it (G70) or cut it in layers of constant X
(G71/G72), writing moves through a :class:`Moves` that undoes the turn.

The behaviour, including its tolerances and its quirks, is that of LinuxCNC's
``src/emc/rs274ngc/interp_g7x.cc`` as built into the ``rs274`` of Debian's
``linuxcnc-uspace`` 2.9.0 package (the reference the goldens were made with), read and
re-expressed here; ``docs/readers/rs274ngc.md`` says where each rule comes from.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Protocol

#: LinuxCNC's geometric tolerance of the lathe cycles
TOL = 1e-6
#: steps of one profile offset before it is declared stuck (LinuxCNC has no bound)
MAX_OFFSET_STEPS = 10_000
#: layers of one roughing cycle before it is declared stuck (LinuxCNC has no bound)
MAX_LAYERS = 100_000


class ProfileError(Exception):
    """A profile the cycles cannot use; the message is LinuxCNC's (after ``G7X error:``)."""


class NoProgress(ProfileError):
    """A roughing layer that would repeat for ever (rs274 2.9.0 hangs there)."""


class Moves(Protocol):
    """Where a cycle's moves go (points are ``z + x*1j``)."""

    def feed(self, end: complex) -> None:
        """A straight feed move (G1) to ``end``."""
        ...

    def rapid(self, end: complex) -> None:
        """A straight rapid move (G0) to ``end``."""
        ...

    def arc(self, ccw: bool, centre: complex, end: complex) -> None:
        """An arc (G3 when ``ccw`` in the ZX view, else G2) about ``centre`` to ``end``."""
        ...


def _cross(a: complex, b: complex) -> float:
    """The imaginary part of ``conj(a) * b`` (the 2-D cross product)."""
    return (a.conjugate() * b).imag


class Segment(ABC):
    """One straight or circular piece of a profile."""

    finish: float = 0.0

    def __init__(self, start: complex, end: complex) -> None:
        self.start = start
        self.end = end
        self.finish = 0.0

    @abstractmethod
    def copy(self) -> Segment:
        """An independent copy."""

    @abstractmethod
    def crossings(self, x: float) -> list[float]:
        """The Z values where the segment meets the line X = ``x``."""

    @abstractmethod
    def offset(self, distance: float) -> None:
        """Move the segment sideways by ``distance`` (positive to the left of its travel)."""

    @abstractmethod
    def size(self) -> float:
        """A length scale; segments below 1e-3 are dropped."""

    def monotonic(self) -> bool:
        """Z does not increase along the segment (beyond 1e-3)."""
        return (self.end - self.start).real <= 1e-3

    @abstractmethod
    def draw(self, out: Moves) -> None:
        """The whole segment as one move (G70)."""

    @abstractmethod
    def climb(self, at: complex, out: Moves) -> tuple[bool, complex]:
        """Follow the segment up from ``at``; (True: a pocket starts here, where it stopped)."""

    @abstractmethod
    def climb_only(self, at: complex, out: Moves) -> complex:
        """Follow the rising part of the segment above ``at``'s X, skipping pockets."""

    @abstractmethod
    def dive(self, at: complex, x: float, out: Moves, fast: bool) -> tuple[bool, complex]:
        """Follow the segment down from ``at`` to layer ``x`` (a rapid when ``fast``);
        (True: the segment does not descend here, where it stopped)."""

    def mirror_x(self) -> None:
        """Negate X."""
        self.start, self.end = self.start.conjugate(), self.end.conjugate()

    def mirror_z(self) -> None:
        """Negate Z."""
        self.start, self.end = -self.start.conjugate(), -self.end.conjugate()

    def turn(self) -> None:
        """A quarter turn: (z, x) becomes (x, -z)."""
        self.start, self.end = -self.start * 1j, -self.end * 1j

    def shift(self, d: complex) -> None:
        """Move by ``d``."""
        self.start += d
        self.end += d

    def finish_corner(self, prev: Segment, nxt: Segment) -> None:
        """Fillets and chamfers fit themselves between their neighbours; others stay."""
        return None

    def _corner(self, prev: Segment, nxt: Segment) -> complex:
        """Fit a corner of size ``finish`` between ``prev`` and ``nxt``; its centre."""
        p, n = prev.copy(), nxt.copy()
        p.offset(self.finish)
        n.offset(self.finish)
        if (p.end - n.start).real > 1e-2:
            self.finish = -self.finish
            p, n = prev.copy(), nxt.copy()
            p.offset(self.finish)
            n.offset(self.finish)
        if (p.end - n.start).real > 1e-2:
            raise ProfileError(f"Corner finish failed at {_show(prev.end)}")
        join(p, n)
        centre = (p.end + n.start) / 2.0
        p.offset(-self.finish)
        n.offset(-self.finish)
        self.start = prev.end = p.end
        self.end = nxt.start = n.start
        return centre


def _show(p: complex) -> str:
    """A point as C++'s ``operator<<`` prints a complex: ``(z,x)``."""
    return f"({p.real:g},{p.imag:g})"


class Line(Segment):
    """A straight segment."""

    def copy(self) -> Line:
        c = Line(self.start, self.end)
        c.finish = self.finish
        return c

    def crossings(self, x: float) -> list[float]:
        s, e = self.start, self.end
        if min(s.imag, e.imag) > x + TOL or max(s.imag, e.imag) < x - TOL:
            return []
        if abs((s - e).imag) < TOL:
            return [s.real, e.real]
        return [(x - s.imag) / (e.imag - s.imag) * (e.real - s.real) + s.real]

    def offset(self, distance: float) -> None:
        d = 1j * distance * (self.start - self.end) / abs(self.start - self.end)
        self.start += d
        self.end += d

    def size(self) -> float:
        return abs(self.start - self.end)

    def draw(self, out: Moves) -> None:
        out.feed(self.end)

    def climb(self, at: complex, out: Moves) -> tuple[bool, complex]:
        if self.end.imag + TOL < self.start.imag:
            return True, at
        if abs(at - self.start) > TOL:
            raise ProfileError("How did we get here?")
        out.feed(self.end)
        return False, self.end

    def climb_only(self, at: complex, out: Moves) -> complex:
        if self.end.imag < self.start.imag:
            return at
        found = self.crossings(at.imag)
        if not found:
            return at
        at = complex(found[0], at.imag)
        out.feed(at)
        out.feed(self.end)
        return self.end

    def dive(self, at: complex, x: float, out: Moves, fast: bool) -> tuple[bool, complex]:
        if self.start.imag <= self.end.imag + TOL:
            return True, at
        move = out.rapid if fast else out.feed
        if x < self.end.imag:
            move(self.end)
            return False, self.end
        found = self.crossings(x)
        if not found:
            raise ProfileError("x too large in straight dive")
        to = complex(found[0], x)
        move(to)
        return False, to


class Arc(Segment):
    """A circular segment about ``centre`` (``ccw`` in the ZX view)."""

    def __init__(self, ccw: bool, start: complex, centre: complex, end: complex) -> None:
        super().__init__(start, end)
        self.ccw = ccw
        self.centre = centre

    def copy(self) -> Arc:
        c = Arc(self.ccw, self.start, self.centre, self.end)
        c.finish = self.finish
        return c

    def _on(self, p: complex) -> bool:
        a = _cross(self.start - self.centre, p - self.centre)
        b = _cross(self.end - self.centre, p - self.centre)
        if self.ccw:
            return a >= -TOL and b <= TOL
        return a <= TOL and b >= -TOL

    def crossings(self, x: float) -> list[float]:
        c = self.centre
        r = abs(self.start - c)
        h = -(x - r - c.imag) * (x + r - c.imag)
        if h < -TOL:
            return []
        h = math.sqrt(max(h, 0.0))
        return [z for z in (c.real + h, c.real - h) if self._on(complex(z, x))]

    def offset(self, distance: float) -> None:
        c = self.centre
        r = abs(self.start - c)
        factor = (r + (distance if self.ccw else -distance)) / r
        self.start = factor * (self.start - c) + c
        self.end = factor * (self.end - c) + c

    def size(self) -> float:
        return min(abs(self.start - self.end), abs(self.start - self.centre))

    def monotonic(self) -> bool:
        if self.finish != 0:
            return True
        entry = (self.start - self.centre).imag
        leave = (self.end - self.centre).imag
        dz = (self.end - self.start).real
        if self.ccw:
            return entry >= -1e-3 and leave >= -1e-3 and dz <= -1e-3
        return entry <= 1e-3 and leave <= 1e-3 and dz <= -1e-3

    def draw(self, out: Moves) -> None:
        out.arc(self.ccw, self.centre, self.end)

    def _top(self) -> complex:
        """Where a counter-clockwise arc stops climbing: its end, or its top."""
        c = self.centre
        if self.end.real < c.real:
            return complex(c.real, c.imag + abs(self.start - c))
        return self.end

    def climb(self, at: complex, out: Moves) -> tuple[bool, complex]:
        c = self.centre
        if not self.ccw:
            if at.real > c.real:
                return True, at
            if abs(at - self.end) > 1e-3:
                out.arc(False, c, self.end)
            return False, self.end
        if at.real < c.real:
            return True, at
        top = self._top()
        if abs(at - top) > 1e-3:
            out.arc(True, c, top)
        return True, top

    def climb_only(self, at: complex, out: Moves) -> complex:
        found = self.crossings(at.imag)
        if not found:
            return at
        c = self.centre
        if not self.ccw:
            if found[-1] > c.real:
                return at
            at = complex(found[-1], at.imag)
            out.feed(at)
            if abs(at - self.end) > 1e-3:
                out.arc(False, c, self.end)
            return self.end
        if found[0] < c.real:
            return at
        at = complex(found[0], at.imag)
        out.feed(at)
        top = self._top()
        if abs(at - top) > 1e-3:
            out.arc(True, c, top)
        return top

    def dive(self, at: complex, x: float, out: Moves, fast: bool) -> tuple[bool, complex]:
        c = self.centre
        if abs(at - self.end) < TOL or (at - self.end).real <= TOL:
            return False, self.end
        found = self.crossings(x) or self.crossings(x - TOL)
        if self.ccw:
            if at.real - TOL > c.real:
                return True, at
            if not found or found[-1] > c.real:
                out.arc(True, c, self.end)
                return False, self.end
            to = complex(found[-1], x)
            out.arc(True, c, to)
            return False, to
        if at.real <= c.real:
            return True, at
        if not found:
            out.arc(False, c, self.end)
            return False, self.end
        if found[0] < c.real:
            return False, at  # only the far side is met: the caller lowers X
        to = complex(found[0], x)
        out.arc(False, c, to)
        return False, to

    def mirror_x(self) -> None:
        super().mirror_x()
        self.ccw = not self.ccw
        self.centre = self.centre.conjugate()

    def mirror_z(self) -> None:
        super().mirror_z()
        self.ccw = not self.ccw
        self.centre = -self.centre.conjugate()

    def turn(self) -> None:
        super().turn()
        self.centre = -self.centre * 1j

    def shift(self, d: complex) -> None:
        super().shift(d)
        self.centre += d


class Fillet(Arc):
    """A rounded corner of radius ``size`` at a profile point (the ``A`` word)."""

    def __init__(self, radius: float, at: complex) -> None:
        super().__init__(False, at, at, at)
        self.finish = radius

    def copy(self) -> Fillet:
        c = Fillet(self.finish, self.start)
        c.ccw, c.centre, c.end = self.ccw, self.centre, self.end
        return c

    def finish_corner(self, prev: Segment, nxt: Segment) -> None:
        self.centre = self._corner(prev, nxt)
        self.ccw = (self.start - self.centre).imag > 0 or (self.end - self.centre).imag > 0
        self.finish = 0.0


class Chamfer(Line):
    """A bevelled corner at a profile point (the ``C`` word): a fillet's ends, joined."""

    def __init__(self, size: float, at: complex) -> None:
        super().__init__(at, at)
        self.finish = size

    def copy(self) -> Chamfer:
        c = Chamfer(self.finish, self.start)
        c.end = self.end
        return c

    def finish_corner(self, prev: Segment, nxt: Segment) -> None:
        self._corner(prev, nxt)


def _circle_line(centre: complex, on_circle: complex, a: complex, b: complex) -> list[complex]:
    """The two meeting points of the circle about ``centre`` through ``on_circle`` with the
    line through ``a`` and ``b``, in LinuxCNC's order (``b`` is the line's reference point)."""
    rot = (a - b).conjugate() / abs(a - b)
    pe = (on_circle - b) * rot
    pc = (centre - b) * rot
    h = abs(pc - pe) ** 2 - pc.imag * pc.imag
    h = math.sqrt(h) if h >= 0 else 0.0
    return [(pc.real + h) / rot + b, (pc.real - h) / rot + b]


def join(p: Segment, n: Segment) -> None:
    """Move the end of ``p`` and the start of ``n`` to where the two meet."""
    if isinstance(p, Line) and isinstance(n, Line):
        rot = (n.start - n.end).conjugate() / abs(n.start - n.end)
        ps = (p.start - n.end) * rot
        pe = (p.end - n.end) * rot
        if (ps - pe).imag == 0:
            raise ProfileError("Cannot intersect parallel lines")
        f = ps.imag / (ps - pe).imag
        meet = (ps + f * (pe - ps)) / rot + n.end
    elif isinstance(n, Line):
        assert isinstance(p, Arc)
        if abs(n.start - p.end) < TOL:
            return
        s1, s2 = _circle_line(p.centre, p.end, n.start, n.end)
        meet = s1 if abs(n.start - s1) < abs(n.start - s2) else s2
    elif isinstance(p, Line):
        assert isinstance(n, Arc)
        if abs(n.start - p.end) < TOL:
            return
        s1, s2 = _circle_line(n.centre, n.end, p.start, p.end)
        meet = s1 if abs(n.start - s1) < abs(n.start - s2) else s2
    else:
        assert isinstance(p, Arc) and isinstance(n, Arc)
        a = abs(n.start - n.centre)
        b = abs(p.start - p.centre)
        c = abs(n.centre - p.centre)
        cos_b = (c * c + a * a - b * b) / 2.0 / a / c
        rot = complex(cos_b, math.sqrt(1 - min(cos_b * cos_b, 1.0)))
        meet = rot * (p.centre - n.centre) / c * a + n.centre
    p.end = n.start = meet


class _Turned:
    """Moves of the turned profile, written back in the program's orientation."""

    def __init__(self, out: Moves, state: int) -> None:
        self.out = out
        self.state = state

    def _point(self, p: complex) -> complex:
        """Undo the mirrors, then the quarter turn (they were made in the other order)."""
        s = self.state
        flips = s & 3
        if flips == 1:
            p = -p.conjugate()
        elif flips == 2:
            p = p.conjugate()
        elif flips == 3:
            p = -p
        return 1j * p if s & 4 else p

    def feed(self, end: complex) -> None:
        self.out.feed(self._point(end))

    def rapid(self, end: complex) -> None:
        self.out.rapid(self._point(end))

    def arc(self, ccw: bool, centre: complex, end: complex) -> None:
        mirrored = self.state & 3 in (1, 2)
        self.out.arc(ccw != mirrored, self._point(centre), self._point(end))


@dataclass
class Profile:
    """The segments of one cycle's profile and how they were turned."""

    segments: list[Segment]
    state: int = 0  # bit 0: Z mirrored, bit 1: X mirrored, bit 2: quarter turn
    step: float = 0.5
    escape: complex = 0.3 + 0.3j
    pocket_starts: list[complex] = field(default_factory=list)

    def copy(self) -> Profile:
        return Profile([s.copy() for s in self.segments], self.state, self.step, self.escape)

    # ------------------------------------------------------------- orientation
    def turn(self) -> None:
        for s in self.segments:
            s.turn()
        self.state ^= 4

    def orient(self) -> None:
        """Mirror so that X and Z fall from the first segment's end to the last's."""
        first, last = self.segments[0].end, self.segments[-1].end
        if (first - last).imag > 0:
            for s in self.segments:
                s.mirror_x()
            self.state ^= 2
        if (first - last).real < 0:
            for s in self.segments:
                s.mirror_z()
            self.state ^= 1

    def check_monotonic(self) -> None:
        lead = self.segments[0]
        if (lead.end - lead.start).real > 0:
            lead.start = complex(lead.end.real, lead.start.imag)
        for s in self.segments:
            if not s.monotonic():
                raise ProfileError("Not monotonic")

    def finish_corners(self) -> None:
        segs = self.segments
        for k in range(1, len(segs) - 1):
            segs[k].finish_corner(segs[k - 1], segs[k + 1])
        self.segments = [s for s in segs if s.size() >= 1e-3]

    # ------------------------------------------------------------- offset
    def add_distance(self, distance: float) -> None:
        """Offset the profile (not its lead-in) by ``distance`` towards the start point."""
        segs = self.segments
        v1 = segs[0].end - segs[0].start
        v2 = segs[-1].start - segs[0].start
        if (v1 / v2).imag < 0:
            distance = -distance
        lead = segs.pop(0)
        done = 0.0
        steps = 0
        while done != distance:
            steps += 1
            if not segs:
                raise ProfileError("nothing of the profile is left at this offset")
            if steps > MAX_OFFSET_STEPS:
                raise ProfileError(f"the profile offset takes more than {MAX_OFFSET_STEPS} steps")
            step = min(min(s.size() / 2 for s in segs), abs(distance - done))
            if distance < 0:
                step = -step
            kept: list[Segment] = []
            for s in segs:
                s.offset(step)
                if s.size() >= 1e-3:
                    kept.append(s)
            segs = self._bridge(kept, step, distance > 0)
            segs = self._rejoin(segs)
            done += step
        for k in range(len(segs) - 1):
            mid = (segs[k].end + segs[k + 1].start) / 2.0
            segs[k].end = segs[k + 1].start = mid
        lead.end = segs[0].start
        self.segments = [lead, *segs]

    @staticmethod
    def _bridge(segs: list[Segment], step: float, ccw: bool) -> list[Segment]:
        """Arcs about the old corner where the offset opened a gap going back in Z."""
        out: list[Segment] = []
        for k, s in enumerate(segs):
            out.append(s)
            if k + 1 < len(segs):
                n = segs[k + 1]
                if (s.end - n.start).real > 1e-2:
                    a, b = s.copy(), n.copy()
                    a.offset(-step)
                    b.offset(-step)
                    out.append(Arc(ccw, s.end, (a.end + b.start) / 2.0, n.start))
        return out

    @staticmethod
    def _rejoin(segs: list[Segment]) -> list[Segment]:
        """Drop what the offset made backwards or tiny, and meet the neighbours again."""
        k = 0
        while k < len(segs) - 1:
            s = segs[k]
            if not s.monotonic():
                before = segs[k - 1] if k > 0 else segs[-1]
                if k > 0 and s.size() >= before.size():
                    del segs[k - 1]
                else:
                    del segs[k]
                k = 0
                if len(segs) < 2:
                    break
                s = segs[0]
            if s.size() < 1e-3:
                del segs[k]
                k = 1
                continue
            join(s, segs[k + 1])
            k += 1
        return segs

    # ------------------------------------------------------------- cycles
    def finishing(self, out: Moves, x: float, z: float, d: float, e: float, p: float) -> None:
        """G70: ``p`` passes along the profile, from allowance ``d`` down to ``e``."""
        self.segments[0].start = complex(z, x)
        probe = self.copy()
        probe.segments.pop(0)
        probe.orient()
        for s in probe.segments:
            if not s.monotonic():
                probe.turn()
                probe.orient()
                break
        probe.check_monotonic()
        if probe.state & 4:
            self.turn()
        self.orient()
        self.finish_corners()
        self.check_monotonic()
        turned = _Turned(out, self.state)
        passes = int(p)
        for n in range(passes, 0, -1):
            distance = (n - 1) * (d - e) / p + e
            path = self.copy()
            path.add_distance(distance)
            segs = path.segments
            turned.rapid(segs[0].start)
            turned.rapid(segs[0].end)
            for s in segs[1:]:
                s.draw(turned)

    def roughing(
        self,
        out: Moves,
        subcycle: int,
        x: float,
        z: float,
        u: float,
        w: float,
        d: float,
        i: float,
        r: float,
        facing: bool,
    ) -> None:
        """G71 (``facing``: G72): layers ``i`` apart down to the profile offset by ``d``;
        ``subcycle`` 1 leaves the pockets, 2 cuts only them."""
        self.segments[0].start = complex(z, x)
        if facing:
            self.turn()
        self.orient()
        self.finish_corners()
        self.check_monotonic()
        self.add_distance(d)
        for s in self.segments:
            s.shift(complex(w, u))
        turned = _Turned(out, self.state)
        self.step = max(i, 2 * TOL)
        self.escape = r * (1 + 1j)
        segs = self.segments
        start = segs[0].start
        turned.rapid(start)
        if segs[-1].end.imag < start.imag:
            segs.append(Line(segs[-1].end, complex(segs[-1].end.real, start.imag)))
        self.pocket_starts.append(start)
        self._pocket(subcycle, start, 0, turned)

    def _pocket(self, cycle: int, at: complex, k: int, out: Moves) -> None:
        """Cut layers from segment ``k`` on, then each pocket met on the way (LinuxCNC
        recurses into a pocket as its last step; here that is a loop, so a profile of many
        pockets cannot exhaust the stack)."""
        segs = self.segments
        if cycle == 2:
            while k < len(segs):
                stop, at = segs[k].dive(at, -1e9, out, k == 0)
                if stop:
                    break
                k += 1
            cycle = 3
        layers = [0]
        pocket: tuple[complex, int] | None = (at, k)
        while pocket is not None:
            pocket = self._layers(cycle, pocket[0], pocket[1], out, layers)

    def _layers(
        self, cycle: int, at: complex, k: int, out: Moves, layers: list[int]
    ) -> tuple[complex, int] | None:
        """The layers of one pocket from segment ``k``: where the next pocket starts."""
        segs = self.segments
        x = self.pocket_starts[-1].imag
        while k < len(segs):
            layers[0] += 1
            if layers[0] > MAX_LAYERS:
                raise ProfileError(f"more than {MAX_LAYERS} roughing layers")
            while x - TOL > at.imag:
                x -= self.step
            before = at
            stop, at = segs[k].dive(at, x, out, k == 0)
            if stop:
                if cycle == 1:
                    while k < len(segs):
                        at = segs[k].climb_only(at, out)
                        k += 1
                    return None
                while k < len(segs):
                    up, at = segs[k].climb(at, out)
                    if up:
                        starts = self.pocket_starts
                        if cycle == 3:
                            if at.imag > starts[-1].imag and len(starts) > 1:
                                starts.pop()
                            if len(starts) == 1:
                                starts.append(at)
                        return at, k
                    k += 1
                return None
            if abs(at.imag - x) > TOL:
                k += 1
                continue
            nk, nx = self._layer(k, x, at, out)
            if (nk, nx) == (k, x):
                if at == segs[k].end:
                    # nothing to cut at the end of this segment: rs274 2.9.0 repeats this
                    # layer for ever, 2.9.10 (commit 111fd21339) goes on to the next segment
                    nk += 1
                elif at == before:
                    raise NoProgress("the roughing cut makes no progress")
            k, x = nk, nx
        return None

    def _layer(self, k: int, x: float, at: complex, out: Moves) -> tuple[int, float]:
        """One layer at height ``at.imag`` from segment ``k``: the next (k, x)."""
        segs = self.segments
        for j in range(k, len(segs)):
            found = segs[j].crossings(at.imag)
            if not found:
                continue
            to_z = found[0] if j != k else found[-1]
            length = abs(to_z - at.real)
            if to_z - TOL > at.real:
                continue
            if length < TOL:
                if j == k:
                    continue
                if abs(at - segs[j].start) < TOL:
                    return j, x
                return k, x - self.step
            to = complex(to_z, at.imag)
            out.feed(to)
            scale = min(1.0, length / 2 / self.escape.real)
            to += scale * self.escape
            out.rapid(to)
            out.rapid(at - (scale * self.escape).conjugate())
            if k == 0:
                out.rapid(at)
            else:
                out.feed(at)
            return k, x - self.step
        return k, x
