"""Motion blocks: G0 G1 G2 G3 (centre and radius format, helices, P turns, three planes),
G4, G5/G5.1 splines and G5.2/G5.3 NURBS as rs274 emits them, G33 and G33.1, G38.2-G38.5
probing, and the dispatch to canned cycles (:mod:`gcode.ngc.cycles`), LinuxCNC's lathe cycles
G70-G72 (:mod:`gcode.ngc.lathe_cycles`) and cutter compensation
(:mod:`gcode.ngc.comp.cutter_comp`). Checks and messages follow LinuxCNC ``convert_motion`` and
``convert_arc``; arcs map to ``ARC_FEED`` as NISTIR 5970 §3.6.1 defines it (XZ plane:
first axis Z, second X).
"""

from __future__ import annotations

import math

from gcode.core import arcs
from gcode.core import linuxcnc as lc
from gcode.core.codes import Words
from gcode.core.state import (
    AXES,
    INCH_MM,
    INVERSE_TIME,
    PER_MINUTE,
    PER_REV,
    PLANE_AXES,
    PLANE_CENTRE,
    CompCode,
    Setup,
)
from gcode.ngc.comp.cutter_comp import CutterCompensator
from gcode.ngc.comp.keep import CompRegister, KeptCompensation
from gcode.ngc.context import NgcContext
from gcode.ngc.cycles import canned_cycle
from gcode.ngc.lathe_cycles import LATHE_CYCLES, lathe_cycle
from gcode.ngc.threading import threading_cycle
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweep
from kernel.ir.canon import Direction, Plane, Units

CYCLES = frozenset({730, 740, 810, 820, 830, 840, 850, 860, 870, 880, 890})
_NAMES = "XYZABC"


def _g(code: int) -> str:
    return f"G{code // 10}" + (f".{code % 10}" if code % 10 else "")


def check_block(ctx: NgcContext, w: Words) -> None:
    """Block-level checks of LinuxCNC ``check_g_codes`` / ``enhance_block``."""
    g = w.g
    loc = ctx.loc
    g0 = g.get(0)
    if g0 in (100, 280, 300, 520, 920) and 1 in g and g[1] != 800 and w.has_axis():
        raise Diagnostic(
            "NGC-TWO-AXIS-USERS", "cannot use two G codes that both use axis values", loc
        )
    if g.get(1) == 800 and w.has_axis() and g0 not in (100, 280, 300, 520, 920):
        raise Diagnostic("NGC-AXIS-WITH-G80", "cannot use axis values with G80", loc)
    if g0 == 530:
        ctx.comp_off("G53")
        if g.get(3, 900 if ctx.s.absolute else 910) == 910:
            raise Diagnostic("NGC-G53-INCREMENTAL", "cannot use G53 incremental", loc)
        mode = g.get(1, ctx.s.motion_mode)
        if mode not in (0, 10):
            raise Diagnostic("NGC-G53-MOTION", "must use G0 or G1 with G53", loc)
    if g0 == 40 and "p" not in w.values:
        raise Diagnostic("NGC-G4-P", "dwell time missing with G4", loc)


def find_ends(ctx: NgcContext, w: Words) -> list[float]:
    """End point in program coordinates (LinuxCNC ``find_ends``)."""
    s = ctx.s
    v = w.values
    pos = s.pos
    if s.diameter_mode and "x" in v:
        v = dict(v)
        v["x"] /= 2.0
    if w.g.get(0) == 530:
        machine = s.to_machine(pos)
        return s.to_program([v.get(a, machine[i]) for i, a in enumerate(AXES)])
    get = v.get
    if s.absolute:
        return [
            get("x", pos[0]),
            get("y", pos[1]),
            get("z", pos[2]),
            get("a", pos[3]),
            get("b", pos[4]),
            get("c", pos[5]),
        ]
    return [
        pos[0] + get("x", 0.0),
        pos[1] + get("y", 0.0),
        pos[2] + get("z", 0.0),
        pos[3] + get("a", 0.0),
        pos[4] + get("b", 0.0),
        pos[5] + get("c", 0.0),
    ]


