"""Fanuc milling cycles whose motion differs from LinuxCNC's (book Table A.2; Fanuc 0i-MF
manual, "Canned cycles"): G84/G74 tapping, G76 fine boring, G87 back boring.

* G84 (G74): rapid to the hole and to R, feed to Z, dwell P (if given), reverse the
  spindle, feed back out to R, dwell P, restore the spindle, then (G98) rapid to the
  initial level. LinuxCNC's G84 feeds out to the clearance level and always dwells.
* G76: rapid to R, feed to Z, dwell P, oriented spindle stop, shift Q away from the wall,
  rapid out (G98 initial level / G99 R), shift back, spindle clockwise again.
* G87: at the initial level: oriented stop, shift Q, rapid down to R (below the hole),
  shift back, spindle clockwise, feed up to Z, dwell P, oriented stop, shift Q, rapid up
  to the initial level, shift back, spindle clockwise (G87 always returns to the initial
  level).

The shift goes along +first plane axis (+X in G17: parameter 5101 RD1/RD2 = 0), the
oriented stop is ``ORIENT_SPINDLE(0)`` (the orientation angle is a machine parameter).
"""

from __future__ import annotations

from dataclasses import dataclass

import kernel.limits as limits
from gcode.core.codes import Words
from gcode.fanuc.state import ExecutorState
from gcode.ngc.motion import AXES, PLANE_AXES
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Direction

OWN = frozenset({740, 760, 840, 870})
TAPPING = frozenset({740, 840})
_NAMES = {740: "G74", 760: "G76", 840: "G84", 870: "G87"}


@dataclass
class _Hole:
    """Levels and positions of one cycle block."""

    f1: int
    f2: int
    fn: int
    r: float
    bottom: float
    initial: float
    clear: float
    height: float
    holes: list[tuple[float, float]]


def _setup(ex: ExecutorState, w: Words, code: int, sticky: bool) -> _Hole:
    ip = ex.ip
    s = ip.s
    v = w.values
    loc = ip.loc
    c = s.cycle
    f1, f2, fn = PLANE_AXES[s.plane]
    a1n, a2n, dn = AXES[f1], AXES[f2], AXES[fn]
    name = _NAMES[code]
    ip.comp_off("canned cycle")
    if "r" in v:
        c.r = v["r"]
    elif not sticky:
        raise Diagnostic("FANUC-CYCLE-R", f"R level missing in {name}", loc)
    if dn in v:
        c.z = v[dn]
    elif not sticky:
        raise Diagnostic("FANUC-CYCLE-Z", f"{dn.upper()} depth missing in {name}", loc)
    if "p" in v:
        c.p = v["p"]
    elif not sticky:
        c.p = 0.0
    if "q" in v:
        c.q = abs(v["q"])
    elif not sticky:
        c.q = 0.0
    count = v.get("l", 1.0)
    limit = limits.current().cycle_passes
    if not count < limit + 1:  # the holes are listed: a bound before any (NaN and inf too)
        raise limits.count_error(f"{name} repeats", count, limit, "cycle_passes", loc)
    repeats = round(count)
    if repeats < 1:
        raise Diagnostic("FANUC-CYCLE-L", f"{name}: repeat count K must be 1 or more", loc)
    if s.feed_rate == 0.0:
        raise Diagnostic("FANUC-ZERO-FEED", f"{name} with zero feed rate", loc)
    pos = s.pos
    first = not s.cycle_series
    if first:
        c.cc = pos[fn]
        s.cycle_series = True
    initial = c.cc
    if s.absolute:
        r, bottom = c.r, c.z
        p1, p2 = v.get(a1n, pos[f1]), v.get(a2n, pos[f2])
        inc1 = inc2 = 0.0
    else:
        r = initial + c.r
        bottom = r + c.z
        p1, p2 = pos[f1], pos[f2]
        inc1, inc2 = v.get(a1n, 0.0), v.get(a2n, 0.0)
    if code == 870:
        if bottom < r:
            raise Diagnostic("FANUC-CYCLE-R-BELOW", "G87: R must be below Z", loc)
        clear = initial
    else:
        if r < bottom:
            raise Diagnostic("FANUC-CYCLE-R-BELOW", f"R below the hole bottom in {name}", loc)
        clear = r if s.retract_r else max(initial, r)
    holes = []
    for _ in range(repeats):
        p1 += inc1
        p2 += inc2
        holes.append((p1, p2))
    height = pos[fn] if first else clear
    return _Hole(f1, f2, fn, r, bottom, initial, clear, height, holes)


