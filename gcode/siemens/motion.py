"""Motions of the 840D reader: G0, G1, G2/G3 (centre, ``CR=``, ``AR=``, ``TURN=``), G33,
``MEAS=1`` probing and G4 dwell, with per-word ``AC()``/``IC()`` and the programmable frame
(840D sl programming manual, fundamentals, "Travel commands").

Program coordinates are mapped through the frame's rotation/scale/mirror before they reach
the IR (gcode.siemens.frames); an arc in a mirrored plane turns the other way.
"""

from __future__ import annotations

import math

from gcode.siemens import arcs
from gcode.siemens.frames import plane_map
from gcode.siemens.machine import Machine, Values
from gcode.siemens.state import PLANES
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

_AXES = "XYZABC"
_AXIS_SET = frozenset(_AXES)
_CIP_WORDS = frozenset({"I1", "J1", "K1"})
#: the motion code the reader gives CIP (group 1, no G number of its own)
CIP = 1000
_ARC_WORDS = frozenset({"I", "J", "K", "CR", "AR"})


def program_position(ex: Machine) -> list[float]:
    """The current point in program coordinates (the frame's inverse of the IR point)."""
    s = ex.s
    return s.frame.inverse(s.pos) if s.frame.linear else s.pos[:3]


def ends(ex: Machine, vals: Values) -> tuple[list[float], list[float], list[float]]:
    """(start, end) in program coordinates (XYZ) and the IR end point (XYZABC)."""
    s = ex.s
    v, modes = vals.v, vals.modes
    start = program_position(ex)
    end = list(start)
    rot = s.pos[3:]
    rot = list(rot)
    for i, letter in enumerate(_AXES):
        if letter in v:
            mode = modes.get(letter)
            absolute = mode == "AC" or (mode is None and s.absolute)
            if i < 3:
                end[i] = v[letter] if absolute else start[i] + v[letter]
            else:
                rot[i - 3] = v[letter] if absolute else rot[i - 3] + v[letter]
    ir = s.frame.apply(end) if s.frame.linear else list(end)
    return start, end, ir + rot


def execute(ex: Machine, vals: Values, exact_stop: bool) -> bool:
    """The block's motion, if it has one; True when it moved (for modal cycle calls)."""
    v = vals.v
    s = ex.s
    keys = v.keys()
    has_axis = not keys.isdisjoint(_AXIS_SET)
    if "MEAS" in v:
        probe(ex, vals, has_axis)
        return False
    arc_words = not keys.isdisjoint(_ARC_WORDS) and not (
        s.motion == 33 and "I" not in v and "J" not in v
    )
    if not has_axis and not (arc_words and s.motion in (2, 3)):
        if arc_words or "TURN" in v:
            raise Diagnostic(
                "SIEM-ARC-WORDS", "centre or radius words without a G2/G3 motion", ex.loc
            )
        return False
    if not keys.isdisjoint(_CIP_WORDS) and s.motion != CIP:
        raise Diagnostic("SIEM-ARC-WORDS", "I1= J1= K1= (intermediate point) without CIP", ex.loc)
    if arc_words and s.motion not in (2, 3):
        raise Diagnostic("SIEM-ARC-WORDS", f"centre or radius words with G{s.motion}", ex.loc)
    if exact_stop:
        ex.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP, source=ex.loc))
    code = s.motion
    if code == 0:
        _, _, end = ends(ex, vals)
        ex.emit(canon.StraightTraverse(*end, source=ex.loc))
        s.pos = end
    elif code == 1:
        _, _, end = ends(ex, vals)
        _check_feed(ex, vals)
        _inverse_time(ex, vals, math.dist(s.pos[:3], end[:3]) or math.dist(s.pos[3:], end[3:]))
        ex.emit(canon.StraightFeed(*end, source=ex.loc))
        s.pos = end
    elif code in (2, 3):
        arc(ex, vals, code == 3)
    elif code == CIP:
        cip(ex, vals)
    else:
        thread(ex, vals)
    if exact_stop and s.control != 60:
        tol = 0.0
        ex.emit(canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, tol, source=ex.loc))
    return True


def _check_feed(ex: Machine, vals: Values) -> None:
    s = ex.s
    if s.feed_mode == 1:
        if "F" not in vals.v or vals.v["F"] <= 0:
            raise Diagnostic("SIEM-FEED", "G93 (inverse time) needs F in every feed block", ex.loc)
        return
    if s.feed <= 0:
        raise Diagnostic("SIEM-FEED", f"G{s.motion} with feed F0 (no feed programmed)", ex.loc)
    if s.feed_mode == 2 and s.speed <= 0:
        raise Diagnostic("SIEM-FEED", "G95 (feed per revolution) with spindle speed S0", ex.loc)


