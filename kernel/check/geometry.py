"""Geometry of canonical motions for the checker: end points, arc data, swept extremes.

ARC_FEED follows NISTIR 5970 §3.6.1 (seed 000): in-plane end, centre, signed turns, end on
the plane normal; the angle atan2(second - centre2, first - centre1) grows for rotation > 0
in all three planes (research/seed-canon-rs274.md, *ARC_FEED argument mapping*).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import kernel.ir.canon as canon
from kernel.check.state import PLANE_AXES, CheckState, Vec6, motion_end
from kernel.ir.arcsweep import arc_sweep

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, slots=True)
class Arc:
    """An ARC_FEED resolved against the current position (program units, radians)."""

    start: Vec6
    end: Vec6
    centre: tuple[float, float]
    r_start: float
    r_end: float
    theta0: float
    sweep: float  # signed, radians
    axes: tuple[int, int, int]


def arc_of(st: CheckState, cmd: canon.ArcFeed) -> Arc:
    """Resolve an ARC_FEED: radii at both ends and the signed swept angle.

    |rotation| = N >= 1 sweeps an angle in ((N-1)·360°, N·360°] (seed 000 §3.6.1);
    rotation 0 has no in-plane motion.
    """
    axes = PLANE_AXES[st.plane]
    i1, i2, _ = axes
    start = st.position
    end = motion_end(st, cmd)
    assert end is not None
    c1, c2 = cmd.first_axis, cmd.second_axis
    r0 = math.hypot(start[i1] - c1, start[i2] - c2)
    r1 = math.hypot(end[i1] - c1, end[i2] - c2)
    t0 = math.atan2(start[i2] - c2, start[i1] - c1)
    t1 = math.atan2(end[i2] - c2, end[i1] - c1)
    return Arc(start, end, (c1, c2), r0, r1, t0, arc_sweep(t0, t1, cmd.rotation), axes)


def arc_extremes(arc: Arc, turned: float = 0.0) -> Iterator[Vec6]:
    """Points an axis-aligned box around the arc must contain: the ends and every
    quadrant point (0°, 90°, 180°, 270°) the sweep passes, at the larger radius.

    ``turned`` (radians) rotates the box's frame: the quadrant points are those of a frame
    turned by it (an XY arc under an XY rotation, boxed in machine coordinates)."""
    yield arc.start
    yield arc.end
    if arc.sweep == 0.0 or not math.isfinite(arc.theta0 + arc.sweep):
        return  # no sweep, or none to place quadrant points on (a NaN or infinite centre)
    i1, i2, _ = arc.axes
    r = max(arc.r_start, arc.r_end)
    lo, hi = sorted((arc.theta0, arc.theta0 + arc.sweep))
    for k in range(4):
        q = k * math.pi / 2 - turned
        # smallest angle >= lo congruent to q
        a = q + math.ceil((lo - q) / TWO_PI) * TWO_PI
        if a <= hi:
            p = list(arc.start)
            p[i1] = arc.centre[0] + r * math.cos(q)
            p[i2] = arc.centre[1] + r * math.sin(q)
            yield (p[0], p[1], p[2], p[3], p[4], p[5])


def swept_points(st: CheckState, cmd: canon.Command) -> list[Vec6]:
    """Points whose bounding box contains the whole move (program coordinates)."""
    end = motion_end(st, cmd)
    if end is None:
        return []
    # under an XY rotation the machine's X and Y are the program's turned by -rotation,
    # so curves in the XY plane are boxed at the machine frame's quadrant angles
    turned = st.rotation if st.plane == canon.Plane.XY else 0.0
    if isinstance(cmd, canon.ArcFeed):
        pts = list(arc_extremes(arc_of(st, cmd), turned))
        # helix: the normal-axis travel is linear, so the end values already bound it
        return pts
    if isinstance(cmd, canon.NurbsFeed):
        # a NURBS curve with positive weights lies in the convex hull of its control points
        i1, i2, _ = PLANE_AXES[st.plane]
        out = [st.position]
        for q in cmd.points:
            p = list(st.position)
            p[i1], p[i2] = q[0], q[1]
            out.append((p[0], p[1], p[2], p[3], p[4], p[5]))
        return out
    if isinstance(cmd, canon.EllipseFeed):
        i1, i2, _ = PLANE_AXES[st.plane]
        half = max(cmd.major, cmd.minor) / 2.0
        out = [st.position, end]
        for k in range(4):
            q = k * math.pi / 2 - turned
            p = list(end)
            p[i1] = cmd.first_axis + half * math.cos(q)
            p[i2] = cmd.second_axis + half * math.sin(q)
            out.append((p[0], p[1], p[2], p[3], p[4], p[5]))
        return out
    return [st.position, end]


def segment_hits_box(
    a: tuple[float, float, float],
    b: tuple[float, float, float],
    lo: tuple[float, float, float],
    hi: tuple[float, float, float],
    eps: float = 1e-6,
) -> bool:
    """Whether the segment a-b enters the open box (lo, hi) shrunk by ``eps`` (slab method)."""
    t0, t1 = 0.0, 1.0
    for k in range(3):
        lo_k, hi_k = lo[k] + eps, hi[k] - eps
        d = b[k] - a[k]
        if abs(d) < 1e-15:
            if not lo_k < a[k] < hi_k:
                return False
            continue
        u0, u1 = (lo_k - a[k]) / d, (hi_k - a[k]) / d
        if u0 > u1:
            u0, u1 = u1, u0
        t0, t1 = max(t0, u0), min(t1, u1)
        if t0 >= t1:
            return False
    return True


def box_overlaps(
    pts: list[tuple[float, float, float]],
    lo: tuple[float, float, float],
    hi: tuple[float, float, float],
    eps: float = 1e-6,
) -> bool:
    """Whether the bounding box of ``pts`` overlaps the open box (lo, hi) shrunk by ``eps``."""
    for k in range(3):
        if max(p[k] for p in pts) <= lo[k] + eps or min(p[k] for p in pts) >= hi[k] - eps:
            return False
    return True
