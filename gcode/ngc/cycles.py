"""Canned cycles G73 G74 G81-G89 with G98/G99 and L repeats, in all three planes.

Each cycle block becomes straight moves, dwells and spindle calls as LinuxCNC's
``convert_cycle_xy/yz/zx`` and ``convert_cycle_g8x`` produce them (NIST v3 §3.5.16, the
research note: a peck cycle decomposes into many STRAIGHT_FEED / STRAIGHT_TRAVERSE calls).
Per plane the hole axis is Z (G17), X (G19) or Y (G18); "depth" below means that axis.

* a series of cycle blocks remembers its initial level (the height before its first
  block); if that is below R, traverse up to R first; G98 returns to the higher of the
  initial level and R, G99 to R (the default of rs274);
* each repeat (L, incremental X/Y in G91): traverse in the plane (on a block's first
  repeat at the current height if that is above R, else at the clearance height), down to
  R, the cycle's own motion, retract (rs274 ``CYCLE_MACRO``, interp_internal.hh);
* R, Z (depth), P, Q are sticky while the same cycle stays in force; in G91 R is measured
  from the start height and the depth from R.
"""

from __future__ import annotations

import math

import kernel.limits as limits
from gcode.core.codes import Words
from gcode.core.cycle_marks import CycleEnd, CycleStart
from gcode.core.state import AXES, INVERSE_TIME, PLANE_AXES, ControlCode
from gcode.ngc import modes
from gcode.ngc.context import NgcContext
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.ir.canon import Direction, MotionMode, Units

#: LinuxCNC's G73/G83 retract clearance above the last peck (0.010 inch)
RAPID_DELTA_INCH = 0.010
_NAMES = {
    730: "G73",
    740: "G74",
    810: "G81",
    820: "G82",
    830: "G83",
    840: "G84",
    850: "G85",
    860: "G86",
    870: "G87",
    880: "G88",
    890: "G89",
}


class _Cycle:
    """Emission helpers in plane coordinates (a1, a2 in the plane, depth along the hole)."""

    def __init__(self, ctx: NgcContext) -> None:
        self.ctx = ctx
        self.f1, self.f2, self.fn = PLANE_AXES[ctx.s.plane]

    def point(self, a1: float, a2: float, d: float) -> list[float]:
        p = list(self.ctx.s.pos)
        p[self.f1], p[self.f2], p[self.fn] = a1, a2, d
        return p

    def traverse(self, a1: float, a2: float, d: float) -> None:
        p = self.point(a1, a2, d)
        self.ctx.emit(canon.StraightTraverse(*p, source=self.ctx.loc))
        self.ctx.s.pos = p
        self.ctx.s.tlo_lag = None

    def feed(self, a1: float, a2: float, d: float) -> None:
        p = self.point(a1, a2, d)
        self.ctx.emit(canon.StraightFeed(*p, source=self.ctx.loc))
        self.ctx.s.pos = p
        self.ctx.s.tlo_lag = None

    def tap_feed(self, a1: float, a2: float, d: float) -> None:
        """A G84/G74 feed as rs274 2.9 prints it: in G18 it orders the coordinates as for
        G19 and in G19 as for G18 (the hole's point lands on swapped axes); in G17 it is a
        plain feed. Its own position still becomes the true point."""
        plane = self.ctx.s.plane
        if plane is canon.Plane.XY:
            self.feed(a1, a2, d)
            return
        f1, f2, fn = PLANE_AXES[canon.Plane.YZ if plane is canon.Plane.XZ else canon.Plane.XZ]
        printed = list(self.ctx.s.pos)
        printed[f1], printed[f2], printed[fn] = a1, a2, d
        self.ctx.emit(canon.StraightFeed(*printed, source=self.ctx.loc))
        self.ctx.s.pos = self.point(a1, a2, d)
        self.ctx.s.tlo_lag = None


