"""The state the RS274/NGC interpreter's modules share, as one typed object.

:class:`NgcContext` holds what :mod:`gcode.ngc.motion`, :mod:`gcode.ngc.offsets`,
:mod:`gcode.ngc.cycles`, :mod:`gcode.ngc.mcodes`, :mod:`gcode.ngc.threading`,
:mod:`gcode.ngc.modes`, :mod:`gcode.ngc.predefined` and :mod:`gcode.ngc.lane.lane` read and
change: the options, the modal state
(:class:`gcode.core.state.Setup`), parameters, tools, the output buffer, the current location,
the O-word flow and the cutter compensator. Those modules take an ``NgcContext`` and import
only this and other leaf modules; :class:`gcode.ngc.interpreter.Interpreter` is an
``NgcContext`` with the run loop, and imports them (never the other way round).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from gcode.core.loopguard import MAX_BLOCKS, MAX_IDLE_BLOCKS
from gcode.core.params import Parameters
from gcode.core.state import SavedModes, Setup
from gcode.ngc.comp.api import CutterComp
from gcode.ngc.oword import Flow
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.tooltable import Tool, ToolTable


@dataclass(frozen=True)
class InterpreterOptions:
    tool_table: ToolTable | None = None  # kernel.tooltable; None: any tool, zero offsets
    parameters: dict[int, float] | None = None  # from a .var file (gcode.core.params.read_var_text)
    search_path: tuple[str, ...] = ()  # subroutine file search path
    linuxcnc_compat: bool = True  # emit LinuxCNC-only commands as rs274 does
    fast_lane: bool = True  # large files: plain CAM lines through gcode.ngc.lane (compiled)
    cycle_marks: bool = False  # bracket canned-cycle expansions (gcode.core.cycle_marks)
    keep_cutter_comp: bool = False  # G41/G42 as canonical commands (gcode.ngc.comp.keep)
    # mark each tool length offset with its register (gcode.core.register_marks)
    register_marks: bool = False
    # work offsets as SET_G5X_OFFSET / SET_G92_OFFSET / SET_XY_ROTATION (which offset is
    # selected, as rs274 says it) even without linuxcnc_compat, instead of NIST's one
    # SET_ORIGIN_OFFSETS total (a writer can then say G54 rather than set the table)
    g5x_offsets: bool = False
    # the loop guard of every reader (gcode.core.loopguard): blocks in a run before
    # LOOP-LIMIT, blocks with no canonical command emitted before LOOP-NO-PROGRESS
    max_blocks: int = MAX_BLOCKS
    max_idle_blocks: int = MAX_IDLE_BLOCKS
    # a centre-format arc whose end radius differs from its start radius by at most this
    # fraction of the start radius is accepted even past LinuxCNC's tolerance (a control
    # that does not refuse such arcs: Mach3); None: LinuxCNC's rule alone
    arc_radius_relative: float | None = None
    # the smallest centre-format arc radius, mm (inch programs: the same length); None:
    # LinuxCNC's (TOLERANCE_MM, TOLERANCE_INCH); Grbl has none (0.0): gcode.c checks only
    # that the end radius agrees with the start's
    arc_min_radius: float | None = None
    # mark where stored offsets are written, G10 L2/L20 and G28.1/G30.1
    # (gcode.core.register_marks.OffsetsStored): a control that first empties its motion
    # buffer there (Grbl 1.1: settings.c settings_write_coord_data)
    store_marks: bool = False
    # an INI file's numbers, read by #<_ini[section]name> (keys upper-case; gcode.ngc.ini)
    ini_values: Mapping[tuple[str, str], float] | None = None
    fanuc_subs: bool = True  # M98/M99 programs allowed (INI DISABLE_FANUC_STYLE_SUB = 0)
    # receives each (PRINT, ...) text, parameters replaced, as rs274 writes it to its output
    print_sink: Callable[[str], None] | None = None


class AnyTool(ToolTable):
    """No tool table given: every tool number exists, with zero offsets and diameter."""

    def get(self, number: int) -> Tool | None:
        found = super().get(number)
        return found if found is not None else Tool(number, number)

    def __contains__(self, number: int) -> bool:
        return True


class NgcContext:
    """One run's shared state, and the two services every module uses: :meth:`emit`
    (through the cutter compensator when it holds a move) and :meth:`comp_off`."""

    def __init__(self, options: InterpreterOptions, flow: Flow) -> None:
        self.options = options
        self.compat = options.linuxcnc_compat
        self.g5x_style = options.linuxcnc_compat or options.g5x_offsets
        if options.tool_table is None:
            self.tools: ToolTable = AnyTool()
        else:  # a copy: G10 L1 edits stay in this run
            self.tools = ToolTable(dict(options.tool_table.tools))
        self.s = Setup()
        self.params = Parameters(options.parameters)
        self.out: list[canon.Command] = []
        self.loc = Location()
        self.flow = flow
        self.m70: dict[int, SavedModes] = {}  # M70 state by call level
        self.comp: CutterComp | None = None  # cutter comp filter once G40-G42 was seen

    def lane_open(self) -> bool:
        """Whether the compiled fast lane may take plain lines now (a reader that rewrites
        blocks before they run says no while a rewrite applies: Mach3's scaling)."""
        return True

    def emit(self, cmd: canon.Command) -> None:
        """Output ``cmd`` (held behind a compensated move if LinuxCNC would hold it)."""
        comp = self.comp
        if comp is not None and comp.holding:
            self.out.extend(comp.passthrough(cmd))
        else:
            self.out.append(cmd)

    def comp_off(self, action: str) -> None:
        """Refuse ``action`` while cutter compensation is on (LinuxCNC's list)."""
        if self.comp is not None:
            self.comp.require_off(action, self.loc)
