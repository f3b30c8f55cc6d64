"""Bottom-and-side and side milling of a straight SLOT (ISO 14649-10 §4.7 slot; operations
ISO 14649-11 §4.2.5-4.2.6).

Slot geometry (the choices are listed in docs/stepnc.md): the course of travel (a
LINEAR_PATH, placed in the feature frame) is the slot's centre line, from its origin along
its direction for its distance ``L``; the swept shape is a SQUARE_U_PROFILE of width ``W``
with a flat floor at the depth plane. Each of the two end conditions (start, end) is
RADIUSED_SLOT_END_TYPE (a half circle of radius W/2 centred on the course end point, the
default when the list is shorter) or OPEN_SLOT_END_TYPE (the slot runs out of the
workpiece at the course end point; the tool overruns it by its radius plus 1 mm).

Toolpath, in the path frame (u along the course, v across): per axial layer, strokes
along the course at equal spacing no wider than the radial depth across the region the
tool centre may reach (the slot shrunk by tool radius plus side allowance), joined at the
ends along that region's boundary; then, unless the strategy is BIDIRECTIONAL_MILLING, one
contour pass around the boundary (CONTOUR_BIDIRECTIONAL, the default), clockwise
(conventional cut) unless CCW or climb is given; the contour pass replaces the two
outermost strokes. Entry at a radiused start by plunging
along the tool axis or ramping along the first stroke (PLUNGE_RAMP); at an open start
the tool descends beside the workpiece.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic
from stepnc.executor import TINY
from stepnc.frames import Frame, direction, frame_of
from stepnc.model import Entity, measure
from stepnc.toolpaths.code import Code, check_count, place
from stepnc.toolpaths.passes import Passes, outside_in, passes_of

OVERRUN = 1.0  # clearance beyond the tool radius past an open end (mm)
END_TYPES = ("RADIUSED_SLOT_END_TYPE", "OPEN_SLOT_END_TYPE")


@dataclass(frozen=True)
class SlotShape:
    length: float  # course of travel distance
    width: float
    depth: float
    open_start: bool
    open_end: bool
    frame: Frame  # path frame in feature coordinates: origin at the start, x along the course


def linear_path_frame(path: Entity, feature: Entity) -> tuple[float, Frame]:
    """(distance, frame with x along the path) of a LINEAR_PATH in feature coordinates."""
    placed = frame_of(path.placement)
    d = placed.vector(direction(path.its_direction))
    length = measure(path.distance)
    if abs(d[2]) > TINY or length is None or length <= TINY:
        raise Diagnostic(
            "STEPNC-PLACEMENT",
            "a linear path must be horizontal in the feature frame with a positive distance",
            feature.where(),
        )
    n = math.hypot(d[0], d[1])
    return length, Frame(placed.origin, (d[0] / n, d[1] / n, 0.0), (0.0, 0.0, 1.0))


def slot_shape(slot: Entity) -> SlotShape:
    """Dimensions, end conditions and path frame of a straight slot."""
    travel, shape = slot.course_of_travel, slot.swept_shape
    if not isinstance(shape, Entity) or shape.type != "SQUARE_U_PROFILE":
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "slot milling supports a SQUARE_U_PROFILE swept shape",
            slot.where(),
        )
    if any(measure(r) for r in (shape.first_radius, shape.second_radius)):
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            "slot milling supports flat floors (no bottom radii in the swept shape)",
            slot.where(),
        )
    length, frame = linear_path_frame(travel, slot)
    width = measure(shape.width)
    depth = -float(slot.depth.position.location.coordinates[2])
    ends = [e.type if isinstance(e, Entity) else "" for e in (slot.end_conditions or ())]
    if len(ends) > 2 or any(t not in END_TYPES for t in ends):
        raise Diagnostic(
            "STEPNC-UNSUPPORTED",
            f"slot end conditions must be at most two of {', '.join(END_TYPES)}",
            slot.where(),
        )
    ends += ["RADIUSED_SLOT_END_TYPE"] * (2 - len(ends))
    if width is None or width <= TINY or depth <= TINY:
        raise Diagnostic(
            "STEPNC-SLOT",
            "a slot needs a positive width and a depth plane below its top",
            slot.where(),
        )
    opens = [t == "OPEN_SLOT_END_TYPE" for t in ends]
    return SlotShape(length, width, depth, opens[0], opens[1], frame)


def generate(ex, job) -> None:  # noqa: ANN001
    """Mill the slot ``job.feature`` with ``job.op``."""
    op, slot = job.op, job.feature
    if slot.type != "SLOT":
        raise ex.error("STEPNC-OP-FEATURE", f"{op.type} cannot machine a {slot.type}", op)
    try:
        shape = slot_shape(slot)
    except Diagnostic as exc:  # locate it in the workingstep
        raise ex.error(exc.code, exc.message, op) from None
    try:
        ps = passes_of(op, shape.depth)
    except ValueError as exc:
        raise ex.error("STEPNC-SLOT", str(exc), op) from None
    half = shape.width / 2.0 - ps.side - ps.diameter / 2.0  # |v| the tool centre may reach
    if half < -TINY:
        raise ex.error(
            "STEPNC-TOOL-WIDTH",
            f"tool diameter {ps.diameter:g} does not fit slot width {shape.width:g} "
            f"minus side allowances {ps.side:g}",
            op,
        )
    strat = op.its_machining_strategy
    parallel = strat is not None and strat.type == "CONTOUR_PARALLEL"
    if parallel:
        rotation = strat.rotation_direction or "CW"
        cutmode = strat.cutmode or ("CLIMB" if rotation == "CCW" else "CONVENTIONAL")
        contour, ccw = True, rotation == "CCW"
    else:
        contour, ccw = stroke_strategy(ex, op, "slot")
    approach = op.approach
    if approach is not None and approach.type not in ("PLUNGE_TOOLAXIS", "PLUNGE_RAMP"):
        raise ex.error(
            "STEPNC-STRATEGY", f"slot entry supports plunge and ramp, not {approach.type}", op
        )
    ramp = float(approach.angle) if approach is not None and approach.type == "PLUNGE_RAMP" else 0
    region = slot_region(shape, max(half, 0.0), ps)
    code = Code()
    try:
        if parallel:
            mill_loops(code, region, ps, ccw, outside_in(rotation, cutmode), ramp)
        else:
            mill(code, region, ps, contour, ccw, ramp)
    except ValueError as exc:
        raise ex.error("STEPNC-ENTRY", str(exc), op) from None
    ex.start_and_run(place(code, job.frame.compose(shape.frame)))


def stroke_strategy(ex, op: Entity, what: str) -> tuple[bool, bool]:  # noqa: ANN001
    """(contour pass, counterclockwise contour) from the operation's strategy:
    CONTOUR_BIDIRECTIONAL (default) or BIDIRECTIONAL_MILLING (no contour pass)."""
    strat = op.its_machining_strategy
    kind = "CONTOUR_BIDIRECTIONAL" if strat is None else strat.type
    if kind not in ("BIDIRECTIONAL_MILLING", "CONTOUR_BIDIRECTIONAL"):
        allowed = "bidirectional and contour-bidirectional"
        if what == "slot":
            allowed = "contour-parallel, " + allowed
        raise ex.error(
            "STEPNC-STRATEGY", f"{what} milling supports {allowed} strategies, not {kind}", op
        )
    ccw = strat is not None and (
        getattr(strat, "rotation_direction", None) == "CCW"
        or getattr(strat, "spiral_cutmode", None) == "CLIMB"
    )
    return kind == "CONTOUR_BIDIRECTIONAL", ccw


@dataclass(frozen=True)
class End:
    """One end of a tool-centre region: its farthest ``tip`` along u, the radius of its two
    rounded corners (``corner`` = h: a half circle; 0: square) and whether it is open."""

    tip: float
    corner: float
    open: bool = False


class Region:
    """Where the tool centre may go: |v| <= h, u between the two ends (a rounded
    rectangle whose two ends may have different corners)."""

    def __init__(self, h: float, lo: End, hi: End) -> None:
        self.h, self.ends = h, (lo, hi)
        self.open_start = lo.open

    def _u(self, at_hi: bool, v: float) -> float:
        e = self.ends[at_hi]
        excess = max(abs(v) - (self.h - e.corner), 0.0)
        inset = e.corner - math.sqrt(max(e.corner * e.corner - excess * excess, 0.0))
        return e.tip - inset if at_hi else e.tip + inset

    def lo(self, v: float) -> float:
        return self._u(False, v)

    def hi(self, v: float) -> float:
        return self._u(True, v)

    def along_end(self, code: Code, at_hi: bool, v0: float, v1: float, z: float) -> None:
        """From (end, v0) to (end, v1) along the region's boundary at one end: straight
        lines and corner arcs."""
        e = self.ends[at_hi]
        c = e.corner if e.corner > TINY else 0.0
        knee = self.h - c  # |v| where a corner arc begins
        vs = [v0]
        if c and knee > TINY:
            for vk in sorted((-knee, knee), reverse=v1 < v0):
                if min(v0, v1) < vk < max(v0, v1):
                    vs.append(vk)
        vs.append(v1)
        cu = e.tip - c if at_hi else e.tip + c
        for a, b in zip(vs, vs[1:], strict=False):
            mid = (a + b) / 2.0
            if c and abs(mid) > knee - TINY:
                cv = math.copysign(knee, mid) if knee > TINY else 0.0
                ccw = (b > a) == at_hi  # round the +u end counterclockwise when v increases
                code.arc(self._u(at_hi, b), b, cu, cv, 1 if ccw else -1, z)
            else:
                code.feed(self._u(at_hi, b), b, z)


def slot_region(shape: SlotShape, h: float, ps: Passes) -> Region:
    out = ps.diameter / 2.0 + OVERRUN
    lo = End(-out, 0.0, True) if shape.open_start else End(-h, h)
    hi = End(shape.length + out, 0.0, True) if shape.open_end else End(shape.length + h, h)
    return Region(h, lo, hi)


def mill(code: Code, g: Region, ps: Passes, contour: bool, ccw: bool, ramp: float) -> None:
    n = max(1, math.ceil((2 * g.h - TINY) / ps.stepover)) if g.h > TINY else 0
    check_count(n, "strokes of the slot")
    vs = [-g.h + 2 * g.h * k / n for k in range(n + 1)] if n else [0.0]
    contour = contour and n > 0
    if contour:  # the contour pass cuts the two outermost strokes (|v| = h) itself
        vs = vs[1:-1]
    start = (g.lo(vs[0]), vs[0]) if vs else (g.lo(-g.h), -g.h)
    code.feed(start[0], start[1], ps.retract)
    for level, z in enumerate(ps.levels):
        top = ps.levels[level - 1] if level else 0.0
        if level:  # up to the top of the layer just cut, across, and in again
            lift = ps.levels[level - 2] if level > 1 else 0.0
            x, y, _ = code.end()
            code.feed(x, y, lift)
            code.traverse(start[0], start[1], lift)
        _enter(code, g, start, top, z, ramp)
        at_hi = False
        for k, v in enumerate(vs):
            if k:
                g.along_end(code, at_hi, vs[k - 1], v, z)
            at_hi = not at_hi
            code.feed(g.hi(v) if at_hi else g.lo(v), v, z)
        if contour:
            corner = -g.h
            if vs:  # along the end from the last stroke to the corner of the +h wall
                g.along_end(code, at_hi, vs[-1], g.h, z)
                corner = g.h
            _contour(code, g, (at_hi, corner), z, ccw)
    x, y, _ = code.end()
    code.feed(x, y, ps.retract)


def inset(g: Region, d: float) -> Region:
    """The tool-centre region shrunk by ``d`` (<= its half width): walls and radiused ends
    move in by ``d``; an open end stays where it is, outside the workpiece."""
    ends = []
    for e, sign in zip(g.ends, (1.0, -1.0), strict=True):
        if e.open:
            ends.append(e)
        else:
            ends.append(End(e.tip + sign * d, max(e.corner - d, 0.0)))
    return Region(g.h - d, ends[0], ends[1])


def mill_loops(
    code: Code, g: Region, ps: Passes, ccw: bool, from_outside: bool, ramp: float
) -> None:
    """CONTOUR_PARALLEL (ISO 14649-11 §4.2.8.2): per layer, closed loops around the
    tool-centre region at equal insets no wider apart than the stepover, from the centre
    line out (or, with the material inside the loops, from the outermost in). Each loop
    starts and ends at its -u, -v corner; neighbouring loops are joined by a straight feed
    between those corners, inside the larger loop."""
    n = max(1, math.ceil((g.h - TINY) / ps.stepover)) if g.h > TINY else 0
    check_count(n, "loops of the slot")
    loops = [inset(g, g.h * (n - k) / n) if n else g for k in range(n + 1)]  # inner first
    if from_outside:
        loops.reverse()
    first = loops[0]
    start = (first.lo(-first.h), -first.h)
    code.feed(start[0], start[1], ps.retract)
    for level, z in enumerate(ps.levels):
        top = ps.levels[level - 1] if level else 0.0
        if level:
            lift = ps.levels[level - 2] if level > 1 else 0.0
            x, y, _ = code.end()
            code.feed(x, y, lift)
            code.traverse(start[0], start[1], lift)
        _enter(code, first, start, top, z, ramp)
        for loop in loops:
            corner = (loop.lo(-loop.h), -loop.h)
            x, y, _ = code.end()
            if abs(x - corner[0]) > TINY or abs(y - corner[1]) > TINY:
                code.feed(corner[0], corner[1], z)
            if loop.h > TINY:
                _contour(code, loop, (False, -loop.h), z, ccw)
            else:  # the innermost loop of a slot as wide as its stepover: the centre line
                code.feed(loop.hi(0.0), 0.0, z)
                code.feed(corner[0], corner[1], z)
    x, y, _ = code.end()
    code.feed(x, y, ps.retract)


def _enter(
    code: Code, g: Region, start: tuple[float, float], top: float, z: float, ramp: float
) -> None:
    """Down from ``top`` to ``z`` at the start of the first stroke."""
    u, v = start
    if g.open_start or not ramp:
        code.feed(u, v, z)
        return
    run = (top - z) / math.tan(math.radians(ramp))
    if u + run > g.hi(v) + TINY:
        raise ValueError(f"a {ramp:g} degree ramp needs {run:.3f} mm, longer than the slot")
    code.feed(u, v, top)
    code.feed(u + run, v, z)
    code.feed(u, v, z)


def _contour(code: Code, g: Region, start: tuple[bool, float], z: float, ccw: bool) -> None:
    """One loop around the tool-centre region from corner ``start`` = (at the +u end,
    v = +h or -h)."""
    h = g.h
    corners = [(False, -h), (True, -h), (True, h), (False, h)]  # counterclockwise
    if not ccw:
        corners.reverse()
    i = corners.index(start)
    for k in range(1, 5):
        a, b = corners[(i + k - 1) % 4], corners[(i + k) % 4]
        if a[0] == b[0]:  # across an end
            g.along_end(code, a[0], a[1], b[1], z)
        else:  # along a wall
            code.feed(g.hi(b[1]) if b[0] else g.lo(b[1]), b[1], z)
