"""Side milling and bottom-and-side milling of a STEP (ISO 14649-10 §4.7 step; operations
ISO 14649-11 §4.2.5-4.2.6).

Step geometry (choices in docs/stepnc.md): the open boundary (a LINEAR_PATH placed in the
feature frame) is the foot of the step's vertical wall, from its origin along its direction
for its distance ``L``; the material removed lies on the right of that direction (local
v < 0) out to the raw workpiece, from the feature top (Z=0) down to the depth plane. A
tapered wall (``wall_boundary``) is not supported.

Toolpath, in the path frame: per axial layer, strokes parallel to the wall from the
outermost one (the tool just reaching the raw block's far edge) towards the wall, equally
spaced no wider than the radial depth, the last one leaving the side allowance on the
wall. Strokes overrun both ends by the tool radius plus 1 mm (the step runs through the
workpiece). BIDIRECTIONAL_MILLING (and ``$``) joins the strokes beside the workpiece;
UNIDIRECTIONAL_MILLING cuts every stroke along the path direction (against it for
CLIMB: with a clockwise spindle the wall is then on the tool's right) and returns at the
retract plane. The tool descends beside the workpiece and leaves at the retract plane
between layers.
"""

from __future__ import annotations

import math

from kernel.diagnostics import Diagnostic
from stepnc.executor import TINY
from stepnc.frames import Frame
from stepnc.model import Entity
from stepnc.prisms import raw_block
from stepnc.toolpaths.code import Code, check_count, place
from stepnc.toolpaths.passes import passes_of
from stepnc.toolpaths.slot import OVERRUN, linear_path_frame


def step_shape(step: Entity) -> tuple[float, float, Frame]:
    """(wall length, depth, path frame in feature coordinates) of a step."""
    if step.wall_boundary is not None:
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "steps with a tapered wall boundary are not supported",
            step.where(),
        )
    length, frame = linear_path_frame(step.open_boundary, step)
    depth = -float(step.depth.position.location.coordinates[2])
    if depth <= TINY:
        raise Diagnostic("STEPNC-STEP", "a step needs a depth plane below its top", step.where())
    return length, depth, frame


def _reach(frame: Frame, step: Entity) -> float:
    """How far the raw block extends on the removal side of the wall (setup frame)."""
    block = raw_block(step.model)
    x0, y0, x1, y1, _ = block.dims
    corners = [block.frame.point((x, y, 0.0)) for x in (x0, x1) for y in (y0, y1)]
    yx, yy = frame.y[0], frame.y[1]
    return max(
        0.0, max(-((c[0] - frame.origin[0]) * yx + (c[1] - frame.origin[1]) * yy) for c in corners)
    )


def generate(ex, job) -> None:  # noqa: ANN001
    """Mill the step ``job.feature`` with ``job.op``."""
    op, step = job.op, job.feature
    if step.type != "STEP":
        raise ex.error("STEPNC-OP-FEATURE", f"{op.type} cannot machine a {step.type}", op)
    try:
        length, depth, path = step_shape(step)
    except Diagnostic as exc:  # locate it in the workingstep
        raise ex.error(exc.code, exc.message, op) from None
    try:
        ps = passes_of(op, depth)
    except ValueError as exc:
        raise ex.error("STEPNC-STEP", str(exc), op) from None
    frame = job.frame.compose(path)
    reach = _reach(frame, step)
    if reach <= ps.side + TINY:
        raise ex.error("STEPNC-STEP", "the raw workpiece has no material to remove here", op)
    strat = op.its_machining_strategy
    kind = "BIDIRECTIONAL_MILLING" if strat is None else strat.type
    if kind not in ("BIDIRECTIONAL_MILLING", "UNIDIRECTIONAL_MILLING"):
        raise ex.error(
            "STEPNC-STRATEGY",
            f"step milling supports bidirectional and unidirectional strategies, not {kind}",
            op,
        )
    r = ps.diameter / 2.0
    wall = -(r + ps.side)  # tool centre of the last stroke
    span = max(0.0, reach - ps.side - 2 * r)  # from the outermost stroke to the wall stroke
    n = math.ceil((span - TINY) / ps.stepover) if span > TINY else 0
    check_count(n, "strokes of the step")
    vs = [wall - span * (n - k) / n for k in range(n + 1)] if n else [wall]
    ends = (-(r + OVERRUN), length + r + OVERRUN)
    if kind == "UNIDIRECTIONAL_MILLING" and strat.cutmode == "CLIMB":
        # a right-hand tool turning clockwise climbs with the wall on its right: cut along -u
        ends = ends[::-1]
    code = Code()
    code.feed(ends[0], vs[0], ps.retract)
    for level, z in enumerate(ps.levels):
        if level:
            code.traverse(ends[0], vs[0], ps.retract)
        code.feed(ends[0], vs[0], z)
        forward = True
        for k, v in enumerate(vs):
            if k and kind == "UNIDIRECTIONAL_MILLING":
                code.traverse(ends[1], vs[k - 1], ps.retract)
                code.traverse(ends[0], v, ps.retract)
                code.feed(ends[0], v, z)
            elif k:
                code.feed(ends[0] if forward else ends[1], v, z)
            code.feed(ends[1] if forward else ends[0], v, z)
            forward = forward if kind == "UNIDIRECTIONAL_MILLING" else not forward
        x, y, _ = code.end()
        code.traverse(x, y, ps.retract)
    ex.start_and_run(place(code, frame))
