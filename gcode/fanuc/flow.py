"""Program flow of a Fanuc run: blocks in order, macro statements, loops, jumps and calls.

``GOTOn`` and ``M99 Pn`` jump to sequence number n of the current (calling) program;
``WHILE [c] DOm`` ... ``ENDm`` loops (m = 1..3, the first ``ENDm`` after the ``DOm``);
``M98 P L`` calls O P L times with the same local variables, ``G65 P L`` with a new local
level holding the arguments, ``G66`` after every move of the calling level, Haas ``M97 P``
jumps to sequence P of the current program and returns at M99. ``M99`` in the main program
would restart it forever: the reader stops there. Fanuc 0i-MF manual, "Subprogram" and
"Custom macro" chapters.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

from gcode.core.corners import CornerFilter
from gcode.core.loopguard import RepeatGuard
from gcode.fanuc.executor import Action, Executor
from gcode.fanuc.lathe import Lathe
from gcode.fanuc.lexer import FBlock
from gcode.fanuc.macro import Variables, evaluate, truth
from gcode.fanuc.options import Flavour
from gcode.fanuc.program import Source, find_program_file, read_source
from gcode.fanuc.sysvars import SystemVariables
from gcode.fanuc.words import resolve
from gcode.ngc.interpreter import LANE_MIN_BYTES, Interpreter, InterpreterOptions
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.canon import Units

if TYPE_CHECKING:  # numpy and the kernels load with the first large program
    from gcode.fanuc.lane import FanucLane
    from gcode.ngc.lane.fastlane import Run

MAX_DEPTH = 32
#: files up to this many lines keep every parsed block (larger ones: loop/subprogram lines)
KEEP_ALL_LINES = 50_000
#: jumps back in a row that read an interface input signal before a loop counts as waiting
#: on the machine (the signal never changes in a stand-alone reading)
MAX_INPUT_WAIT = 1000
#: states kept to tell a main program repeating itself for ever (memory bound)
MAX_STATES = 10_000
#: passes through the same state at an unconditional GOTO back before FANUC-LOOP-LIMIT
MAX_REPEATS = 10_000


@dataclass
class Frame:
    """One running program: where it is, how often it runs again, its open loops."""

    src: Source
    pc: int
    start: int  # index of its O line (-1: none)
    entry: int
    kind: str  # main m98 g65 m97
    repeats: int = 0
    args: dict[int, float] | None = None
    loops: dict[int, int] = field(default_factory=dict)
    started: bool = False
    number: int = 0


class Reader:
    """One run of one program file."""

    def __init__(self, src: Source, options: InterpreterOptions, flavour: Flavour) -> None:
        # offsets as G5x selections: a converted program then says G54, not G10 L2 P1
        ngc = replace(options, linuxcnc_compat=False, fast_lane=False, g5x_offsets=True)
        self.options = options
        self.fl = flavour
        self.ip = Interpreter(ngc)
        self.ex = Executor(self.ip, flavour)
        if flavour.lathe:
            lathe = Lathe(self.ex)
            lathe.contour_blocks = self._contour_blocks
            self.ex.lathe = lathe
        self.sysvars = SystemVariables(self)
        self.vars = Variables(self.sysvars, options.parameters)
        self._input_mark = 0  # input signal reads at the last jump back
        self.repeat_guard = RepeatGuard(MAX_STATES, MAX_REPEATS)  # at unconditional GOTOs back
        self._waiting = 0  # jumps back in a row, each after reading an input signal
        self.main = src
        self.loaded: dict[int, tuple[Source, int]] = {}
        self.frames = [Frame(src, 0, src.main_program_line(), 0, "main")]
        self.jumps = 0
        self.guard = self.ip.flow.guard  # gcode.core.loopguard, shared with the interpreter
        self.current_seq: int | None = None
        self.current_program = 0
        self.corners = CornerFilter()  # ,C / ,R: the asking move waits for the next one

    # ------------------------------------------------------------------ run
    def run(self) -> Iterator[canon.Command]:
        """The canonical commands of the program (the lane's runs as commands)."""
        for item in self.chunks(arcs=True):
            if isinstance(item, canon.Command):
                yield item
            else:
                yield from item.commands(self.main.path)

    def chunks(self, arcs: bool = False) -> Iterator[canon.Command | Run]:
        """Commands, and for a large file runs of plain blocks as
        :class:`gcode.ngc.lane.fastlane.Run` (gcode.fanuc.lane); ``arcs``: runs may hold
        arcs."""
        try:
            yield from self._run(self._lane(arcs))
        except Diagnostic as exc:
            out = self.ip.out
            yield from list(out)  # what the failing block made before its error
            out.clear()
            if exc.code.startswith("NGC-"):
                raise Diagnostic("FANUC-" + exc.code[4:], exc.message, exc.location) from None
            raise

    def _lane(self, arcs: bool) -> FanucLane | None:
        """The compiled fast lane for a large main program (imported here: it needs numpy,
        which a small program then never loads)."""
        if not self.options.fast_lane or len(self.main.lines.data) < LANE_MIN_BYTES:
            return None
        from gcode.fanuc.lane import FanucLane

        return FanucLane.for_source(self.main, arcs)

    def _run(self, lane: FanucLane | None) -> Iterator[canon.Command | Run]:
        ip = self.ip
        out = ip.out
        ip.loc = Location(self.main.path, 0, 0)
        ip._preamble()
        if self.ex.lathe is not None:
            self.ex.lathe.start()
        keep_all = len(self.main.lines) <= KEEP_ALL_LINES
        frames = self.frames
        guard = self.guard
        while True:
            if out:
                guard.output += len(out)
                yield from self._released(out)
                out.clear()
            fr = frames[-1]
            src = fr.src
            if fr.pc >= len(src.lines):
                if self._end_of_text(fr):
                    break
                continue
            idx = fr.pc
            if (
                lane is not None
                and fr.started
                and len(frames) == 1
                and not fr.loops
                and not self.corners.pending
            ):
                run = lane.take(self.ex, idx)
                if run is not None:
                    fr.pc += run.lines
                    guard.blocks += run.lines
                    guard.output += len(run)
                    yield run
                    continue
            fr.pc += 1
            guard.blocks += 1
            blk = src.block(idx, keep_all or len(frames) > 1 or bool(fr.loops))
            kind = blk.kind
            if kind == "empty":
                if blk.comment is not None:
                    self._comment(blk, src)
                continue
            if kind in ("percent", "program"):
                if not fr.started and (fr.kind == "main" or fr.start == -1):
                    if kind == "program":
                        self.current_program = blk.label
                    continue
                if self._end_of_text(fr):
                    break
                continue
            if blk.deleted and self.fl.block_delete:
                continue
            fr.started = True
            self.ex.last_comment = blk.comment  # the message of #3000 / #3006
            if blk.seq is not None:
                self.current_seq = blk.seq
            if blk.comment is not None:
                self._comment(blk, src)
            if kind == "words":
                if self._words(blk, fr):
                    break
            elif kind == "if_block":
                if self._if_block(blk, fr):
                    break
            elif kind == "output":
                continue
            else:
                self._statement(blk, fr, idx)
        yield from self._released(out)
        out.clear()
        yield from self.corners.finish("FANUC-CORNER")

    def _released(self, out: list[canon.Command]) -> list[canon.Command]:
        """The commands of the block just run that may go out now: a move that asked for a
        chamfer or corner R (``,C`` / ``,R``) waits for the next move (gcode.core.corners)."""
        request, self.ex.corner = self.ex.corner, None
        return self.corners.released(out, request, "FANUC-CORNER")

    def _comment(self, blk: FBlock, src: Source) -> None:
        self.ex.last_comment = blk.comment
        loc = Location(src.path, blk.line, 1)
        self.ip.emit(canon.Comment(blk.comment or "", source=loc))

    # ------------------------------------------------------------------ blocks
    def _words(self, blk: FBlock, fr: Frame) -> bool:
        path = fr.src.path
        items: list[tuple[str, int | float, int]] = []
        if blk.plain:
            loc = Location(path, blk.line, 1)
            ex = self.ex
            if ex.plain_ok:  # the CAM hot path: constant G00-G03 X Y Z I J K R F words
                ex.ip.loc = loc
                if ex._plain(blk.words):
                    return False
            items = [
                (letter, val, blk.column(index))
                for letter, val, index in blk.words
                if not isinstance(val, tuple)  # a plain block has constants only
            ]
        else:
            loc = Location(path, blk.line, blk.column(blk.words[0][2]) if blk.words else 1)
            for letter, word, index in blk.words:
                col = blk.column(index)
                if isinstance(word, tuple):  # an expression
                    got = evaluate(word, self.vars, Location(path, blk.line, col))
                    if got is None:
                        continue  # a vacant variable: the word is not there
                    items.append((letter, got, col))
                else:
                    items.append((letter, word, col))
        self.ex.depth = self.vars.depth
        self.ex.last_comment = blk.comment
        return any(self._act(action, fr, loc) for action in self.ex.block(items, loc))

    def _if_block(self, blk: FBlock, fr: Frame) -> bool:
        """Haas ``IF [c] <block>``: when c holds, the block's assignment and words run as a
        block of their own; else the rest of the block is ignored (Haas mill manual,
        "Macros", conditional execution). A Fanuc control wants GOTO or THEN there."""
        path = fr.src.path
        if not self.fl.if_without_then:
            loc = Location(path, blk.line, blk.column(blk.label))
            raise Diagnostic("FANUC-SYNTAX", "GOTO or THEN expected after IF [...]", loc)
        loc = Location(path, blk.line, 1)
        if not truth(blk.expr, self.vars, loc):
            return False
        if blk.then is not None:
            target = evaluate(blk.then[0], self.vars, loc)
            self.vars.write(target or 0.0, evaluate(blk.then[1], self.vars, loc), loc)
        return bool(blk.words) and self._words(blk, fr)

    def _statement(self, blk: FBlock, fr: Frame, idx: int) -> None:
        loc = Location(fr.src.path, blk.line, 1)
        kind = blk.kind
        vars = self.vars
        if kind == "assign":
            target = evaluate(blk.target, vars, loc)
            vars.write(target or 0.0, evaluate(blk.expr, vars, loc), loc)
        elif kind == "if_goto":
            if truth(blk.expr, vars, loc):
                self._goto(fr, evaluate(blk.target, vars, loc), loc)
        elif kind == "if_then":
            if truth(blk.expr, vars, loc):
                assert blk.then is not None
                target = evaluate(blk.then[0], vars, loc)
                vars.write(target or 0.0, evaluate(blk.then[1], vars, loc), loc)
        elif kind == "goto":
            target = evaluate(blk.target, vars, loc)
            self._goto(fr, target, loc)
            if fr.pc <= idx and fr.kind == "main" and not fr.loops:
                self._repeats_for_ever(fr, loc)
        elif kind == "while":
            self._check_loop_id(blk.label, loc)
            if truth(blk.expr, vars, loc):
                fr.loops[blk.label] = idx
            else:
                fr.loops.pop(blk.label, None)
                fr.pc = self._find_end(fr, idx, blk.label, loc) + 1
        elif kind == "do":
            self._check_loop_id(blk.label, loc)
            fr.loops[blk.label] = idx
        elif kind == "end":
            start = fr.loops.get(blk.label)
            if start is None:
                raise Diagnostic("FANUC-LOOP", f"END{blk.label} without DO{blk.label}", loc)
            fr.pc = start
            self._count_jump(
                loc, f"WHILE ... DO{blk.label} (line {start + 1}) END{blk.label}", start + 1
            )

    @staticmethod
    def _check_loop_id(label: int, loc: Location) -> None:
        if not 1 <= label <= 3:
            raise Diagnostic("FANUC-LOOP", f"DO{label}: the loop number must be 1, 2 or 3", loc)

    def _find_end(self, fr: Frame, idx: int, label: int, loc: Location) -> int:
        src = fr.src
        for i in range(idx + 1, len(src.lines)):
            blk = src.block(i, True)
            if blk.kind == "end" and blk.label == label:
                return i
            if blk.kind in ("program", "percent"):
                break
        raise Diagnostic("FANUC-LOOP", f"DO{label} without END{label}", loc)

    def _goto(self, fr: Frame, target: float | None, loc: Location) -> None:
        if target is None:
            raise Diagnostic("FANUC-GOTO", "GOTO a vacant variable: no sequence number", loc)
        if target != round(target) or target < 0:
            raise Diagnostic("FANUC-GOTO", f"bad sequence number in GOTO: {target:g}", loc)
        line = fr.src.find_sequence(fr.start, int(target))
        if line is None:
            raise Diagnostic("FANUC-GOTO", f"sequence number N{int(target)} not found", loc)
        if line < fr.pc:
            self._count_jump(loc, f"GOTO{int(target)}", line + 1)
        fr.pc = line
        for m, start in list(fr.loops.items()):
            if start >= line:  # jumping out of (or back before) a loop ends it
                del fr.loops[m]

    def _repeats_for_ever(self, fr: Frame, loc: Location) -> None:
        """An unconditional GOTO back in the main program arriving with the same variables,
        position and modes as before: nothing can leave the loop (a production loop
        ``N1 ... GOTO1``), the control runs it for ever. After :data:`MAX_REPEATS` such
        passes the reader stops with FANUC-LOOP-LIMIT instead of running to the jump limit."""
        v = self.vars
        s = self.ex.ip.s
        state = (
            fr.pc,
            tuple(v.locals),
            tuple(sorted(v.common.items())),
            tuple(round(p, 9) for p in s.pos),
            tuple(sorted(self.sysvars.outputs.items())),
            (self.ex.motion, s.absolute, s.feed_rate, s.origin_index),
        )
        if self.repeat_guard.endless(state):
            raise Diagnostic(
                "FANUC-LOOP-LIMIT",
                f"the program repeats itself for ever from this GOTO ({MAX_REPEATS} passes "
                "through the same state): endless loop",
                loc,
            )

    def _count_jump(self, loc: Location, construct: str, target: int = 0) -> None:
        """A jump back to line ``target``: the flavour's jump limit, then the shared loop
        guard."""
        self.jumps += 1
        if self.jumps > self.fl.max_loops:
            raise Diagnostic(
                "FANUC-LOOP-LIMIT", f"more than {self.fl.max_loops} jumps back: endless loop?", loc
            )
        reads = self.sysvars.input_reads
        self._waiting = self._waiting + 1 if reads != self._input_mark else 0
        self._input_mark = reads
        if self._waiting > MAX_INPUT_WAIT:
            raise Diagnostic(
                "FANUC-WAIT-INPUT",
                f"{construct}: the loop waits for an interface input signal (#1000-#1035), "
                "which a reading without the machine holds at 0: it would wait for ever",
                loc,
            )
        self.guard.back(construct, loc, target)

    # ------------------------------------------------------------------ calls
    def _act(self, a: Action, fr: Frame, loc: Location) -> bool:
        if a.kind == "end":
            return True
        if a.kind in ("m98", "g65"):
            if a.repeats > 0:
                self._call(a.number, a.repeats, a.kind, a.args if a.kind == "g65" else None, loc)
        elif a.kind == "m97":
            assert a.seq is not None
            line = fr.src.find_sequence(fr.start, a.seq)
            if line is None:
                raise Diagnostic("FANUC-CALL", f"M97: sequence number N{a.seq} not found", loc)
            if a.repeats > 0:
                self._push(Frame(fr.src, line, fr.start, line, "m97", a.repeats - 1), loc)
        elif a.kind == "m99":
            return self._return(a.seq, loc)
        elif a.kind == "skip":  # after G71-G73: on after the contour's last block
            assert a.seq is not None
            line = self._sequence(fr, a.seq, loc)
            fr.pc = max(fr.pc, line + 1)
        return False

    def _sequence(self, fr: Frame, seq: int, loc: Location) -> int:
        line = fr.src.find_sequence(fr.start, seq)
        if line is None:
            raise Diagnostic("FANUC-CYCLE-PQ", f"sequence number N{seq} not found", loc)
        return line

    def _contour_blocks(
        self, p: int, q: int, loc: Location
    ) -> Iterator[tuple[int, dict[str, float], list[int]]]:
        """The words of blocks N p .. N q (a G70-G73 contour), evaluated and resolved."""
        fr = self.frames[-1]
        first, last = self._sequence(fr, p, loc), self._sequence(fr, q, loc)
        if last < first:
            raise Diagnostic("FANUC-CYCLE-PQ", f"N{q} comes before N{p}", loc)
        inch = self.ip.s.units is Units.INCHES
        for i in range(first, last + 1):
            blk = fr.src.block(i, True)
            at = Location(fr.src.path, blk.line, 1)
            if blk.kind == "empty" or (blk.deleted and self.fl.block_delete):
                continue
            if blk.kind != "words":
                raise Diagnostic("FANUC-CYCLE-CONTOUR", "macro statement in a contour", at)
            raw: dict[str, int | float] = {}
            gs: list[int] = []
            for letter, word, index in blk.words:
                if letter[0] == ",":
                    raise Diagnostic(
                        "FANUC-CORNER",
                        f"{letter} (chamfer or corner R) in a G70-G73 contour is not read",
                        Location(fr.src.path, blk.line, blk.column(index)),
                    )
                val = evaluate(word, self.vars, at) if isinstance(word, tuple) else word
                if val is None:
                    continue
                if letter == "G":
                    gs.append(round(val * 10))
                elif letter != "N":
                    raw[letter] = val
            yield blk.line, resolve(raw, inch, set(gs), False, False, False), gs

    def _push(self, frame: Frame, loc: Location) -> None:
        if len(self.frames) >= MAX_DEPTH:
            raise Diagnostic("FANUC-CALL-DEPTH", f"more than {MAX_DEPTH} nested calls", loc)
        self.frames.append(frame)

    def _call(
        self, number: int, repeats: int, kind: str, args: dict[int, float] | None, loc: Location
    ) -> None:
        src, oline = self._find_program(number, loc)
        frame = Frame(src, oline + 1, oline, oline + 1, kind, repeats - 1, args, number=number)
        self._push(frame, loc)
        frame.started = oline >= 0
        if kind == "g65":
            self.vars.enter(args or {})

    def _find_program(self, number: int, loc: Location) -> tuple[Source, int]:
        for src in (self.frames[-1].src, self.main):
            if number in src.programs:
                return src, src.programs[number]
        if number in self.loaded:
            return self.loaded[number]
        path = find_program_file(number, self.options.search_path, self.main.path)
        if path is None:
            raise Diagnostic("FANUC-NO-PROGRAM", f"program O{number:04d} not found", loc)
        src = read_source(path)
        found = (src, src.programs.get(number, -1))
        self.loaded[number] = found
        return found

    def _return(self, seq: int | None, loc: Location) -> bool:
        fr = self.frames[-1]
        if fr.kind == "main":
            if seq is None:
                return True  # M99 in a main program repeats it forever: stop reading
            self._goto(fr, float(seq), loc)
            return False
        if fr.repeats > 0:
            fr.repeats -= 1
            fr.pc = fr.entry
            fr.started = fr.start >= 0
            fr.loops.clear()
            self._count_jump(loc, "M99 (subprogram repeat)")
            if fr.kind == "g65":
                self.vars.leave()
                self.vars.enter(fr.args or {})
            return False
        self.frames.pop()
        if fr.kind == "g65":
            self.vars.leave()
        if seq is not None:
            caller = self.frames[-1]
            self._goto(caller, float(seq), loc)
        return False

    def _end_of_text(self, fr: Frame) -> bool:
        """The program's text ran out (next O number, %, end of file)."""
        if fr.kind == "main":
            return True
        loc = Location(fr.src.path, min(fr.pc, len(fr.src.lines)), 1)
        return self._return(None, loc)


def read(path: str, options: InterpreterOptions, flavour: Flavour) -> Iterator[canon.Command]:
    yield from Reader(read_source(path), options, flavour).run()


def read_chunks(
    path: str, options: InterpreterOptions, flavour: Flavour, arcs: bool = False
) -> Iterator[canon.Command | Run]:
    """Like :func:`read`, with the runs of plain blocks of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays (``Reader.chunks``)."""
    yield from Reader(read_source(path), options, flavour).chunks(arcs)


def read_text(
    text: str, name: str, options: InterpreterOptions, flavour: Flavour
) -> Iterator[canon.Command]:
    yield from Reader(Source.from_text(name, text), options, flavour).run()
