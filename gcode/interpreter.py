"""The RS274/NGC interpreter: program text -> canonical machining commands (a generator).

Each line is read (:mod:`gcode.lexer`, cached per file offset by :mod:`gcode.program`),
its words evaluated (:mod:`gcode.blocks`), and executed in the order of the NIST
RS274/NGC v3 report (Table 8) as LinuxCNC extends it: comment and message, G93/G94/G95,
F, S, T, M62-M68, M6/M61, M3/M4/M5/M19, M7/M8/M9, M48-M53, G4, G17-G19, G20/G21, G40-G42,
G43/G49, G54-G59.3, G61/G61.1/G64, G90/G91, G90.1/G91.1, G98/G99, G10/G28/G30/G92,
motion (G0-G3, G5.x, G33, G38.x, G73-G89), then M0/M1/M2/M30/M60. O-word lines go to
:mod:`gcode.oword`. Output matches LinuxCNC's ``rs274`` (``../shared/corpus/README.md``).

Public API: :func:`interpret`, :func:`interpret_text`,
:class:`InterpreterOptions`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass

from gcode import linuxcnc as lc
from gcode import motion, offsets
from gcode.blocks import check_letter_uses, evaluate_block, is_constant
from gcode.codes import Words
from gcode.lexer import Block
from gcode.messages import comment_commands
from gcode.oword import Flow
from gcode.params import Parameters
from gcode.predefined import named_parameter, numbered_parameter
from gcode.program import ProgramFile
from gcode.state import G80, INCH_MM, Setup
from kernel import canon
from kernel.canon import Direction, Plane, Units
from kernel.diagnostics import Diagnostic, Location
from kernel.tooltable import Tool, ToolTable


@dataclass(frozen=True)
class InterpreterOptions:
    tool_table: ToolTable | None = None  # kernel.tooltable; None: any tool, zero offsets
    parameters: dict[int, float] | None = None  # from a .var file (gcode.params.read_var_text)
    search_path: tuple[str, ...] = ()  # subroutine file search path
    linuxcnc_compat: bool = True  # emit LinuxCNC-only commands as rs274 does
    fast_lane: bool = True  # large files: plain CAM lines through gcode.fastlane (compiled)
    cycle_marks: bool = False  # bracket canned-cycle expansions (gcode.cycle_marks)
    keep_cutter_comp: bool = False  # G41/G42 as canonical commands (gcode.comp_keep)
    # work offsets as SET_G5X_OFFSET / SET_G92_OFFSET / SET_XY_ROTATION (which offset is
    # selected, as rs274 says it) even without linuxcnc_compat, instead of NIST's one
    # SET_ORIGIN_OFFSETS total (a writer can then say G54 rather than set the table)
    g5x_offsets: bool = False


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the program in ``path`` (streaming)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.run(ProgramFile(os.fspath(path)))


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[object]:
    """Like :func:`interpret`, but runs of plain CAM lines of a large file come as one
    :class:`gcode.fastlane.Run` each (for writers that format them in compiled code)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.chunks(ProgramFile(os.fspath(path)))


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a program given as text (``name`` is used in locations)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.run(ProgramFile(name, data=text.encode("utf-8")))


_PLANES = {170: Plane.XY, 180: Plane.XZ, 190: Plane.YZ}
#: files from this size on use the compiled fast lane (gcode.lane)
LANE_MIN_BYTES = 1 << 20


def _lane_for(pf: ProgramFile) -> object | None:
    """The compiled fast lane for a large program file (imported only then)."""
    try:
        if os.path.getsize(pf.path) < LANE_MIN_BYTES:
            return None
        from gcode.lane import Lane
    except (OSError, ImportError):
        return None
    return Lane.for_file(pf)


class AnyTool(ToolTable):
    """No tool table given: every tool number exists, with zero offsets and diameter."""

    def get(self, number: int) -> Tool | None:
        found = super().get(number)
        return found if found is not None else Tool(number, number)

    def __contains__(self, number: int) -> bool:
        return True


