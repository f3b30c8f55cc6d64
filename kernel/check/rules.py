"""The rules of ``cnc check``: one small function per problem class.

Each rule looks at one canonical command and the :class:`~kernel.check.state.CheckState` the
commands before it left, and returns a message when the command is a problem (or None).
``at_end`` rules judge the whole program once the stream is exhausted. Rule ids, names and
default severities are stable; each has a section in ``docs/check-rules.md``.

Rule families: CNC0xx program structure, CNC1xx motion and travel, CNC2xx tools, CNC3xx arcs
and curves, CNC4xx rapids and stock, CNC5xx spindle, CNC6xx coolant, CNC7xx controller
capabilities, CNC8xx cutter compensation.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import kernel.ir.canon as canon
from kernel.check.config import CheckConfig
from kernel.check.geometry import box_overlaps, swept_points
from kernel.check.state import PLANE_AXES, CheckState, motion_end
from kernel.diagnostics import Severity
from kernel.machine import AXIS_NAMES, Machine
from kernel.tooltable import ToolTable

FEEDS: tuple[type[canon.Command], ...] = (
    canon.StraightFeed,
    canon.ArcFeed,
    canon.NurbsFeed,
    canon.EllipseFeed,
)
MOTIONS: tuple[type[canon.Command], ...] = (*FEEDS, canon.StraightTraverse, canon.StraightProbe)
EPS = 1e-6


@dataclass(frozen=True, slots=True)
class CheckContext:
    """What the rules judge against: the machine profile, its tools, the check settings.

    ``spindle_range`` is (min, max) rpm from the profile's ``[spindle]`` table;
    ``tool_mm_per_unit`` the length unit of the tool table (sim.tbl is in inches: 25.4);
    ``default_machine`` says the machine is the built-in default, not the user's profile,
    so a limit finding says where its limit came from.
    """

    machine: Machine
    config: CheckConfig = field(default_factory=CheckConfig)
    tools: ToolTable | None = None
    tool_mm_per_unit: float = 1.0
    spindle_range: tuple[float, float] = (0.0, math.inf)
    default_machine: bool = False

    def of_machine(self) -> str:
        """What a limit finding appends: nothing for the user's profile; for the built-in
        default, that the limit is its own and how to give the real machine."""
        if self.default_machine:
            return " of the built-in default machine; give -m PROFILE"
        return ""


RuleFn = Callable[[canon.Command, CheckState, CheckContext], "str | None"]
EndFn = Callable[[CheckState, CheckContext], "str | None"]


@dataclass(frozen=True, slots=True)
class Rule:
    """A problem class: stable id, short name, default severity, one-line summary.

    ``kinds`` are the command types ``check`` is called for; consecutive offending commands
    of those kinds are reported once, with a count.
    """

    id: str
    name: str
    severity: Severity
    summary: str
    check: RuleFn | None = None
    at_end: EndFn | None = None
    kinds: tuple[type[canon.Command], ...] = ()
    default_enabled: bool = True


RULES: dict[str, Rule] = {}


def rule(
    rid: str,
    name: str,
    severity: Severity,
    summary: str,
    kinds: tuple[type[canon.Command], ...] = MOTIONS,
    default_enabled: bool = True,
    end: bool = False,
) -> Callable[[Callable], Callable]:
    """Register a rule function under ``rid``."""

    def deco(fn: Callable) -> Callable:
        RULES[rid] = Rule(
            rid,
            name,
            severity,
            summary,
            None if end else fn,
            fn if end else None,
            kinds,
            default_enabled,
        )
        return fn

    return deco


# The interpreter's own errors become findings of this rule (engine.check_stream).
RULES["CNC001"] = Rule(
    "CNC001",
    "interpreter-error",
    Severity.ERROR,
    "The program cannot be interpreted: a syntax or semantic error stops it here.",
)


# Judged on the program's text by its front end, not on the canonical stream: the front end
# hands check_stream the findings (``text_findings``); the trigger program is G-code.
RULES["CNC050"] = Rule(
    "CNC050",
    "number-without-decimal-point",
    Severity.WARNING,
    "A Fanuc/Haas length or angle without a decimal point counts increments (X100 = 0.1 mm).",
)
#: rules whose findings come from a front end's reading of the text (their trigger programs
#: in tests/check are G-code, not canonical text)
TEXT_RULES: frozenset[str] = frozenset({"CNC050"})


# --------------------------------------------------------------------------- helpers
def fmt_num(v: float) -> str:
    return f"{v:.4f}".rstrip("0").rstrip(".") if math.isfinite(v) else str(v)


def is_cutting(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> bool:
    """A feed move cuts, except a straight retract along +Z (reamers and taps leave the hole
    that way, spindle stopped or reversed); with a stock box configured, only feed moves
    that reach into the stock cut."""
    if not isinstance(cmd, FEEDS):
        return False
    if isinstance(cmd, canon.StraightFeed):
        p = st.position
        if abs(cmd.x - p[0]) <= EPS and abs(cmd.y - p[1]) <= EPS and cmd.z > p[2] + EPS:
            return False
    stock = ctx.config.stock
    if stock is None:
        return True
    pts = [st.work_mm(p)[:3] for p in swept_points(st, cmd)]
    return box_overlaps(pts, stock[0], stock[1])


def tool_length_mm(ctx: CheckContext, tool: int) -> float | None:
    if ctx.tools is None or tool == 0 or tool not in ctx.tools:
        return None
    t = ctx.tools.get(tool)
    return None if t is None else t.z_offset * ctx.tool_mm_per_unit


# --------------------------------------------------------------------------- CNC0xx program
@rule(
    "CNC010",
    "program-end-missing",
    Severity.ERROR,
    "The program has no M2/M30 program end.",
    kinds=(),
    end=True,
)
def program_end_missing(st: CheckState, ctx: CheckContext) -> str | None:
    return None if st.ended else "program ends without M2 or M30 (PROGRAM_END)"


@rule(
    "CNC020",
    "units-changed",
    Severity.WARNING,
    "Length units switch (G20/G21) after motion has started.",
    kinds=(canon.UseLengthUnits,),
)
def units_changed(cmd: canon.UseLengthUnits, st: CheckState, ctx: CheckContext) -> str | None:
    if st.moved and st.units is not None and cmd.units != st.units:
        return f"length units change to {cmd.units.name.lower()} after motion has started"
    return None


@rule(
    "CNC030",
    "first-move-is-feed",
    Severity.WARNING,
    "The first motion is a feed move from an unknown start position.",
)
def first_move_is_feed(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if not st.moved and isinstance(cmd, FEEDS):
        return "first motion is a feed move; its start point is wherever the machine stands"
    return None


@rule(
    "CNC040",
    "dwell-too-long",
    Severity.WARNING,
    "A dwell is longer than check.max_dwell (often P given in ms).",
    kinds=(canon.Dwell,),
)
def dwell_too_long(cmd: canon.Dwell, st: CheckState, ctx: CheckContext) -> str | None:
    limit = ctx.config.max_dwell
    if cmd.seconds > limit:
        return f"dwell of {fmt_num(cmd.seconds)} s exceeds {fmt_num(limit)} s (P is in seconds)"
    return None


# --------------------------------------------------------------------------- CNC1xx motion
@rule(
    "CNC101",
    "soft-limit",
    Severity.ERROR,
    "A move leaves the machine's travel (offsets and tool length included).",
)
def soft_limit(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    pts = [st.machine_point(p) for p in swept_points(st, cmd)]
    if not pts:
        return None
    for axis in ctx.machine.axes:
        i = AXIS_NAMES.index(axis.name)
        hi = max(p[i] for p in pts)
        lo = min(p[i] for p in pts)
        unit = "deg" if axis.rotary else "mm"
        if hi > axis.max + EPS:
            return (
                f"{axis.name.upper()} reaches {fmt_num(hi)} {unit} in machine coordinates, "
                f"beyond the travel limit {fmt_num(axis.max)} {unit}{ctx.of_machine()}"
            )
        if lo < axis.min - EPS:
            return (
                f"{axis.name.upper()} reaches {fmt_num(lo)} {unit} in machine coordinates, "
                f"beyond the travel limit {fmt_num(axis.min)} {unit}{ctx.of_machine()}"
            )
    return None


@rule(
    "CNC102", "axis-missing", Severity.ERROR, "A move commands an axis the machine does not have."
)
def axis_missing(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    end = motion_end(st, cmd)
    if end is None:
        return None
    have = set(ctx.machine.axis_names)
    for i, name in enumerate(AXIS_NAMES):
        if name not in have and abs(end[i] - st.position[i]) > EPS:
            if ctx.default_machine:
                return (
                    f"moves the {name.upper()} axis, which the built-in default machine "
                    "does not have; give -m PROFILE"
                )
            return f"moves the {name.upper()} axis, which this machine does not have"
    return None


def _path_speed_cap(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> float | None:
    """Fastest path speed (mm/s) the axes allow along this move's direction."""
    m = ctx.machine
    vel = dict(zip(AXIS_NAMES, m.limit_vector("velocity"), strict=True))
    if isinstance(cmd, canon.StraightFeed):
        d = [(getattr(cmd, a) - st.position[i]) * st.mm_per_unit for i, a in enumerate("xyz")]
        length = math.sqrt(sum(x * x for x in d))
        if length < EPS:
            return None
        caps = [vel[a] * length / abs(x) for a, x in zip("xyz", d, strict=True) if abs(x) > EPS]
        return min(caps, default=None)
    if isinstance(cmd, canon.ArcFeed):
        i1, i2, _ = PLANE_AXES[st.plane]
        return min(vel[AXIS_NAMES[i1]], vel[AXIS_NAMES[i2]])
    return None


