"""Explicit toolpaths of a FREEFORM_OPERATION (ISO 14649-10 §4.8): a TOOLPATH_LIST of
CUTTER_LOCATION_TRAJECTORY (tool-tip curves in feature coordinates) and FEEDSTOP.

Curves: POLYLINE, TRIMMED_CURVE on a LINE, CIRCLE or HELIX (trimmed by points),
COMPOSITE_CURVE, and planar B_SPLINE_CURVE_WITH_KNOTS (emitted as one NURBS_FEED in the
XY plane, NISTIR 5970 App. A.7). ``TRAJECTORY_PATH`` moves at feed, ``CONNECT`` at
traverse, as in NIST's ``op_trajectory``. Consecutive segments must join (a gap is
``STEPNC-PATH-GAP``); the first point is reached with the security-plane approach.
"""

from __future__ import annotations

import math

from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.executor import TINY
from stepnc.frames import Frame, coords, frame_of
from stepnc.model import Entity
from stepnc.toolpaths.code import Code, place

Vec = tuple[float, float, float]


def generate(ex, job) -> None:  # noqa: ANN001
    op = job.op
    tpl = op.its_toolpath
    if tpl is None or not tpl.its_list:
        raise ex.error("STEPNC-NO-TOOLPATH", f"{op.type} needs an explicit toolpath list", op)
    if not job.frame.vertical:
        raise ex.error(
            "STEPNC-PLACEMENT",
            "explicit toolpaths need a feature Z axis along the machine Z axis",
            op,
        )
    join: Vec | None = None
    for seg in tpl.its_list:
        # a segment's own technology and machine functions override the operation's for that
        # segment only (ISO 14649-10 §4.8.1; NIST op_freeform); output is on change only
        ex.machine_functions(seg.its_machine_functions or op.its_machine_functions)
        ex.technology(seg.its_technology or op.its_technology, op.its_tool)
        if seg.type == "FEEDSTOP":
            ex.emit(canon.Dwell(float(seg.dwell)))
            continue
        if seg.its_direction is False:
            raise ex.error(
                "STEPNC-UNSUPPORTED", "trajectories followed backwards are not supported", seg
            )
        rapid = seg.its_type == "CONNECT"
        if seg.its_type not in ("CONNECT", "TRAJECTORY_PATH"):
            raise ex.error(
                "STEPNC-UNSUPPORTED",
                f"toolpath type {seg.its_type} is not supported (TRAJECTORY_PATH, CONNECT)",
                seg,
            )
        code = Code()
        nurbs: list[canon.NurbsFeed] = []
        first = join is None
        join = _curve(ex, seg.basiccurve, code, rapid, join, nurbs, job.frame)
        placed = place(code, job.frame)
        if first:
            ex.start_and_run(placed)
        else:
            ex.run(placed)
        for n in nurbs:
            ex.emit(n)
            ex.x, ex.y = n.points[-1][0], n.points[-1][1]


def _point(p: Entity) -> Vec:
    return coords(p)


def _start(code: Code, p: Vec, join: Vec | None, ex, seg: Entity) -> None:  # noqa: ANN001
    if join is None:
        code.feed(*p)
    elif math.dist(join, p) > TINY:
        raise ex.error(
            "STEPNC-PATH-GAP",
            f"trajectory #{seg.id} starts at {p}, not at the end {join} of the previous segment",
            seg,
        )