def polar_words(ctx: NgcContext, w: Words) -> Words:
    """The block with its polar words ``@`` (radius) and ``^`` (angle, degrees) turned into
    the X and Y words they stand for (LinuxCNC ``find_ends``, as rs274 2.9 computes them).

    Polar coordinates are about the program origin in G17 only. In G90 a missing ``@`` or
    ``^`` is the current point's; in G91 both are added to the current point's radius and
    angle (so at the origin the move is undefined), and the result is given as the X/Y
    increments G91 expects, with the polar increments kept for :func:`gcode.ngc.cycles.polar_step`.
    """
    s = ctx.s
    v = w.values
    loc = ctx.loc
    if s.plane is not Plane.XY:
        raise Diagnostic("NGC-POLAR-PLANE", "cannot use polar coordinate except in G17 plane", loc)
    for letter in "xy":
        if letter in v:
            raise Diagnostic(
                "NGC-POLAR-XY",
                f"cannot specify both polar coordinate and {letter.upper()} word",
                Location(loc.file, loc.line, w.columns.get(letter, loc.column)),
            )
    x0, y0 = s.pos[0], s.pos[1]
    radius0 = math.hypot(x0, y0)
    angle0 = math.degrees(math.atan2(y0, x0))
    if s.absolute:
        radius = v.get("@", radius0)
        angle = v.get("^", angle0)
    else:
        if radius0 == 0.0:
            raise Diagnostic(
                "NGC-POLAR-ORIGIN",
                "incremental motion with polar coordinates is indeterminate when at the origin",
                loc,
            )
        radius = radius0 + v.get("@", 0.0)
        angle = angle0 + v.get("^", 0.0)
    x = radius * math.cos(math.radians(angle))
    y = radius * math.sin(math.radians(angle))
    # G91 keeps its polar increments: a canned cycle's L repeats apply them again from
    # each hole (rs274 2.9 drills a bolt circle with ``G91 G81 ^60 L6``)
    values = {k: val for k, val in v.items() if not s.absolute or k not in "@^"}
    values["x"], values["y"] = (x, y) if s.absolute else (x - x0, y - y0)
    columns = dict(w.columns)
    columns["x"] = columns["y"] = columns.get("@", columns.get("^", loc.column))
    return Words(g=w.g, m=w.m, values=values, columns=columns)


def traverse(ctx: NgcContext, end: list[float]) -> None:
    s = ctx.s
    comp = ctx.comp
    if comp is not None and comp.engaged:
        ctx.out.extend(comp.straight(s.pos, end, rapid=True, source=ctx.loc))
    else:
        if comp is not None:
            comp.arc_not_allowed = False
        ctx.emit(canon.StraightTraverse(*end, source=ctx.loc))
    s.pos = end
    s.tlo_lag = None


def feed(ctx: NgcContext, end: list[float]) -> None:
    s = ctx.s
    comp = ctx.comp
    if comp is not None and comp.engaged:
        ctx.out.extend(comp.straight(s.pos, end, rapid=False, source=ctx.loc))
    else:
        if comp is not None:
            comp.arc_not_allowed = False
        ctx.emit(canon.StraightFeed(*end, source=ctx.loc))
    s.pos = end
    s.tlo_lag = None


def _check_feed(ctx: NgcContext, w: Words, what: str) -> None:
    s = ctx.s
    if s.feed_mode == PER_MINUTE:
        if s.feed_rate == 0.0:
            raise Diagnostic(
                "NGC-ZERO-FEED",
                f"cannot do {what} with zero feed rate: F is 0 (no F word since the start, or F0)",
                ctx.loc,
            )
    elif s.feed_mode == PER_REV:
        if s.feed_rate == 0.0:
            raise Diagnostic(
                "NGC-ZERO-FEED",
                f"cannot do {what} with zero feed rate: F is 0 (no F word since the start, or F0)",
                ctx.loc,
            )
        if s.speed == 0.0:
            raise Diagnostic(
                "NGC-ZERO-SPEED-FPR",
                "cannot feed with zero spindle speed in feed per rev mode",
                ctx.loc,
            )
    elif "f" not in w.values:
        raise Diagnostic(
            "NGC-INVERSE-TIME-F", f"F word missing with inverse time {what} move", ctx.loc
        )


