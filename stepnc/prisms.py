"""Prisms, the analytic shapes of :mod:`stepnc.volumes`, and the raw workpiece as one.

A prism lies in a frame: a rounded rectangle, a circle or a polygon in the frame's XY plane,
extruded from ``z_top`` down to ``z_bottom`` (frame coordinates). A leaf of the STEP-NC
front end: the toolpath generators need the raw block (how far a step reaches), and the
feature volumes, built from their shapes, are prisms too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic
from stepnc.frames import Frame, frame_of
from stepnc.model import Entity, Model


@dataclass(frozen=True)
class Prism:
    """``kind`` 'rect' (x0, y0, x1, y1, corner radius) or 'circle' (cx, cy, r)."""

    frame: Frame
    kind: str
    dims: tuple[float, ...]
    z_top: float
    z_bottom: float
    name: str = ""

    def contains(self, pts: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Which of the (n, 3) setup-coordinate points lie inside (grown by ``tol``)."""
        f = self.frame
        rel = pts - np.asarray(f.origin)
        basis = np.array([f.x, f.y, f.z])
        local = rel @ basis.T
        x, y, z = local[:, 0], local[:, 1], local[:, 2]
        inside_z = (z <= self.z_top + tol) & (z >= self.z_bottom - tol)
        if self.kind == "circle":
            cx, cy, r = self.dims
            return inside_z & ((x - cx) ** 2 + (y - cy) ** 2 <= (r + tol) ** 2)
        if self.kind == "poly":
            return inside_z & _in_polygon(x, y, self.vertices(), tol)
        x0, y0, x1, y1, rad = self.dims
        # rounded rectangle: distance to the inner rectangle shrunk by the corner radius
        qx = np.maximum(np.maximum(x0 + rad - x, x - (x1 - rad)), 0.0)
        qy = np.maximum(np.maximum(y0 + rad - y, y - (y1 - rad)), 0.0)
        inside_xy = (x >= x0 - tol) & (x <= x1 + tol) & (y >= y0 - tol) & (y <= y1 + tol)
        return inside_z & inside_xy & (qx * qx + qy * qy <= (rad + tol) ** 2)

    def vertices(self) -> np.ndarray:
        """Polygon corners (n, 2) of a 'poly' prism, in the feature frame."""
        return np.asarray(self.dims, dtype=float).reshape(-1, 2)

    def volume(self) -> float:
        h = self.z_top - self.z_bottom
        if self.kind == "circle":
            return float(np.pi * self.dims[2] ** 2 * h)
        if self.kind == "poly":
            v = self.vertices()
            area = 0.5 * abs(
                np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(v[:, 1], np.roll(v[:, 0], -1))
            )
            return float(area * h)
        x0, y0, x1, y1, r = self.dims
        return ((x1 - x0) * (y1 - y0) - (4.0 - np.pi) * r * r) * h


def _in_polygon(x: np.ndarray, y: np.ndarray, v: np.ndarray, tol: float) -> np.ndarray:
    """Even-odd rule, plus points within ``tol`` of an edge (vectorised over points)."""
    inside = np.zeros(x.shape, dtype=bool)
    near = np.zeros(x.shape, dtype=bool)
    for (x0, y0), (x1, y1) in zip(v, np.roll(v, -1, axis=0), strict=True):
        crosses = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        inside ^= crosses & (x < xc)
        dx, dy = x1 - x0, y1 - y0
        t = np.clip(((x - x0) * dx + (y - y0) * dy) / max(dx * dx + dy * dy, 1e-300), 0, 1)
        near |= (x - x0 - t * dx) ** 2 + (y - y0 - t * dy) ** 2 <= tol * tol
    return inside | near


def raw_block(model: Model, default: tuple[float, ...] | None = None) -> Prism:
    """The raw workpiece: the BLOCK of the workpiece (or its raw piece), else ``default``
    as ``(x0, y0, z0, x1, y1, z1)`` in setup coordinates."""
    for wp in model.all("WORKPIECE"):
        for cand in (wp, wp.its_rawpiece):
            if (
                isinstance(cand, Entity)
                and isinstance(cand.its_bounding_geometry, Entity)
                and cand.its_bounding_geometry.type == "BLOCK"
            ):
                b = cand.its_bounding_geometry
                fr = frame_of(b.position)
                return Prism(
                    fr, "rect", (0.0, 0.0, float(b.x), float(b.y), 0.0), float(b.z), 0.0, "raw"
                )
    if default is None:
        raise Diagnostic(
            "STEPNC-NO-RAWPIECE",
            "the workpiece has no bounding BLOCK; give the raw block explicitly",
            model.project().where(),
        )
    x0, y0, z0, x1, y1, z1 = default
    return Prism(
        Frame((x0, y0, z0)), "rect", (0.0, 0.0, x1 - x0, y1 - y0, 0.0), z1 - z0, 0.0, "raw"
    )


__all__ = ["Prism", "raw_block"]
