"""Analytic shapes of the material each feature removes (the raw workpiece's block and the
:class:`~stepnc.prisms.Prism` they are made of are in :mod:`stepnc.prisms`).

Shapes are prisms in a feature frame: a rounded rectangle, a circle or a plain rectangle in
the frame's XY plane, extruded from ``z_top`` down to ``z_bottom`` (feature coordinates).
They serve two consumers: :mod:`stepnc.geometry` builds cadquery solids from them, and the
gouge check tests tool points against them with numpy (no OpenCASCADE needed).

Feature volumes (ISO 14649-10 §4.7): PLANAR_FACE removes ``length x width x depth`` from
its top; CLOSED_POCKET removes its boundary profile (corner radius = orthogonal radius)
down to its depth plane; ROUND_HOLE removes a cylinder of its diameter, through the whole
workpiece when its bottom is a THROUGH_BOTTOM_CONDITION; a straight SLOT, a STEP and an
OPEN_POCKET are unions of prisms (:func:`feature_prisms`).
"""

from __future__ import annotations

from kernel.diagnostics import Diagnostic
from stepnc.frames import Frame, coords, frame_of
from stepnc.model import Entity, Model, measure
from stepnc.prisms import Prism
from stepnc.schema import GROUPS
from stepnc.toolpaths.facing import face_size
from stepnc.toolpaths.open_pocket import open_pocket_shape
from stepnc.toolpaths.slot import slot_shape
from stepnc.toolpaths.step import step_shape

THROUGH = 1.0e4  # extrusion depth standing for "through the workpiece" (mm)


def workpiece_frame(model: Model) -> Frame:
    plan = model.project().main_workplan
    setup = plan.its_setup
    if setup is not None:
        for wps in setup.its_workpiece_setup or ():
            return frame_of(wps.its_origin)
    return Frame()


def feature_volume(feature: Entity, wp: Frame) -> Prism | None:
    """The removal volume of a feature, or None for features without a closed volume."""
    frame = wp.compose(frame_of(feature.feature_placement))
    t = feature.type
    depth_z = (
        coords(feature.depth.position.location)[2] if isinstance(feature.depth, Entity) else None
    )
    if t == "PLANAR_FACE":
        length, width, depth = face_size(feature)
        return Prism(frame, "rect", (0.0, 0.0, length, width, 0.0), 0.0, -depth, feature.its_id)
    if t == "CLOSED_POCKET":
        b = feature.feature_boundary
        bottom = -THROUGH if feature.bottom_condition.type.startswith("THROUGH") else depth_z
        if b.type == "RECTANGULAR_CLOSED_PROFILE":
            w, length = measure(b.profile_width), measure(b.profile_length)
            r = measure(feature.orthogonal_radius) if feature.orthogonal_radius else 0.0
            return Prism(
                frame,
                "rect",
                (-length / 2, -w / 2, length / 2, w / 2, r or 0.0),
                0.0,
                bottom,
                feature.its_id,
            )
        if b.type == "CIRCULAR_CLOSED_PROFILE":
            return Prism(
                frame, "circle", (0.0, 0.0, measure(b.diameter) / 2), 0.0, bottom, feature.its_id
            )
        if b.type == "GENERAL_CLOSED_PROFILE" and b.closed_profile_shape.type == "POLYLINE":
            shape = frame_of(b.placement)
            pts = [shape.point(coords(p))[:2] for p in b.closed_profile_shape.points]
            if len(pts) > 1 and pts[0] == pts[-1]:
                pts = pts[:-1]
            if len(pts) < 3:
                raise Diagnostic("STEPNC-CURVE", "a closed profile needs three points", b.where())
            flat = tuple(c for p in pts for c in p)
            return Prism(frame, "poly", flat, 0.0, bottom, feature.its_id)
        raise Diagnostic(
            "STEPNC-UNSUPPORTED", f"no solid for a pocket bounded by {b.type}", feature.where()
        )
    if t == "ROUND_HOLE":
        if feature.change_in_diameter is not None:
            raise Diagnostic(
                "STEPNC-UNSUPPORTED",
                "no solid for a tapered ROUND_HOLE (change_in_diameter)",
                feature.where(),
            )
        r = measure(feature.diameter) / 2
        through = feature.bottom_condition.type == "THROUGH_BOTTOM_CONDITION"
        return Prism(
            frame, "circle", (0.0, 0.0, r), 0.0, -THROUGH if through else depth_z, feature.its_id
        )
    raise Diagnostic("STEPNC-UNSUPPORTED", f"no solid for a {t} feature", feature.where())


def feature_prisms(feature: Entity, wp: Frame) -> list[Prism]:
    """The removal volume of a feature as prisms whose union it is: a straight SLOT is the
    rectangle swept along its course plus a disc at each radiused end; a STEP is the
    half-plane right of its wall line, between the line's ends; a rectangular OPEN_POCKET
    extends from its back wall through its open side (conventions in
    :mod:`stepnc.toolpaths.slot`, :mod:`~stepnc.toolpaths.step`, :mod:`~.open_pocket`)."""
    if feature.type == "SLOT":
        s = slot_shape(feature)
        frame = wp.compose(frame_of(feature.feature_placement)).compose(s.frame)
        w, name = s.width / 2, feature.its_id
        out = [Prism(frame, "rect", (0.0, -w, s.length, w, 0.0), 0.0, -s.depth, name)]
        for is_open, u in ((s.open_start, 0.0), (s.open_end, s.length)):
            if not is_open:
                out.append(Prism(frame, "circle", (u, 0.0, w), 0.0, -s.depth, name))
        return out
    if feature.type == "STEP":
        length, depth, path = step_shape(feature)
        frame = wp.compose(frame_of(feature.feature_placement)).compose(path)
        dims = (0.0, -THROUGH, length, 0.0, 0.0)
        return [Prism(frame, "rect", dims, 0.0, -depth, feature.its_id)]
    if feature.type == "OPEN_POCKET":
        length, width, depth, corner, shape = open_pocket_shape(feature)
        frame = wp.compose(frame_of(feature.feature_placement)).compose(shape)
        dims = (-THROUGH, -width / 2, length, width / 2, corner)  # open side: beyond the part
        return [Prism(frame, "rect", dims, 0.0, -depth, feature.its_id)]
    return [feature_volume(feature, wp)]


def feature_volumes(model: Model) -> list[Prism]:
    """Removal volumes of every feature of the program (file order)."""
    wp = workpiece_frame(model)
    features = GROUPS["feature"]
    return [
        prism
        for inst in model.p21.instances.values()
        if inst.name in features
        for prism in feature_prisms(Entity(model, inst), wp)
    ]
