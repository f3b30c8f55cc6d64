"""Placements (AXIS2_PLACEMENT_3D) as frames, and the chain setup -> workpiece -> feature.

A :class:`Frame` is an origin and a right-handed orthonormal basis (x = ref_direction,
z = axis, y = z x x), ISO 10303-42 §4.4.x; composing frames follows NIST's ``find_location``
(research/seed-book-stepnc.md §7: coordinates are given in setup coordinates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic
from stepnc.model import Entity

Vec = tuple[float, float, float]


def _unit(v: Vec) -> Vec:
    n = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    if n == 0.0:
        raise ValueError("zero-length direction")
    return (v[0] / n, v[1] / n, v[2] / n)


def _cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@dataclass(frozen=True)
class Frame:
    origin: Vec = (0.0, 0.0, 0.0)
    x: Vec = (1.0, 0.0, 0.0)
    z: Vec = (0.0, 0.0, 1.0)

    @property
    def y(self) -> Vec:
        return _cross(self.z, self.x)

    def point(self, p: Vec) -> Vec:
        """A point given in this frame, in the parent frame."""
        x, y, z = self.x, self.y, self.z
        o = self.origin
        return (
            o[0] + p[0] * x[0] + p[1] * y[0] + p[2] * z[0],
            o[1] + p[0] * x[1] + p[1] * y[1] + p[2] * z[1],
            o[2] + p[0] * x[2] + p[1] * y[2] + p[2] * z[2],
        )

    def vector(self, v: Vec) -> Vec:
        x, y, z = self.x, self.y, self.z
        return (
            v[0] * x[0] + v[1] * y[0] + v[2] * z[0],
            v[0] * x[1] + v[1] * y[1] + v[2] * z[1],
            v[0] * x[2] + v[1] * y[2] + v[2] * z[2],
        )

    def compose(self, child: Frame) -> Frame:
        """``child`` (given in this frame) expressed in this frame's parent."""
        return Frame(self.point(child.origin), self.vector(child.x), self.vector(child.z))

    @property
    def vertical(self) -> bool:
        return abs(self.z[0]) < 1e-9 and abs(self.z[1]) < 1e-9 and self.z[2] > 0

    @property
    def angle(self) -> float:
        """Rotation of the x axis about Z (radians), for vertical frames."""
        return math.atan2(self.x[1], self.x[0])


def coords(point: Entity) -> Vec:
    """Coordinates of a CARTESIAN_POINT entity (missing ones are 0)."""
    c = (*(float(v) for v in point.coordinates), 0.0, 0.0, 0.0)
    return (c[0], c[1], c[2])


def direction(d: Entity) -> Vec:
    """Unit vector of a DIRECTION entity (missing ratios are 0)."""
    r = (*(float(v) for v in d.direction_ratios), 0.0, 0.0, 0.0)
    return _unit((r[0], r[1], r[2]))


def frame_of(placement: object) -> Frame:
    """Frame of an AXIS2_PLACEMENT_3D entity (``$`` placement: identity)."""
    if not isinstance(placement, Entity):
        return Frame()
    try:
        origin = coords(placement.location)
        z = direction(placement.axis) if placement.axis is not None else (0.0, 0.0, 1.0)
        if placement.ref_direction is not None:
            xr = direction(placement.ref_direction)
        else:
            xr = (1.0, 0.0, 0.0) if abs(z[0]) < 0.9 else (0.0, 1.0, 0.0)
    except ValueError as exc:
        raise Diagnostic(
            "STEPNC-PLACEMENT", f"bad placement #{placement.id}: {exc}", placement.where()
        ) from None
    # make x orthogonal to z (ISO 10303-42 first_proj_axis)
    d = sum(a * b for a, b in zip(xr, z, strict=True))
    x = _unit((xr[0] - d * z[0], xr[1] - d * z[1], xr[2] - d * z[2]))
    return Frame(origin, x, z)
