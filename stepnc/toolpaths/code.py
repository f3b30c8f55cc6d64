"""Pseudocode for toolpaths in feature coordinates (NIST interpreter's ``code[][7]``).

Lines are tuples: ``(FEED, x, y, z)``, ``(TRAVERSE, x, y, z)`` and
``(ARC, end_x, end_y, centre_x, centre_y, turns, end_z)`` with ``turns`` > 0
counterclockwise seen from +Z (NISTIR 5970 ARC_FEED rotation).
"""

from __future__ import annotations

import math

import kernel.limits as limits
from kernel.diagnostics import Location
from stepnc.frames import Frame

FEED, ARC, TRAVERSE = 1, 2, 3
Line = tuple


def check_count(count: float, what: str) -> None:
    """LIMIT-COUNT when an operation would generate more than ``kernel.limits``'
    ``toolpath_passes`` passes or lines (a 0.0001 mm tool or stepover); the executor
    locates it at the operation."""
    limit = limits.current().toolpath_passes
    if count > limit:
        raise limits.count_error(what, count, limit, "toolpath_passes", Location())


class Code(list):
    """A list of pseudocode lines with writers named after the NIST helpers; generated
    toolpaths stop at ``kernel.limits``' ``toolpath_passes`` lines (:func:`check_count`)."""

    def _grow(self) -> None:
        if len(self) % 65536 == 0 and len(self):
            check_count(len(self), "toolpath lines of one operation")

    def feed(self, x: float, y: float, z: float) -> None:
        self._grow()
        self.append((FEED, x, y, z))

    def traverse(self, x: float, y: float, z: float) -> None:
        self._grow()
        self.append((TRAVERSE, x, y, z))

    def arc(self, ex: float, ey: float, cx: float, cy: float, turns: int, z: float) -> None:
        self._grow()
        self.append((ARC, ex, ey, cx, cy, int(turns), z))

    def feed_y(self, x: float, y: float, z: float) -> None:
        """Feed in a frame rotated 90 degrees counterclockwise (NIST ``write_feed_y``)."""
        self._grow()
        self.append((FEED, -y, x, z))

    def traverse_y(self, x: float, y: float, z: float) -> None:
        self._grow()
        self.append((TRAVERSE, -y, x, z))

    def end(self) -> tuple[float, float, float]:
        last = self[-1]
        return (last[1], last[2], last[6] if last[0] == ARC else last[3])


def _rotate(x: float, y: float, angle: float, frame: Frame) -> tuple[float, float]:
    # NIST transform_code: polar form about the frame origin, rotated by the frame angle
    arm = math.hypot(x, y)
    a = angle + math.atan2(y, x)
    return frame.origin[0] + arm * math.cos(a), frame.origin[1] + arm * math.sin(a)


def place(code: Code, frame: Frame) -> Code:
    """Feature coordinates -> setup coordinates for a frame whose Z axis is vertical."""
    angle = frame.angle
    dz = frame.origin[2]
    out = Code()
    for line in code:
        if line[0] == ARC:
            ex, ey = _rotate(line[1], line[2], angle, frame)
            cx, cy = _rotate(line[3], line[4], angle, frame)
            out.append((ARC, ex, ey, cx, cy, line[5], dz + line[6]))
        else:
            x, y = _rotate(line[1], line[2], angle, frame)
            out.append((line[0], x, y, dz + line[3]))
    return out