def canned_cycle(ctx: NgcContext, w: Words, code: int, previous: int | None) -> None:
    s = ctx.s
    v = w.values
    loc = ctx.loc
    name = _NAMES.get(code, f"G{code // 10}")
    c = s.cycle
    sticky = previous == code
    ctx.comp_off("canned cycle")
    if s.feed_mode == INVERSE_TIME:
        raise Diagnostic(
            "NGC-CYCLE-INVERSE-TIME", "cannot use inverse time feed with canned cycles", loc
        )
    cyc = _Cycle(ctx)
    f1, f2, fn = cyc.f1, cyc.f2, cyc.fn
    a1n, a2n, dn = AXES[f1], AXES[f2], AXES[fn]
    if "r" in v:
        c.r = v["r"]
    elif not sticky:
        raise Diagnostic("NGC-CYCLE-R", "R clearance plane unspecified in cycle", loc)
    if dn in v:
        c.z = v[dn]
    elif not sticky:
        raise Diagnostic("NGC-CYCLE-DEPTH", f"{dn.upper()} value unspecified in canned cycle", loc)
    if "l" in v:
        lv = v["l"]
        if lv < 0 or abs(lv - round(lv)) > 1e-4:
            raise Diagnostic("NGC-CYCLE-L", "negative or non-integer L word in canned cycle", loc)
        repeats = int(round(lv))
        if repeats == 0:
            raise Diagnostic("NGC-CYCLE-L", "cannot do zero repeats of cycle", loc)
    else:
        repeats = 1
    if "p" in v:
        if v["p"] < 0:
            raise Diagnostic("NGC-CYCLE-P", "negative P word used in canned cycle", loc)
        c.p = v["p"]
    if code in (730, 830):
        if "q" in v:
            c.q = v["q"]
        elif not sticky:
            raise Diagnostic("NGC-CYCLE-Q", f"Q word missing with {name}", loc)
        if c.q <= 0:
            raise Diagnostic("NGC-CYCLE-Q", f"Q value is negative or zero in {name}", loc)
    if code in (820, 860, 880, 890) and "p" not in v and not sticky:
        raise Diagnostic("NGC-CYCLE-P", f"dwell time P word missing with {name}", loc)
    if code == 870:
        for letter in PLANE_CENTRE_LETTERS[s.plane]:
            if letter in v:
                setattr(c, letter, v[letter])
            elif not sticky:
                raise Diagnostic("NGC-CYCLE-G87", f"{letter.upper()} word missing with G87", loc)
    if any(a in v for a in "abc"):
        which = next(a for a in "abc" if a in v)
        raise Diagnostic("NGC-CYCLE-ROTARY", f"cannot put an {which.upper()} in canned cycle", loc)
    if s.feed_rate == 0.0:
        raise Diagnostic("NGC-ZERO-FEED", f"cannot feed with zero feed rate ({name})", loc)

    pos = s.pos
    first = not s.cycle_series
    if first:  # the initial level of a series of cycle blocks (LinuxCNC ``cycle_il``)
        c.cc = pos[fn]
        s.cycle_series = True
    old = c.cc
    height = pos[fn]
    if s.absolute:
        r = c.r
        bottom = c.z
        a1, a2 = v.get(a1n, pos[f1]), v.get(a2n, pos[f2])
        inc1 = inc2 = 0.0
    else:
        r = c.r + old
        bottom = r + c.z
        a1, a2 = pos[f1], pos[f2]
        inc1, inc2 = v.get(a1n, 0.0), v.get(a2n, 0.0)
    if r < bottom:
        plane = {2: "XY", 1: "XZ", 0: "YZ"}[fn]
        raise Diagnostic(
            "NGC-CYCLE-R-BELOW", f"R less than {dn.upper()} in cycle in {plane} plane", loc
        )
    if code == 840 and s.spindle is not Direction.CLOCKWISE:
        raise Diagnostic(
            "NGC-CYCLE-SPINDLE",
            f"spindle not turning clockwise in G84 ({_turning(s.spindle)})",
            loc,
        )
    if code == 740 and s.spindle is not Direction.COUNTERCLOCKWISE:
        raise Diagnostic("NGC-CYCLE-SPINDLE", "spindle not turning counterclockwise in G74", loc)

    marks = ctx.options.cycle_marks
    if marks:
        ctx.emit(
            CycleStart(
                code,
                s.plane,
                s.retract_r,
                a1 + inc1,
                a2 + inc2,
                r,
                bottom,
                c.q,
                c.p,
                repeats,
                source=loc,
            )
        )
    if old < r:
        cyc.traverse(pos[f1], pos[f2], r)
        old = height = r
    clear = r if s.retract_r else old
    exact = ctx.compat and s.control_mode is not ControlCode.G61
    if exact:
        ctx.emit(canon.SetMotionControlMode(MotionMode.EXACT_PATH, source=loc))
    if not first and height <= r:
        # a later block of the series starts its first hole at the current height only
        # when that is above R (a G98 block after a G99 one); at or below R it moves
        # at the clearance height (rs274 ``CYCLE_MACRO``, interp_internal.hh)
        height = clear
    polar = not s.absolute and ("@" in v or "^" in v)
    _check_passes(ctx, code, repeats, r, bottom)
    for _ in range(repeats):
        if polar:  # each repeat turns about the origin again (G17 only: motion.polar_words)
            inc1, inc2 = polar_step(v, a1, a2)
        a1 += inc1
        a2 += inc2
        # a block's first move at the height chosen above, its later repeats' at the
        # clearance height (LinuxCNC ``CYCLE_MACRO``)
        cyc.traverse(a1, a2, height)
        if height != r:
            cyc.traverse(a1, a2, r)
        _one_hole(ctx, cyc, code, a1, a2, r, bottom, clear)
        height = clear
    if exact:
        words = Words(values={"p": s.blend_p, "q": s.blend_q})
        modes.control_mode(ctx, s.control_mode, words, check=False)
    if marks:
        ctx.emit(CycleEnd(tuple(s.pos), source=loc))


