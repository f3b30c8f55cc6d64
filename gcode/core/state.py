"""The interpreter's machine model: modal state, position and offsets (NIST v3 §3.4, LinuxCNC).

One mutable object per run (the interpreter is a state machine; copying it per line would
cost more than the line). Positions are *program* coordinates in the current length units,
as rs274 prints them in motions: machine = program + G5x offset + G92 offset + tool offset
(the XY rotation of G10 L2 R is applied below the interpreter, as in LinuxCNC). Offsets are
kept in current units too and converted when G20/G21 changes the units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import IntEnum

from kernel.ir.canon import Direction, FeedMode, Plane, Units

#: motion-mode codes (``round(G*10)``), see :mod:`gcode.core.codes`
G0, G1, G2, G3 = 0, 10, 20, 30
G80 = 800
INCH_MM = 25.4
AXES = "xyzabc"
#: plane -> (first, second, normal) axis indices and the centre-word letters
PLANE_AXES = {Plane.XY: (0, 1, 2), Plane.XZ: (2, 0, 1), Plane.YZ: (1, 2, 0)}
PLANE_CENTRE = {Plane.XY: ("i", "j", "k"), Plane.XZ: ("k", "i", "j"), Plane.YZ: ("j", "k", "i")}
#: the feed modes as module constants (attribute access on an enum class is slow in 3.11,
#: and these are compared on every feed move)
PER_MINUTE = FeedMode.UNITS_PER_MINUTE
INVERSE_TIME = FeedMode.INVERSE_TIME
PER_REV = FeedMode.UNITS_PER_REVOLUTION


class FeedCode(IntEnum):
    """The feed-mode G codes of modal group 5 (``round(G*10)``) and the mode each selects."""

    G93 = 930
    G94 = 940
    G95 = 950

    @property
    def mode(self) -> FeedMode:
        """The feed mode this code selects."""
        return _FEED_MODES[self]

    @classmethod
    def of(cls, mode: FeedMode) -> FeedCode:
        """The G code that selects ``mode``."""
        return _FEED_CODES[mode]


_FEED_MODES = {
    FeedCode.G93: FeedMode.INVERSE_TIME,
    FeedCode.G94: FeedMode.UNITS_PER_MINUTE,
    FeedCode.G95: FeedMode.UNITS_PER_REVOLUTION,
}
_FEED_CODES = {mode: code for code, mode in _FEED_MODES.items()}


class ControlCode(IntEnum):
    """Path control G codes of modal group 13 (``round(G*10)``)."""

    G61 = 610  # exact path
    G61_1 = 611  # exact stop
    G64 = 640  # continuous (blending)


class ToolLengthCode(IntEnum):
    """Tool length offset G codes of modal group 8 (``round(G*10)``)."""

    G43 = 430
    G43_1 = 431
    G43_2 = 432
    G49 = 490


class CompCode(IntEnum):
    """Cutter compensation G codes of modal group 7 (``round(G*10)``)."""

    G40 = 400
    G41 = 410
    G41_1 = 411
    G42 = 420
    G42_1 = 421


@dataclass(slots=True)
class CycleWords:
    """Sticky canned-cycle values (LinuxCNC keeps R, Z, P, Q, ... between cycle blocks)."""

    r: float = 0.0
    z: float = 0.0
    p: float = 0.0
    q: float = 0.0
    i: float = 0.0
    j: float = 0.0
    k: float = 0.0
    l: int = 1  # noqa: E741 - the L word
    cc: float = 0.0  # clear plane of the previous cycle block (G98)


@dataclass(slots=True)
class Setup:
    """Everything the interpreter remembers between lines."""

    # position (program coordinates, current units): x y z a b c
    pos: list[float] = field(default_factory=lambda: [0.0] * 6)
    units: Units = Units.MM
    plane: Plane = Plane.XY
    absolute: bool = True  # G90 / G91
    ijk_absolute: bool = False  # G90.1 / G91.1
    diameter_mode: bool = False  # G7 (lathe diameter) / G8 (radius)
    feed_mode: FeedMode = FeedMode.UNITS_PER_MINUTE  # G94; G93 inverse time, G95 per rev
    feed_rate: float = 0.0
    speed: float = 0.0
    css: bool = False  # G96
    css_max: float = 0.0
    spindle: Direction = Direction.STOPPED
    motion_mode: int | None = G80  # rs274 starts with no motion mode (axis words refused)
    retract_r: bool = True  # G99 (retract to R, rs274's initial mode); G98 otherwise
    cycle_series: bool = False  # inside a series of canned-cycle blocks
    control_mode: ControlCode = ControlCode.G64
    blend_p: float = 0.0
    blend_q: float = 0.0
    origin_index: int = 1  # G54 .. G59.3 -> 1..9
    #: the work offset number (gcode.core.register_marks) slot 9 holds: a Fanuc G54.1 P n
    #: or Siemens G510-G599 is run in G59.3's slot
    slot9_number: int = 9
    g5x: list[float] = field(default_factory=lambda: [0.0] * 6)
    g92: list[float] = field(default_factory=lambda: [0.0] * 6)
    #: work offsets of G54..G59.3 (index 1..9; 0 unused): x y z a b c and the XY rotation R
    coords: list[list[float]] = field(default_factory=lambda: [[0.0] * 7 for _ in range(10)])
    g28: list[float] = field(default_factory=lambda: [0.0] * 6)  # machine coordinates
    g30: list[float] = field(default_factory=lambda: [0.0] * 6)
    g92_saved: list[float] = field(default_factory=lambda: [0.0] * 6)  # G92.2 / G92.3
    rotation: float = 0.0
    tool_offset: list[float] = field(default_factory=lambda: [0.0] * 9)
    tool_length_mode: ToolLengthCode = ToolLengthCode.G49
    current_tool: int = 0
    #: the tool M6 last loaded: rs274's spindle slot, whose table entry #5400-#5413 show
    #: (M61 changes the current tool number but not that entry)
    loaded_tool: int = 0
    current_pocket: int = 0
    selected_tool: int = -1
    selected_pocket: int = -1
    mist: bool = False
    flood: bool = False
    feed_override: bool = True
    speed_override: bool = True
    adaptive_feed: bool = False
    feed_hold: bool = True
    comp_side: CompCode = CompCode.G40
    comp_radius: float = 0.0
    cycle: CycleWords = field(default_factory=CycleWords)
    probe_flag: bool = False
    #: rs274's canon does not move its own position on a tool-length change: until the
    #: next motion, canon position = ours + tlo_lag; M6/M61 take the canon position back
    tlo_lag: list[float] | None = None
    #: an M6/M61 ran in this block: rs274 re-reads its canon position when the next block is
    #: read, so a tool-length change in the same block is taken back too
    resync_pending: bool = False
    spline_i: float = 0.0  # G5 continuation (cycle_i / cycle_j of LinuxCNC)
    spline_j: float = 0.0
    nurbs_points: list[tuple[float, float, float]] = field(default_factory=list)
    nurbs_order: int = 3

    @property
    def inches(self) -> bool:
        return self.units is Units.INCHES

    def machine_offset(self, i: int) -> float:
        """Program -> machine offset of axis ``i`` (0..5)."""
        return self.g5x[i] + self.g92[i] + self.tool_offset[i]

    def to_machine(self, p: list[float]) -> list[float]:
        """Program -> machine coordinates: add G92, turn by the XY rotation (G10 L2 R) about
        the G5x origin, add the G5x offset and the tool offset (LinuxCNC's order)."""
        m = [p[i] + self.g92[i] for i in range(6)]
        if self.rotation:
            a = math.radians(self.rotation)
            x, y = m[0], m[1]
            m[0], m[1] = x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)
        return [m[i] + self.g5x[i] + self.tool_offset[i] for i in range(6)]

    def to_program(self, m: list[float]) -> list[float]:
        """Machine -> program coordinates (inverse of :meth:`to_machine`)."""
        p = [m[i] - self.g5x[i] - self.tool_offset[i] for i in range(6)]
        if self.rotation:
            a = math.radians(self.rotation)
            x, y = p[0], p[1]
            p[0], p[1] = x * math.cos(a) + y * math.sin(a), -x * math.sin(a) + y * math.cos(a)
        return [p[i] - self.g92[i] for i in range(6)]

    def scale_lengths(self, factor: float) -> None:
        """G20/G21: re-express every stored length in the new units (no motion)."""
        for v in (self.pos, self.g5x, self.g92, self.g28, self.g30, self.g92_saved, *self.coords):
            for i in range(3):
                v[i] *= factor
        # the tool length offset keeps its numbers (rs274 does not convert it)
        self.comp_radius *= factor
        c = self.cycle
        c.r *= factor
        c.z *= factor
        c.q *= factor
        c.i *= factor
        c.j *= factor
        c.k *= factor
        c.cc *= factor
        self.nurbs_points = [(x * factor, y * factor, w) for x, y, w in self.nurbs_points]


