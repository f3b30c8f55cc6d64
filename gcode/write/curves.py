"""NURBS and ellipses in the writer: kept where the dialect states them, else approximated.

LinuxCNC G5.2 takes the current position as the first control point and clamped uniform
knots; Fanuc G06.2 takes ``P`` (order), ``K`` (knots), ``R`` (weights). Anything else is
replaced by arcs or chords within the tolerance (:mod:`gcode.write.approximate`) and recorded.
"""

from __future__ import annotations

import numpy as np

from gcode.write import approximate
from gcode.write.approximate import nurbs_problem
from gcode.write.context import WriterContext
from gcode.write.handlers import arc, feed
from gcode.write.state import PLANE_AXES, clamped_uniform_knots
from kernel.ir import canon
from kernel.path.ellipse import ellipse_chords


def nurbs(w: WriterContext, c: canon.NurbsFeed) -> None:
    w.flush()
    problem = nurbs_problem(c)
    if problem:
        w.refuse("CONV-NURBS", problem)
    first, second, normal, _, _ = PLANE_AXES[w.plane]
    s = w.fmt.scale
    pts = np.array(c.points, dtype=float)
    knots = np.array(c.knots, dtype=float) if c.knots else None
    if knots is None or len(knots) != len(pts) + c.order:
        knots = np.array(clamped_uniform_knots(len(pts), c.order))
    span = knots[-1] - knots[0]
    unit = (knots - knots[0]) / span if span > 0 else knots
    start = np.array([w.written(first), w.written(second)]) / s
    on_start = np.allclose(pts[0, :2], start, atol=1e-6)
    uniform = np.allclose(unit, clamped_uniform_knots(len(pts), c.order), atol=1e-9)
    if (
        w.d.nurbs == "g5.2"
        and w.plane == canon.Plane.XY
        and on_start
        and uniform
        and abs(pts[0, 2] - 1.0) < 1e-12
    ):
        lines = [
            f"{first}{w.fmt.length(p[0] * s)} {second}{w.fmt.length(p[1] * s)} "
            f"P{w.fmt.number(p[2])}"
            for p in pts[1:]
        ]
        fw = w.feed_word()
        w.block("G5.2", lines[0], f"L{c.order}", fw)
        for line in lines[1:]:
            w.block(line)
        w.block("G5.3")
        w.motion = None
        _end_at(w, first, second, pts[-1, 0] * s, pts[-1, 1] * s)
        return
    if w.d.nurbs == "g06.2" and on_start:
        fw = w.feed_word()
        for i, p in enumerate(pts):
            lead = ["G06.2", f"P{c.order}"] if i == 0 else []
            w.block(
                *lead,
                f"K{w.fmt.number(knots[i], 6)}",
                f"{first}{w.fmt.length(p[0] * s)}",
                f"{second}{w.fmt.length(p[1] * s)}",
                f"R{w.fmt.number(p[2])}",
                fw if i == 0 else "",
            )
        for k in knots[len(pts) :]:
            w.block(f"K{w.fmt.number(k, 6)}")
        w.motion = None
        _end_at(w, first, second, pts[-1, 0] * s, pts[-1, 1] * s)
        return
    if w.o.on_missing == "refuse":
        w.refuse("CONV-NURBS", f"{w.d.title} cannot state this NURBS curve")
    tol = w.o.tolerance / s

    def curve(u: np.ndarray) -> np.ndarray:
        return approximate.nurbs_evaluate(c.order, pts, knots, u)

    arcs = bool(w.d.arc_formats)
    pieces, worst = approximate.fit_curve(curve, knots[0], knots[-1], tol, arcs, knots)
    _write_pieces(w, c, pieces)
    w.change(
        "CONV-NURBS",
        "approximated",
        f"NURBS of order {c.order} with {len(pts)} points as {len(pieces)} "
        f"{'arcs/lines' if arcs else 'lines'}",
        pieces=len(pieces),
        deviation=worst * s,
        tolerance=w.o.tolerance,
    )


def _end_at(w: WriterContext, first: str, second: str, v1: float, v2: float) -> None:
    w.cur[first], w.cur[second] = v1, v2
    w.words[first] = first + w.fmt.length(v1)
    w.words[second] = second + w.fmt.length(v2)


def _write_pieces(w: WriterContext, c: canon.Command, pieces: list[approximate.Piece]) -> None:
    first, second, normal, _, _ = PLANE_AXES[w.plane]
    s = w.fmt.scale
    z = w.written(normal) / s
    for p in pieces:
        if p.centre is None:
            t = {first: p.end[0], second: p.end[1], normal: z}
            feed(
                w,
                canon.StraightFeed(
                    t["X"], t["Y"], t["Z"], w.cur["A"], w.cur["B"], w.cur["C"], source=c.source
                ),
            )
        else:
            arc(
                w,
                canon.ArcFeed(
                    p.end[0],
                    p.end[1],
                    p.centre[0],
                    p.centre[1],
                    1 if p.ccw else -1,
                    z,
                    w.cur["A"],
                    w.cur["B"],
                    w.cur["C"],
                    source=c.source,
                ),
            )


def ellipse(w: WriterContext, c: canon.EllipseFeed) -> None:
    w.flush()
    if w.o.on_missing == "refuse":
        w.refuse("CONV-ELLIPSE", f"{w.d.title} has no elliptical arcs")
    first, second, normal, _, _ = PLANE_AXES[w.plane]
    s = w.fmt.scale
    start = (w.written(first) / s, w.written(second) / s)
    z0 = w.written(normal) / s
    ch = ellipse_chords(
        start,
        (c.first_end, c.second_end),
        (c.first_axis, c.second_axis),
        c.major,
        c.minor,
        c.angle_to_first,
        c.rotation,
        c.axis_end_point - z0,
        w.o.tolerance / s,
        c.source,
    )
    pts, sag = ch.plane_points(), ch.deviation
    a0 = (w.cur["A"], w.cur["B"], w.cur["C"])
    for p1, p2, f in pts:
        if f == 1.0:  # the last chord ends exactly on the programmed end point
            t = {first: p1, second: p2, normal: c.axis_end_point}
            rot = [c.a, c.b, c.c]
        else:
            t = {first: p1, second: p2, normal: z0 + (c.axis_end_point - z0) * f}
            rot = [a0[i] + (v - a0[i]) * f for i, v in enumerate((c.a, c.b, c.c))]
        feed(w, canon.StraightFeed(t["X"], t["Y"], t["Z"], *rot, source=c.source))
    w.change(
        "CONV-ELLIPSE",
        "approximated",
        f"ELLIPSE_FEED as {len(pts)} lines",
        pieces=len(pts),
        deviation=sag * s,
        tolerance=w.o.tolerance,
    )
