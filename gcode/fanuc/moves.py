"""Motion under the programmable transforms, and G06.2 NURBS blocks.

:func:`transform_block` turns a motion block given in program coordinates (absolute or
incremental, Cartesian or G16 polar) into absolute transformed words for the RS274/NGC
executor: end point and arc centre mapped by :class:`~gcode.fanuc.transforms.Transforms`,
``R`` arcs turned into centres first (gcode.core.arcs, the RS274 rule: R > 0 up to a half
circle), G02/G03 swapped under an odd mirror. Canned cycles map their hole position only.
"""

from __future__ import annotations

import math

from gcode.core import arcs
from gcode.core.codes import Words
from gcode.fanuc.state import ExecutorState, NurbsCollector
from gcode.fanuc.transforms import polar_to_cartesian
from gcode.fanuc.words import CYCLES
from gcode.ngc.motion import PLANE_AXES, PLANE_CENTRE
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane, Units

AXES = "xyzabc"
_UPPER = "XYZ"


def _prog_pos(ex: ExecutorState) -> list[float]:
    pos = ex.ip.s.pos
    return ex.tf.inverse(pos[:3]) + list(pos[3:])


# --------------------------------------------------------------------------- set-up
def start_scaling(ex: ExecutorState, v: dict[str, float], loc: Location) -> None:
    """G51 X Y Z (centre, default the current position) P (all axes) or I J K (per axis)."""
    tf = ex.tf
    here = _prog_pos(ex)
    tf.scale_centre = [v.get(a, here[i]) for i, a in enumerate(_UPPER)]
    if "P" in v:
        tf.scale = [v["P"]] * 3
    elif any(k in v for k in "IJK"):
        tf.scale = [v.get(k, 1.0) for k in "IJK"]
    else:
        raise Diagnostic("FANUC-G51", "G51 needs a magnification P or I J K", loc)
    if any(abs(f) < 1e-9 for f in tf.scale):
        raise Diagnostic("FANUC-G51", "scaling magnification of zero", loc)
    tf.scale_on = True


def start_mirror(ex: ExecutorState, v: dict[str, float], loc: Location, absolute: bool) -> None:
    """G51.1 X Y Z: mirror about the given axis values."""
    here = _prog_pos(ex)
    given = [a for a in _UPPER if a in v]
    if not given:
        raise Diagnostic("FANUC-G51-1", "G51.1 needs the mirror axis (X, Y or Z)", loc)
    for i, a in enumerate(_UPPER):
        if a in v:
            ex.tf.mirror[i] = v[a] if absolute else here[i] + v[a]


def stop_mirror(ex: ExecutorState, v: dict[str, float]) -> None:
    """G50.1 X Y Z: cancel the mirror of the given axes (all when none is given)."""
    given = [i for i, a in enumerate(_UPPER) if a in v] or [0, 1, 2]
    for i in given:
        ex.tf.mirror[i] = None


def start_rotation(
    ex: ExecutorState, v: dict[str, float], plane: Plane, absolute: bool, loc: Location
) -> None:
    """G68 a b R: rotation by R degrees about (a, b) in the plane active at G68."""
    tf = ex.tf
    f1, f2, _ = PLANE_AXES[plane]
    here = _prog_pos(ex)
    n1, n2 = _UPPER[f1], _UPPER[f2]
    c1 = v.get(n1, here[f1] if absolute else 0.0)
    c2 = v.get(n2, here[f2] if absolute else 0.0)
    if not absolute:
        c1, c2 = here[f1] + (v.get(n1, 0.0)), here[f2] + (v.get(n2, 0.0))
    if any(k in v for k in "IJK"):
        raise Diagnostic("FANUC-G68-3D", "3-D coordinate rotation (G68 I J K) is not read", loc)
    tf.rot_axes = (f1, f2)
    tf.rot_centre = (c1, c2)
    tf.rot_angle = v.get("R", 0.0) + (tf.rot_angle if (not absolute and tf.rotate_on) else 0.0)
    tf.rotate_on = True


# --------------------------------------------------------------------------- motion
def transform_block(
    ex: ExecutorState, w: Words, plane: Plane, absolute: bool, loc: Location
) -> None:
    """Rewrite the motion words of ``w`` as absolute transformed coordinates."""
    s = ex.ip.s
    tf = ex.tf
    v = w.values
    code = w.g.get(1, ex.motion)
    f1, f2, fn = PLANE_AXES[plane]
    start = _prog_pos(ex)
    end = [v.get(a, start[i]) if absolute else start[i] + v.get(a, 0.0) for i, a in enumerate(AXES)]
    if tf.polar:
        a1, a2 = AXES[f1], AXES[f2]
        if absolute:  # about the work origin; an omitted radius or angle is the current one
            centre = (0.0, 0.0)
            radius = v.get(a1, math.hypot(start[f1], start[f2]))
            angle = v.get(a2, math.degrees(math.atan2(start[f2], start[f1])))
        else:  # about the current position; the angle adds to the last commanded one
            centre = (start[f1], start[f2])
            radius = v.get(a1, tf.polar_last[0])
            angle = tf.polar_last[1] + v.get(a2, 0.0)
        tf.polar_last = (radius, angle)
        end[f1], end[f2] = polar_to_cartesian(radius, angle, centre)
    if code in CYCLES:
        if not absolute or tf.scale_on:
            raise Diagnostic(
                "FANUC-TRANSFORM-CYCLE",
                "canned cycles under scaling or in G91 with a transform are not read",
                loc,
            )
        moved = tf.forward(end[:3])
        for i in (f1, f2):
            v[AXES[i]] = moved[i]
    elif code in (0, 10, 20, 30):
        moved = tf.forward(end[:3]) + end[3:]
        for i, a in enumerate(AXES):
            if a in v or i < 3:
                v[a] = moved[i]
        if code in (20, 30):
            _arc(ex, w, code, plane, start, end, loc)
    else:
        raise Diagnostic(
            "FANUC-TRANSFORM-MOTION", "this motion is not read under G16/G51/G51.1/G68", loc
        )
    w.g.pop(3, None)
    s.absolute = True