def run(ex: ExecutorState, w: Words, code: int, sticky: bool) -> None:
    """One G74/G76/G84/G87 block (its words in RS274 form: x y z r p q l)."""
    ip = ex.ip
    s = ip.s
    loc = ip.loc
    h = _setup(ex, w, code, sticky)
    turning = s.spindle
    if code in TAPPING:
        want = Direction.CLOCKWISE if code == 840 else Direction.COUNTERCLOCKWISE
        if turning is not want:
            way = "clockwise" if code == 840 else "counterclockwise"
            raise Diagnostic(
                "FANUC-CYCLE-SPINDLE", f"{_NAMES[code]} needs the spindle turning {way}", loc
            )
    elif turning is Direction.STOPPED:
        raise Diagnostic("FANUC-CYCLE-SPINDLE", f"{_NAMES[code]} with the spindle stopped", loc)
    for a, b in h.holes:
        if code in TAPPING:
            _tap(ex, h, code, a, b, loc)
        elif code == 760:
            _fine_bore(ex, h, a, b, loc)
        else:
            _back_bore(ex, h, a, b, loc)
        h.height = h.clear
    s.spindle = turning


def _move(
    ex: ExecutorState, h: _Hole, kind: type, a: float, b: float, d: float, loc: Location
) -> None:
    s = ex.ip.s
    p = list(s.pos)
    p[h.f1], p[h.f2], p[h.fn] = a, b, d
    ex.ip.emit(kind(*p, source=loc))
    s.pos = p


def _dwell(ex: ExecutorState, loc: Location) -> None:
    p = ex.ip.s.cycle.p
    if p > 0:
        ex.ip.emit(canon.Dwell(p, source=loc))


def _tap(ex: ExecutorState, h: _Hole, code: int, a: float, b: float, loc: Location) -> None:
    ip = ex.ip
    rapid, feed = canon.StraightTraverse, canon.StraightFeed
    reverse = canon.StartSpindleCounterclockwise if code == 840 else canon.StartSpindleClockwise
    restore = canon.StartSpindleClockwise if code == 840 else canon.StartSpindleCounterclockwise
    _move(ex, h, rapid, a, b, max(h.height, h.r), loc)
    if ip.s.pos[h.fn] != h.r:
        _move(ex, h, rapid, a, b, h.r, loc)
    _move(ex, h, feed, a, b, h.bottom, loc)
    _dwell(ex, loc)
    ip.emit(reverse(source=loc))
    _move(ex, h, feed, a, b, h.r, loc)
    _dwell(ex, loc)
    ip.emit(restore(source=loc))
    if h.clear != h.r:
        _move(ex, h, rapid, a, b, h.clear, loc)


def _orient(ex: ExecutorState, loc: Location) -> None:
    ex.ip.emit(canon.OrientSpindle(0.0, Direction.CLOCKWISE, source=loc))


def _bore_out(ex: ExecutorState, h: _Hole, a: float, b: float, loc: Location) -> None:
    """G76 and G87 at the bottom: feed there, dwell, orient the spindle and shift by Q off
    the wall, leave by rapids to the clearance height and back over the hole, spindle on."""
    rapid = canon.StraightTraverse
    q = ex.ip.s.cycle.q
    _move(ex, h, canon.StraightFeed, a, b, h.bottom, loc)
    _dwell(ex, loc)
    _orient(ex, loc)
    _move(ex, h, rapid, a + q, b, h.bottom, loc)
    _move(ex, h, rapid, a + q, b, h.clear, loc)
    _move(ex, h, rapid, a, b, h.clear, loc)
    ex.ip.emit(canon.StartSpindleClockwise(source=loc))


def _fine_bore(ex: ExecutorState, h: _Hole, a: float, b: float, loc: Location) -> None:
    ip = ex.ip
    rapid = canon.StraightTraverse
    _move(ex, h, rapid, a, b, max(h.height, h.r), loc)
    if ip.s.pos[h.fn] != h.r:
        _move(ex, h, rapid, a, b, h.r, loc)
    _bore_out(ex, h, a, b, loc)


def _back_bore(ex: ExecutorState, h: _Hole, a: float, b: float, loc: Location) -> None:
    ip = ex.ip
    rapid = canon.StraightTraverse
    q = ip.s.cycle.q
    _move(ex, h, rapid, a, b, h.height, loc)
    _orient(ex, loc)
    _move(ex, h, rapid, a + q, b, h.height, loc)
    _move(ex, h, rapid, a + q, b, h.r, loc)
    _move(ex, h, rapid, a, b, h.r, loc)
    ip.emit(canon.StartSpindleClockwise(source=loc))
    _bore_out(ex, h, a, b, loc)