def polar_step(v: dict[str, float], x0: float, y0: float) -> tuple[float, float]:
    """The X/Y increments of a G91 polar block (``@``/``^`` kept in ``v``) from (x0, y0)."""
    radius = math.hypot(x0, y0) + v.get("@", 0.0)
    angle = math.radians(math.degrees(math.atan2(y0, x0)) + v.get("^", 0.0))
    return radius * math.cos(angle) - x0, radius * math.sin(angle) - y0


def _check_passes(ctx: NgcContext, code: int, repeats: int, r: float, bottom: float) -> None:
    """LIMIT-COUNT before a cycle whose repeats times pecks pass ``kernel.limits``' budget
    (an L1e9 or a peck of 1e-6 mm would run for hours and fill memory)."""
    pecks = 1.0
    q = ctx.s.cycle.q
    if code in (730, 830) and q > 0:
        pecks = max(1.0, (r - bottom) / q + 1.0)
    limit = limits.current().cycle_passes
    if repeats * pecks > limit:
        raise limits.count_error(
            f"{_NAMES[code]} passes", repeats * pecks, limit, "cycle_passes", ctx.loc
        )


PLANE_CENTRE_LETTERS = {
    canon.Plane.XY: ("i", "j", "k"),
    canon.Plane.XZ: ("k", "i", "j"),
    canon.Plane.YZ: ("j", "k", "i"),
}


def _turning(d: Direction) -> str:
    return {
        Direction.STOPPED: "stopped",
        Direction.COUNTERCLOCKWISE: "turning counterclockwise",
        Direction.CLOCKWISE: "turning clockwise",
    }[d]


