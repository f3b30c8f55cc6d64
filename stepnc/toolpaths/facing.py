"""Plane rough and finish milling of a PLANAR_FACE: bidirectional and unidirectional
strategies (ISO 14649-11 §4.2.8.1; algorithm of NIST's ``mill_planar_bi/uni``).

The face is the rectangle [0, length] x [0, width] of the feature frame, its top at Z=0 and
its bottom at ``-depth``. Cuts run parallel to the strategy's feed direction (feature +X when
not given) and overhang each edge by ``overcut - diameter/2``; passes go down in equal
steps no deeper than the axial cutting depth.
"""

from __future__ import annotations

from kernel.diagnostics import Diagnostic
from stepnc.executor import ALLOW, TINY, UP
from stepnc.frames import direction
from stepnc.model import Entity, tool_dimension
from stepnc.toolpaths.code import Code, place


def face_size(face: Entity) -> tuple[float, float, float]:
    """(length along X, width along Y, depth) of a planar face (NIST ``check_planar_face``)."""
    from stepnc.model import measure

    travel = face.course_of_travel
    distance = measure(travel.distance)
    along = direction(travel.its_direction)
    across = measure(face.removal_boundary.profile_length)
    depth = -float(face.depth.position.location.coordinates[2])
    if distance is None or across is None:
        raise Diagnostic(
            "STEPNC-FACE",
            "planar face needs a travel distance and a removal boundary length",
            face.where(),
        )
    if abs(along[1]) > abs(along[0]):
        return across, distance, depth
    return distance, across, depth


def generate(ex, job) -> None:  # noqa: ANN001
    """Mill the planar face ``job.feature`` with plane milling ``job.op``."""
    op, face = job.op, job.feature
    if face.type != "PLANAR_FACE":
        raise ex.error("STEPNC-OP-FEATURE", f"{op.type} needs a PLANAR_FACE, not {face.type}", op)
    dim = tool_dimension(op.its_tool)
    diameter = float(dim.diameter)
    edge = float(dim.cutting_edge_length) if dim.cutting_edge_length is not None else diameter
    length, width, depth = face_size(face)
    strat = op.its_machining_strategy
    overlap = strat.overlap if strat is not None and strat.overlap is not None else 0.2
    stepover = diameter * (1 - float(overlap))
    pass_depth = (
        float(op.axial_cutting_depth)
        if op.axial_cutting_depth is not None
        else min(diameter / 2.0, edge / 2.0)
    )
    overcut = float(op.overcut_length) if op.overcut_length is not None else 1.25 * diameter
    if op.allowance_bottom is not None:
        mill_depth = depth - float(op.allowance_bottom)
    else:
        mill_depth = depth - (ALLOW if op.type == "PLANE_ROUGH_MILLING" else 0.0)
    if mill_depth <= 0 or pass_depth <= 0 or stepover <= 0:
        raise ex.error("STEPNC-FACE", "face depth, pass depth and stepover must be positive", op)
    passes = 1 + int((mill_depth - TINY) / pass_depth)
    pass_depth = mill_depth / passes
    retract = float(op.retract_plane) if op.retract_plane is not None else UP
    overage = overcut - diameter / 2.0
    code = Code()
    if strat is None or strat.type == "BIDIRECTIONAL_MILLING":
        _bidirectional(
            code, length, width, passes, diameter, pass_depth, stepover, overage, retract, strat
        )
    elif strat.type == "UNIDIRECTIONAL_MILLING":
        _unidirectional(
            code, length, width, passes, diameter, pass_depth, stepover, overage, retract, strat
        )
    else:
        raise ex.error(
            "STEPNC-STRATEGY",
            f"plane milling supports bidirectional and unidirectional milling, not {strat.type}",
            strat,
        )
    ex.start_and_run(place(code, job.frame))


def _first_direction(strat: Entity | None) -> int:
    """1=+X, 2=-X, 3=+Y, 4=-Y (NIST ``direction1``)."""
    d = strat.feed_direction if strat is not None else None
    if d is None:
        return 1
    v = direction(d)
    return 1 if v[0] > TINY else 2 if v[0] < -TINY else 3 if v[1] > 0 else 4


def _layout(
    code: Code,
    first: int,
    length: float,
    width: float,
    stepover: float,
    diameter: float,
    overage: float,
    left_first: bool,
):  # noqa: ANN202
    """Shared start geometry of both strategies: (feeder, traverser, cuts, x1, x2, y1, sign).

    ``left_first`` says whether the first strip is on the low side (+1 steps)."""
    half = stepover - diameter / 2.0
    if first < 3:
        feeder, traverser = code.feed, code.traverse
        cuts = 1 + int((width - TINY) / stepover)
        x1, x2 = (-overage, length + overage) if first == 1 else (length + overage, -overage)
        y1, sign = (half, 1) if left_first else (width - half, -1)
    else:
        feeder, traverser = code.feed_y, code.traverse_y
        cuts = 1 + int((length - TINY) / stepover)
        x1, x2 = (-overage, width + overage) if first == 3 else (width + overage, -overage)
        y1, sign = (-length + half, 1) if left_first else (-half, -1)
    return feeder, traverser, cuts, x1, x2, y1, sign


def _bidirectional(
    code: Code,
    length: float,
    width: float,
    passes: int,
    diameter: float,
    pass_depth: float,
    stepover: float,
    overage: float,
    retract: float,
    strat: Entity | None,
) -> None:
    first = _first_direction(strat)
    left = strat is not None and strat.stepover_direction == "LEFT"
    # +X/+Y first cut: LEFT steps towards +Y; -X/-Y first cut: LEFT steps towards -Y
    low_side = left if first in (1, 3) else not left
    feeder, traverser, cuts, x1, x2, y1, sign = _layout(
        code, first, length, width, stepover, diameter, overage, low_side
    )
    feeder(x1, y1, retract)
    z = 0.0
    for n in range(passes):
        y, x = y1, x1
        z -= pass_depth
        feeder(x, y, z)
        for m in range(cuts):
            x = x2 if x == x1 else x1
            feeder(x, y, z)
            if m < cuts - 1:
                y += sign * stepover
                feeder(x, y, z)
        traverser(x, y, retract)
        if n < passes - 1:
            traverser(x1, y1, retract)


def _unidirectional(
    code: Code,
    length: float,
    width: float,
    passes: int,
    diameter: float,
    pass_depth: float,
    stepover: float,
    overage: float,
    retract: float,
    strat: Entity,
) -> None:
    first = _first_direction(strat)
    climb = strat.cutmode == "CLIMB"
    # conventional cutting with a right-hand tool keeps the material on the left of +X cuts
    low_side = (not climb) if first in (1, 3) else climb
    feeder, traverser, cuts, x1, x2, y1, sign = _layout(
        code, first, length, width, stepover, diameter, overage, low_side
    )
    feeder(x1, y1, retract)
    z = 0.0
    for n in range(passes):
        y = y1
        z -= pass_depth
        feeder(x1, y, z)
        for m in range(cuts):
            feeder(x2, y, z)
            traverser(x2, y, retract)
            if m < cuts - 1:
                y += sign * stepover
                traverser(x1, y, retract)
                feeder(x1, y, z)
        if n < passes - 1:
            traverser(x1, y1, retract)