def _inverse_time_rate(ctx: NgcContext, w: Words, length: float) -> None:
    s = ctx.s
    if s.feed_mode == INVERSE_TIME:
        rate = max(0.1, length * w.values["f"])  # LinuxCNC's lower bound
        s.feed_rate = rate
        ctx.emit(canon.SetFeedRate(rate, source=ctx.loc))


def _straight_length(start: list[float], end: list[float]) -> float:
    d = math.dist(start[:3], end[:3])
    return d if d > 0.0 else math.dist(start[3:], end[3:])


def execute_motion(ctx: NgcContext, w: Words, code: int | None) -> None:
    """Run the motion ``code`` (the block's, or the modal one for bare axis words)."""
    s = ctx.s
    loc = ctx.loc
    if code == 10 or code == 0:
        s.motion_mode = code
        s.cycle_series = False
        end = find_ends(ctx, w)
        if code == 0:
            traverse(ctx, end)
            return
        _check_feed(ctx, w, "G1")
        if s.feed_mode == INVERSE_TIME:
            _inverse_time_rate(ctx, w, _straight_length(s.pos, end))
        feed(ctx, end)
        return
    if code is None or code == 800:
        raise Diagnostic(
            "NGC-AXIS-NO-MOTION", "cannot use axis values without a G code that uses them", loc
        )
    previous = s.motion_mode
    s.motion_mode = code
    if code not in CYCLES:
        s.cycle_series = False
    if code in (20, 30):
        arc(ctx, w, code == 20)
    elif code in CYCLES:
        canned_cycle(ctx, w, code, previous)
    elif code == 760:
        threading_cycle(ctx, w, find_ends(ctx, w))
    elif code in (382, 383, 384, 385):
        probe(ctx, w, code)
    elif code in (330, 331):
        synchronised(ctx, w, code)
    elif code in (50, 51):
        s.motion_mode = previous  # rs274 keeps the motion mode across G5/G5.1
        spline(ctx, w, code)
    elif code in (52, 53):
        nurbs(ctx, w, code)
    elif code in LATHE_CYCLES:
        lathe_cycle(ctx, w, code, execute_motion)
    else:
        raise Diagnostic("NGC-UNSUPPORTED-MOTION", f"{_g(code)} is not supported", loc)


# --------------------------------------------------------------------------- arcs
def arc(ctx: NgcContext, w: Words, clockwise: bool) -> None:
    s = ctx.s
    v = w.values
    loc = ctx.loc
    comp = ctx.comp
    if comp is not None:
        comp.check_arc_allowed(loc)
    plane = s.plane
    ci, cj, ck = PLANE_CENTRE[plane]
    f1, f2, fn = PLANE_AXES[plane]
    ijk = ci in v or cj in v or ck in v
    if "r" not in v and not ijk:
        raise Diagnostic("NGC-ARC-NO-CENTRE", "R, I, J and K words all missing for arc", loc)
    if "r" in v and ijk:
        raise Diagnostic("NGC-ARC-MIXED", "mixed radius and IJK format for arc", loc)
    _check_feed(ctx, w, "arc")
    a1, a2 = AXES[f1], AXES[f2]
    if "r" in v and a1 not in v and a2 not in v:
        raise Diagnostic(
            "NGC-ARC-AXES",
            f"{a1.upper()} and {a2.upper()} words missing for arc in {(a1 + a2).upper()} plane",
            loc,
        )
    if ijk and ck in v:
        raise Diagnostic(
            "NGC-ARC-WRONG-CENTRE-WORD",
            f"{ck.upper()} word given for arc in {(AXES[min(f1, f2)] + AXES[max(f1, f2)])} plane",
            loc,
        )
    end = find_ends(ctx, w)
    start = s.pos
    p = v.get("p")
    turn = arcs.turns_for(clockwise, p, loc)
    st = (start[f1], start[f2])
    en = (end[f1], end[f2])
    inches = s.units is Units.INCHES
    if "r" in v:
        at_r = Location(loc.file, loc.line, w.columns.get("r", loc.column))
        centre = arcs.radius_format(st, en, v["r"], clockwise, loc, inches, at_r)
    else:
        if s.ijk_absolute:
            for letter in (ci, cj):
                if letter not in v:
                    raise Diagnostic(
                        "NGC-ARC-ABS-CENTRE",
                        f"{letter.upper()} word missing in absolute center arc",
                        loc,
                    )
            centre = (v[ci], v[cj])
        else:
            centre = (st[0] + v.get(ci, 0.0), st[1] + v.get(cj, 0.0))
        names = (AXES[f1], AXES[f2])
        lenient = ctx.options.arc_radius_relative
        smallest = ctx.options.arc_min_radius
        if smallest is not None and inches:
            smallest /= 25.4
        arcs.centre_format(st, en, centre, names, inches, loc, lenient, smallest)
    if s.feed_mode == INVERSE_TIME:
        _inverse_time_rate(ctx, w, _arc_length(st, en, centre, turn, end[fn] - start[fn]))
    if comp is not None and comp.engaged:
        ctx.out.extend(comp.arc(start, end, centre, turn, source=loc))
    else:
        ctx.emit(
            canon.ArcFeed(
                en[0],
                en[1],
                centre[0],
                centre[1],
                turn,
                end[fn],
                end[3],
                end[4],
                end[5],
                source=loc,
            )
        )
    s.pos = end
    s.tlo_lag = None


