"""The machine state seen by ``check``: what the canonical stream has set so far.

The checker walks the stream once; before each command the rules see the state the
previous commands left (units, offsets, position, tool, spindle, feed, coolant, plane,
cutter compensation). Positions are kept in program units as the IR carries them (NISTIR
5970 §3.3, seed 000); :meth:`CheckState.machine_point` converts to machine mm with the
origin offsets and the tool length offset, the frame the travel limits live in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import kernel.ir.canon as canon
from kernel.ir.canon import CompSide, Direction, FeedMode, Plane

Vec6 = tuple[float, float, float, float, float, float]
ZERO6: Vec6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

#: (first, second, normal) axis indices of ARC_FEED per plane (seed-canon-rs274.md, mapping table)
PLANE_AXES: dict[Plane, tuple[int, int, int]] = {
    Plane.XY: (0, 1, 2),
    Plane.YZ: (1, 2, 0),
    Plane.XZ: (2, 0, 1),
}


@dataclass(slots=True)
class CheckState:
    """Mutable modal state, advanced one canonical command at a time."""

    mm_per_unit: float = 1.0
    units: canon.Units | None = None
    position: Vec6 = ZERO6  # program coordinates, program units (a, b, c in degrees)
    origin_mm: Vec6 = ZERO6  # program origin in machine coordinates, mm / degrees
    g5x_mm: Vec6 = ZERO6  # LinuxCNC's split of the origin: work offset ...
    g92_mm: Vec6 = ZERO6  # ... plus G92 offset (SET_G5X_OFFSET / SET_G92_OFFSET)
    rotation: float = 0.0  # SET_XY_ROTATION (G10 L2 R), radians about Z
    tlo_mm: float = 0.0
    tlo_set: bool = False  # a USE_TOOL_LENGTH_OFFSET came since the last tool change
    plane: Plane = Plane.XY
    feed: float = 0.0
    feed_set: bool = False
    feed_mode: FeedMode = FeedMode.UNITS_PER_MINUTE
    spindle_speed: float = 0.0
    spindle: Direction = Direction.STOPPED
    css: bool = False  # G96: SET_SPINDLE_SPEED is a surface speed, css_max the rpm cap
    css_max: float = 0.0
    tool: int = 0  # loaded tool number; -1: a tool known by name only (STEP-NC)
    tool_name: str = "T0"
    selected: int = 0
    flood: bool = False
    mist: bool = False
    comp_radius: float = 0.0  # program units
    comp_side: CompSide | None = None
    probe_on: bool = False
    synch: bool = False
    moved: bool = False  # some motion happened
    ended: bool = False
    extra: dict[str, object] = field(default_factory=dict)

    def machine_point(self, p: Vec6) -> Vec6:
        """Program point -> machine coordinates (mm, degrees): origin offset plus tool length.

        With an XY rotation the order is rs274's: G92 offset, rotation about Z, G5x offset."""
        k = self.mm_per_unit
        if self.rotation:
            g92, g5x = self.g92_mm, self.g5x_mm
            x, y = p[0] * k + g92[0], p[1] * k + g92[1]
            c, s = math.cos(self.rotation), math.sin(self.rotation)
            return (
                c * x - s * y + g5x[0],
                s * x + c * y + g5x[1],
                p[2] * k + g92[2] + g5x[2] + self.tlo_mm,
                p[3] + self.origin_mm[3],
                p[4] + self.origin_mm[4],
                p[5] + self.origin_mm[5],
            )
        o = self.origin_mm
        return (
            p[0] * k + o[0],
            p[1] * k + o[1],
            p[2] * k + o[2] + self.tlo_mm,
            p[3] + o[3],
            p[4] + o[4],
            p[5] + o[5],
        )

    def work_mm(self, p: Vec6) -> Vec6:
        """Program point in mm (work coordinates), rotary axes unchanged."""
        k = self.mm_per_unit
        return (p[0] * k, p[1] * k, p[2] * k, p[3], p[4], p[5])

    def cooling(self) -> bool:
        return self.flood or self.mist


def motion_end(st: CheckState, cmd: canon.Command, start: Vec6 | None = None) -> Vec6 | None:
    """Where ``cmd`` leaves the controlled point (program coordinates), None if no motion;
    from ``start`` instead of the state's position when given."""
    position = st.position if start is None else start
    match cmd:
        case canon.StraightTraverse() | canon.StraightFeed() | canon.StraightProbe():
            return (cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c)
        case canon.ArcFeed() | canon.EllipseFeed():
            i1, i2, n = PLANE_AXES[st.plane]
            p = list(position)
            p[i1], p[i2], p[n] = cmd.first_end, cmd.second_end, cmd.axis_end_point
            p[3], p[4], p[5] = cmd.a, cmd.b, cmd.c
            return (p[0], p[1], p[2], p[3], p[4], p[5])
        case canon.NurbsFeed(points=pts) if pts:
            i1, i2, _ = PLANE_AXES[st.plane]
            p = list(position)
            p[i1], p[i2] = pts[-1][0], pts[-1][1]
            return (p[0], p[1], p[2], p[3], p[4], p[5])
    return None


