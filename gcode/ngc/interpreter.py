"""The RS274/NGC interpreter: program text -> canonical machining commands (a generator).

Each line is read (:mod:`gcode.core.lexer`, cached per file offset by :mod:`gcode.core.program`),
its words evaluated (:mod:`gcode.core.blocks`), and executed in the order of the NIST
RS274/NGC v3 report (Table 8) as LinuxCNC extends it: comment and message, G93/G94/G95,
F, S, T, M62-M68, M6/M61, M3/M4/M5/M19, M7/M8/M9, M48-M53, G4, G17-G19, G20/G21, G40-G42,
G43/G49, G54-G59.3, G61/G61.1/G64, G90/G91, G90.1/G91.1, G98/G99, G10/G28/G30/G92,
motion (G0-G3, G5.x, G33, G38.x, G73-G89), then M0/M1/M2/M30/M60. O-word lines go to
:mod:`gcode.ngc.oword`. Output matches LinuxCNC's ``rs274`` (``../shared/corpus/README.md``).

Public API: :func:`interpret`, :func:`interpret_text`, :class:`InterpreterOptions`. The
state the modules share is :class:`gcode.ngc.context.NgcContext`; :class:`Interpreter` is
one, with the run loop, and the only module here that imports motion, offsets, M codes, ...
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING

from gcode.core import linuxcnc as lc
from gcode.core.blocks import Assignment, check_letter_uses, evaluate_block, is_constant
from gcode.core.codes import Words
from gcode.core.lexer import Block
from gcode.core.loopguard import LoopGuard
from gcode.core.messages import DEBUG_FLAG, comment_commands
from gcode.core.program import ProgramFile
from gcode.core.state import G80, INVERSE_TIME, ControlCode, FeedCode, SavedModes
from gcode.ngc import mcodes, modes, motion, offsets
from gcode.ngc.context import AnyTool, InterpreterOptions, NgcContext
from gcode.ngc.oword import Flow
from gcode.ngc.predefined import named_parameter, numbered_parameter
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Plane, Units

if TYPE_CHECKING:  # the fast lane needs numpy: loaded only for a large file (_lane_for)
    from gcode.ngc.lane.fastlane import Run
    from gcode.ngc.lane.lane import Lane

__all__ = [
    "LANE_MIN_BYTES",
    "AnyTool",
    "Interpreter",
    "InterpreterOptions",
    "interpret",
    "interpret_chunks",
    "interpret_text",
]


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the program in ``path`` (streaming)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.run(ProgramFile(os.fspath(path)))


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[canon.Command | Run]:
    """Like :func:`interpret`, but runs of plain CAM lines of a large file come as one
    :class:`gcode.ngc.lane.fastlane.Run` each (for writers that format them in compiled code);
    with ``arcs`` the runs may hold ``ARC_FEED`` events too (``fastlane.ARC``)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.chunks(ProgramFile(os.fspath(path)), arcs)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a program given as text (``name`` is used in locations)."""
    interp = Interpreter(options or InterpreterOptions())
    return interp.run(ProgramFile(name, data=text.encode("utf-8")))


_PLANES = {170: Plane.XY, 180: Plane.XZ, 190: Plane.YZ}
#: the words of a block :meth:`Interpreter._motion_block` runs: axis and F words, and in
#: G2/G3 the centre and R words
_LINE_WORDS = frozenset("xyzabcf")
_MOTION_WORDS = frozenset("xyzabcfijkr")
#: files from this size on may use the compiled fast lane (gcode.ngc.lane.lane), when
#: :func:`_lane_pays`; 0 forces the lane on for every file (the equivalence tests do)
LANE_MIN_BYTES = 1 << 17
#: how much of a program's head :func:`_lane_pays` samples
LANE_SAMPLE_BYTES = 1 << 16
#: the measured break-even (docs/performance.md, CPU time of ``cnc canon``, in units of
#: one plain line's general-path time over the lane's): loading numpy and the kernels costs
#: as much as the lane saves on about 12,000 plain lines; an arc line saves about 2.5 times
#: what a plain line does (1.5 more; R-format arcs save more than centre-format ones)
LANE_LOAD_COST = 12_000.0
LANE_ARC_SAVING = 1.5
#: lines the lane can take (an optional N word, one G0-G3, axis, centre, R and F words with
#: plain numbers), case and blanks as the lane reads them
_LANE_LINE = re.compile(
    rb"^[ \t]*(?:[nN][ \t]*\d+[ \t]*)?(?:[gG][ \t]*0*[0-3](?![\d.])[ \t]*)?"
    rb"(?:[xyzabcfijkrXYZABCFIJKR][ \t]*[-+]?[ \t]*(?:\d+\.?\d*|\.\d+)[ \t]*)+\r*$",
    re.M,
)
_ARC_WORD = re.compile(rb"[ijkrIJKR]")
#: G40, G41, G42 (and G41.1, G42.1): where cutter compensation starts and ends
_COMP_WORD = re.compile(rb"[gG][ \t]*0*4[ \t]*([012])(?:\.1)?(?![\d.])")


def _lane_pays(path: str) -> bool:
    """Whether the lane wins back its loading on ``path``: the lines it would take, estimated
    from the file's size and its head (plain lines and arcs, which the general path takes
    more slowly), outweigh :data:`LANE_LOAD_COST`. A macro program of expressions, however
    large, has none. Only the choice of path depends on it, never the output."""
    if LANE_MIN_BYTES == 0:
        return True
    try:
        size = os.path.getsize(path)
        if size < LANE_MIN_BYTES:
            return False
        with open(path, "rb") as fh:
            head = fh.read(LANE_SAMPLE_BYTES)
    except OSError:
        return False
    head = head[: head.rfind(b"\n") + 1] or head
    lines: list[bytes] = []
    start = 0
    compensated = False  # the lane takes no line under cutter compensation (G41/G42)
    for word in _COMP_WORD.finditer(head):
        if not compensated:
            lines += _LANE_LINE.findall(head, start, word.start())
        compensated = word.group(1) != b"0"
        start = word.end()
    if not compensated:
        lines += _LANE_LINE.findall(head, start)
    arcs = sum(1 for line in lines if _ARC_WORD.search(line))
    return (len(lines) + LANE_ARC_SAVING * arcs) * size / len(head) >= LANE_LOAD_COST


def _lane_for(pf: ProgramFile, arcs: bool) -> Lane | None:
    """The compiled fast lane for a large program file of CAM lines (imported here: it needs
    numpy, which a small program then never loads); ``arcs``: its runs may hold arcs."""
    if not _lane_pays(pf.path):
        return None
    from gcode.ngc.lane.lane import Lane

    return Lane.for_file(pf, arcs)


def _attach_line(diag: Diagnostic, pf: ProgramFile) -> None:
    """Give ``diag`` the text of its line when it is the line ``pf`` read last (the CLI shows
    it under the message, in the user's own case and spacing)."""
    loc = diag.location
    if diag.record.source_line is None and loc.file == pf.path and loc.line:
        text = pf.line_text(loc.line)
        if text is not None:
            diag.with_source_line(text)


class Interpreter(NgcContext):
    """One run of one program. Not reusable; create one per program."""

    def __init__(self, options: InterpreterOptions) -> None:
        super().__init__(
            options,
            Flow(self, options.search_path, LoopGuard(options.max_blocks, options.max_idle_blocks)),
        )
        self.params.predefined = self._named
        self.params.dynamic = self._numbered
        offsets.init_offsets(self)
        self.params.values[DEBUG_FLAG] = 1.0  # volatile: rs274 sets it after the .var file

    def _named(self, name: str) -> float | None:
        return named_parameter(self, name)

    def _numbered(self, index: int) -> float | None:
        return numbered_parameter(self, index)

    # ------------------------------------------------------------------ run loop
    def run(self, main: ProgramFile) -> Iterator[canon.Command]:
        """The canonical commands of ``main`` (runs of the fast lane as commands)."""
        for item in self.chunks(main, arcs=True):
            if isinstance(item, canon.Command):
                yield item
            else:
                yield from item.commands(main.path)

    def chunks(self, main: ProgramFile, arcs: bool = False) -> Iterator[canon.Command | Run]:
        """Commands, and for large files runs of plain lines as :class:`gcode.ngc.lane.fastlane.Run`
        (the CLI formats those in compiled code); ``arcs``: runs may hold arcs."""
        lane = _lane_for(main, arcs) if self.options.fast_lane else None
        self.flow.start(main)
        self.loc = Location(main.path, 0, 0)
        self._preamble()
        out = self.out
        guard = self.flow.guard
        try:
            while True:
                if lane is not None:
                    found = lane.take(self)
                    if found is not None:
                        guard.output += 1
                        if out:
                            yield from out
                            out.clear()
                        yield found
                block = self.flow.next_block()
                if block is None:
                    self.flow.end_of_file()
                    break
                if out:
                    guard.output += len(out)
                    yield from out
                    out.clear()
                if self.execute_line(block):
                    break
        except Diagnostic as diag:
            _attach_line(diag, self.flow.file)
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
        if cached is not None and cached.plain:
            # the CAM hot path: axis words in the current motion mode
            self.loc = Location(file, block.line, block.col0)
            motion.execute_motion(self, cached, self.s.motion_mode)
            return False
        if block.comments:
            self.loc = Location(file, block.line, block.comments[-1][1])
            sink = self.options.print_sink
            for cmd in comment_commands(block.comments[-1][0], self.params, self.loc, sink):
                self.emit(cmd)
        if not block.words and not block.assignments:
            return False
        self.loc = Location(file, block.line, block.words[0].column if block.words else 1)
        if cached is not None:
            words = cached
            assigns: list[Assignment] = []
        else:
            words, assigns = evaluate_block(block, self.params, file)
            if self.flow.file.caching and is_constant(block):  # a block read again: loops
                block.cached_words = words
        for target, value, loc in assigns:
            if isinstance(target, str):
                self.params.set_named(target, value, loc)
            else:
                self.params.set_numbered(target, value, loc)
                offsets.parameter_written(self, int(round(target)))
        if words.g or words.m or words.values:
            return self.execute(words)
        return False

    def execute(self, w: Words) -> bool:
        """NIST v3 Table 8 order of execution for one block; True at program end."""
        ended = self._execute(w)
        if self.s.resync_pending:
            offsets.resync(self)
        return ended

    def _execute(self, w: Words) -> bool:
        """The block's steps, in order (:meth:`execute`)."""
        s = self.s
        g = w.g
        v = w.values
        loc = self.loc
        if w.plain:
            # the CAM hot path: axis words in the current motion mode
            motion.execute_motion(self, w, s.motion_mode)
            return False
        if (
            not w.m
            and v.keys() <= _MOTION_WORDS
            and (not g or (len(g) == 1 and g.get(1, G80) != G80))
        ):
            # the other CAM block: G0-G3 with axis, centre, R and F words; none of the
            # steps below but F and the motion applies, and no letter check can fail
            mode = g.get(1, s.motion_mode if w.has_axis() else None)
            if v.keys() <= _LINE_WORDS or mode == 20 or mode == 30:
                return self._motion_block(w)
        motion.check_block(self, w)
        if w.m:
            mcodes.check_user_m(self, w)
        if v:
            mode = g.get(1, s.motion_mode if w.has_axis() else None)
            check_letter_uses(w, mode, loc)
        if 14 in g:
            modes.spindle_mode(self, g[14], v)
        if 5 in g:
            modes.feed_mode(self, FeedCode(g[5]))
        if "f" in v:
            f = v["f"]
            if f < 0:
                raise Diagnostic("NGC-NEGATIVE-F", "negative F word used", self._at(w, "f"))
            if s.feed_mode != INVERSE_TIME:  # in G93 F belongs to the block's move only
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
            mcodes.m_codes(self, w)
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
            modes.units(self, Units.INCHES if g[6] == 200 else Units.MM)
        if 15 in g:
            s.diameter_mode = g[15] == 70
        if 7 in g:
            motion.cutter_comp_mode(self, w)
        if 8 in g:
            offsets.tool_length(self, w)
        if 12 in g:
            offsets.select_coordinate_system(self, g[12])
        if 13 in g:
            modes.control_mode(self, ControlCode(g[13]), w)
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
        if "@" in v or "^" in v:
            w = motion.polar_words(self, w)
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
            w.has_axis()
            and not (0 in g and g[0] in (100, 280, 300, 520, 920))
            and g.get(8) != 431
            and w.m.get(4) != 98  # rs274 2.9 ignores axis words beside M98
        ):
            if s.motion_mode is None or s.motion_mode == G80:
                raise Diagnostic(
                    "NGC-AXIS-NO-MOTION",
                    "cannot use axis values without a G code that uses them",
                    loc,
                )
            motion.execute_motion(self, w, s.motion_mode)
        if 4 in w.m:
            code = w.m[4]
            if code in (98, 99) and not self.options.fanuc_subs:
                raise Diagnostic(
                    "NGC-FANUC-SUBS-DISABLED",
                    f"M{code} used, but Fanuc-style subroutines are disabled "
                    "(DISABLE_FANUC_STYLE_SUB in the INI file)",
                    loc,
                )
            if code == 98:
                if "p" not in v:
                    raise Diagnostic("NGC-M98-NO-P", "M98 with no P word", loc)
                self.flow.m98(v["p"], v.get("l", 1.0), loc)
                return False
            if code == 99 and self.flow.m99(loc):
                return False
            return mcodes.program_stop(self, 2 if code == 99 else code)
        return False

    def _motion_block(self, w: Words) -> bool:
        """:meth:`_execute` of a block of motion words only (its F word, then its motion)."""
        s = self.s
        v = w.values
        if "f" in v:
            f = v["f"]
            if f < 0:
                raise Diagnostic("NGC-NEGATIVE-F", "negative F word used", self._at(w, "f"))
            if s.feed_mode != INVERSE_TIME:
                s.feed_rate = f
                self.emit(canon.SetFeedRate(f, source=self.loc))
        if w.g:
            motion.execute_motion(self, w, w.g[1])
        elif w.has_axis():
            if s.motion_mode is None or s.motion_mode == G80:
                raise Diagnostic(
                    "NGC-AXIS-NO-MOTION",
                    "cannot use axis values without a G code that uses them",
                    self.loc,
                )
            motion.execute_motion(self, w, s.motion_mode)
        return False

    def _at(self, w: Words, letter: str) -> Location:
        return Location(self.loc.file, self.loc.line, w.columns.get(letter, self.loc.column))

    # ------------------------------------------------------------------ O-word flow host
    def restore_modes(self, saved: SavedModes) -> None:
        """The end of an M73 subroutine restores the modes saved at its start."""
        mcodes.restore_state(self, saved)