def _arc_length(
    st: tuple[float, float],
    en: tuple[float, float],
    centre: tuple[float, float],
    turn: int,
    height: float,
) -> float:
    """Helix length (LinuxCNC ``find_arc_length``)."""
    r = math.hypot(st[0] - centre[0], st[1] - centre[1])
    a0 = math.atan2(st[1] - centre[1], st[0] - centre[0])
    a1 = math.atan2(en[1] - centre[1], en[0] - centre[0])
    return math.hypot(r * abs(arc_sweep(a0, a1, turn)), height)


# --------------------------------------------------------------------------- G4
def dwell(ctx: NgcContext, w: Words) -> None:
    p = w.values.get("p")
    if p is None or p < 0:
        raise Diagnostic("NGC-G4-P", "dwell time missing with G4", ctx.loc)
    ctx.emit(canon.Dwell(p, source=ctx.loc))


# --------------------------------------------------------------------------- probing
def probe(ctx: NgcContext, w: Words, code: int) -> None:
    """G38.2-G38.5 (LinuxCNC ``convert_probe``); the stand-alone probe never trips."""
    s = ctx.s
    loc = ctx.loc
    if not w.has_axis():
        raise Diagnostic("NGC-PROBE-AXES", "X, Y, and Z words all missing with G38.x", loc)
    ctx.comp_off("probe")
    if s.feed_mode == PER_REV:
        raise Diagnostic("NGC-PROBE-FPR", "cannot probe with feed per rev mode", loc)
    if s.feed_rate == 0.0:
        raise Diagnostic("NGC-PROBE-ZERO-FEED", "cannot probe with zero feed rate", loc)
    end = find_ends(ctx, w)
    distance = math.dist(end[:3], s.pos[:3])
    if distance < 1e-12 and code in (382, 384):
        # only the probes that fail when not tripped; rs274 2.9 runs a zero-length G38.3/G38.5
        raise Diagnostic(
            "NGC-PROBE-TOO-CLOSE",
            "start point too close to probe point: the probe move is "
            f"{distance:.4f} long (start and end are the same point)",
            loc,
        )
    ctx.emit(canon.TurnProbeOn(source=loc))
    ctx.emit(canon.StraightProbe(*end, source=loc))
    ctx.emit(canon.TurnProbeOff(source=loc))
    # rs274's stand-alone canon reports the probe backed off 0.01 in (0.254 mm) towards
    # the start (saicanon.cc STRAIGHT_PROBE); the interpreter continues from there
    back = 0.01 if s.units is Units.INCHES else 0.254
    start = s.pos if s.tlo_lag is None else [p + d for p, d in zip(s.pos, s.tlo_lag, strict=True)]
    span = math.dist(start[:3], end[:3]) or 1.0
    s.pos = [end[i] + back * (start[i] - end[i]) / span for i in range(3)] + end[3:]
    s.tlo_lag = None
    values = ctx.params.values
    for i in range(6):
        values[5061 + i] = end[i]
    values[5070] = 0.0
    s.probe_flag = True