@rule(
    "CNC103",
    "feed-too-fast",
    Severity.WARNING,
    "The programmed feed exceeds what the machine's axes or maximum feed allow.",
    kinds=FEEDS,
)
def feed_too_fast(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if st.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or st.synch:
        return None
    f = st.feed * st.mm_per_unit  # mm/min
    caps = []
    if ctx.config.max_feed is not None:
        caps.append((ctx.config.max_feed, "check.max_feed"))
    if ctx.machine.controller.max_feed > 0:
        caps.append((ctx.machine.controller.max_feed * 60.0, "controller.max_feed"))
    axis_cap = _path_speed_cap(cmd, st, ctx)
    if axis_cap is not None:
        caps.append((axis_cap * 60.0, "the axis velocity limits" + ctx.of_machine()))
    for cap, why in caps:
        if f > cap * (1 + 1e-9):
            return f"feed {fmt_num(f)} mm/min exceeds {fmt_num(cap)} mm/min allowed by {why}"
    return None


@rule("CNC104", "feed-zero", Severity.ERROR, "A feed move runs with a zero feed rate.", kinds=FEEDS)
def feed_zero(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if st.synch or st.feed_mode == canon.FeedMode.INVERSE_TIME:
        return None
    if st.feed <= 0.0:
        return "feed move with feed rate 0: the machine will not move"
    return None


@rule(
    "CNC105",
    "feed-per-rev-spindle-stopped",
    Severity.ERROR,
    "A feed-per-revolution or spindle-synchronised move runs with the spindle stopped.",
    kinds=FEEDS,
)
def feed_per_rev_stopped(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    per_rev = st.synch or st.feed_mode == canon.FeedMode.UNITS_PER_REVOLUTION
    if per_rev and (st.spindle == canon.Direction.STOPPED or st.spindle_speed <= 0):
        return "feed per revolution (G95/G33) with the spindle stopped: the axes will not move"
    return None


@rule(
    "CNC106",
    "probe-spindle-on",
    Severity.ERROR,
    "A probing move runs with the spindle turning.",
    kinds=(canon.StraightProbe,),
)
def probe_spindle_on(cmd: canon.Command, st: CheckState, ctx: CheckContext) -> str | None:
    if st.spindle != canon.Direction.STOPPED:
        return "probing move (G38) with the spindle turning (NISTIR 5970 §3.6.6)"
    return None


@rule(
    "CNC107",
    "blend-tolerance-large",
    Severity.WARNING,
    "G64 P allows a path deviation larger than check.max_blend.",
    kinds=(canon.SetMotionControlMode,),
)
def blend_tolerance_large(
    cmd: canon.SetMotionControlMode, st: CheckState, ctx: CheckContext
) -> str | None:
    tol = cmd.tolerance * st.mm_per_unit
    limit = ctx.config.max_blend
    if cmd.mode == canon.MotionMode.CONTINUOUS and tol > limit:
        return (
            f"G64 P{fmt_num(cmd.tolerance)} lets the path deviate {fmt_num(tol)} mm "
            f"(limit {fmt_num(limit)} mm)"
        )
    return None