def _inverse_time(ex: Machine, vals: Values, length: float) -> None:
    """G93: the move lasts 1/F minutes; the IR carries its per-minute rate (as rs274)."""
    s = ex.s
    if s.feed_mode == 1:
        s.feed = max(0.1, length * vals.v["F"])  # LinuxCNC's lower bound, for equal IR
        ex.emit(canon.SetFeedRate(s.feed, source=ex.loc))


def arc(ex: Machine, vals: Values, ccw: bool) -> None:
    s = ex.s
    v, modes = vals.v, vals.modes
    loc = ex.loc
    _, (f, sn, n), (ci, cj) = PLANES[s.plane]
    ck = "IJK"[n]
    if ck in v:
        raise Diagnostic(
            "SIEM-ARC-CENTRE",
            f"{ck} is not a centre word in the G{_g(s.plane)} plane",
            ex.at(vals, ck),
        )
    has_centre = ci in v or cj in v
    forms = sum([has_centre and "AR" not in v, "CR" in v, "AR" in v])
    if forms == 0:
        raise Diagnostic("SIEM-ARC-CENTRE", "circle without centre (I J K), CR= or AR=", loc)
    if "CR" in v and (has_centre or "AR" in v):
        raise Diagnostic("SIEM-ARC-CENTRE", "CR= together with a centre or AR=", loc)
    _check_feed(ex, vals)
    start, end, ir_end = ends(ex, vals)
    st = (start[f], start[sn])
    en = (end[f], end[sn])
    inch = s.units is canon.Units.INCHES
    centre = None
    if has_centre:
        centre = (
            v.get(ci, 0.0) if modes.get(ci) == "AC" else st[0] + v.get(ci, 0.0),
            v.get(cj, 0.0) if modes.get(cj) == "AC" else st[1] + v.get(cj, 0.0),
        )
    if "CR" in v:
        centre = arcs.centre_from_radius(st, en, v["CR"], ccw, inch, loc)
    elif "AR" in v:
        if centre is not None:
            if any(k in v for k in _AXES[:3]):
                raise Diagnostic("SIEM-ARC-AR", "AR= with a centre takes no end point", loc)
            en = arcs.end_from_angle(st, centre, v["AR"], ccw, loc)
            end[f], end[sn] = en
            ir_end[:3] = s.frame.apply(end) if s.frame.linear else list(end)
        else:
            centre = arcs.centre_from_angle(st, en, v["AR"], ccw, loc)
    assert centre is not None
    arcs.check_centre(st, en, centre, inch, loc)
    turns = 1
    if "TURN" in v:
        extra = v["TURN"]
        if extra < 0 or extra != int(extra):
            raise Diagnostic(
                "SIEM-ARC-TURN",
                "TURN= takes a whole number of extra turns >= 0",
                ex.at(vals, "TURN"),
            )
        turns += int(extra)
    _emit_arc(ex, vals, start, ir_end, centre, ccw, turns)


def _emit_arc(
    ex: Machine,
    vals: Values,
    start: list[float],
    ir_end: list[float],
    centre: tuple[float, float],
    ccw: bool,
    turns: int,
) -> None:
    """ARC_FEED for an arc given in program coordinates, through the frame."""
    s = ex.s
    loc = ex.loc
    _, (f, sn, n), _ = PLANES[s.plane]
    c3 = list(start)
    c3[f], c3[sn] = centre
    ir_centre = c3
    if s.frame.linear:
        mapped = plane_map(s.frame, (f, sn, n))
        if mapped is None:
            raise Diagnostic(
                "SIEM-FRAME-ARC",
                "the active frame does not keep circles of this plane circles (rotation out of "
                "the plane or unequal scaling)",
                loc,
            )
        if mapped[1]:
            ccw = not ccw  # 840D: an odd number of mirrored axes reverses G2/G3
        ir_centre = s.frame.apply(c3)
    rotation = turns if ccw else -turns
    if s.feed_mode == 1:
        ir_start = (s.pos[f], s.pos[sn])
        sweep = arcs.sweep(
            ir_start, (ir_end[f], ir_end[sn]), (ir_centre[f], ir_centre[sn]), rotation
        )
        radius = math.dist(ir_start, (ir_centre[f], ir_centre[sn]))
        _inverse_time(ex, vals, math.hypot(radius * sweep, ir_end[n] - s.pos[n]))
    ex.emit(
        canon.ArcFeed(
            ir_end[f],
            ir_end[sn],
            ir_centre[f],
            ir_centre[sn],
            rotation,
            ir_end[n],
            *ir_end[3:],
            source=loc,
        )
    )
    s.pos = ir_end