def _arc(
    ex: ExecutorState,
    w: Words,
    code: int,
    plane: Plane,
    start: list[float],
    end: list[float],
    loc: Location,
) -> None:
    s = ex.ip.s
    tf = ex.tf
    v = w.values
    f1, f2, _ = PLANE_AXES[plane]
    ci, cj, ck = PLANE_CENTRE[plane]
    if tf.radius_factor((f1, f2)) is None:
        raise Diagnostic(
            "FANUC-SCALE-ARC", "an arc under different magnifications per axis is an ellipse", loc
        )
    st, en = (start[f1], start[f2]), (end[f1], end[f2])
    if "r" in v:
        inches = s.units is Units.INCHES
        centre = arcs.radius_format(st, en, v.pop("r"), code == 20, loc, inches)
    else:
        centre = (st[0] + v.pop(ci, 0.0), st[1] + v.pop(cj, 0.0))
    c3 = list(start[:3])
    c3[f1], c3[f2] = centre
    moved = tf.forward(c3)
    v.pop(ck, None)
    v[ci] = moved[f1] - s.pos[f1]
    v[cj] = moved[f2] - s.pos[f2]
    flip = tf.flips((f1, f2))
    w.g[1] = (30 if code == 20 else 20) if flip else code


# --------------------------------------------------------------------------- G06.2
def nurbs_block(
    ex: ExecutorState, v: dict[str, float], loc: Location, start: bool
) -> NurbsCollector | None:
    """One G06.2 block (``start``) or continuation block; the collector, or None once the
    last knot is read and ``NURBS_FEED`` is emitted."""
    ip = ex.ip
    s = ip.s
    if ex.tf.active or ex.tf.polar:
        raise Diagnostic("FANUC-TRANSFORM-NURBS", "G06.2 under a transform is not read", loc)
    if s.plane is not Plane.XY:
        raise Diagnostic("FANUC-NURBS-PLANE", "G06.2 is read in the XY plane only", loc)
    if "F" in v:
        ip.execute(Words(values={"f": v["F"]}))
    if start:
        if ex.nurbs is not None:
            raise Diagnostic("FANUC-NURBS-INCOMPLETE", "G06.2 inside a G06.2 curve", loc)
        order = v.get("P", 4.0)
        if order != round(order) or not 2 <= order <= 6:
            raise Diagnostic("FANUC-NURBS-ORDER", "G06.2 order P must be 2..6", loc)
        col = NurbsCollector(int(order), loc=loc)
    else:
        assert ex.nurbs is not None
        col = ex.nurbs
    if "K" not in v:
        raise Diagnostic("FANUC-NURBS-KNOT", "every G06.2 block needs a knot K", loc)
    if col.knots and v["K"] < col.knots[-1] - 1e-12:
        raise Diagnostic("FANUC-NURBS-KNOT", "knots must not decrease", loc)
    col.knots.append(v["K"])
    if "X" in v or "Y" in v:
        if col.end_knots:
            raise Diagnostic("FANUC-NURBS-KNOT", "control point after the end knots", loc)
        if "Z" in v and abs((v["Z"] if s.absolute else s.pos[2] + v["Z"]) - s.pos[2]) > 1e-9:
            raise Diagnostic("FANUC-NURBS-3D", "G06.2 with Z motion is not read", loc)
        last = col.points[-1] if col.points else (s.pos[0], s.pos[1], 1.0)
        if s.absolute:
            x, y = v.get("X", last[0]), v.get("Y", last[1])
        else:
            x, y = last[0] + v.get("X", 0.0), last[1] + v.get("Y", 0.0)
        weight = v.get("R", 1.0)
        if weight <= 0:
            raise Diagnostic("FANUC-NURBS-WEIGHT", "G06.2 weight R must be positive", loc)
        if not col.points and math.hypot(x - s.pos[0], y - s.pos[1]) > 1e-4:
            raise Diagnostic(
                "FANUC-NURBS-START", "the first G06.2 control point must be the start point", loc
            )
        col.points.append((x, y, weight))
        return col
    col.end_knots += 1
    if col.end_knots < col.order:
        return col
    if len(col.points) < col.order:
        raise Diagnostic("FANUC-NURBS-POINTS", "fewer control points than the order", loc)
    if s.feed_rate == 0.0:
        raise Diagnostic("FANUC-ZERO-FEED", "G06.2 with zero feed rate", loc)
    ip.emit(canon.NurbsFeed(col.order, tuple(col.points), tuple(col.knots), source=loc))
    x, y, _ = col.points[-1]
    s.pos = [x, y, *s.pos[2:]]
    return None
