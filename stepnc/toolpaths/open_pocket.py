"""Bottom-and-side and side milling of a rectangular OPEN_POCKET, entered from its open
side (ISO 14649-10 §4.7 open pocket; ISO 14649-11 §4.2.5-4.2.6).

Geometry (choices in docs/stepnc.md): the open boundary is a GENERAL_PROFILE whose curve
is a polyline P0 P1 P2 P3 of three sides of a rectangle (right angles, |P0P1| = |P2P3|);
the segment P3 P0 is the open side, at the edge of the workpiece. The pocket frame has its
origin at the middle of the open side and +X from P0 towards P1 (into the pocket); the two
closed corners at P1 and P2 are rounded with the pocket's orthogonal radius; the floor is
flat (planar bottom condition).

Toolpath: the slot generator's strokes (:mod:`stepnc.toolpaths.slot`) perpendicular to the
open side, from beside the workpiece (tool radius + 1 mm outside the open side) to the
back wall, joined along the back wall and its corner arcs, then (CONTOUR_BIDIRECTIONAL,
the default) one pass along the walls; every layer starts beside the workpiece, so no
plunge into material is needed and the approach strategy is not used.
"""

from __future__ import annotations

import math

from kernel.diagnostics import Diagnostic
from stepnc.executor import TINY
from stepnc.frames import Frame, coords, frame_of
from stepnc.model import Entity, measure
from stepnc.toolpaths.code import Code, place
from stepnc.toolpaths.passes import passes_of
from stepnc.toolpaths.slot import OVERRUN, End, Region, mill, stroke_strategy


def open_pocket_shape(pocket: Entity) -> tuple[float, float, float, float, Frame]:
    """(length into the pocket, width, depth, corner radius, pocket frame in feature
    coordinates) of a rectangular open pocket."""
    boundary = pocket.open_boundary
    curve = boundary.its_profile if boundary.type == "GENERAL_PROFILE" else None
    if not isinstance(curve, Entity) or curve.type != "POLYLINE":
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "open pocket milling supports a GENERAL_PROFILE polyline open boundary",
            pocket.where(),
        )
    if pocket.bottom_condition.type != "PLANAR_POCKET_BOTTOM_CONDITION":
        raise Diagnostic(
            "STEPNC-UNSUPPORTED", "open pocket milling supports planar bottoms", pocket.where()
        )
    placed = frame_of(boundary.placement)
    pts = [placed.point(coords(p)) for p in curve.points]
    bad = len(pts) != 4 or any(abs(p[2] - pts[0][2]) > TINY for p in pts)
    if not bad:
        sides = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:], strict=False)]
        lengths = [math.hypot(*e) for e in sides]
        dots = [abs(a[0] * b[0] + a[1] * b[1]) for a, b in zip(sides, sides[1:], strict=False)]
        bad = (
            min(lengths) <= TINY
            or max(dots) > TINY * max(lengths) ** 2
            or abs(lengths[0] - lengths[2]) > TINY
            or sides[0][0] * sides[2][0] + sides[0][1] * sides[2][1] > 0
        )
    if bad:
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "an open pocket boundary must be three sides of a rectangle (four points)",
            pocket.where(),
        )
    length, width = lengths[0], lengths[1]
    x = (sides[0][0] / length, sides[0][1] / length, 0.0)
    mid = ((pts[0][0] + pts[3][0]) / 2, (pts[0][1] + pts[3][1]) / 2, pts[0][2])
    depth = -float(pocket.depth.position.location.coordinates[2])
    corner = measure(pocket.orthogonal_radius) or 0.0
    if depth <= TINY or corner > min(width / 2.0, length) + TINY:
        raise Diagnostic(
            "STEPNC-POCKET",
            "an open pocket needs a depth plane below its top and a corner radius no larger "
            "than half its width",
            pocket.where(),
        )
    return length, width, depth, corner, Frame(mid, x, (0.0, 0.0, 1.0))


def generate(ex, job) -> None:  # noqa: ANN001
    """Mill the open pocket ``job.feature`` with ``job.op``."""
    op, pocket = job.op, job.feature
    try:
        length, width, depth, corner, frame = open_pocket_shape(pocket)
    except Diagnostic as exc:  # locate it in the workingstep
        raise ex.error(exc.code, exc.message, op) from None
    try:
        ps = passes_of(op, depth)
    except ValueError as exc:
        raise ex.error("STEPNC-POCKET", str(exc), op) from None
    r = ps.diameter / 2.0
    h = width / 2.0 - ps.side - r
    back = length - ps.side - r
    if h < -TINY or back < -TINY or corner - ps.side < r - TINY:
        raise ex.error(
            "STEPNC-TOOL-WIDTH",
            f"tool diameter {ps.diameter:g} does not fit open pocket {pocket.its_id!r} "
            f"({length:g} x {width:g}, corner radius {corner:g}) with side allowance "
            f"{ps.side:g}",
            op,
        )
    contour, ccw = stroke_strategy(ex, op, "open pocket")
    h = max(h, 0.0)
    region = Region(
        h,
        End(-(r + OVERRUN), 0.0, True),
        End(max(back, 0.0), min(max(corner - ps.side - r, 0.0), h)),
    )
    code = Code()
    mill(code, region, ps, contour, ccw, 0.0)
    ex.start_and_run(place(code, job.frame.compose(frame)))
