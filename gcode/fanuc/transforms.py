"""Programmable coordinate transforms: G51/G50 scaling, G51.1/G50.1 mirror, G68/G69
rotation and G16/G15 polar input (docs/dialects.md "A Fanuc reader"; Fanuc 0i-MF manual,
"Coordinate value and dimension" and "Functions to simplify programming").

Program coordinates are mapped to the coordinates the motion uses in the order the lead's
notes give: scaling (``x' = c + f (x - c)`` per axis), then mirror (``x' = 2 m - x``), then
rotation about a centre in the plane that was active at G68. A negative scale factor
mirrors too; an odd number of mirrored axes in an arc's plane reverses G02/G03.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(slots=True)
class Transforms:
    scale_on: bool = False
    scale_centre: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    scale: list[float] = field(default_factory=lambda: [1.0, 1.0, 1.0])
    mirror: list[float | None] = field(default_factory=lambda: [None, None, None])
    rotate_on: bool = False
    rot_axes: tuple[int, int] = (0, 1)
    rot_centre: tuple[float, float] = (0.0, 0.0)
    rot_angle: float = 0.0  # degrees
    polar: bool = False
    polar_last: tuple[float, float] = (0.0, 0.0)  # last commanded radius and angle

    @property
    def active(self) -> bool:
        return self.scale_on or self.rotate_on or any(m is not None for m in self.mirror)

    def forward(self, p: list[float]) -> list[float]:
        """Program point (x, y, z, ...) -> transformed point."""
        q = list(p)
        if self.scale_on:
            for i in range(3):
                q[i] = self.scale_centre[i] + self.scale[i] * (q[i] - self.scale_centre[i])
        for i, m in enumerate(self.mirror):
            if m is not None:
                q[i] = 2.0 * m - q[i]
        if self.rotate_on:
            a, b = self.rot_axes
            ca, cb = self.rot_centre
            t = math.radians(self.rot_angle)
            da, db = q[a] - ca, q[b] - cb
            q[a] = ca + da * math.cos(t) - db * math.sin(t)
            q[b] = cb + da * math.sin(t) + db * math.cos(t)
        return q

    def inverse(self, q: list[float]) -> list[float]:
        """Transformed point -> program point (``forward`` undone)."""
        p = list(q)
        if self.rotate_on:
            a, b = self.rot_axes
            ca, cb = self.rot_centre
            t = -math.radians(self.rot_angle)
            da, db = p[a] - ca, p[b] - cb
            p[a] = ca + da * math.cos(t) - db * math.sin(t)
            p[b] = cb + da * math.sin(t) + db * math.cos(t)
        for i, m in enumerate(self.mirror):
            if m is not None:
                p[i] = 2.0 * m - p[i]
        if self.scale_on:
            for i in range(3):
                f = self.scale[i]
                p[i] = self.scale_centre[i] + (p[i] - self.scale_centre[i]) / f
        return p

    def flips(self, axes: tuple[int, int]) -> bool:
        """True when an arc in the plane of ``axes`` changes direction (odd mirror)."""
        n = 0
        for i in axes:
            if self.mirror[i] is not None:
                n += 1
            if self.scale_on and self.scale[i] < 0:
                n += 1
        return n % 2 == 1

    def radius_factor(self, axes: tuple[int, int]) -> float | None:
        """How an arc radius in the plane of ``axes`` scales; None when the two axes
        scale differently (the arc would become an ellipse)."""
        if not self.scale_on:
            return 1.0
        f1, f2 = abs(self.scale[axes[0]]), abs(self.scale[axes[1]])
        if abs(f1 - f2) > 1e-12:
            return None
        return f1


def polar_to_cartesian(
    radius: float, angle: float, centre: tuple[float, float]
) -> tuple[float, float]:
    """G16: radius and angle (degrees, counterclockwise from the first plane axis)."""
    t = math.radians(angle)
    return centre[0] + radius * math.cos(t), centre[1] + radius * math.sin(t)