def _curve(
    ex,
    curve: Entity,
    code: Code,
    rapid: bool,
    join: Vec | None,  # noqa: ANN001
    nurbs: list,
    frame: Frame,
) -> Vec:
    move = code.traverse if rapid else code.feed
    t = curve.type
    if t == "POLYLINE":
        pts = [_point(p) for p in curve.points]
        if len(pts) < 2:
            raise ex.error("STEPNC-CURVE", "a polyline needs two points", curve)
        _start(code, pts[0], join, ex, curve)
        for p in pts[1:]:
            move(*p)
        return pts[-1]
    if t == "COMPOSITE_CURVE":
        for seg in curve.segments:
            if seg.parent_curve.type == "B_SPLINE_CURVE_WITH_KNOTS":
                raise ex.error(
                    "STEPNC-UNSUPPORTED", "B-splines inside composite curves are not supported", seg
                )
            if seg.same_sense is False:
                raise ex.error(
                    "STEPNC-UNSUPPORTED", "reversed composite curve segments are not supported", seg
                )
            join = _curve(ex, seg.parent_curve, code, rapid, join, nurbs, frame)
        assert join is not None
        return join
    if t == "TRIMMED_CURVE":
        trims = (curve.trim_1, curve.trim_2)
        if any(
            len(tr) != 1 or not isinstance(tr[0], Entity) or tr[0].type != "CARTESIAN_POINT"
            for tr in trims
        ):
            raise ex.error(
                "STEPNC-CURVE",
                "trimmed curves must be trimmed by one cartesian point at each end",
                curve,
            )
        a, b = _point(trims[0][0]), _point(trims[1][0])
        _start(code, a, join, ex, curve)
        basis = curve.basis_curve
        if basis.type == "LINE":
            move(*b)
        elif basis.type in ("CIRCLE", "HELIX"):
            if rapid:
                raise ex.error("STEPNC-UNSUPPORTED", "arcs cannot be traversed at rapid", curve)
            pl = frame_of(basis.position)
            if not pl.vertical:
                raise ex.error("STEPNC-UNSUPPORTED", "arc axes must be parallel to Z", basis)
            cx, cy = pl.origin[0], pl.origin[1]
            if basis.type == "CIRCLE":
                turns = 1 if curve.sense_agreement else -1
            else:
                rotation = (b[2] - a[2]) / float(basis.pitch)
                turns = (
                    int((1 - TINY) + rotation)
                    if rotation > 0
                    else int((TINY - 1) + rotation)
                    if rotation < 0
                    else 0
                )
            code.arc(b[0], b[1], cx, cy, turns, b[2])
        else:
            raise ex.error("STEPNC-UNSUPPORTED", f"trimmed {basis.type} is not supported", curve)
        return b
    if t == "B_SPLINE_CURVE_WITH_KNOTS":
        if rapid:
            raise ex.error("STEPNC-UNSUPPORTED", "B-splines cannot be traversed at rapid", curve)
        pts = [frame.point(_point(p)) for p in curve.control_points_list]
        if max(p[2] for p in pts) - min(p[2] for p in pts) > TINY:
            raise ex.error(
                "STEPNC-UNSUPPORTED",
                "only B-splines in a plane of constant Z can be sent as NURBS_FEED",
                curve,
            )
        order = int(curve.degree) + 1
        counts = [int(m) for m in curve.knot_multiplicities]
        # counted before the knots are listed: a multiplicity of 1e9 would list a billion
        if (
            order < 2
            or len(counts) != len(curve.knots)
            or min(counts, default=0) < 1
            or sum(counts) != len(pts) + order
        ):
            raise ex.error(
                "STEPNC-CURVE",
                f"B-spline of degree {curve.degree} with knot multiplicities adding up to "
                f"{sum(counts)}: needs degree >= 1, one multiplicity >= 1 per knot and "
                f"{len(pts)} control points + degree + 1 knots",
                curve,
            )
        knots: list[float] = []
        for k, m in zip(curve.knots, counts, strict=True):
            knots.extend([float(k)] * m)
        first = _point(curve.control_points_list[0])
        _start(code, first, join, ex, curve)
        nurbs.append(canon.NurbsFeed(order, tuple((p[0], p[1], 1.0) for p in pts), tuple(knots)))
        last = _point(curve.control_points_list[-1])
        return last
    raise Diagnostic(
        "STEPNC-UNSUPPORTED", f"curve {t} is not supported as a toolpath", curve.where()
    )


#: a curve followed into placed-ready pseudocode (AP238 cutter-location toolpaths use it too)
follow_curve = _curve
