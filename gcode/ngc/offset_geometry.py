"""Plane geometry of cutter radius compensation (LinuxCNC ``interp_convert.cc``).

Pure functions over plane coordinates ``(first, second)`` of the selected plane (XY: x, y;
XZ: z, x, as in ``ARC_FEED``), used by :mod:`gcode.ngc.comp.cutter_comp`. Angles are radians,
``side`` is +1 for left (G41) and -1 for right (G42), ``turn`` is the signed turn count of
``ARC_FEED`` (+ counter-clockwise). Every formula is the one LinuxCNC's interpreter uses
(``convert_straight_comp1/2``, ``convert_arc_comp1/2``, ``find_turn``; semantics learnt from
the LinuxCNC source, not copied), so that the compensated path agrees with rs274's to
rounding. The book (research/seed-book-interp.md §2.3.4) only states the principle: the
tool-centre path lies at distance R from the programmed path, left (G41) or right (G42) of
the direction of travel, and consecutive offsets are *connected*; Figs. 2.16/2.17 with the
connection rules did not survive, so LinuxCNC is the reference for the corners:

* convex corner (the path turns away from the tool): an arc of radius R around the
  programmed corner point joins the two offset elements;
* concave corner (the path turns towards the tool): the held previous element is cut back to
  the intersection of the two offset elements (line/line, line/arc, arc/line, arc/arc);
* tangent continuation (within :data:`SMALL` rad): the elements simply meet.
"""

from __future__ import annotations

import functools
import math
from typing import Any

#: LinuxCNC ``TOLERANCE_CONCAVE_CORNER``: corners within this angle (rad) count as tangent.
SMALL = 0.05
#: LinuxCNC ``TOLERANCE_EQUAL``.
TOLERANCE_EQUAL = 0.0001
HALF_PI = math.pi / 2
TWO_PI = 2 * math.pi


@functools.cache
def _long_double() -> tuple[Any, Any, Any]:
    """numpy's long double, its sine and ``M_PIl``, imported on first use: only cutter
    compensation needs them, and a program without it then starts without numpy."""
    import numpy as np

    return np.longdouble, np.sin, np.longdouble("3.14159265358979323846264338327950288")


def plus_pi(angle: float, k: float) -> float:
    """``angle + k * M_PIl`` as LinuxCNC's C++ computes it: its angle constants are long
    double, so the sum is long double until stored in a double. Matching that keeps our last
    bit, and so rs274's rounding at a printed fourth decimal, the same.

    numpy's long double scalars take about 3 us a sum; a contour's angles come back (each
    lap or depth pass of a compensated contour), so results are kept (bounded)."""
    key = (angle, k)
    found = _PLUS_PI.get(key)
    if found is not None:
        return found
    _LD, _sin, _PI_LD = _long_double()
    result = float(_LD(angle) + _LD(k) * _PI_LD)
    if len(_PLUS_PI) >= 65536:
        _PLUS_PI.clear()
    _PLUS_PI[key] = result
    return result


#: :func:`plus_pi`'s results by (angle, k): a pure function of its two numbers
_PLUS_PI: dict[tuple[float, float], float] = {}


Point = tuple[float, float]


def find_turn(start: Point, centre: Point, turn: int, end: Point) -> float:
    """Signed swept angle of an arc (LinuxCNC ``find_turn``): + CCW, 0 when ``turn`` is 0.

    ``|turn|`` > 1 adds full circles; a zero-length arc with ``turn`` != 0 is a full circle.
    """
    if turn == 0:
        return 0.0
    alpha = math.atan2(start[1] - centre[1], start[0] - centre[0])
    beta = math.atan2(end[1] - centre[1], end[0] - centre[0])
    if turn > 0:
        if beta <= alpha:
            beta = plus_pi(beta, 2)
        return plus_pi(beta - alpha, 2 * (turn - 1))
    if alpha <= beta:
        alpha = plus_pi(alpha, 2)
    return plus_pi(beta - alpha, 2 * (turn + 1))


