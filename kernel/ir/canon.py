"""The intermediate representation: NIST canonical machining commands (NISTIR 5970).

One small immutable class per canonical command, named as in NISTIR 5970 (``STRAIGHT_FEED``
-> :class:`StraightFeed`), fields in the NISTIR argument order and units (seed 000 §3 and
Appendix B). Lengths are in the *current length units* set by :class:`UseLengthUnits`,
angles in degrees, feed in units/min, spindle speed in rpm, dwell in seconds.

Additions, each because a seed or the reference interpreter requires it:

* the program-flow events the NIST v3 interpreter emits (``PROGRAM_STOP``,
  ``OPTIONAL_PROGRAM_STOP``, ``PROGRAM_END``; seed 002 §2.2.3, research note §0.10);
* the cutter-radius-compensation commands proposed in NISTIR 5970 Appendix A.8;
* ``NURBS_FEED`` (Appendix A.7; G5.2/G5.3 of LinuxCNC and G06.2 of the book, ch. 2);
* the motion-control tolerance as a second argument of ``SET_MOTION_CONTROL_MODE``
  (NISTIR 5970 §3.5.3 says a maximum deviation setter is missing; G64 P supplies it);
* the feed and spindle modes (G93/G94/G95, G96/G97; book Appendix A) and the synchronised
  feed per revolution of ``START_SPEED_FEED_SYNCH`` (G33, G76, rigid tapping), which the
  kernel needs to turn a program into time;
* ``MACHINE_FUNCTION`` (our extension, docs/canonical-ir.md): an M code the control does not
  define and hands to the machine's PLC (chip conveyor, clamps, ...), kept so that planning,
  checks and conversion see it rather than a reader refusing the program.

Every command may carry ``source`` (file, line, column, and for STEP-NC the workingstep id)
so that reports and errors point back to the program.

The module also holds the canonical text form (one command per line, four decimals, as
printed by NIST's and LinuxCNC's interpreters), a reader for it, and a JSON-lines form.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import field, fields
from enum import Enum
from operator import attrgetter
from typing import Any, ClassVar

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location
from kernel.record import record

Source = Location


# --------------------------------------------------------------------------- enumerations
class Plane(str, Enum):
    """``CANON_PLANE`` (NISTIR 5970 App. B)."""

    XY = "CANON_PLANE_XY"
    YZ = "CANON_PLANE_YZ"
    XZ = "CANON_PLANE_XZ"


class Units(str, Enum):
    """``CANON_UNITS``; CM exists in NISTIR 5970 only."""

    INCHES = "CANON_UNITS_INCHES"
    MM = "CANON_UNITS_MM"
    CM = "CANON_UNITS_CM"

    @property
    def mm_per_unit(self) -> float:
        return {"CANON_UNITS_INCHES": 25.4, "CANON_UNITS_MM": 1.0, "CANON_UNITS_CM": 10.0}[
            self.value
        ]


class MotionMode(str, Enum):
    """``CANON_MOTION_MODE`` (NISTIR 5970 §3.5.3): G61.1, G61 and G64."""

    EXACT_STOP = "CANON_EXACT_STOP"
    EXACT_PATH = "CANON_EXACT_PATH"
    CONTINUOUS = "CANON_CONTINUOUS"


class FeedReference(str, Enum):
    """``CANON_FEED_REFERENCE`` (NISTIR 5970 §3.5.1)."""

    WORKPIECE = "CANON_WORKPIECE"
    XYZ = "CANON_XYZ"


class Direction(str, Enum):
    """``CANON_DIRECTION``; STOPPED is for state tracking only."""

    STOPPED = "CANON_STOPPED"
    CLOCKWISE = "CANON_CLOCKWISE"
    COUNTERCLOCKWISE = "CANON_COUNTERCLOCKWISE"


class Axis(str, Enum):
    """``CANON_AXIS``."""

    X = "CANON_AXIS_X"
    Y = "CANON_AXIS_Y"
    Z = "CANON_AXIS_Z"
    A = "CANON_AXIS_A"
    B = "CANON_AXIS_B"
    C = "CANON_AXIS_C"


class CompSide(str, Enum):
    """``CANON_COMP_DIRECTION`` of the Appendix A.8 proposal."""

    LEFT = "CANON_COMP_LEFT"
    RIGHT = "CANON_COMP_RIGHT"


class FeedMode(int, Enum):
    """How ``SET_FEED_RATE`` is read: per minute (G94), inverse time (G93), per rev (G95)."""

    UNITS_PER_MINUTE = 0
    INVERSE_TIME = 1
    UNITS_PER_REVOLUTION = 2


_ENUMS: tuple[type[Enum], ...] = (
    Plane,
    Units,
    MotionMode,
    FeedReference,
    Direction,
    Axis,
    CompSide,
)
_ENUM_BY_VALUE: dict[str, Enum] = {m.value: m for e in _ENUMS for m in e}
#: field annotation -> enum: a field of one takes no other enum's values
_ENUM_TYPES: dict[str, type[Enum]] = {e.__name__: e for e in _ENUMS}
# LinuxCNC prints directions with the long NISTIR names too.
_ENUM_BY_VALUE["CANON_DIRECTION_CLOCKWISE"] = Direction.CLOCKWISE
_ENUM_BY_VALUE["CANON_DIRECTION_COUNTERCLOCKWISE"] = Direction.COUNTERCLOCKWISE
_ENUM_BY_VALUE["CANON_DIRECTION_STOPPED"] = Direction.STOPPED


# --------------------------------------------------------------------------- base class
@record
class Command:
    """Base of every canonical command. ``NAME`` is the NISTIR spelling."""

    NAME: ClassVar[str] = ""
    source: Location | None = field(default=None, compare=False, kw_only=True, repr=False)

    def args(self) -> tuple[object, ...]:
        """The arguments in NISTIR order (without ``source``)."""
        getter = _ARGS.get(type(self))
        if getter is None:
            getter = _ARGS[type(self)] = _args_getter(type(self))
        return getter(self)

    def to_text(self) -> str:
        """``NAME(arg, ...)`` with numbers to four decimals, as the NIST print functions do."""
        return f"{self.NAME}({', '.join(format_arg(a) for a in self.args())})"

    def to_json(self) -> dict[str, object]:
        out: dict[str, object] = {"cmd": self.NAME}
        for f in fields(self):
            if f.name == "source":
                continue
            v = getattr(self, f.name)
            out[f.name] = (
                v.value if isinstance(v, Enum) else (list(v) if isinstance(v, tuple) else v)
            )
        if self.source is not None:
            s = self.source
            out["source"] = {
                k: v
                for k, v in (
                    ("file", s.file),
                    ("line", s.line),
                    ("column", s.column),
                    ("entity", s.entity),
                    ("workingstep", s.workingstep),
                )
                if v not in (None, 0)
            }
        return out


#: per command class: its arguments' getter (a class's fields are read once, not per command)
_ARGS: dict[type, Callable[[Any], tuple[object, ...]]] = {}


def _args_getter(cls: type) -> Callable[[Any], tuple[object, ...]]:
    names = [f.name for f in fields(cls) if f.name != "source"]
    if not names:
        return lambda cmd: ()
    if len(names) == 1:
        one = attrgetter(names[0])
        return lambda cmd: (one(cmd),)
    many: Callable[[Any], tuple[object, ...]] = attrgetter(*names)
    return many


def named_field(cmd: Command, name: str) -> Any:
    """Field ``name`` of ``cmd``, read by name: for the commands the kernel knows by NAME
    only (LinuxCNC additions a front end defines), whose classes it cannot name."""
    return getattr(cmd, name)


def format_arg(v: object) -> str:
    """One argument as the NIST print functions and rs274 print it (four decimals, no -0)."""
    if isinstance(v, Enum):
        return str(v.value)
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        s = f"{v:.4f}"
        return "0.0000" if s == "-0.0000" else s
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, tuple):
        return ", ".join(format_arg(x) for x in v)
    raise TypeError(f"cannot format {v!r}")


# --------------------------------------------------------------------------- NISTIR 5970 §3.2
@record
class InitCanon(Command):
    NAME: ClassVar[str] = "INIT_CANON"


@record
class EndCanon(Command):
    NAME: ClassVar[str] = "END_CANON"


# --------------------------------------------------------------------------- §3.3 representation
@record
class SelectPlane(Command):
    NAME: ClassVar[str] = "SELECT_PLANE"
    plane: Plane


@record
class SetOriginOffsets(Command):
    """Program origin in absolute coordinates (G92 + G54..G59.3 combined)."""

    NAME: ClassVar[str] = "SET_ORIGIN_OFFSETS"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class UseLengthUnits(Command):
    NAME: ClassVar[str] = "USE_LENGTH_UNITS"
    units: Units


# --------------------------------------------------------------------------- §3.4 free-space motion
@record
class SetTraverseRate(Command):
    NAME: ClassVar[str] = "SET_TRAVERSE_RATE"
    rate: float


@record
class StraightTraverse(Command):
    NAME: ClassVar[str] = "STRAIGHT_TRAVERSE"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


# ---------------------------------------------------------------------- §3.5 machining attributes
@record
class SetFeedRate(Command):
    NAME: ClassVar[str] = "SET_FEED_RATE"
    rate: float


@record
class SetFeedReference(Command):
    NAME: ClassVar[str] = "SET_FEED_REFERENCE"
    reference: FeedReference


@record
class SetMotionControlMode(Command):
    """G61.1 / G61 / G64; ``tolerance`` is the G64 P blending tolerance (0: as fast as possible)."""

    NAME: ClassVar[str] = "SET_MOTION_CONTROL_MODE"
    mode: MotionMode
    tolerance: float = 0.0


@record
class SetNaivecamTolerance(Command):
    """G64 Q: collinear-segment merging tolerance (LinuxCNC)."""

    NAME: ClassVar[str] = "SET_NAIVECAM_TOLERANCE"
    tolerance: float


@record
class SetFeedMode(Command):
    """G94 / G93 / G95: the program's feed mode, and how ``SET_FEED_RATE`` numbers read.

    ``UNITS_PER_MINUTE`` and ``INVERSE_TIME``: rates are length units (or degrees) per
    minute. In G93 the interpreter turns each move's inverse-time F into the per-minute rate
    that makes the move last 1/F minutes and emits that (NIST RS274/NGC v3 §3.5.10; rs274
    does the same and prints mode 0); the mode only records that the program was in G93,
    for writers. ``UNITS_PER_REVOLUTION``: rates are length units per spindle revolution.
    """

    NAME: ClassVar[str] = "SET_FEED_MODE"
    mode: FeedMode


@record
class SetSpindleMode(Command):
    """G97 (``css_max`` 0) or G96 constant surface speed with a maximum rpm (G96 D)."""

    NAME: ClassVar[str] = "SET_SPINDLE_MODE"
    css_max: float = 0.0
    css: bool = False


@record
class StartSpeedFeedSynch(Command):
    """Spindle-synchronised motion (G33, G76, G33.1): ``feed_per_revolution`` in length units."""

    NAME: ClassVar[str] = "START_SPEED_FEED_SYNCH"
    feed_per_revolution: float = 0.0
    velocity_mode: bool = False


@record
class StopSpeedFeedSynch(Command):
    NAME: ClassVar[str] = "STOP_SPEED_FEED_SYNCH"


# ---------------------------------------------------------------------- §3.6 machining functions
@record
class ArcFeed(Command):
    """Helical arc: in-plane end, centre, signed turns, end on the plane normal (§3.6.1).

    In the XZ plane the first axis is Z and the second is X; the normal axis is Y.
    """

    NAME: ClassVar[str] = "ARC_FEED"
    first_end: float
    second_end: float
    first_axis: float
    second_axis: float
    rotation: int
    axis_end_point: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class Dwell(Command):
    NAME: ClassVar[str] = "DWELL"
    seconds: float


@record
class EllipseFeed(Command):
    """Elliptical helix; ``major``/``minor`` are full axis lengths (§3.6.3)."""

    NAME: ClassVar[str] = "ELLIPSE_FEED"
    major: float
    minor: float
    angle_to_first: float
    first_end: float
    second_end: float
    first_axis: float
    second_axis: float
    rotation: int
    axis_end_point: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class Stop(Command):
    NAME: ClassVar[str] = "STOP"


@record
class StraightFeed(Command):
    NAME: ClassVar[str] = "STRAIGHT_FEED"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class StraightProbe(Command):
    NAME: ClassVar[str] = "STRAIGHT_PROBE"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class NurbsFeed(Command):
    """Planar rational B-spline at feed rate (App. A.7; G5.2/G5.3, book ch. 2 ``G06.2``).

    ``order`` is degree + 1; ``points`` are (first, second, weight) in the selected plane;
    ``knots`` has ``len(points) + order`` entries (clamped uniform when G5.2 gives none).
    Read from LinuxCNC's elided print ``NURBS_FEED(n, ...)`` the order is 0 (unknown) and
    the ``n`` points are NaN: only their number is known (:attr:`elided`).
    """

    NAME: ClassVar[str] = "NURBS_FEED"
    order: int
    points: tuple[tuple[float, float, float], ...] = ()
    knots: tuple[float, ...] = ()

    @property
    def elided(self) -> bool:
        """True when only the number of control points is known (LinuxCNC's print)."""
        return self.order == 0

    def args(self) -> tuple[object, ...]:
        flat: list[object] = [self.order, len(self.points)]
        for p in self.points:
            flat.extend(float(v) for v in p)
        flat.extend(float(k) for k in self.knots)
        return tuple(flat)


# --------------------------------------------------------------------------- §3.7 spindle functions
@record
class OrientSpindle(Command):
    NAME: ClassVar[str] = "ORIENT_SPINDLE"
    orientation: float
    direction: Direction


@record
class SetSpindleSpeed(Command):
    NAME: ClassVar[str] = "SET_SPINDLE_SPEED"
    speed: float


@record
class SpindleRetract(Command):
    NAME: ClassVar[str] = "SPINDLE_RETRACT"


@record
class SpindleRetractTraverse(Command):
    NAME: ClassVar[str] = "SPINDLE_RETRACT_TRAVERSE"


@record
class StartSpindleClockwise(Command):
    NAME: ClassVar[str] = "START_SPINDLE_CLOCKWISE"


@record
class StartSpindleCounterclockwise(Command):
    NAME: ClassVar[str] = "START_SPINDLE_COUNTERCLOCKWISE"


@record
class StopSpindleTurning(Command):
    NAME: ClassVar[str] = "STOP_SPINDLE_TURNING"


@record
class UseNoSpindleForce(Command):
    NAME: ClassVar[str] = "USE_NO_SPINDLE_FORCE"


@record
class UseSpindleForce(Command):
    NAME: ClassVar[str] = "USE_SPINDLE_FORCE"
    force: float


# --------------------------------------------------------------------------- §3.8 tool functions
@record
class ChangeTool(Command):
    """Load the tool of ``slot``. ``name`` is an optional tool identifier (STEP-NC)."""

    NAME: ClassVar[str] = "CHANGE_TOOL"
    slot: int
    name: str = ""

    def to_text(self) -> str:
        return f"{self.NAME}({self.name if self.name else self.slot})"


@record
class SelectTool(Command):
    NAME: ClassVar[str] = "SELECT_TOOL"
    slot: int


@record
class UseToolLengthOffset(Command):
    NAME: ClassVar[str] = "USE_TOOL_LENGTH_OFFSET"
    length: float


# --------------------------------------------------------------------------- §3.9 miscellaneous
@record
class ClampAxis(Command):
    NAME: ClassVar[str] = "CLAMP_AXIS"
    axis: Axis


@record
class Comment(Command):
    NAME: ClassVar[str] = "COMMENT"
    text: str


@record
class DisableFeedOverride(Command):
    NAME: ClassVar[str] = "DISABLE_FEED_OVERRIDE"


@record
class DisableSpeedOverride(Command):
    NAME: ClassVar[str] = "DISABLE_SPEED_OVERRIDE"


@record
class EnableFeedOverride(Command):
    NAME: ClassVar[str] = "ENABLE_FEED_OVERRIDE"


@record
class EnableSpeedOverride(Command):
    NAME: ClassVar[str] = "ENABLE_SPEED_OVERRIDE"


@record
class FloodOff(Command):
    NAME: ClassVar[str] = "FLOOD_OFF"


@record
class FloodOn(Command):
    NAME: ClassVar[str] = "FLOOD_ON"


@record
class Message(Command):
    NAME: ClassVar[str] = "MESSAGE"
    text: str


@record
class MistOff(Command):
    NAME: ClassVar[str] = "MIST_OFF"


@record
class MistOn(Command):
    NAME: ClassVar[str] = "MIST_ON"


@record
class PalletShuttle(Command):
    NAME: ClassVar[str] = "PALLET_SHUTTLE"


@record
class ThroughToolOff(Command):
    NAME: ClassVar[str] = "THROUGH_TOOL_OFF"


@record
class ThroughToolOn(Command):
    NAME: ClassVar[str] = "THROUGH_TOOL_ON"


@record
class TurnProbeOff(Command):
    NAME: ClassVar[str] = "TURN_PROBE_OFF"


@record
class TurnProbeOn(Command):
    NAME: ClassVar[str] = "TURN_PROBE_ON"


@record
class UnclampAxis(Command):
    NAME: ClassVar[str] = "UNCLAMP_AXIS"
    axis: Axis


# --------------------------------------------------------------------------- App. A.8 proposal
@record
class SetCutterRadiusCompensation(Command):
    NAME: ClassVar[str] = "SET_CUTTER_RADIUS_COMPENSATION"
    radius: float


@record
class StartCutterRadiusCompensation(Command):
    NAME: ClassVar[str] = "START_CUTTER_RADIUS_COMPENSATION"
    side: CompSide


@record
class StopCutterRadiusCompensation(Command):
    NAME: ClassVar[str] = "STOP_CUTTER_RADIUS_COMPENSATION"


# --------------------------------------------------------------------------- program flow (v3)
@record
class ProgramStop(Command):
    """M0 (and M60 after the pallet shuttle)."""

    NAME: ClassVar[str] = "PROGRAM_STOP"


@record
class OptionalProgramStop(Command):
    """M1."""

    NAME: ClassVar[str] = "OPTIONAL_PROGRAM_STOP"


@record
class ProgramEnd(Command):
    """M2 / M30."""

    NAME: ClassVar[str] = "PROGRAM_END"


# --------------------------------------------------------------------------- machine functions
@record
class MachineFunction(Command):
    """An M code the control passes to the machine (its PLC): ``code`` with the block's
    optional P and Q values. Our extension; the machine profile's ``[m_codes]`` names it
    and gives its time (kernel.machine). Text form ``MACHINE_FUNCTION(31)``, with
    ``P=``/``Q=`` arguments when the block gave them: ``MACHINE_FUNCTION(59, P=1101.0000)``."""

    NAME: ClassVar[str] = "MACHINE_FUNCTION"
    code: int
    p: float | None = None
    q: float | None = None

    def to_text(self) -> str:
        """``MACHINE_FUNCTION(code[, P=p][, Q=q])``: P and Q are named, so either may be
        absent without the other shifting place."""
        extra = "".join(
            f", {k}={format_arg(float(v))}"
            for k, v in (("P", self.p), ("Q", self.q))
            if v is not None
        )
        return f"{self.NAME}({self.code}{extra})"

    @property
    def word(self) -> str:
        """The code as a G-code word: ``M31``."""
        return f"M{self.code}"


# --------------------------------------------------------------------------- LinuxCNC additions
# Commands LinuxCNC's rs274 prints that NISTIR 5970 lacks and that carry data the kernel or
# the readers of reference outputs use (offsets, rotation, rigid tapping, tool-table edits).
# The interpreter emits them in its LinuxCNC-compatible mode so ``cnc canon`` reads like
# rs274; print-only variants (I/O bits, nine-value tool offsets) live in gcode/core/linuxcnc.py.
@record
class SetG5xOffset(Command):
    """Active work offset: index 1..9 (G54..G59.3) and its x y z a b c."""

    NAME: ClassVar[str] = "SET_G5X_OFFSET"
    index: int
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class SetG92Offset(Command):
    NAME: ClassVar[str] = "SET_G92_OFFSET"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@record
class SetXYRotation(Command):
    """G10 L2 R: rotation of the work coordinate system about Z, degrees."""

    NAME: ClassVar[str] = "SET_XY_ROTATION"
    angle: float


@record
class OnReset(Command):
    NAME: ClassVar[str] = "ON_RESET"


@record
class StartChange(Command):
    """M6 begins: LinuxCNC's hook before ``CHANGE_TOOL``."""

    NAME: ClassVar[str] = "START_CHANGE"


@record
class ChangeToolNumber(Command):
    """M61 Q: declare the tool in the spindle without a change."""

    NAME: ClassVar[str] = "CHANGE_TOOL_NUMBER"
    number: int


@record
class SetToolTableEntry(Command):
    """G10 L1/L10/L11: a tool-table row rewritten (offsets x y z a b c u v w)."""

    NAME: ClassVar[str] = "SET_TOOL_TABLE_ENTRY"
    pocket: int
    tool: int
    offset: tuple[float, ...]
    diameter: float
    front_angle: float
    back_angle: float
    orientation: int

    def to_text(self) -> str:
        """As rs274 prints it: the nine offsets separated by blanks, no diameter."""
        off = " ".join(format_arg(v) for v in self.offset)
        return (
            f"{self.NAME}({self.pocket}, {self.tool}, {off}, "
            f"{format_arg(self.front_angle)}, {format_arg(self.back_angle)}, {self.orientation})"
        )


@record
class RigidTap(Command):
    """G33.1: feed to (x, y, z) synchronised with the spindle, reverse, and come back."""

    NAME: ClassVar[str] = "RIGID_TAP"
    x: float
    y: float
    z: float


@record
class Finish(Command):
    """End of the canonical stream after program end (LinuxCNC)."""

    NAME: ClassVar[str] = "FINISH"


ALL_COMMANDS: tuple[type[Command], ...] = tuple(
    c for c in list(globals().values()) if isinstance(c, type) and issubclass(c, Command) and c.NAME
)
BY_NAME: dict[str, type[Command]] = {c.NAME: c for c in ALL_COMMANDS}

#: Motions in the sense of the corpus equivalence rule (corpus/README.md).
MOTIONS: tuple[type[Command], ...] = (
    StraightTraverse,
    StraightFeed,
    ArcFeed,
    NurbsFeed,
    StraightProbe,
    Dwell,
)

#: Commands LinuxCNC prints that have no NISTIR counterpart and carry nothing the IR needs.
LINUXCNC_ONLY: frozenset[str] = frozenset(
    {
        "SET_G5X_OFFSET",
        "SET_G92_OFFSET",
        "SET_XY_ROTATION",
        "ON_RESET",
        "SET_FEED_MODE",
        "SET_SPINDLE_MODE",
        "SET_NAIVECAM_TOLERANCE",
        "START_CHANGE",
        "CHANGE_TOOL_NUMBER",
        "SET_TOOL_TABLE_ENTRY",
        "SET_MOTION_OUTPUT_BIT",
        "CLEAR_MOTION_OUTPUT_BIT",
        "SET_AUX_OUTPUT_BIT",
        "CLEAR_AUX_OUTPUT_BIT",
        "SET_MOTION_OUTPUT_VALUE",
        "SET_AUX_OUTPUT_VALUE",
        "FINISH",
    }
)


# --------------------------------------------------------------------------- text form
def write_text(commands: Iterable[Command], start: int = 1) -> Iterator[str]:
    """Yield the canonical text form, one line per command, numbered like the NIST SAI.

    Lines read ``    1 N..... STRAIGHT_FEED(1.0000, ...)``: sequence number, the block's
    line-number field (``N.....`` when the block had none, as LinuxCNC prints), command.
    """
    n = start
    for cmd in commands:
        yield f"{n:5d} N..... {cmd.to_text()}"
        n += 1


@record
class TextCommand:
    """One line of a canonical text file as read: the name and raw argument strings.

    Readers of foreign outputs (LinuxCNC, NIST) produce these; :func:`parse_command`
    turns the ones the IR knows into :class:`Command` objects.
    """

    name: str
    args: tuple[str, ...]
    line: int


_LINE_RE = re.compile(r"^\s*(?:\d+\s+)?(?:N[.\d]*\s+)?([A-Z_][A-Z0-9_]*)\((.*)\)\s*$")


def _split_args(raw: str) -> tuple[str, ...]:
    raw = raw.strip()
    if not raw:
        return ()
    if raw.startswith('"'):
        return (raw,)
    # LinuxCNC separates some arguments by blanks only (SET_SPINDLE_MODE(0 0.0000), and the
    # nine-value USE_TOOL_LENGTH_OFFSET); treat commas and blanks alike.
    return tuple(p for p in re.split(r"[,\s]+", raw) if p)


def read_text(lines: Iterable[str], file: str | None = None) -> Iterator[TextCommand]:
    """Read canonical text (ours, LinuxCNC ``rs274`` or NIST output) into raw commands.

    Lines that are not commands (interpreter chatter after an error) are skipped.
    """
    for i, line in enumerate(lines, 1):
        limits.check_digits(line, file, i)
        m = _LINE_RE.match(line.rstrip("\n"))
        if not m:
            continue
        name, raw = m.group(1), m.group(2)
        yield TextCommand(name, _split_args(raw), i)


# Commands whose LinuxCNC print has a leading spindle index NISTIR does not have.
_SPINDLE_INDEXED = frozenset(
    {
        "SET_SPINDLE_SPEED",
        "START_SPINDLE_CLOCKWISE",
        "START_SPINDLE_COUNTERCLOCKWISE",
        "STOP_SPINDLE_TURNING",
        "ORIENT_SPINDLE",
        "ENABLE_SPEED_OVERRIDE",
        "DISABLE_SPEED_OVERRIDE",
        "SPINDLE_RETRACT",
        "SPINDLE_RETRACT_TRAVERSE",
    }
)


def _convert(raw: str, typ: object) -> object:
    if raw.startswith('"') and raw.endswith('"') and len(raw) >= 2:
        return raw[1:-1]
    enum = _ENUM_TYPES.get(typ) if isinstance(typ, str) else None
    if raw in _ENUM_BY_VALUE:
        value = _ENUM_BY_VALUE[raw]
        if typ in ("float", float) or (enum is not None and not isinstance(value, enum)):
            raise ValueError(f"{raw} where a {typ} is expected")
        return value
    if enum in (Units, Plane):  # no numeric spelling (LinuxCNC prints others as numbers)
        raise ValueError(f"{raw} is not a {typ}")
    if typ in ("int", int):
        return int(float(raw))
    if typ in ("bool", bool):
        return bool(int(float(raw)))
    if typ in ("FeedMode",):
        return FeedMode(int(float(raw)))
    return float(raw)


def parse_command(tc: TextCommand, file: str | None = None) -> Command:
    """Turn a :class:`TextCommand` into an IR command.

    Accepts our own form and LinuxCNC's variants (spindle index first, ``CHANGE_TOOL(name)``,
    ``NURBS_FEED(order, ...)`` with elided data). Raises :class:`Diagnostic` ``CANON-SYNTAX``
    for anything else.
    """
    loc = Location(file, tc.line, 1)
    cls = BY_NAME.get(tc.name)
    if tc.name == "START_SPEED_FEED_SYNC":  # LinuxCNC's spelling
        cls = StartSpeedFeedSynch
    if cls is None:
        raise Diagnostic("CANON-UNKNOWN", f"unknown canonical command {tc.name}", loc)
    args = list(tc.args)
    try:
        if cls is NurbsFeed:
            if len(args) < 2 or args[1] == "...":
                # LinuxCNC prints NURBS_FEED(<number of control points>, ...) without the
                # curve (saicanon.cc): order unknown (0), the count kept as blank points
                count = int(float(args[0]))
                if count > limits.current().nurbs_points:
                    raise ValueError(f"{count} control points (limit: --limit nurbs_points=N)")
                return NurbsFeed(0, ((math.nan, math.nan, math.nan),) * count, source=loc)
            order = int(float(args[0]))
            n = int(float(args[1]))
            vals = [float(a) for a in args[2:]]
            if not 0 <= 3 * n <= len(vals):
                raise ValueError(f"{n} control points but {len(vals)} values")
            pts = tuple(tuple(vals[3 * i : 3 * i + 3]) for i in range(n))
            return NurbsFeed(order, pts, tuple(vals[3 * n :]), source=loc)  # type: ignore[arg-type]
        if cls is ChangeTool:
            joined = " ".join(args)
            try:
                return ChangeTool(int(joined), source=loc)
            except ValueError:
                return ChangeTool(0, joined, source=loc)
        if cls is SetToolTableEntry and len(args) == 14:  # rs274 prints no diameter
            f = [float(a) for a in args]
            return SetToolTableEntry(
                int(f[0]), int(f[1]), tuple(f[2:11]), 0.0, f[11], f[12], int(f[13]), source=loc
            )
        if cls is UseToolLengthOffset and len(args) == 9:  # LinuxCNC: x y z, a b c, u v w
            return UseToolLengthOffset(float(args[2]), source=loc)
        if cls is MachineFunction:
            return _machine_function(args, loc)
        if cls is SetSpindleMode and len(args) == 2 and "." not in args[0]:
            # LinuxCNC: spindle index (an integer), css max (0: G97)
            return SetSpindleMode(float(args[1]), float(args[1]) > 0, source=loc)
        if cls is SetFeedMode and len(args) == 2:
            # LinuxCNC: spindle, mode with 0 per minute (G94, and G93 already converted)
            # and 1 per revolution (G95)
            per_rev = int(float(args[1])) == 1
            mode = FeedMode.UNITS_PER_REVOLUTION if per_rev else FeedMode.UNITS_PER_MINUTE
            return SetFeedMode(mode, source=loc)
        if cls is StartSpeedFeedSynch and len(args) == 3:  # spindle, feed/rev, velocity mode
            args = args[1:]
        if cls is SetMotionControlMode and len(args) == 1:
            args.append("0")
        flds = [f for f in fields(cls) if f.name != "source"]
        if tc.name in _SPINDLE_INDEXED and len(args) == len(flds) + 1:
            args = args[1:]
        if (
            cls in (StraightFeed, StraightTraverse, StraightProbe, SetOriginOffsets)
            and len(args) > 6
        ):
            args = args[:6]  # LinuxCNC with u v w
        if len(args) > len(flds):
            raise ValueError(f"{len(args)} arguments, expected at most {len(flds)}")
        values = [_convert(a, f.type) for a, f in zip(args, flds, strict=False)]
        return cls(*values, source=loc)
    except (ValueError, IndexError, TypeError, OverflowError) as exc:
        raise Diagnostic(
            "CANON-SYNTAX", f"cannot read {tc.name}({', '.join(tc.args)}): {exc}", loc
        ) from None


def _machine_function(args: list[str], loc: Location) -> MachineFunction:
    """``MACHINE_FUNCTION(code[, P=p][, Q=q])`` back into its command."""
    if not args:
        raise ValueError("no M code")
    named: dict[str, float] = {}
    for a in args[1:]:
        key, sep, value = a.partition("=")
        if not sep or key not in ("P", "Q") or key in named:
            raise ValueError(f"argument {a!r} is not P=value or Q=value")
        named[key] = float(value)
    code = float(args[0])
    if code != int(code) or code < 0:
        raise ValueError(f"M code {args[0]} is not a whole number >= 0")
    return MachineFunction(int(code), named.get("P"), named.get("Q"), source=loc)


def read_commands(
    lines: Iterable[str], file: str | None = None, *, keep_linuxcnc: bool = False
) -> Iterator[Command]:
    """Read canonical text into IR commands.

    LinuxCNC-only commands (:data:`LINUXCNC_ONLY`) are skipped, except the feed and spindle
    modes; with ``keep_linuxcnc`` those the IR has a class for (work offsets, XY rotation,
    tool-table edits, ...) are kept, which a planner placing moves on the machine needs,
    and only the print-only ones (I/O bits) are skipped.
    """
    for tc in read_text(lines, file):
        if tc.name in LINUXCNC_ONLY:
            if keep_linuxcnc and tc.name not in BY_NAME:
                continue
            if not keep_linuxcnc and tc.name not in _MODE_COMMANDS:
                continue
        yield parse_command(tc, file)


_MODE_COMMANDS = frozenset({"SET_FEED_MODE", "SET_SPINDLE_MODE", "SET_NAIVECAM_TOLERANCE"})


# --------------------------------------------------------------------------- JSON lines
def to_jsonl(commands: Iterable[Command]) -> Iterator[str]:
    """One JSON object per line: ``{"cmd": NAME, <field>: value, ..., "source": {...}}``."""
    for cmd in commands:
        yield json.dumps(cmd.to_json(), separators=(",", ":"))


def from_json(obj: dict[str, Any]) -> Command:
    """Inverse of :meth:`Command.to_json` (``obj``: a decoded JSON object, whose values
    may be of any JSON type)."""
    cls = BY_NAME.get(str(obj.get("cmd")))
    if cls is None:
        raise Diagnostic("CANON-UNKNOWN", f"unknown canonical command {obj.get('cmd')!r}")
    kwargs: dict[str, Any] = {}
    for f in fields(cls):
        if f.name == "source" or f.name not in obj:
            continue
        v = obj[f.name]
        if isinstance(v, str) and v in _ENUM_BY_VALUE:
            v = _ENUM_BY_VALUE[v]
        elif f.name == "mode" and cls is SetFeedMode:
            v = FeedMode(int(v))
        elif f.name == "points":
            v = tuple(tuple(p) for p in v)
        elif f.name == "knots":
            v = tuple(v)
        kwargs[f.name] = v
    src = obj.get("source")
    if isinstance(src, dict):
        kwargs["source"] = Location(**src)
    return cls(**kwargs)
