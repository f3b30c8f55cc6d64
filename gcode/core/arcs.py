"""Arc geometry for G2/G3: centre format (I J K) and radius format (R) -> ARC_FEED data.

The canonical ``ARC_FEED`` takes the end point, the centre and a signed number of turns
(NISTIR 5970 §3.6.1, end-center-turns format, App. A.3). RS274 gives either the centre
(end-center-direction) or a signed radius (end-radius-direction); both are checked the way
LinuxCNC checks them: the radius to the end may differ from the radius to the start by at
most LinuxCNC's default centre-arc tolerance (0.0028 in, 0.028 mm) or by 0.1 % of the
radius; a radius arc needs ``|R|`` at least half the chord.
"""

from __future__ import annotations

import math

from kernel.diagnostics import Diagnostic, Location

#: smallest arc radius (LinuxCNC TOLERANCE_INCH / TOLERANCE_MM)
ZERO_RADIUS_INCH = 0.0002
ZERO_RADIUS_MM = 0.002
#: allowed start/end radius difference, LinuxCNC's default CENTER_ARC_RADIUS_TOLERANCE
RADIUS_TOLERANCE_INCH = 2 * 0.001 * math.sqrt(2)
RADIUS_TOLERANCE_MM = 2 * 0.01 * math.sqrt(2)
SPIRAL_RELATIVE_TOLERANCE = 0.001
TINY = 1e-12


def turns_for(clockwise: bool, p: float | None, loc: Location) -> int:
    """Signed turn count: -1/+1 for G2/G3, times P full turns when P is given."""
    n = 1
    if p is not None:
        n = round(p)
        if abs(p - n) > 1e-4:
            raise Diagnostic("NGC-ARC-P-INTEGER", "P value not an integer with G2 or G3", loc)
        if n < 1:
            raise Diagnostic("NGC-ARC-P-POSITIVE", "P value must be positive with G2 or G3", loc)
    return -n if clockwise else n


def centre_format(
    start: tuple[float, float],
    end: tuple[float, float],
    centre: tuple[float, float],
    names: tuple[str, str],
    inches: bool,
    loc: Location,
    relative: float | None = None,
    smallest: float | None = None,
) -> None:
    """Check an I J K arc: the radii to start and end must agree (LinuxCNC ``arc_data_ijk``).

    ``relative``: a difference up to this fraction of the start radius is accepted too.
    ``smallest``: the smallest radius (program units) instead of LinuxCNC's.
    """
    r1 = math.hypot(start[0] - centre[0], start[1] - centre[1])
    r2 = math.hypot(end[0] - centre[0], end[1] - centre[1])
    tol = RADIUS_TOLERANCE_INCH if inches else RADIUS_TOLERANCE_MM
    zero = ZERO_RADIUS_INCH if inches else ZERO_RADIUS_MM
    if smallest is not None:
        zero = smallest
    if r1 < zero or r2 < zero:
        raise Diagnostic("NGC-ARC-ZERO-RADIUS", "zero-radius arc", loc)
    abs_err = abs(r1 - r2)
    rel_err = abs_err / (max(r1, r2) or 1.0)
    lenient = relative is not None and abs_err <= relative * r1
    if abs_err > tol and rel_err > SPIRAL_RELATIVE_TOLERANCE and not lenient:
        a, b = (n.upper() for n in names)
        raise Diagnostic(
            "NGC-ARC-RADIUS",
            "radius to end of arc differs from radius to start: "
            f"start=({a}{start[0]:.4f},{b}{start[1]:.4f}) centre=({a}{centre[0]:.4f},"
            f"{b}{centre[1]:.4f}) end=({a}{end[0]:.4f},{b}{end[1]:.4f}) r1={r1:.4f} "
            f"r2={r2:.4f} abs_err={abs_err:.4g} rel_err={rel_err * 100:.4f}%: arc radius "
            f"{r1:.4f} but end point is {r2:.4f} from the centre",
            loc,
        )


#: how far half the chord may exceed |R| (LinuxCNC RADIUS_TOLERANCE_INCH / _MM)
R_REACH_INCH = 0.00005
R_REACH_MM = R_REACH_INCH * 25.4


def radius_format(
    start: tuple[float, float],
    end: tuple[float, float],
    radius: float,
    clockwise: bool,
    loc: Location,
    inches: bool = False,
    r_loc: Location | None = None,
) -> tuple[float, float]:
    """Centre of an R arc (LinuxCNC ``arc_data_r``): negative R means more than 180°.

    Half the chord may exceed ``|R|`` by 0.00005 in (0.00127 mm); the arc is then a
    semicircle. ``r_loc`` is where the R word stands (an R too small is reported there).
    """
    if start == end:
        raise Diagnostic("NGC-ARC-R-SAME-POINT", "current point same as end point of arc", loc)
    abs_r = abs(radius)
    mid = ((end[0] + start[0]) / 2.0, (end[1] + start[1]) / 2.0)
    half = math.hypot(mid[0] - end[0], mid[1] - end[1])
    reach = R_REACH_INCH if inches else R_REACH_MM
    if abs_r == 0.0 or half - abs_r > reach:
        raise Diagnostic(
            "NGC-ARC-R-TOO-SMALL",
            f"arc radius too small to reach end point: |R| is {abs_r:.4f} but half the chord "
            f"is {half:.4f} (the end point is {2 * half:.4f} from the start)",
            r_loc or loc,
        )
    if half / abs_r > 1.0 - TINY:
        half = abs_r  # allow a small error for a semicircle
    theta = math.atan2(end[1] - start[1], end[0] - start[0])
    theta += (
        -math.pi / 2
        if (clockwise and radius > 0) or (not clockwise and radius < 0)
        else (math.pi / 2)
    )
    turn2 = math.acos(max(-1.0, min(1.0, half / abs_r)))
    offset = abs_r * math.sin(turn2)
    return (mid[0] + offset * math.cos(theta), mid[1] + offset * math.sin(theta))