# --------------------------------------------------------------------------- G33
def synchronised(ctx: NgcContext, w: Words, code: int) -> None:
    """G33 spindle-synchronised feed; G33.1 rigid tapping (in and out)."""
    s = ctx.s
    loc = ctx.loc
    v = w.values
    if "k" not in v:
        raise Diagnostic("NGC-G33-K", "K word missing with G33/G33.1", loc)
    if s.spindle is Direction.STOPPED:
        raise Diagnostic("NGC-G33-SPINDLE", f"spindle not turning in {_g(code)}", loc)
    end = find_ends(ctx, w)
    k = v["k"]
    comp = ctx.comp
    if code == 330 and comp is not None and comp.engaged:
        # LinuxCNC makes a compensated G33 a plain compensated feed (or refuses it)
        ctx.out.extend(comp.straight(s.pos, end, rapid=False, g33=True, source=loc))
        s.pos = end
        return
    ctx.emit(canon.StartSpeedFeedSynch(k, False, source=loc))
    if code == 331:
        ctx.emit(lc.RigidTap(end[0], end[1], end[2], source=loc))
    else:
        ctx.emit(canon.StraightFeed(*end, source=loc))
        s.pos = end
        s.tlo_lag = None
    ctx.emit(canon.StopSpeedFeedSynch(source=loc))


# --------------------------------------------------------------------------- splines
def spline(ctx: NgcContext, w: Words, code: int) -> None:
    """G5 cubic / G5.1 quadratic B-spline: one ``NURBS_FEED`` of order 4 / 3 (rs274)."""
    s = ctx.s
    loc = ctx.loc
    v = w.values
    ctx.comp_off("spline")
    if s.feed_mode == PER_MINUTE and s.feed_rate == 0.0:
        raise Diagnostic("NGC-ZERO-FEED", "cannot make a spline with zero feed rate", loc)
    if s.feed_mode == INVERSE_TIME and "f" not in v:
        raise Diagnostic("NGC-INVERSE-TIME-F", "F word missing with inverse time spline", loc)
    if s.plane is not Plane.XY:
        raise Diagnostic("NGC-SPLINE-PLANE", "splines must be in the XY plane", loc)
    if any(a in v for a in "zabc"):
        raise Diagnostic("NGC-SPLINE-AXES", "splines may not have motion in Z, A, B, or C", loc)
    end = find_ends(ctx, w)
    x0, y0 = s.pos[0], s.pos[1]
    if code == 51:
        if "i" not in v or "j" not in v:
            raise Diagnostic("NGC-SPLINE-IJ", "must specify both I and J with G5.1", loc)
        pts: tuple[tuple[float, float, float], ...] = (
            (x0, y0, 1.0),
            (x0 + v["i"], y0 + v["j"], 1.0),
            (end[0], end[1], 1.0),
        )
        order = 3
    else:
        if ("i" in v) != ("j" in v):
            raise Diagnostic("NGC-SPLINE-IJ", "must specify both I and J, or neither", loc)
        if "i" in v:
            x1, y1 = x0 + v["i"], y0 + v["j"]
        else:
            x1, y1 = x0 + s.spline_i, y0 + s.spline_j
        if "p" not in v or "q" not in v:
            raise Diagnostic("NGC-SPLINE-PQ", "must specify both P and Q with G5", loc)
        x2, y2 = end[0] + v["p"], end[1] + v["q"]
        pts = ((x0, y0, 1.0), (x1, y1, 1.0), (x2, y2, 1.0), (end[0], end[1], 1.0))
        order = 4
        s.spline_i, s.spline_j = -v["p"], -v["q"]
    ctx.emit(canon.NurbsFeed(order, pts, _clamped_knots(len(pts), order), source=loc))
    s.pos = [end[0], end[1], *s.pos[2:]]
    _nurbs_canon_position(s)


