"""The machine state a STEP-NC workplan is executed against, and the canonical commands it
emits for tool changes, spindle, coolant, feed and positioning.

The behaviour follows NIST's ISO 14649 interpreter (research/seed-book-stepnc.md §7;
``change_tool``, ``handle_speed``, ``handle_feed``, ``handle_machine_functions``,
``start_cut``, ``run_code``): a command is emitted only when the state changes; between
workingsteps the tool leaves through the security plane. Units: ISO 14649-10 §4.2.1 gives
feed in m/s and spindle speed in rev/s (positive = counterclockwise); the IR uses mm/min
and rpm.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from stepnc.model import Entity, tool_dimension
from stepnc.tooling import ToolEntry
from stepnc.toolpaths.code import ARC, FEED, Code

TINY = 0.0001  # NIST ISO14649_TINY (mm)
UP = 5.0  # NIST ISO14649_UP: default retract above the feature top (mm)
ALLOW = 0.2  # NIST ISO14649_ALLOW: default rough-milling allowance (mm)


@dataclass(frozen=True)
class Start:
    """Machine state before the first workingstep. ``None`` means unknown (so the first
    command that sets it is always emitted)."""

    position: tuple[float, float, float]
    retracted_z: float
    feed: float
    speed: float
    spindle: canon.Direction | None
    flood: bool | None
    mist: bool | None


#: NIST's stand-alone driver syncs its state from a simulated machine. Observed in
#: ``ex1.can``: the first tool change stops the spindle and turns flood off, the first
#: traverse is at Z=200 with the spindle retracted to 250, and the 2400 mm/min feed of the
#: first operation is not re-sent (docs/stepnc.md, "NIST-compatible mode").
NIST_START = Start((0.0, 0.0, 200.0), 250.0, 2400.0, 0.0, None, None, False)
#: Default mode: a known, retracted, stopped machine.
DEFAULT_START = Start((0.0, 0.0, 250.0), 250.0, 0.0, 0.0, canon.Direction.STOPPED, False, False)


def start_within(start: Start, z_max: float) -> Start:
    """``start`` with its retract height lowered to a machine's Z travel limit ``z_max``
    (the NIST start state retracts to Z 250, above many machines' travel)."""
    if start.retracted_z <= z_max:
        return start
    x, y, z = start.position
    return replace(start, position=(x, y, min(z, z_max)), retracted_z=z_max)


class Executor:
    """Canonical-command writer with the interpreter's world model."""

    def __init__(
        self,
        file: str | None,
        tools: dict[str, ToolEntry] | None,
        mode: str,
        start: Start | None = None,
    ) -> None:
        if mode not in ("nist", "default"):
            raise Diagnostic("STEPNC-MODE", f"unknown mode {mode!r} (nist or default)")
        self.file = file
        self.tools = tools
        self.mode = mode
        if start is None:
            start = NIST_START if mode == "nist" else DEFAULT_START
        self.start = start
        self.x, self.y, self.z = start.position
        self.retracted_z = start.retracted_z
        self.feedrate = start.feed
        self.speed = start.speed
        self.spindle = start.spindle
        self.flood = start.flood
        self.mist = start.mist
        self.tool_id: str | None = None
        self.security_z = 0.0
        # turning (stepnc.toolpaths.turning): plane, feed mode, constant surface speed and
        # the stock left by earlier turning workingsteps (a stepnc.lathe.Profile)
        self.plane = canon.Plane.XY
        self.feed_mode = canon.FeedMode.UNITS_PER_MINUTE
        self.css = False
        self.css_max = 0.0
        self.stock: object | None = None
        self.home = (start.position[0], start.position[2])
        self.out: list[canon.Command] = []
        self.source = Location(file)
        self._pockets: dict[str, int] = {}

    # ------------------------------------------------------------------ output
    def emit(self, cmd: canon.Command) -> None:
        object.__setattr__(cmd, "source", self.source)
        self.out.append(cmd)

    def preamble(self, asked: Start) -> None:
        """The program's first commands (millimetres, no origin offset, XYZ feed reference,
        spindle retracted), after a comment when the start state ``asked`` for had to be
        lowered to the machine's Z travel (:func:`start_within`) into this executor's."""
        if self.start is not asked:
            self.emit(
                canon.Comment(
                    f"retract height Z{asked.retracted_z:g} of the STEP-NC start state "
                    f"lowered to the machine's Z travel limit {self.start.retracted_z:g}"
                )
            )
        self.emit(canon.UseLengthUnits(canon.Units.MM))
        self.emit(canon.SetOriginOffsets(0.0, 0.0, 0.0))
        self.emit(canon.SetFeedReference(canon.FeedReference.XYZ))
        self.emit(canon.SpindleRetract())

    def take(self) -> list[canon.Command]:
        out, self.out = self.out, []
        return out

    def at(self, entity: Entity, ws: Entity | None) -> None:
        """Attribute the following commands to ``entity`` inside workingstep ``ws``."""
        loc = entity.where(ws.id if ws is not None else None)
        self.source = loc

    def error(self, code: str, message: str, entity: Entity) -> Diagnostic:
        return Diagnostic(code, message, self.source if self.source.entity else entity.where())

    # ------------------------------------------------------------------ tools
    def tool_entry(self, tool: Entity) -> ToolEntry:
        ident = str(tool.its_id)
        if self.tools is not None:
            entry = self.tools.get(ident)
            if entry is None:
                raise self.error(
                    "STEPNC-TOOL-MISSING", f"tool {ident!r} is not in the tool file", tool
                )
            return entry
        pocket = self._pockets.setdefault(ident, len(self._pockets) + 1)
        edges = tool.its_cutting_edge or ()
        length = float(edges[0].tool_offset_length) if edges else 0.0
        return ToolEntry(pocket, ident, length, float(tool_dimension(tool).diameter))

    def pocket_of(self, ident: str, tool: Entity) -> int:
        """The tool file's pocket of tool ``ident``, else pockets numbered in order of use."""
        if self.tools is not None:
            entry = self.tools.get(ident)
            if entry is None:
                raise self.error(
                    "STEPNC-TOOL-MISSING", f"tool {ident!r} is not in the tool file", tool
                )
            return entry.pocket
        return self._pockets.setdefault(ident, len(self._pockets) + 1)

    def handle_tool(self, tool: Entity) -> None:
        if str(tool.its_id) != self.tool_id:
            self.change_tool(tool)

    def stop_for_tool_change(self) -> None:
        """Stop the spindle and turn the coolant off, each only if on: what precedes a
        tool change (milling, turning and AP238 alike)."""
        if self.spindle is not canon.Direction.STOPPED:
            self.emit(canon.StopSpindleTurning())
            self.spindle = canon.Direction.STOPPED
        if self.flood is not False:
            self.emit(canon.FloodOff())
            self.flood = False
        if self.mist is not False:
            self.emit(canon.MistOff())
            self.mist = False

    def change_tool(self, tool: Entity) -> None:
        entry = self.tool_entry(tool)
        self.stop_for_tool_change()
        if self.z != self.retracted_z:
            self.emit(canon.SpindleRetract())
        self.emit(canon.UseToolLengthOffset(0.0))
        self.emit(canon.ChangeTool(entry.pocket, entry.id))
        self.emit(canon.UseToolLengthOffset(entry.length))
        self.tool_id = entry.id
        if self.mode == "default":
            # the change leaves the spindle fully retracted with the new tool
            self.z = self.retracted_z - entry.length

    # ------------------------------------------------------------------ technology
    def machine_functions(self, mf: Entity) -> None:
        if mf.coolant is True and self.flood is not True:
            self.emit(canon.FloodOn())
            self.flood = True
        elif mf.coolant is False and self.flood is not False:
            self.emit(canon.FloodOff())
            self.flood = False
        if mf.mist is True and self.mist is not True:
            self.emit(canon.MistOn())
            self.mist = True
        elif mf.mist is False and self.mist is True:
            self.emit(canon.MistOff())
            self.mist = False

    def handle_speed(self, tech: Entity, tool: Entity, factor: float | None) -> None:
        """Spindle: rev/s (positive counterclockwise, ISO 14649-10 §4.2.1) to rpm."""
        if tech.spindle is not None:
            new = float(tech.spindle) * -60.0
        elif tech.cutspeed is not None:
            diameter = self.tool_entry(tool).diameter
            if diameter == 0:
                raise self.error("STEPNC-TOOL-DIAMETER", "cut speed needs a tool diameter", tool)
            # NIST computes rev/s here (no factor 60); the default mode converts to rpm
            scale = 1000.0 if self.mode == "nist" else 60000.0
            new = -scale * float(tech.cutspeed) / (diameter * 3.141592653589793)
        else:
            raise self.error(
                "STEPNC-NO-SPEED", "technology gives neither spindle nor cutspeed", tech
            )
        if factor is not None:
            new *= factor
        if new > 0:
            self._spin(new, canon.Direction.CLOCKWISE, canon.StartSpindleClockwise)
        elif new < 0:
            self._spin(-new, canon.Direction.COUNTERCLOCKWISE, canon.StartSpindleCounterclockwise)
        else:
            if self.spindle is not canon.Direction.STOPPED:
                self.emit(canon.StopSpindleTurning())
                self.spindle = canon.Direction.STOPPED
            if self.speed != 0.0:
                self.emit(canon.SetSpindleSpeed(0.0))
                self.speed = 0.0

    def spin(self, speed: float, direction: canon.Direction) -> None:
        """Spindle at ``speed`` in ``direction`` (commands only for what changes)."""
        if direction is canon.Direction.CLOCKWISE:
            self._spin(speed, direction, canon.StartSpindleClockwise)
        else:
            self._spin(speed, direction, canon.StartSpindleCounterclockwise)

    def _spin(self, speed: float, direction: canon.Direction, start: type) -> None:
        if speed != self.speed:
            self.emit(canon.SetSpindleSpeed(speed))
            self.speed = speed
        if self.spindle is not direction:
            self.emit(start())
            self.spindle = direction

    def feed_value(self, tech: Entity, tool: Entity) -> float:
        if tech.feedrate is not None:
            if float(tech.feedrate) < 0:
                raise self.error(
                    "STEPNC-NO-FEED", f"feedrate {tech.feedrate:g} m/s is negative", tech
                )
            return float(tech.feedrate) * 60000.0  # m/s -> mm/min
        if tech.feedrate_per_tooth is not None:
            teeth = tool.its_tool_body.number_of_teeth
            if not teeth:
                raise self.error("STEPNC-NO-TEETH", "feed per tooth needs number_of_teeth", tool)
            if float(tech.feedrate_per_tooth) < 0:
                raise self.error(
                    "STEPNC-NO-FEED",
                    f"feed per tooth {tech.feedrate_per_tooth:g} mm is negative",
                    tech,
                )
            return float(tech.feedrate_per_tooth) * int(teeth) * self.speed
        raise self.error(
            "STEPNC-NO-FEED", "technology gives neither feedrate nor feed per tooth", tech
        )

    def handle_feed(self, tech: Entity, tool: Entity, factor: float | None) -> None:
        value = self.feed_value(tech, tool)
        if factor is not None:
            value *= factor
        self.set_feed(value)

    def set_feed(self, value: float) -> None:
        if value != self.feedrate:
            self.emit(canon.SetFeedRate(value))
            self.feedrate = value

    def technology(self, tech: Entity, tool: Entity) -> None:
        self.handle_speed(tech, tool, None)
        self.handle_feed(tech, tool, None)
        self.technology_some(tech)

    def technology_some(self, tech: Entity) -> None:
        if tech.synchronize_spindle_with_feed is True:
            raise self.error(
                "STEPNC-UNSUPPORTED",
                "spindle-synchronised feed is not supported for milling technology",
                tech,
            )
        if tech.its_adaptive_control is not None:
            raise self.error("STEPNC-UNSUPPORTED", "adaptive control is not supported", tech)

    # ------------------------------------------------------------------ motion
    def start_cut(self, x: float, y: float, z: float) -> None:
        """Up to the security plane if the XY position changes, across, then down."""
        if abs(self.x - x) > TINY or abs(self.y - y) > TINY:
            if self.z < self.security_z:
                self.emit(canon.StraightTraverse(self.x, self.y, self.security_z))
                self.z = self.security_z
            self.emit(canon.StraightTraverse(x, y, self.z))
            self.x, self.y = x, y
        if abs(self.z - z) > TINY:
            self.emit(canon.StraightTraverse(x, y, z))
            self.z = z

    def feed_to(self, x: float, y: float, z: float) -> None:
        self.emit(canon.StraightFeed(x, y, z))
        self.x, self.y, self.z = x, y, z

    def run(self, code: Code) -> None:
        """Emit placed pseudocode; the position follows the last motion."""
        for line in code:
            if line[0] == FEED:
                self.emit(canon.StraightFeed(line[1], line[2], line[3]))
            elif line[0] == ARC:
                self.emit(canon.ArcFeed(line[1], line[2], line[3], line[4], line[5], line[6]))
            else:
                self.emit(canon.StraightTraverse(line[1], line[2], line[3]))
        if code:
            self.x, self.y, self.z = code.end()

    def start_and_run(self, code: Code) -> None:
        """NIST: the first line only marks where to start the cut."""
        if code[0][3] > self.security_z + TINY:
            raise Diagnostic(
                "STEPNC-RETRACT-ABOVE-SECURITY",
                f"the retract plane (Z={code[0][3]:.4f}) is above the security "
                f"plane (Z={self.security_z:.4f})",
                self.source,
            )
        self.start_cut(code[0][1], code[0][2], code[0][3])
        self.run(Code(code[1:]))