def _one_hole(
    ctx: NgcContext,
    cyc: _Cycle,
    code: int,
    a1: float,
    a2: float,
    r: float,
    bottom: float,
    clear: float,
) -> None:
    s = ctx.s
    loc = ctx.loc
    c = s.cycle
    if code in (860, 870, 880) and s.spindle is Direction.STOPPED:
        raise Diagnostic("NGC-CYCLE-SPINDLE", f"spindle not turning in {_NAMES[code]}", loc)
    if code == 810:
        cyc.feed(a1, a2, bottom)
        cyc.traverse(a1, a2, clear)
    elif code == 820:
        cyc.feed(a1, a2, bottom)
        ctx.emit(canon.Dwell(c.p, source=loc))
        cyc.traverse(a1, a2, clear)
    elif code in (730, 830):
        delta = RAPID_DELTA_INCH * (25.4 if s.units is Units.MM else 1.0)
        depth = r - c.q
        while depth > bottom:
            cyc.feed(a1, a2, depth)
            if code == 830:
                cyc.traverse(a1, a2, r)
            cyc.traverse(a1, a2, depth + delta)
            depth -= c.q
        cyc.feed(a1, a2, bottom)
        cyc.traverse(a1, a2, clear)
    elif code in (840, 740):
        ctx.emit(canon.DisableFeedOverride(source=loc))
        ctx.emit(canon.DisableSpeedOverride(source=loc))
        cyc.tap_feed(a1, a2, bottom)
        ctx.emit(canon.StopSpindleTurning(source=loc))
        if code == 840:
            ctx.emit(canon.StartSpindleCounterclockwise(source=loc))
        else:
            ctx.emit(canon.StartSpindleClockwise(source=loc))
        ctx.emit(canon.Dwell(c.p, source=loc))
        cyc.tap_feed(a1, a2, clear)
        ctx.emit(canon.StopSpindleTurning(source=loc))
        if code == 840:
            ctx.emit(canon.StartSpindleClockwise(source=loc))
        else:
            ctx.emit(canon.StartSpindleCounterclockwise(source=loc))
        ctx.emit(canon.EnableFeedOverride(source=loc))
        ctx.emit(canon.EnableSpeedOverride(source=loc))
    elif code == 850:
        cyc.feed(a1, a2, bottom)
        cyc.feed(a1, a2, r)
        cyc.traverse(a1, a2, clear)
    elif code == 860:
        cyc.feed(a1, a2, bottom)
        ctx.emit(canon.Dwell(c.p, source=loc))
        ctx.emit(canon.StopSpindleTurning(source=loc))
        cyc.traverse(a1, a2, clear)
        _restart_spindle(ctx)
    elif code == 880:
        cyc.feed(a1, a2, bottom)
        ctx.emit(canon.Dwell(c.p, source=loc))
        ctx.emit(canon.StopSpindleTurning(source=loc))
        ctx.emit(canon.ProgramStop(source=loc))
        _restart_spindle(ctx)
        s.pos[cyc.fn] = clear  # the operator retracted by hand (LinuxCNC assumes so)
    elif code == 890:
        cyc.feed(a1, a2, bottom)
        ctx.emit(canon.Dwell(c.p, source=loc))
        cyc.feed(a1, a2, clear)
    elif code == 870:
        _back_bore(ctx, cyc, a1, a2, r, bottom, clear)


def _restart_spindle(ctx: NgcContext) -> None:
    loc = ctx.loc
    if ctx.s.spindle is Direction.CLOCKWISE:
        ctx.emit(canon.StartSpindleClockwise(source=loc))
    else:
        ctx.emit(canon.StartSpindleCounterclockwise(source=loc))


def _back_bore(
    ctx: NgcContext, cyc: _Cycle, a1: float, a2: float, r: float, bottom: float, clear: float
) -> None:
    """G87 (LinuxCNC ``convert_cycle_g87``): in beside the hole, back-bore up to K, out."""
    s = ctx.s
    loc = ctx.loc
    c = s.cycle
    letters = PLANE_CENTRE_LETTERS[s.plane]
    off1, off2 = getattr(c, letters[0]), getattr(c, letters[1])
    middle = getattr(c, letters[2]) if s.absolute else bottom + getattr(c, letters[2])
    orient = canon.OrientSpindle(0.0, Direction.COUNTERCLOCKWISE, source=loc)
    cyc.traverse(a1 + off1, a2 + off2, r)
    ctx.emit(canon.StopSpindleTurning(source=loc))
    ctx.emit(orient)
    cyc.traverse(a1 + off1, a2 + off2, bottom)
    cyc.traverse(a1, a2, bottom)
    _restart_spindle(ctx)
    cyc.feed(a1, a2, middle)
    cyc.feed(a1, a2, bottom)
    ctx.emit(canon.StopSpindleTurning(source=loc))
    ctx.emit(orient)
    cyc.traverse(a1 + off1, a2 + off2, bottom)
    cyc.traverse(a1 + off1, a2 + off2, clear)
    cyc.traverse(a1, a2, clear)
    _restart_spindle(ctx)