def _nurbs_canon_position(s: Setup) -> None:
    """rs274's canon takes its X Y after NURBS_FEED from one past the end of the point list
    (saicanon.cc), which reads as 0 in practice; M6 and G38 continue from there."""
    lag = s.tlo_lag or [0.0] * 6
    s.tlo_lag = [-s.pos[0], -s.pos[1], *lag[2:]]


def _clamped_knots(n: int, order: int) -> tuple[float, ...]:
    """Clamped uniform knot vector with ``n + order`` entries on [0, 1]."""
    inner = n - order
    return (0.0,) * order + tuple((i + 1) / (inner + 1) for i in range(inner)) + (1.0,) * order


def nurbs(ctx: NgcContext, w: Words, code: int) -> None:
    """G5.2 collects control points (X Y with weight P, order L); G5.3 emits them."""
    s = ctx.s
    v = w.values
    loc = ctx.loc
    pts = s.nurbs_points
    if code == 52:
        if ("x" in v) != ("y" in v):
            raise Diagnostic(
                "NGC-NURBS-XY",
                "you must specify both X and Y coordinates for control points",
                loc,
            )
        p = v.get("p", -1.0)
        if p <= 0 and pts:
            raise Diagnostic(
                "NGC-NURBS-WEIGHT", "must specify positive weight P for every control point", loc
            )
        if s.feed_mode == PER_MINUTE and s.feed_rate == 0.0:
            raise Diagnostic("NGC-ZERO-FEED", "cannot make a NURBS with 0 feedrate", loc)
        if not pts:
            weight = p if ("x" not in v and p > 0) else 1.0
            pts.append((s.pos[0], s.pos[1], weight))
            s.nurbs_order = 3
        if "l" in v and v["l"] > 3:
            s.nurbs_order = int(v["l"])
        if "x" in v:
            end = find_ends(ctx, w)
            pts.append((end[0], end[1], p))
        s.motion_mode = 52
        return
    # G5.3
    if len(pts) < s.nurbs_order:
        raise Diagnostic(
            "NGC-NURBS-POINTS",
            f"you must specify a number of control points at least equal to the order "
            f"L = {s.nurbs_order}",
            loc,
        )
    order = s.nurbs_order
    ctx.emit(canon.NurbsFeed(order, tuple(pts), _clamped_knots(len(pts), order), source=loc))
    s.pos = [pts[-1][0], pts[-1][1], *s.pos[2:]]
    _nurbs_canon_position(s)
    s.nurbs_points = []
    s.motion_mode = None


# --------------------------------------------------------------------------- G40-G42
def cutter_comp_mode(ctx: NgcContext, w: Words) -> None:
    """G40 / G41 / G42 / G41.1 / G42.1 through
    :class:`gcode.ngc.comp.cutter_comp.CutterCompensator`."""
    s = ctx.s
    code = w.g[7]
    loc = ctx.loc
    comp = ctx.comp
    if comp is None:
        kind = KeptCompensation if ctx.options.keep_cutter_comp else CutterCompensator
        comp = ctx.comp = kind(comments=ctx.compat)
        comp.set_units(s.units is Units.INCHES)
    side = CompCode(code)
    if side is CompCode.G40:
        off = comp.stop_offset()
        if off is not None:  # the tool's point, taken up by a following tool change
            lag = s.tlo_lag or [0.0] * 6
            s.tlo_lag = [lag[0] + off[0], lag[1] + off[1], lag[2] + off[2], *lag[3:]]
        ctx.out.extend(comp.stop(source=loc))
        s.comp_side = side
        return
    v = w.values
    scale = INCH_MM if s.units is Units.MM else 1.0

    def lookup(number: int | None) -> tuple[float, int] | None:
        tool = ctx.tools.get(s.current_tool if number is None else number)
        if tool is None:
            return None
        return tool.diameter * scale, tool.orientation

    name = _g(code)
    if isinstance(comp, KeptCompensation):
        d = v.get("d")
        by_value = name.endswith(".1")
        register = None if by_value else (int(d) if d else s.current_tool)
        ctx.emit(CompRegister(register, source=loc))
    ctx.out.extend(comp.start(name, s.plane, d=v.get("d"), l=v.get("l"), tool=lookup, source=loc))
    s.comp_side = side
