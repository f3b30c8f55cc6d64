"""Stock and fixtures given as triangle meshes (STL, or STEP tessellated by the caller).

A mesh becomes a height field over its bounding box's XY rectangle at the simulation's
resolution: each cell holds the highest triangle Z over its centre (the rasteriser of the
design comparison, :func:`kernel.stock.mesh.top_surface`). A stock cell no triangle covers
holds no material (its column ends at the box's bottom); a fixture cell no triangle covers
is ``-inf`` (nothing there). The column model fills everything below the top surface down
to the box's bottom, so an overhang of the mesh is taken as solid below it.

Fixtures (vices, clamps, plates) are obstacles: :class:`Fixture` is a named height field
that the simulation never cuts; any swept tool, shank or holder below its top is a
collision (``SIM-FIXTURE``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic, Location
from kernel.stock.heightfield import HeightField, StockBox
from kernel.stock.mesh import top_surface


def mesh_box(tri: np.ndarray, code: str, where: str | None) -> StockBox:
    """The bounding box of triangles (n, 3, 3); ``code`` when it is flat in some axis."""
    if tri.size == 0 or not np.isfinite(tri).all():
        raise Diagnostic(code, "the mesh has no triangles or non-finite vertices", Location(where))
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    box = StockBox(*(float(v) for v in (*lo, *hi)))
    if not (box.x1 > box.x0 and box.y1 > box.y0 and box.z1 > box.z0):
        raise Diagnostic(code, "the mesh is flat: it has no volume", Location(where))
    return box


def mesh_field(
    tri: np.ndarray, resolution: float, code: str, where: str | None, box: StockBox | None = None
) -> HeightField:
    """A height field over the mesh's bounding box (or ``box``) whose columns rise to the
    mesh's top surface; cells it does not cover hold no material."""
    hf = HeightField(box or mesh_box(tri, code, where), resolution)
    top = top_surface(tri, hf)
    hf.h[...] = np.clip(np.where(np.isfinite(top), top, hf.box.z0), hf.box.z0, hf.box.z1)
    return hf


@dataclass(frozen=True, slots=True)
class Fixture:
    """An obstacle: ``grid.h`` is its top over each cell (``-inf`` where there is none)."""

    name: str
    grid: HeightField


def fixture_from_mesh(tri: np.ndarray, resolution: float, name: str) -> Fixture:
    """A fixture from its triangles (``SIM-FIXTURE-SPEC`` when the mesh is flat)."""
    grid = HeightField(mesh_box(tri, "SIM-FIXTURE-SPEC", name), resolution)
    grid.h[...] = top_surface(tri, grid)
    return Fixture(name, grid)


def fixture_from_box(box: StockBox, resolution: float, name: str) -> Fixture:
    """A block (or an upright cylinder) as a fixture."""
    grid = HeightField(box, resolution)
    grid.h[grid.h <= box.z0] = -np.inf
    return Fixture(name, grid)