def _scaled(st: CheckState, v: tuple[float, ...]) -> Vec6:
    k = st.mm_per_unit
    return (v[0] * k, v[1] * k, v[2] * k, v[3], v[4], v[5])


def _linuxcnc(st: CheckState, cmd: canon.Command) -> bool:
    """LinuxCNC-only commands a front end may pass through (gcode.core.linuxcnc; the kernel knows
    them by NAME only, never importing a front end). True when ``cmd`` was one of them."""
    name = cmd.NAME
    if name in ("SET_G5X_OFFSET", "SET_G92_OFFSET"):
        v = tuple(canon.named_field(cmd, k) for k in ("x", "y", "z", "a", "b", "c"))
        if name == "SET_G5X_OFFSET":
            st.g5x_mm = _scaled(st, v)
        else:
            st.g92_mm = _scaled(st, v)
        g5x, g92 = st.g5x_mm, st.g92_mm
        st.origin_mm = (
            g5x[0] + g92[0],
            g5x[1] + g92[1],
            g5x[2] + g92[2],
            g5x[3] + g92[3],
            g5x[4] + g92[4],
            g5x[5] + g92[5],
        )
        return True
    if name == "USE_TOOL_LENGTH_OFFSET" and hasattr(cmd, "offset"):
        st.tlo_mm = canon.named_field(cmd, "offset")[2] * st.mm_per_unit
        st.tlo_set = True
        return True
    if name == "CHANGE_TOOL_NUMBER":
        st.tool = int(canon.named_field(cmd, "number"))
        st.tool_name = f"T{st.tool}"
        return True
    if name == "SET_XY_ROTATION":
        st.rotation = math.radians(canon.named_field(cmd, "angle"))
        return True
    return False


def advance(st: CheckState, cmd: canon.Command) -> None:  # noqa: C901 - one branch per command
    """Apply ``cmd`` to ``st`` (the modal effects only; rules judge the command beforehand)."""
    if _linuxcnc(st, cmd):
        return
    match cmd:
        case canon.UseLengthUnits(units=u):
            # rs274 keeps positions and offsets numerically in the new units after G20/G21
            # converts them; the stream's next commands are already in the new units.
            factor = st.mm_per_unit / u.mm_per_unit
            p = st.position
            st.position = (p[0] * factor, p[1] * factor, p[2] * factor, p[3], p[4], p[5])
            st.feed *= factor
            st.comp_radius *= factor
            st.units, st.mm_per_unit = u, u.mm_per_unit
        case canon.SetOriginOffsets():
            st.origin_mm = _scaled(st, (cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c))
            st.g5x_mm, st.g92_mm = st.origin_mm, ZERO6
        case canon.UseToolLengthOffset(length=length):
            st.tlo_mm = length * st.mm_per_unit
            st.tlo_set = True
        case canon.SelectPlane(plane=plane):
            st.plane = plane
        case canon.SetFeedRate(rate=rate):
            st.feed, st.feed_set = rate, True
        case canon.SetFeedMode(mode=mode):
            st.feed_mode = mode
        case canon.SetSpindleMode(css_max=css_max, css=css):
            st.css, st.css_max = css, css_max
        case canon.SetSpindleSpeed(speed=speed):
            st.spindle_speed = speed
        case canon.StartSpindleClockwise():
            st.spindle = Direction.CLOCKWISE
        case canon.StartSpindleCounterclockwise():
            st.spindle = Direction.COUNTERCLOCKWISE
        case canon.StopSpindleTurning() | canon.OrientSpindle():
            st.spindle = Direction.STOPPED
        case canon.SelectTool(slot=slot):
            st.selected = slot
        case canon.ChangeTool(slot=slot, name=name):
            st.tool = slot if slot or not name else -1
            st.tool_name = name or f"T{slot}"
            st.tlo_set = False
        case canon.FloodOn():
            st.flood = True
        case canon.FloodOff():
            st.flood = False
        case canon.MistOn():
            st.mist = True
        case canon.MistOff():
            st.mist = False
        case canon.SetCutterRadiusCompensation(radius=r):
            st.comp_radius = r
        case canon.StartCutterRadiusCompensation(side=side):
            st.comp_side = side
        case canon.StopCutterRadiusCompensation():
            st.comp_side = None
        case canon.TurnProbeOn():
            st.probe_on = True
        case canon.TurnProbeOff():
            st.probe_on = False
        case canon.StartSpeedFeedSynch():
            st.synch = True
        case canon.StopSpeedFeedSynch():
            st.synch = False
        case canon.ProgramEnd():
            st.ended = True
            st.spindle = Direction.STOPPED
            st.flood = st.mist = False
            st.comp_side = None
        case _:
            end = motion_end(st, cmd)
            if end is not None:
                st.position = end
                st.moved = True