@dataclass(frozen=True, slots=True)
class SavedModes:
    """The modal state M70/M73 save and M72 (or the end of an M73 subroutine) restores,
    as LinuxCNC saves it."""

    units: Units
    plane: Plane
    absolute: bool
    ijk_absolute: bool
    feed_mode: FeedMode
    feed_rate: float
    speed: float
    spindle: Direction
    mist: bool
    flood: bool
    motion_mode: int | None
    retract_r: bool
    control_mode: ControlCode
    blend_p: float
    blend_q: float
    origin_index: int
    css: bool
    css_max: float
    tool_length_mode: ToolLengthCode

    @classmethod
    def of(cls, s: Setup) -> SavedModes:
        """The saved part of ``s`` now."""
        return cls(
            units=s.units,
            plane=s.plane,
            absolute=s.absolute,
            ijk_absolute=s.ijk_absolute,
            feed_mode=s.feed_mode,
            feed_rate=s.feed_rate,
            speed=s.speed,
            spindle=s.spindle,
            mist=s.mist,
            flood=s.flood,
            motion_mode=s.motion_mode,
            retract_r=s.retract_r,
            control_mode=s.control_mode,
            blend_p=s.blend_p,
            blend_q=s.blend_q,
            origin_index=s.origin_index,
            css=s.css,
            css_max=s.css_max,
            tool_length_mode=s.tool_length_mode,
        )
