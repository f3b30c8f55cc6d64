"""Circle geometry of the 840D's G2/G3 forms, in the two coordinates of the active plane
(840D sl programming manual, fundamentals, "Circular interpolation"):

* end point and centre (``I J K``, incremental from the start; ``I=AC(..)`` absolute);
* end point and radius ``CR=`` (negative: more than a half circle);
* end point (or centre) and opening angle ``AR=`` (0 < AR < 360 degrees).

The radius check and its tolerances are LinuxCNC's (gcode.core.arcs) so that a converted
program is accepted by both readers.
"""

from __future__ import annotations

import math

from gcode.core.arcs import (
    R_REACH_INCH,
    R_REACH_MM,
    RADIUS_TOLERANCE_INCH,
    RADIUS_TOLERANCE_MM,
    SPIRAL_RELATIVE_TOLERANCE,
    ZERO_RADIUS_INCH,
    ZERO_RADIUS_MM,
)
from kernel.diagnostics import Diagnostic, Location
from kernel.ir.arcsweep import arc_sweep

Point = tuple[float, float]


def check_centre(start: Point, end: Point, centre: Point, inch: bool, loc: Location) -> None:
    """The radii to start and end must agree (LinuxCNC's centre-arc tolerance)."""
    r1 = math.dist(start, centre)
    r2 = math.dist(end, centre)
    if r1 < (ZERO_RADIUS_INCH if inch else ZERO_RADIUS_MM) or r2 < (
        ZERO_RADIUS_INCH if inch else ZERO_RADIUS_MM
    ):
        raise Diagnostic("SIEM-ARC-RADIUS", "zero-radius arc", loc)
    err = abs(r1 - r2)
    if (
        err > (RADIUS_TOLERANCE_INCH if inch else RADIUS_TOLERANCE_MM)
        and err / max(r1, r2) > SPIRAL_RELATIVE_TOLERANCE
    ):
        raise Diagnostic(
            "SIEM-ARC-RADIUS",
            f"radius to the end ({r2:.4f}) differs from the radius to the start ({r1:.4f})",
            loc,
        )


def centre_from_radius(
    start: Point, end: Point, radius: float, ccw: bool, inch: bool, loc: Location
) -> Point:
    """Centre of a ``CR=`` arc: left of the chord for G3 with CR > 0 (right for G2);
    CR < 0 puts it on the other side (the arc is more than a half circle)."""
    if math.dist(start, end) < 1e-12:
        raise Diagnostic(
            "SIEM-ARC-CR", "CR= cannot state a full circle: the end point is the start point", loc
        )
    half = math.dist(start, end) / 2
    r = abs(radius)
    if r == 0.0 or half - r > (R_REACH_INCH if inch else R_REACH_MM):
        raise Diagnostic("SIEM-ARC-CR", f"radius CR={radius:g} cannot reach the end point", loc)
    h = math.sqrt(max(r * r - half * half, 0.0))
    ux, uy = (end[0] - start[0]) / (2 * half), (end[1] - start[1]) / (2 * half)
    side = 1.0 if ccw == (radius > 0) else -1.0
    mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
    return mx - side * h * uy, my + side * h * ux


def centre_from_angle(start: Point, end: Point, angle: float, ccw: bool, loc: Location) -> Point:
    """Centre of an ``AR=`` arc through ``start`` and ``end`` opening ``angle`` degrees."""
    if not 0.0 < angle < 360.0:
        raise Diagnostic(
            "SIEM-ARC-AR", f"opening angle AR={angle:g} must be within 0..360 degrees", loc
        )
    chord = math.dist(start, end)
    if chord < 1e-12:
        raise Diagnostic("SIEM-ARC-AR", "AR= needs an end point apart from the start", loc)
    half = math.radians(angle) / 2
    d = chord / 2 / math.tan(half)  # distance of the centre from the chord's middle
    ux, uy = (end[0] - start[0]) / chord, (end[1] - start[1]) / chord
    side = 1.0 if ccw else -1.0  # G3: centre left of the chord for angles below 180
    mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
    return mx - side * d * uy, my + side * d * ux


def end_from_angle(start: Point, centre: Point, angle: float, ccw: bool, loc: Location) -> Point:
    """End of an ``AR=`` arc given by its centre: the start turned by ``angle`` degrees."""
    if not 0.0 < angle <= 360.0:
        raise Diagnostic(
            "SIEM-ARC-AR", f"opening angle AR={angle:g} must be within 0..360 degrees", loc
        )
    a = math.radians(angle if ccw else -angle)
    dx, dy = start[0] - centre[0], start[1] - centre[1]
    return (
        centre[0] + dx * math.cos(a) - dy * math.sin(a),
        centre[1] + dx * math.sin(a) + dy * math.cos(a),
    )


def sweep(start: Point, end: Point, centre: Point, turns: int) -> float:
    """Angle swept (radians, positive) by an arc of ``turns`` signed turns (helix length)."""
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
    return abs(arc_sweep(a0, a1, turns))
