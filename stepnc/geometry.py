"""Solids of a STEP-NC program with cadquery (imported lazily): the raw workpiece, the
removal volume of each feature, and the finished part = workpiece minus features, with
STEP and STL export (ISO 14649-10 §4.7 feature definitions; shapes from
:mod:`stepnc.volumes`)."""

from __future__ import annotations

from typing import Any

from stepnc.model import Model
from stepnc.prisms import Prism, raw_block
from stepnc.volumes import feature_volumes


def _cq() -> Any:
    try:
        import cadquery as cq
    except ImportError as exc:  # pragma: no cover - cadquery is a declared extra
        from kernel.diagnostics import Diagnostic

        raise Diagnostic("STEPNC-NO-CADQUERY", f"cadquery is needed for solids: {exc}") from None
    return cq


def prism_solid(p: Prism) -> Any:
    """A cadquery Workplane holding the prism's solid in setup coordinates."""
    cq = _cq()
    f = p.frame
    plane = cq.Plane(origin=f.point((0.0, 0.0, p.z_bottom)), xDir=f.x, normal=f.z)
    wp = cq.Workplane(plane)
    h = p.z_top - p.z_bottom
    if p.kind == "circle":
        cx, cy, r = p.dims
        return wp.center(cx, cy).circle(r).extrude(h)
    if p.kind == "poly":
        return wp.polyline([tuple(v) for v in p.vertices()]).close().extrude(h)
    x0, y0, x1, y1, rad = p.dims
    sk = wp.center((x0 + x1) / 2, (y0 + y1) / 2).rect(x1 - x0, y1 - y0).extrude(h)
    if rad > 0:
        sk = sk.edges("|Z").fillet(rad)
    return sk


def finished_part(model: Model, raw: tuple[float, ...] | None = None) -> Any:
    """Workpiece minus every feature volume, as a cadquery Workplane."""
    part = prism_solid(raw_block(model, raw))
    for vol in feature_volumes(model):
        part = part.cut(prism_solid(vol))
    return part


def volume(shape: Any) -> float:
    return float(shape.val().Volume())


def export(shape: Any, path: str) -> None:
    """Write STEP (``.step``/``.stp``) or STL (``.stl``) chosen by the file suffix."""
    cq = _cq()
    cq.exporters.export(shape, path)