def cip(ex: Machine, vals: Values) -> None:
    """CIP X Y Z I1= J1= K1=: the circle from the current point through the intermediate
    point to the end point (840D sl fundamentals, "Circular interpolation with
    intermediate point"). The intermediate point follows G90/G91 (and AC()/IC()); the three
    points must lie in the active plane (the IR's arcs are in the principal planes)."""
    s = ex.s
    v, modes = vals.v, vals.modes
    loc = ex.loc
    _, (f, sn, n), _ = PLANES[s.plane]
    if not v.keys() & _CIP_WORDS:
        raise Diagnostic("SIEM-ARC-CIP", "CIP without an intermediate point I1= J1= K1=", loc)
    _check_feed(ex, vals)
    start, end, ir_end = ends(ex, vals)
    mid = list(start)
    for i, letter in enumerate(("I1", "J1", "K1")):
        if letter in v:
            mode = modes.get(letter)
            absolute = mode == "AC" or (mode is None and s.absolute)
            mid[i] = v[letter] if absolute else start[i] + v[letter]
    tol = 1e-6 * max(1.0, *(abs(x) for x in start + end + mid))
    if abs(mid[n] - start[n]) > tol or abs(end[n] - start[n]) > tol:
        raise Diagnostic(
            "SIEM-ARC-CIP",
            f"CIP: the three points must lie in the G{_g(s.plane)} plane (no circle in space)",
            loc,
        )
    (x0, y0), (x1, y1), (x2, y2) = (
        (start[f], start[sn]),
        (mid[f], mid[sn]),
        (end[f], end[sn]),
    )
    cross = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
    chord = max(math.dist((x0, y0), (x2, y2)), math.dist((x0, y0), (x1, y1)))
    if abs(cross) <= 1e-9 * max(chord * chord, 1e-12):
        raise Diagnostic("SIEM-ARC-CIP", "CIP: the three points are on a line", loc)
    # circumcentre of the triangle (start, intermediate, end)
    d = 2 * cross
    s0, s1, s2 = x0 * x0 + y0 * y0, x1 * x1 + y1 * y1, x2 * x2 + y2 * y2
    cx = (s0 * (y1 - y2) + s1 * (y2 - y0) + s2 * (y0 - y1)) / d
    cy = (s0 * (x2 - x1) + s1 * (x0 - x2) + s2 * (x1 - x0)) / d
    _emit_arc(ex, vals, start, ir_end, (cx, cy), cross > 0, 1)


def _g(plane: str) -> int:
    return {"XY": 17, "ZX": 18, "YZ": 19}[plane]


def thread(ex: Machine, vals: Values) -> None:
    """G33 Z.. K..: spindle-synchronised feed, lead K (modal)."""
    s = ex.s
    for letter in ("I", "J"):
        if letter in vals.v:
            raise Diagnostic(
                "SIEM-THREAD",
                f"G33 lead {letter}: only K (along Z) is supported",
                ex.at(vals, letter),
            )
    if "K" in vals.v:
        s.lead = vals.v["K"]
    if s.lead is None or s.lead <= 0:
        raise Diagnostic("SIEM-THREAD", "G33 without a lead K", ex.loc)
    if s.direction is canon.Direction.STOPPED:
        raise Diagnostic("SIEM-THREAD", "G33 with the spindle stopped", ex.loc)
    _, _, end = ends(ex, vals)
    ex.emit(canon.StartSpeedFeedSynch(s.lead, False, source=ex.loc))
    ex.emit(canon.StraightFeed(*end, source=ex.loc))
    ex.emit(canon.StopSpeedFeedSynch(source=ex.loc))
    s.pos = end


def probe(ex: Machine, vals: Values, has_axis: bool) -> None:
    """MEAS=1 G1 X..: a probing move (the reader's probe never trips: it ends at the target)."""
    s = ex.s
    if vals.v["MEAS"] not in (1.0, -1.0, 2.0, -2.0):
        raise Diagnostic(
            "SIEM-PROBE",
            "MEAS= takes the probe number 1 or 2 (negative: deflect)",
            ex.at(vals, "MEAS"),
        )
    if s.motion != 1 or not has_axis:
        raise Diagnostic("SIEM-PROBE", "MEAS= needs a G1 move with axis words", ex.loc)
    _check_feed(ex, vals)
    _, _, end = ends(ex, vals)
    ex.emit(canon.TurnProbeOn(source=ex.loc))
    ex.emit(canon.StraightProbe(*end, source=ex.loc))
    ex.emit(canon.TurnProbeOff(source=ex.loc))
    s.pos = end


def dwell(ex: Machine, vals: Values) -> None:
    """G4 F seconds, or G4 S spindle revolutions (at the programmed speed)."""
    v = vals.v
    if ("F" in v) == ("S" in v):
        raise Diagnostic("SIEM-DWELL", "G4 takes either F (seconds) or S (revolutions)", ex.loc)
    if "F" in v:
        seconds = v["F"]
    else:
        if ex.s.speed <= 0:
            raise Diagnostic("SIEM-DWELL", "G4 S (revolutions) with spindle speed S0", ex.loc)
        seconds = v["S"] / ex.s.speed * 60.0
    if seconds < 0:
        raise Diagnostic("SIEM-DWELL", "negative dwell", ex.loc)
    ex.emit(canon.Dwell(seconds, source=ex.loc))
