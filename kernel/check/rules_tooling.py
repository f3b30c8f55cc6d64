"""Rules about tools, arcs, rapids, spindle, coolant, controller codes and cutter compensation.

Registered into :data:`kernel.check.rules.RULES` on import (``kernel.check`` imports this
module). See ``docs/check-rules.md`` for each rule's rationale and an example.
"""

from __future__ import annotations

import math

import kernel.ir.canon as canon
from kernel.check.config import ARC_TOLERANCES
from kernel.check.geometry import arc_of, segment_hits_box
from kernel.check.rules import (
    EPS,
    FEEDS,
    CheckContext,
    fmt_num,
    is_cutting,
    rule,
    tool_length_mm,
)
from kernel.check.state import CheckState
from kernel.diagnostics import Severity

STOPPED = canon.Direction.STOPPED


# --------------------------------------------------------------------------- CNC2xx tools
def _tool_length_applies(ctx: CheckContext) -> bool:
    """G43 is the program's job: not with ``tool_length = "machine"``, not on a laser or
    plasma (no tool length), not on a lathe (T0101 applies the offsets)."""
    traits = ctx.machine.traits
    return ctx.config.tool_length_by_program and not (traits.beam or traits.turret_offsets)


@rule(
    "CNC201",
    "tool-not-in-table",
    Severity.ERROR,
    "A tool is selected or loaded that the tool table does not list.",
    kinds=(canon.SelectTool, canon.ChangeTool),
)
def tool_not_in_table(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not isinstance(cmd, canon.SelectTool | canon.ChangeTool):
        return None
    slot = cmd.slot
    if ctx.tools is None or slot == 0 or slot in ctx.tools:
        return None
    return f"tool T{slot} is not in the tool table"


@rule(
    "CNC202",
    "no-tool-loaded",
    Severity.WARNING,
    "Cutting with no tool loaded (T0), e.g. M6 forgotten.",
    kinds=FEEDS,
    default_enabled=False,
)
def no_tool_loaded(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if st.tool == 0 and is_cutting(cmd, st, ctx):
        return "cutting with no tool loaded (no M6 before this move)"
    return None


@rule(
    "CNC203",
    "tool-length-offset-missing",
    Severity.WARNING,
    "Cutting with a tool whose length offset was never applied (G43 missing).",
    kinds=FEEDS,
)
def tlo_missing(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not _tool_length_applies(ctx) or st.tool == 0 or not is_cutting(cmd, st, ctx):
        return None
    length = tool_length_mm(ctx, st.tool)
    if length is not None:
        if abs(length) > EPS and abs(st.tlo_mm) <= EPS:
            return (
                f"cutting with T{st.tool} (length {fmt_num(length)} mm) without a tool length "
                "offset: G43 missing after M6"
            )
        return None
    if not st.tlo_set:
        return f"cutting with {st.tool_name} without a tool length offset: G43 missing after M6"
    return None


@rule(
    "CNC204",
    "tool-length-offset-mismatch",
    Severity.WARNING,
    "The active tool length offset is not the loaded tool's (G43 H for another tool).",
    kinds=FEEDS,
)
def tlo_mismatch(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not _tool_length_applies(ctx) or abs(st.tlo_mm) <= EPS:
        return None
    length = tool_length_mm(ctx, st.tool)
    if length is None or abs(length - st.tlo_mm) <= 1e-3 or not is_cutting(cmd, st, ctx):
        return None
    return (
        f"tool length offset {fmt_num(st.tlo_mm)} mm does not match T{st.tool}'s length "
        f"{fmt_num(length)} mm (G43 H for another tool?)"
    )


@rule(
    "CNC205",
    "tool-change-low",
    Severity.WARNING,
    "A tool change happens with the tool below check.safe_z.",
    kinds=(canon.ChangeTool,),
)
def tool_change_low(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    safe = ctx.config.safe_z
    if safe is None or not st.moved:
        return None
    z = st.work_mm(st.position)[2]
    if z < safe - EPS:
        return f"tool change at Z {fmt_num(z)} mm, below the safe height {fmt_num(safe)} mm"
    return None


# --------------------------------------------------------------------------- CNC3xx arcs
@rule(
    "CNC301",
    "arc-radius-mismatch",
    Severity.ERROR,
    "An arc's start and end radii differ beyond the target controller's tolerance.",
    kinds=(canon.ArcFeed,),
)
def arc_radius_mismatch(cmd: canon.ArcFeed, st: CheckState, ctx: CheckContext) -> str | None:
    """Tolerances of research/anchors.md §1.1 (LinuxCNC interp_arc.cc, Grbl, Mach3)."""
    if cmd.rotation == 0:
        return None
    arc = arc_of(st, cmd)
    k = st.mm_per_unit
    r0, r1 = arc.r_start * k, arc.r_end * k
    diff = abs(r1 - r0)
    absolute, relative, hard = ARC_TOLERANCES[ctx.config.arc_tolerance]
    if diff > hard + EPS or (diff > absolute + 1e-9 and diff > relative * max(r0, r1)):
        return (
            f"arc radius {fmt_num(r0)} mm at the start, {fmt_num(r1)} mm at the end: they differ "
            f"by {fmt_num(diff)} mm ({ctx.config.arc_tolerance} tolerance)"
        )
    return None


@rule(
    "CNC302",
    "nurbs-invalid",
    Severity.ERROR,
    "A NURBS curve has a wrong knot count, decreasing knots or a non-positive weight.",
    kinds=(canon.NurbsFeed,),
)
def nurbs_invalid(cmd: canon.NurbsFeed, st: CheckState, ctx: CheckContext) -> str | None:
    if cmd.elided or not cmd.points:  # LinuxCNC prints NURBS_FEED(count, ...) without data
        return None
    n, k = len(cmd.points), cmd.order
    if cmd.knots and len(cmd.knots) != n + k:
        return f"NURBS of order {k} with {n} points needs {n + k} knots, has {len(cmd.knots)}"
    if any(b < a for a, b in zip(cmd.knots, cmd.knots[1:], strict=False)):
        return "NURBS knot vector decreases"
    if any(p[2] <= 0 for p in cmd.points):
        return "NURBS weight is not positive"
    if n < k:
        return f"NURBS of order {k} needs at least {k} control points, has {n}"
    return None


# --------------------------------------------------------------------------- CNC4xx rapids
@rule(
    "CNC401",
    "rapid-into-stock",
    Severity.ERROR,
    "A rapid (G0) move enters the stock.",
    kinds=(canon.StraightTraverse,),
)
def rapid_into_stock(cmd: canon.StraightTraverse, st: CheckState, ctx: CheckContext) -> str | None:
    stock = ctx.config.stock
    if stock is None:
        return None
    a = st.work_mm(st.position)[:3]
    b = st.work_mm((cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c))[:3]
    if abs(b[0] - a[0]) <= EPS and abs(b[1] - a[1]) <= EPS and b[2] >= a[2]:
        return None  # a straight retract leaves along the way the tool came in
    if segment_hits_box(a, b, stock[0], stock[1]):
        return "rapid move enters the stock: use G1 to cut, or retract first"
    return None


@rule(
    "CNC402",
    "rapid-below-safe-height",
    Severity.WARNING,
    "A rapid moves across X/Y with the tool below check.safe_z.",
    kinds=(canon.StraightTraverse,),
)
def rapid_below_safe(cmd: canon.StraightTraverse, st: CheckState, ctx: CheckContext) -> str | None:
    safe = ctx.config.safe_z
    if safe is None:
        return None
    a = st.work_mm(st.position)
    b = st.work_mm((cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c))
    if math.hypot(b[0] - a[0], b[1] - a[1]) <= EPS:
        return None
    z = min(a[2], b[2])
    if z < safe - EPS:
        return f"rapid across X/Y at Z {fmt_num(z)} mm, below the safe height {fmt_num(safe)} mm"
    return None


# --------------------------------------------------------------------------- CNC5xx spindle
@rule(
    "CNC501",
    "spindle-speed-too-high",
    Severity.ERROR,
    "The programmed spindle speed exceeds the spindle's maximum.",
    kinds=(canon.SetSpindleSpeed,),
)
def spindle_too_fast(cmd: canon.SetSpindleSpeed, st: CheckState, ctx: CheckContext) -> str | None:
    hi = ctx.spindle_range[1]
    where = ctx.of_machine()
    if st.css:  # G96: S is a surface speed; the rpm is capped by D (css_max)
        if st.css_max > hi + EPS:
            return (
                f"G96 D{fmt_num(st.css_max)} allows more than the maximum {fmt_num(hi)} rpm" + where
            )
        return None
    if cmd.speed > hi + EPS:
        if ctx.machine.traits.beam:
            return f"power S{fmt_num(cmd.speed)} exceeds the maximum S{fmt_num(hi)}{where}"
        return f"spindle speed S{fmt_num(cmd.speed)} exceeds the maximum {fmt_num(hi)} rpm{where}"
    return None


@rule(
    "CNC502",
    "spindle-speed-too-low",
    Severity.WARNING,
    "The spindle runs below its minimum speed.",
    kinds=FEEDS,
)
def spindle_too_slow(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    lo = ctx.spindle_range[0]
    if st.css or ctx.machine.traits.beam:  # G96: the rpm follows the diameter; a beam: power
        return None
    if st.spindle != STOPPED and 0 < st.spindle_speed < lo - EPS:
        return f"spindle speed S{fmt_num(st.spindle_speed)} is below the minimum {fmt_num(lo)} rpm"
    return None


@rule(
    "CNC503",
    "spindle-reversal",
    Severity.WARNING,
    "The spindle reverses (M3 <-> M4) without stopping (M5) first.",
    kinds=(canon.StartSpindleClockwise, canon.StartSpindleCounterclockwise),
)
def spindle_reversal(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    new = (
        canon.Direction.CLOCKWISE
        if isinstance(cmd, canon.StartSpindleClockwise)
        else canon.Direction.COUNTERCLOCKWISE
    )
    if st.spindle not in (STOPPED, new) and not ctx.machine.traits.beam:  # M3/M4: laser modes
        return "spindle reverses direction without M5 in between"
    return None


@rule(
    "CNC504",
    "spindle-off-cutting",
    Severity.ERROR,
    "Cutting with the spindle stopped.",
    kinds=FEEDS,
)
def spindle_off_cutting(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if ctx.machine.traits.beam:  # a feed move with the beam or torch off is a travel move
        return None
    if st.spindle == STOPPED and not st.probe_on and is_cutting(cmd, st, ctx):
        return "cutting with the spindle stopped (M3/M4 missing)"
    return None


@rule(
    "CNC505",
    "spindle-zero-speed",
    Severity.ERROR,
    "Cutting with the spindle switched on at 0 rpm (S missing).",
    kinds=FEEDS,
)
def spindle_zero_speed(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    traits = ctx.machine.traits
    if traits.beam or traits.manual_speed:  # S0: beam off (travel); a router's dial sets rpm
        return None
    if st.spindle != STOPPED and st.spindle_speed <= 0 and is_cutting(cmd, st, ctx):
        return "cutting with the spindle on at speed 0 (S word missing)"
    return None


# --------------------------------------------------------------------------- CNC6xx coolant
@rule(
    "CNC601",
    "coolant-off-cutting",
    Severity.WARNING,
    "Cutting with flood and mist coolant off (opt-in).",
    kinds=FEEDS,
    default_enabled=False,
)
def coolant_off_cutting(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not st.cooling() and is_cutting(cmd, st, ctx):
        return "cutting with coolant off (M7/M8 missing)"
    return None


# --------------------------------------------------------------------------- CNC7xx controller
def codes_of(cmd: canon.Command) -> tuple[str, ...]:
    """The G/M codes a canonical command stands for (RS274/NGC; NISTIR 5970 Table 3)."""
    match cmd:
        case canon.NurbsFeed():
            return ("G5.2",)
        case canon.ArcFeed(rotation=r):
            return ("G2",) if r < 0 else ("G3",)
        case canon.StraightProbe():
            return ("G38.2",)
        case canon.Dwell():
            return ("G4",)
        case canon.SelectPlane(plane=p):
            return {canon.Plane.XY: ("G17",), canon.Plane.XZ: ("G18",), canon.Plane.YZ: ("G19",)}[p]
        case canon.SetFeedMode(mode=m):
            return {
                canon.FeedMode.INVERSE_TIME: ("G93",),
                canon.FeedMode.UNITS_PER_MINUTE: (),
                canon.FeedMode.UNITS_PER_REVOLUTION: ("G95",),
            }[m]
        case canon.SetSpindleMode(css=True):
            return ("G96",)
        case canon.StartSpeedFeedSynch():
            return ("G33",)
        case canon.SetMotionControlMode(mode=m):
            return {
                canon.MotionMode.EXACT_STOP: ("G61.1",),
                canon.MotionMode.EXACT_PATH: ("G61",),
                canon.MotionMode.CONTINUOUS: ("G64",),
            }[m]
        case canon.StartCutterRadiusCompensation(side=s):
            return ("G41",) if s == canon.CompSide.LEFT else ("G42",)
        case canon.MistOn():
            return ("M7",)
        case canon.FloodOn():
            return ("M8",)
        case canon.OrientSpindle():
            return ("M19",)
        case canon.PalletShuttle():
            return ("M60",)
        case canon.OptionalProgramStop():
            return ("M1",)
        case canon.ProgramStop():
            return ("M0",)
        case canon.StartSpindleCounterclockwise():
            return ("M4",)
        case canon.ChangeTool():
            return ("M6",)
        case canon.MachineFunction(code=code):
            return (f"M{code}",)
    return ()


@rule(
    "CNC701",
    "unsupported-code",
    Severity.ERROR,
    "The program uses a code the target controller does not support (check.unsupported).",
    kinds=(),
)
def unsupported_code(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not ctx.config.unsupported:
        return None
    bad = [c for c in codes_of(cmd) if c in ctx.config.unsupported]
    if bad:
        return f"{'/'.join(bad)} is not supported by the target controller ({cmd.NAME})"
    return None


@rule(
    "CNC702",
    "machine-function-unknown",
    Severity.NOTE,
    "An M code for the machine's PLC (MACHINE_FUNCTION) that the profile's [m_codes] does "
    "not name.",
    kinds=(canon.MachineFunction,),
)
def machine_function_unknown(
    cmd: canon.MachineFunction, st: CheckState, ctx: CheckContext
) -> str | None:
    if cmd.code in ctx.machine.m_codes:
        return None
    return f"M{cmd.code} goes to the machine's PLC but the profile's [m_codes] does not name it"


@rule(
    "CNC703",
    "machine-function-forbidden",
    Severity.ERROR,
    "An M code the profile's [m_codes] forbids (forbid = true).",
    kinds=(canon.MachineFunction,),
)
def machine_function_forbidden(
    cmd: canon.MachineFunction, st: CheckState, ctx: CheckContext
) -> str | None:
    spec = ctx.machine.m_codes.get(cmd.code)
    if spec is None or not spec.forbid:
        return None
    what = f" ({spec.name})" if spec.name else ""
    return f"M{cmd.code}{what} is forbidden on this machine ([m_codes] forbid = true)"


# --------------------------------------------------------------------------- CNC8xx comp
@rule(
    "CNC801",
    "cutter-comp-gouge",
    Severity.ERROR,
    "With cutter compensation on, a concave arc is tighter than the tool radius.",
    kinds=(canon.ArcFeed,),
)
def comp_gouge(cmd: canon.ArcFeed, st: CheckState, ctx: CheckContext) -> str | None:
    """Tool on the left of a CCW arc (or right of a CW one) sits inside it: the offset radius
    is r - R, so R >= r gouges (NISTIR 5970 App. A.8 semantics)."""
    if st.comp_side is None or st.comp_radius <= 0 or cmd.rotation == 0:
        return None
    inside = (st.comp_side == canon.CompSide.LEFT) == (cmd.rotation > 0)
    r = arc_of(st, cmd).r_end
    if inside and st.comp_radius >= r - EPS:
        k = st.mm_per_unit
        return (
            f"tool radius {fmt_num(st.comp_radius * k)} mm does not fit the concave arc of "
            f"radius {fmt_num(r * k)} mm: compensation gouges"
        )
    return None


@rule(
    "CNC802",
    "cutter-comp-radius-zero",
    Severity.WARNING,
    "Cutter compensation is switched on with a zero tool radius.",
    kinds=(canon.StartCutterRadiusCompensation,),
)
def comp_radius_zero(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if st.comp_radius <= 0:
        return "cutter compensation on with tool radius 0 (diameter missing in the tool table?)"
    return None


@rule(
    "CNC803",
    "cutter-comp-left-on",
    Severity.WARNING,
    "Cutter compensation is still on when the program ends.",
    kinds=(canon.ProgramEnd,),
)
def comp_left_on(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    return "program ends with cutter compensation on (G40 missing)" if st.comp_side else None