def tool_inside_arc(side: int, turn: int) -> bool:
    """LinuxCNC ``TOOL_INSIDE_ARC``: left of a CCW arc or right of a CW arc."""
    return (side > 0 and turn > 0) or (side < 0 and turn < 0)


def offset_point(p: Point, angle: float, radius: float) -> Point:
    """``p`` moved by ``radius`` in direction ``angle``."""
    return (p[0] + radius * math.cos(angle), p[1] + radius * math.sin(angle))


def entry_line_end(current: Point, target: Point, side: int, radius: float) -> tuple[Point, float]:
    """First straight move after G41/G42 (``convert_straight_comp1``).

    The tool goes straight from where it is to the point one radius beside the programmed
    end, perpendicular to the line from the current point to that end. Returns the
    compensated end and the perpendicular's direction ``alpha`` (LinuxCNC queues the move
    with ``(cos alpha, sin alpha)`` as its "direction", which the gouge test later uses).
    """
    alpha = plus_pi(math.atan2(target[1] - current[1], target[0] - current[0]), side / 2)
    return offset_point(target, alpha, radius), alpha


def line_corner(
    current: Point, programmed: Point, target: Point, side: int
) -> tuple[float, float, float, float]:
    """Corner classification before a straight move (``convert_straight_comp2``).

    ``current`` is the compensated tool position at the end of the previous element,
    ``programmed`` the programmed corner, ``target`` the programmed end of the new line.
    Returns ``(beta, theta, alpha, gamma)``: ``beta`` is the corner angle less 90° (< 0 or
    > 180° concave, > :data:`SMALL` convex), ``theta`` the direction from the corner to the
    tool, ``alpha`` the new line's direction and ``gamma`` the offset direction relative to
    it (+90° left, -90° right).
    """
    theta = math.atan2(current[1] - programmed[1], current[0] - programmed[0])
    alpha = math.atan2(target[1] - programmed[1], target[0] - programmed[0])
    if side > 0:
        if theta < alpha:
            theta = plus_pi(theta, 2)
        return plus_pi(theta - alpha, -0.5), theta, alpha, HALF_PI
    if alpha < theta:
        alpha = plus_pi(alpha, 2)
    return plus_pi(alpha - theta, -0.5), theta, alpha, -HALF_PI


def line_line_retreat(beta: float, radius: float) -> float:
    """How far the previous offset line is cut back at a concave line/line corner.

    The inside corner angle is ``beta + 180°``; the offset lines meet ``R / tan(half)``
    before the end of the previous offset line. LinuxCNC computes the half angle in long
    double, so it is never exactly zero (its "zero degree inside corner" test cannot fire);
    a path that doubles back is cut back a very long way and then fails the gouge test.
    """
    _LD, _sin, _PI_LD = _long_double()
    half = float((_LD(beta) + _PI_LD) / 2)
    return radius / math.tan(half)


def normalise_beta(beta: float) -> float:
    """Bring an arc corner angle into LinuxCNC's range (-90°, 270°]."""
    _LD, _sin, _PI_LD = _long_double()
    if _LD(beta) > _LD(1.5) * _PI_LD:
        return plus_pi(beta, -2)
    if _LD(beta) < -_PI_LD / 2:
        return plus_pi(beta, 2)
    return beta


def arc_entry_centre(current: Point, end: Point, centre: Point) -> Point | None:
    """Centre of the first compensated arc after G41/G42 (``convert_arc_comp1``).

    ``end`` is the *compensated* end point, ``centre`` the programmed arc's centre. The new
    centre lies on the line end->centre, equidistant from ``current`` and ``end``. ``None``
    when that is impossible (LinuxCNC: tool radius not less than arc radius).
    """
    b_len = math.hypot(current[1] - end[1], current[0] - end[0]) / 2.0
    ab_ang = math.atan2(centre[1] - end[1], centre[0] - end[0])
    a_ang = math.atan2(current[1] - end[1], current[0] - end[0]) - ab_ang
    if abs(math.cos(a_ang)) < TOLERANCE_EQUAL:
        return None
    c_len = b_len / math.cos(a_ang)
    return offset_point(end, ab_ang, c_len)