class Interpreter:
    """One run of one program. Not reusable; create one per program."""

    def __init__(self, options: InterpreterOptions) -> None:
        self.options = options
        self.compat = options.linuxcnc_compat
        self.g5x_style = options.linuxcnc_compat or options.g5x_offsets
        if options.tool_table is None:
            self.tools: ToolTable = AnyTool()
        else:  # a copy: G10 L1 edits stay in this run
            self.tools = ToolTable(dict(options.tool_table.tools))
        self.s = Setup()
        self.params = Parameters(options.parameters, predefined=self._named)
        self.params.dynamic = self._numbered
        self.out: list[canon.Command] = []
        self.loc = Location()
        self.flow = Flow(self)
        self.saved_states: list[dict[str, object]] = []  # M70/M73 frames
        self.m70: dict[int, dict[str, object]] = {}
        self.comp: object | None = None  # cutter comp filter when active
        offsets.init_offsets(self)

    # ------------------------------------------------------------------ output
    def emit(self, cmd: canon.Command) -> None:
        comp = self.comp
        if comp is not None and comp.holding:  # type: ignore[attr-defined]
            self.out.extend(comp.passthrough(cmd))  # type: ignore[attr-defined]
        else:
            self.out.append(cmd)

    def comp_off(self, action: str) -> None:
        """Refuse ``action`` while cutter compensation is on (LinuxCNC's list)."""
        if self.comp is not None:
            self.comp.require_off(action, self.loc)  # type: ignore[attr-defined]

    def _named(self, name: str) -> float | None:
        return named_parameter(self, name)

    def _numbered(self, index: int) -> float | None:
        return numbered_parameter(self, index)

    # ------------------------------------------------------------------ run loop
    def run(self, main: ProgramFile) -> Iterator[canon.Command]:
        """The canonical commands of ``main`` (runs of the fast lane as commands)."""
        for item in self.chunks(main):
            if isinstance(item, canon.Command):
                yield item
            else:
                yield from item.commands(main.path)

    def chunks(self, main: ProgramFile) -> Iterator[object]:
        """Commands, and for large files runs of plain lines as :class:`gcode.fastlane.Run`
        (the CLI formats those in compiled code)."""
        lane = _lane_for(main) if self.options.fast_lane else None
        self.flow.start(main)
        self.loc = Location(main.path, 0, 0)
        self._preamble()
        out = self.out
        try:
            while True:
                if lane is not None:
                    found = lane.take(self)
                    if found is not None:
                        if out:
                            yield from out
                            out.clear()
                        yield found
                block = self.flow.next_block()
                if block is None:
                    self.flow.end_of_file()
                    break
                if out:
                    yield from out
                    out.clear()
                if self.execute_line(block):
                    break
        except Diagnostic:
            yield from out
            out.clear()
            raise
        finally:
            if lane is not None:
                lane.close()
            self.flow.close()
        yield from out
        out.clear()

    def _preamble(self) -> None:
        s = self.s
        src = self.loc
        self.emit(canon.UseLengthUnits(s.units, source=src))
        if self.g5x_style:
            offsets.emit_g5x(self)
            self.emit(lc.SetG92Offset(*s.g92, source=src))
            self.emit(lc.SetXYRotation(s.rotation, source=src))
        else:
            offsets.emit_origin(self)
        self.emit(canon.SetFeedReference(canon.FeedReference.XYZ, source=src))
        if self.compat:
            self.emit(lc.OnReset(source=src))

    def finish_percent(self) -> None:
        if self.compat:
            self.emit(lc.Finish(source=self.loc))
            self.emit(lc.OnReset(source=self.loc))
            self.emit(lc.OnReset(source=self.loc))

    # ------------------------------------------------------------------ one line
    def execute_line(self, block: Block) -> bool:
        """Execute one non-O-word line; True when the program ended."""
        file = self.flow.file.path
        cached = block.cached_words
        if cached is not None and cached.plain:  # type: ignore[attr-defined]
            # the CAM hot path: axis words in the current motion mode
            self.loc = Location(file, block.line, block.col0)
            motion.execute_motion(self, cached, self.s.motion_mode)  # type: ignore[arg-type]
            return False
        if block.comments:
            self.loc = Location(file, block.line, block.comments[-1][1])
            for cmd in comment_commands(block.comments[-1][0], self.params, self.loc):
                self.emit(cmd)
        if not block.words and not block.assignments:
            return False
        self.loc = Location(file, block.line, block.words[0].column if block.words else 1)
        if cached is not None:
            words = cached  # type: ignore[assignment]
            assigns: list = []
        else:
            words, assigns = evaluate_block(block, self.params, file)
            if is_constant(block):
                block.cached_words = words
        for kind, target, value, loc in assigns:
            if kind == "named":
                self.params.set_named(target, value, loc)  # type: ignore[arg-type]
            else:
                self.params.set_numbered(target, value, loc)  # type: ignore[arg-type]
                offsets.parameter_written(self, int(round(target)))  # type: ignore[arg-type]
        if words.g or words.m or words.values:
            return self.execute(words)
        return False

    def execute(self, w: Words) -> bool:
        """NIST v3 Table 8 order of execution for one block; True at program end."""
        s = self.s
        g = w.g
        v = w.values
        loc = self.loc
        if w.plain:
            # the CAM hot path: axis words in the current motion mode
            motion.execute_motion(self, w, s.motion_mode)
            return False
        motion.check_block(self, w)
        if v:
            mode = g.get(1, s.motion_mode if w.has_axis() else None)
            check_letter_uses(w, mode, loc)
        if 14 in g:
            self._spindle_mode(g[14], v)
        if 5 in g:
            self._feed_mode(g[5])
        if "f" in v:
            f = v["f"]
            if f < 0:
                raise Diagnostic("NGC-NEGATIVE-F", "negative F word used", self._at(w, "f"))
            if s.feed_mode != 1:  # in G93 F belongs to the block's move only
                s.feed_rate = f
                self.emit(canon.SetFeedRate(f, source=loc))
        if "s" in v:
            sp = v["s"]
            if sp < 0:
                raise Diagnostic("NGC-NEGATIVE-S", "negative spindle speed used", self._at(w, "s"))
            s.speed = sp
            self.emit(canon.SetSpindleSpeed(sp, source=loc))
        if "t" in v:
            offsets.select_tool(self, w)
        if w.m:
            self._m_codes(w)
        if 0 in g and g[0] == 40:
            motion.dwell(self, w)
        if 2 in g:
            if g[2] not in _PLANES:
                raise Diagnostic("NGC-PLANE", "planes G17.1, G18.1, G19.1 not supported", loc)
            if _PLANES[g[2]] is not s.plane:
                self.comp_off("plane")
            s.plane = _PLANES[g[2]]
            self.emit(canon.SelectPlane(s.plane, source=loc))
        if 6 in g:
            self._units(Units.INCHES if g[6] == 200 else Units.MM)
        if 15 in g:
            s.diameter_mode = g[15] == 70
        if 7 in g:
            motion.cutter_comp_mode(self, w)
        if 8 in g:
            offsets.tool_length(self, w)
        if 12 in g:
            offsets.select_coordinate_system(self, g[12])
        if 13 in g:
            self._control_mode(g[13], w)
        if 3 in g and s.absolute != (g[3] == 900):
            s.absolute = g[3] == 900
            if self.compat:
                d = "absolute" if s.absolute else "incremental"
                self.emit(canon.Comment(f"interpreter: distance mode changed to {d}", source=loc))
        if 4 in g and s.ijk_absolute != (g[4] == 901):
            s.ijk_absolute = g[4] == 901
            if self.compat:
                d = "absolute" if s.ijk_absolute else "incremental"
                self.emit(
                    canon.Comment(f"interpreter: IJK distance mode changed to {d}", source=loc)
                )
        if 10 in g:
            s.retract_r = g[10] == 990
            if self.compat:
                d = "r_plane" if s.retract_r else "old_z"
                self.emit(canon.Comment(f"interpreter: retract mode set to {d}", source=loc))
        if 0 in g and g[0] not in (40, 530):
            offsets.modal_0(self, w)
        if 1 in g:
            s_mode = g[1]
            if s_mode == G80:
                s.motion_mode = G80
                s.cycle_series = False
                if self.compat:
                    self.emit(canon.Comment("interpreter: motion mode set to none", source=loc))
            else:
                motion.execute_motion(self, w, s_mode)
        elif (
            w.has_axis() and not (0 in g and g[0] in (100, 280, 300, 520, 920)) and g.get(8) != 431
        ):
            if s.motion_mode is None or s.motion_mode == G80:
                raise Diagnostic(
                    "NGC-AXIS-NO-MOTION",
                    "cannot use axis values without a G code that uses them",
                    loc,
                )
            motion.execute_motion(self, w, s.motion_mode)
        if 4 in w.m:
            return self._stop(w.m[4])
        return False

    def _at(self, w: Words, letter: str) -> Location:
        return Location(self.loc.file, self.loc.line, w.columns.get(letter, self.loc.column))

    # ------------------------------------------------------------------ G helpers
    def _spindle_mode(self, code: int, v: dict[str, float]) -> None:
        s = self.s
        if code == 960:
            s.css = True
            s.css_max = v.get("d", s.css_max)
        else:
            s.css = False
        self.emit(canon.SetSpindleMode(s.css_max if s.css else 0.0, s.css, source=self.loc))

    def _feed_mode(self, code: int) -> None:
        s = self.s
        mode = {930: 1, 940: 0, 950: 2}[code]
        s.feed_mode = mode
        loc = self.loc
        names = {0: "units per minute", 1: "inverse time", 2: "units per revolution"}
        if self.compat:
            self.emit(canon.Comment(f"interpreter: feed mode set to {names[mode]}", source=loc))
        self.emit(canon.SetFeedMode(canon.FeedMode(mode), source=loc))
        if mode != 1:
            s.feed_rate = 0.0
            self.emit(canon.SetFeedRate(0.0, source=loc))

    def _units(self, units: Units) -> None:
        s = self.s
        if s.units is not units:
            s.scale_lengths(1.0 / INCH_MM if units is Units.INCHES else INCH_MM)
            s.units = units
        if self.comp is not None:
            self.comp.set_units(units is Units.INCHES)  # type: ignore[attr-defined]
        self.emit(canon.UseLengthUnits(units, source=self.loc))

    def _control_mode(self, code: int, w: Words, check: bool = True) -> None:
        s = self.s
        loc = self.loc
        if check:
            self.comp_off("control mode")
        s.control_mode = code
        if code == 610:
            self.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_PATH, source=loc))
        elif code == 611:
            self.emit(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP, source=loc))
        else:
            p = w.values.get("p", -1.0)
            q = w.values.get("q", -1.0)
            if p < 0:
                p = 0.0
            if q < 0:
                q = p
            s.blend_p, s.blend_q = p, q
            self.emit(canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, p, source=loc))
            self.emit(canon.SetNaivecamTolerance(q, source=loc))

    # ------------------------------------------------------------------ M codes
    def _m_codes(self, w: Words) -> None:
        from gcode.mcodes import m_codes

        m_codes(self, w)

    def _stop(self, code: int) -> bool:
        from gcode.mcodes import program_stop

        return program_stop(self, code)

    # ------------------------------------------------------------------ misc state
    def spindle_state(self) -> Direction:
        return self.s.spindle
