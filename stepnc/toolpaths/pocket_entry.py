"""Entry moves into a pocket layer (ISO 14649-11 §4.2.7 approach strategies; NIST's
``find_pocket_plunge_start*`` and ``enter_pocket_pass*``): plunge along the tool axis, ramp,
zigzag and helix, all ending at the -X end of the pocket's centre line (``end_x``, 0).

An approach is ``(kind, args)``: ``("PLUNGE_RAMP", (angle,))``,
``("PLUNGE_ZIGZAG", (angle, width))``, ``("PLUNGE_HELIX", (radius, angle))``.
"""

from __future__ import annotations

import math

from stepnc.executor import TINY
from stepnc.toolpaths.code import Code, check_count


def tand(deg: float) -> float:
    return math.tan(math.radians(deg))


def _check(kind: str, args: tuple, plunge: float) -> None:
    """ValueError (STEPNC-ENTRY at the operation) for an approach that cannot descend: an
    angle outside (0, 90] degrees, a zigzag width or helix radius that is not positive (a
    zigzag of a negative angle climbed for ever); LIMIT-COUNT for more zigzag strokes
    or helix turns than ``toolpath_passes`` (a zigzag of 1e-300 degrees)."""
    if kind == "PLUNGE_TOOLAXIS":
        return
    angle = args[1] if kind == "PLUNGE_HELIX" else args[0]
    if not 0.0 < angle <= 90.0:
        raise ValueError(
            f"a {angle:g} degree approach angle: it must be over 0 and at most 90 degrees"
        )
    if kind == "PLUNGE_ZIGZAG":
        if not args[1] > 0.0:
            raise ValueError(f"a zigzag of width {args[1]:g} mm")
        check_count(plunge / (args[1] * tand(angle)), "zigzag strokes of the approach")
    elif kind == "PLUNGE_HELIX":
        if not args[0] > 0.0:
            raise ValueError(f"a helix of radius {args[0]:g} mm")
        check_count(plunge / (2 * math.pi * args[0] * tand(angle)), "helix turns of the approach")


def plunge_start(
    length: float, width: float, plunge: float, approach: tuple
) -> tuple[float, float, float]:
    """(start_x, start_y, aux) for entering at (end_x, 0); aux = zigzag offset or turns."""
    kind, args = approach
    _check(kind, args, plunge)
    end_x = (length - width) / -2.0
    if kind == "PLUNGE_TOOLAXIS":
        return end_x, 0.0, 0.0
    if kind == "PLUNGE_RAMP":
        distance = plunge / tand(args[0])
        if distance < width / 2.0:
            return end_x - distance, 0.0, 0.0
        if distance < length - width / 2.0:
            return end_x + distance, 0.0, 0.0
        if distance < length:
            return length / 2.0, 0.0, 0.0
        raise ValueError("ramp does not fit in the pocket")
    if kind == "PLUNGE_ZIGZAG":
        angle, distance = args
        depth = plunge
        positive = True
        if distance < width / 2.0:
            zig = distance * tand(angle)
            while depth > zig + TINY:
                positive = not positive
                depth -= zig
            x = end_x - depth / tand(angle) if positive else end_x - distance + depth / tand(angle)
        elif distance < length + TINY:
            zig = (width / 2.0) * tand(angle)
            if depth < zig + TINY:
                x = end_x - depth / tand(angle)
            else:
                depth -= zig
                zig = distance * tand(angle)
                positive = False
                while depth > zig + TINY:
                    positive = not positive
                    depth -= zig
                x = (
                    (length / -2.0 + distance - depth / tand(angle))
                    if positive
                    else (length / -2.0 + depth / tand(angle))
                )
        else:
            raise ValueError("zigzag does not fit in the pocket")
        return x, 0.0, depth / tand(angle) if positive else -depth / tand(angle)
    radius, angle = args
    if radius > width / 2.0 + TINY:
        raise ValueError("helix does not fit in the pocket")
    turn_depth = 2 * math.pi * radius * tand(angle)
    whole = int(plunge / turn_depth)
    fraction = (plunge - whole * turn_depth) / turn_depth
    theta = 2 * math.pi * fraction - math.pi / 2
    return end_x + radius * math.cos(theta), radius * math.sin(theta), float(-whole - 1)


def enter(
    code: Code,
    approach: tuple,
    start: tuple[float, float, float],
    start_z: float,
    end_x: float,
    end_z: float,
) -> None:
    kind, args = approach
    if kind in ("PLUNGE_TOOLAXIS", "PLUNGE_RAMP"):
        code.feed(end_x, 0, end_z)
    elif kind == "PLUNGE_ZIGZAG":
        angle, distance = args
        offset = start[2]
        if offset > 0:
            x1 = start[0] + offset
            x2 = x1 - distance
            x = x1
        else:
            x2 = start[0] + offset
            x1 = x2 + distance
            x = x2
        z = start_z - abs(offset) * tand(angle)
        code.feed(x, 0, z)
        zig = distance * tand(angle)
        z -= zig
        while z > end_z + TINY:
            x = x2 if x == x1 else x1
            code.feed(x, 0, z)
            z -= zig
        if abs(x - end_x) > TINY:
            code.feed(end_x, 0, end_z)
    else:
        radius = args[0]
        code.arc(end_x, -radius, end_x, 0, int(start[2]), end_z)
        code.arc(end_x, 0, end_x, radius / -2.0, -1, end_z)