def line_to_arc_meet(
    centre: Point,
    arc_radius: float,
    tool_radius: float,
    beta: float,
    theta: float,
    turn: int,
    side: int,
) -> Point | None:
    """Where a held offset line meets the offset of a following arc at a concave corner.

    ``theta`` is the direction of travel at the end of the line (``convert_arc_comp2``).
    ``None`` when the tool cannot reach the arc without gouging.
    """
    _LD, _sin, _PI_LD = _long_double()
    cy = float(_LD(arc_radius) * _sin(_LD(beta) - _PI_LD / 2))
    if tool_inside_arc(side, turn):
        dist = arc_radius - tool_radius
        ratio = (cy + tool_radius) / dist
        if ratio > 1.0 or ratio < -1.0:
            return None
        angle = theta + math.asin(ratio) if turn > 0 else theta - math.asin(ratio)
    else:
        dist = arc_radius + tool_radius
        ratio = (cy - tool_radius) / dist
        if ratio > 1.0 or ratio < -1.0:
            return None
        sign = -1 if turn > 0 else 1
        angle = float(_LD(theta) + _PI_LD + sign * _LD(math.asin(ratio)))
    return offset_point(centre, angle, dist)


def arc_to_arc_meet(
    prev_centre: Point,
    prev_radius: float,
    prev_turn: int,
    centre: Point,
    new_radius: float,
    turn: int,
    side: int,
) -> Point | None:
    """Intersection of a held offset arc with the next offset arc (concave arc/arc corner).

    ``prev_radius`` and ``new_radius`` are the *offset* radii. Uses the law of cosines on the
    triangle of the two centres and the meeting point. ``None`` if the circles do not meet.
    """
    arc_cc = math.hypot(prev_centre[1] - centre[1], prev_centre[0] - centre[0])
    cos_a = (prev_radius**2 + arc_cc**2 - new_radius**2) / (2 * prev_radius * arc_cc)
    if cos_a > 1.0 or cos_a < -1.0:
        return None
    pullback = math.acos(cos_a)
    cc_dir = math.atan2(centre[1] - prev_centre[1], centre[0] - prev_centre[0])
    if tool_inside_arc(side, prev_turn):
        direction = cc_dir + pullback if turn > 0 else cc_dir - pullback
    else:
        direction = cc_dir - pullback if turn > 0 else cc_dir + pullback
    return offset_point(prev_centre, direction, prev_radius)


def arc_to_line_meet(
    prev_centre: Point,
    prev_radius: float,
    prev_turn: int,
    programmed: Point,
    target: Point,
    tool_radius: float,
    side: int,
) -> Point | None:
    """Intersection of a held offset arc with the next offset line (concave arc/line corner).

    ``prev_radius`` is the held (compensated) arc's radius, ``programmed`` the corner and
    ``target`` the new line's programmed end. ``None`` if they do not meet.
    """
    base_dir = math.atan2(target[1] - programmed[1], target[0] - programmed[0])
    theta = plus_pi(base_dir, 0.5 if prev_turn > 0 else -0.5)
    phi = math.atan2(prev_centre[1] - programmed[1], prev_centre[0] - programmed[0])
    inside = tool_inside_arc(side, prev_turn)
    uncomp = prev_radius + tool_radius if inside else prev_radius - tool_radius
    d = uncomp * math.cos(theta - phi)  # old centre's distance from the new line
    if inside:
        ratio = (d - tool_radius) / prev_radius
        if ratio > 1.0 or ratio < -1.0:
            return None
        sign = -1.0 if prev_turn > 0 else 1.0
    else:
        ratio = (d + tool_radius) / prev_radius
        if ratio > 1.0 or ratio < -1.0:
            return None
        sign = 1.0 if prev_turn > 0 else -1.0
    return offset_point(prev_centre, plus_pi(sign * math.acos(ratio) + theta, 1), prev_radius)
