"""Program flow of the 840D reader: blocks in order, jumps, control structures,
subprogram calls and program end (840D sl programming manual, job planning, "Program
jumps" and "Control structures"; fundamentals, "Subprograms").

* ``GOTOF``/``GOTOB`` search forward/backward, ``GOTO`` forward then backward, ``GOTOC``
  like GOTO without an error when the target is missing; targets are labels or N numbers.
* ``IF``/``ELSE``/``ENDIF``, ``WHILE``/``ENDWHILE``, ``FOR``/``ENDFOR`` (the counter
  steps by 1; no pass when the start exceeds the end), ``REPEAT``/``UNTIL``,
  ``LOOP``/``ENDLOOP``. A jump out of a structure leaves it.
* ``CASE e OF c1 GOTOF A ... DEFAULT GOTOF B``: the jump of the first constant equal to
  the value, else DEFAULT's, else the next block (job planning, "Program jumps").
* ``REPEAT A P=n`` (the lines from label A up to the REPEAT), ``REPEAT A B P=n`` (A to B),
  ``REPEAT A ENDLABEL P=n`` (A to the next ``ENDLABEL:``), ``REPEATB A P=n`` (the line of
  A): the section runs n more times, then the block after the REPEAT (job planning,
  "Program section repetition"); without P once.
* ``L100``/``NAME`` call ``L100.SPF``/``NAME.SPF``, ``P n`` times; ``M17``, ``RET``, ``M2``
  or ``M30`` (or the file's end) return. R parameters are global, DEF variables local.
  ``NAME(a, b)`` passes arguments to the callee's ``PROC NAME(REAL A, VAR INT B)``
  parameters: by value, or for ``VAR`` by reference (the caller's variable or R parameter
  gets the parameter's value at the return); an omitted argument is 0 (fundamentals,
  "Subprograms with parameter transfer"; job planning, "Subprogram technique").
* Bounded: at most :data:`MAX_LOOPS` backward jumps and loop passes in a run, and
  :data:`MAX_DEPTH` program levels (SIEM-LOOP-LIMIT, SIEM-CALL-DEPTH).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

from gcode.core.corners import CornerFilter
from gcode.core.loopguard import LoopGuard, RepeatGuard
from gcode.siemens.blocks import Block, Word
from gcode.siemens.cycles import PATTERNS, STANDARD_CYCLES, check_cycle, run_cycle
from gcode.siemens.executor import Executor
from gcode.siemens.expr import Variables, evaluate
from gcode.siemens.fastpath import plain_words
from gcode.siemens.frames import change
from gcode.siemens.program import Program, find_subprogram
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

if TYPE_CHECKING:  # numpy and the kernels load with the first large read-back
    from gcode.ngc.lane.fastlane import Run
    from gcode.siemens.lane import SiemensLane

MAX_LOOPS = 1_000_000
END = Block(0)  # the block that ended a level (M2/M17/M30), when read by the fast path
MAX_DEPTH = 16
#: loop passes in a row that read a PLC input before a loop counts as waiting on the machine
MAX_INPUT_WAIT = 1000
#: states kept to tell a main program repeating itself for ever (memory bound)
MAX_STATES = 10_000
#: passes through the same state at an unconditional jump back before SIEM-LOOP-LIMIT
MAX_REPEATS = 10_000


@dataclass
class Open:
    """An entered control structure: its kind, opening and closing line."""

    kind: str
    start: int
    end: int
    data: tuple = ()


@dataclass
class Section:
    """A running section repetition: its first and last line, passes left, where to go on."""

    start: int
    end: int
    left: int
    after: int
    construct: str


@dataclass
class Level:
    program: Program
    scope: Variables
    index: int = 0
    repeat: int = 1
    structures: list[Open] = field(default_factory=list)
    call: Location | None = None
    #: PROC parameters as passed (type, name, value): bound again at each pass (P)
    bound: tuple[tuple[str, str, float], ...] = ()
    #: VAR parameters: (parameter name, the caller's target) written back at the return
    results: tuple[tuple[str, tuple], ...] = ()
    sections: list[Section] = field(default_factory=list)
    modal: bool = False  # called by MCALL: its own moves call nothing


class Runner:
    def __init__(self, ex: Executor, main: Program) -> None:
        self.ex = ex
        self.levels = [Level(main, Variables(ex.r, ex.system_variable))]
        self.programs: dict[str, Program] = {main.name: main}
        self.loops = 0
        self.input_mark = 0  # PLC input reads at the last loop pass
        self.waiting = 0  # loop passes in a row, each after reading a PLC input
        self.repeat_guard = RepeatGuard(MAX_STATES, MAX_REPEATS)  # at unconditional jumps back
        opts = ex.options
        self.guard = LoopGuard(opts.max_blocks, opts.max_idle_blocks)
        #: (cycle name, calling program) -> whether a program file of that name is found
        self.cycle_files: dict[tuple[str, str], bool] = {}
        self.corners = CornerFilter()  # CHF/CHR/RND: the asking move waits for the next one

    def run(self) -> Iterator[canon.Command]:
        """The canonical commands of the program."""
        return cast(Iterator[canon.Command], self.chunks(None))

    def chunks(self, lane: SiemensLane | None) -> Iterator[canon.Command | Run]:
        """The canonical commands, and with ``lane`` the runs of plain blocks of the main
        program's top level as :class:`gcode.ngc.lane.fastlane.Run` arrays
        (gcode.siemens.lane)."""
        ex = self.ex
        out = ex.out
        guard = self.guard
        main = self.levels[0].program
        ex.preamble(Location(main.name, 0, 0))
        yield from out
        out.clear()
        try:
            while self.levels:
                level = self.levels[-1]
                program = level.program
                if not program.has_line(level.index):
                    if self._return(level, None):
                        break
                    continue
                index = level.index
                if (
                    lane is not None
                    and len(self.levels) == 1
                    and not level.sections
                    and not level.structures
                    and not self.corners.pending  # the held move waits for the next block
                    and not ex.s.rounding  # RNDM: every corner is rounded, none is plain
                ):
                    run = lane.take(ex, index)
                    if run is not None:
                        level.index += run.lines
                        guard.blocks += run.lines
                        guard.output += len(run)
                        yield run
                        continue
                level.index += 1
                guard.blocks += 1
                words = plain_words(program.line(index))
                if words is not None:
                    if words:
                        ex.loc = Location(program.name, index + 1, words[0][2])
                        if ex.execute_words(words, level.scope):
                            ex.modal_call_due = False
                            if self._return(level, END):
                                break
                        elif ex.modal_call_due:
                            self._modal_call(level)
                        if out:
                            guard.output += len(out)
                            yield from self._released(out)
                            out.clear()
                    if level.sections and level.sections[-1].end == index:
                        self._section_end(level)
                    continue
                block = program.block(index)
                ex.loc = Location(program.name, block.line, block.col)
                if block.comment is not None:
                    out.append(canon.Comment(block.comment, source=ex.loc))
                if block.kind == "nc":
                    ended = bool(block.items) and ex.execute(block, level.scope)
                    if ended:
                        ex.modal_call_due = False
                        if self._return(level, block):
                            break
                    elif ex.modal_call_due:
                        self._modal_call(level)
                else:
                    self.statement(level, block, index)
                if level.sections and level.sections[-1].end == index:
                    self._section_end(level)
                if out:
                    guard.output += len(out)
                    yield from self._released(out)
                    out.clear()
        except Diagnostic:
            yield from out
            out.clear()
            raise
        yield from self._released(out)
        out.clear()
        yield from self.corners.finish("SIEM-CORNER")

    def _released(self, out: list[canon.Command]) -> list[canon.Command]:
        """The commands of the block just run that may go out now: a move that asked for a
        chamfer or rounding waits for the next move (gcode.core.corners)."""
        request, self.ex.corner = self.ex.corner, None
        return self.corners.released(out, request, "SIEM-CORNER")

    # ------------------------------------------------------------------ levels
    def _return(self, level: Level, block: Block | None) -> bool:
        """End of a program level (M2/M17/M30/RET or its end); True at the program's end."""
        if level.repeat > 1:
            level.repeat -= 1
            level.index = 0
            level.structures.clear()
            level.sections.clear()
            level.scope = self._bind(level.bound)
            return False
        self.levels.pop()
        if self.levels:
            caller = self.levels[-1].scope
            for name, target in level.results:
                self._assign(caller, target, level.scope.get(name, self.ex.loc))
            return False
        if block is not None:
            self._end()
        return True

    def _end(self) -> None:
        """M2/M30 of the main program: the 840D resets the channel's modal state."""
        ex = self.ex
        s, loc = ex.s, ex.loc
        if s.plane != "XY":
            s.plane = "XY"
            ex.emit(canon.SelectPlane(canon.Plane.XY, source=loc))
        s.feed = 0.0
        ex.emit(canon.SetFeedRate(0.0, source=loc))
        s.direction = canon.Direction.STOPPED
        ex.emit(canon.StopSpindleTurning(source=loc))
        ex.emit(canon.ProgramEnd(source=loc))

    def _cycle_file(self, name: str, level: Level) -> bool:
        """Whether cycle ``name`` is a program file on the search path (or beside the
        calling program). The 840D looks for a called name in the program's own
        directories before its cycle directories (job planning, "Subprogram call", search
        path), so a CYCLE81.SPF there is called as a subprogram with the arguments, and
        only a name without such a file is the standard cycle this reader expands."""
        key = (name, level.program.name)
        found = self.cycle_files.get(key)
        if found is None:
            path = find_subprogram(name, self.ex.options.search_path, level.program.name)
            found = self.cycle_files[key] = path is not None
        return found

    def _modal_call(self, level: Level) -> None:
        """``MCALL NAME``: NAME is called after each block that moves (job planning, "Modal
        subprogram call": the subprogram runs after every block with path motion until
        MCALL alone), with the arguments evaluated at each call; not from the blocks of the
        modally called subprogram itself."""
        ex = self.ex
        ex.modal_call_due = False
        if ex.s.mcall is None or any(open_level.modal for open_level in self.levels):
            return
        name, args, _ = ex.s.mcall
        call = Block(ex.loc.line or 0, kind="CALL", args=(name, ("num", 1.0), args))
        self.call(level, call)
        self.levels[-1].modal = True

    def call(self, level: Level, block: Block) -> None:
        name, repeat_node, args = block.args
        ex = self.ex
        repeat = evaluate(repeat_node, level.scope)
        if repeat < 1 or repeat != int(repeat):
            raise Diagnostic(
                "SIEM-CALL", f"{name} P{repeat:g}: the pass count is a whole number >= 1", ex.loc
            )
        if len(self.levels) >= MAX_DEPTH:
            raise Diagnostic("SIEM-CALL-DEPTH", f"more than {MAX_DEPTH} program levels", ex.loc)
        path = find_subprogram(name, ex.options.search_path, level.program.name)
        if path is None:
            if name in PATTERNS:
                run_cycle(ex, name, args, level.scope)  # HOLES1, HOLES2: the control's own
                return
            if name in STANDARD_CYCLES:
                check_cycle(ex, name, args)  # the control's cycle, which is not expanded
            raise Diagnostic("SIEM-SUBPROGRAM", f"subprogram {name} ({name}.SPF) not found", ex.loc)
        program = self.programs.get(path)
        if program is None:
            program = self.programs[path] = Program.load(path)
        program.caching = True
        bound, results = self._parameters(name, program, args, level.scope)
        callee = Level(program, self._bind(bound), repeat=int(repeat), call=ex.loc)
        callee.bound, callee.results = bound, results
        self.levels.append(callee)

    def _bind(self, bound: tuple[tuple[str, str, float], ...]) -> Variables:
        scope = Variables(self.ex.r, self.ex.system_variable)
        for kind, pname, value in bound:
            scope.define(kind, pname, value, self.ex.loc)
        return scope

    def _parameters(
        self, name: str, program: Program, args: tuple | None, scope: Variables
    ) -> tuple[tuple[tuple[str, str, float], ...], tuple[tuple[str, tuple], ...]]:
        """The callee's PROC parameters with the call's arguments: (type, name, value) by
        value, and (name, caller target) for each VAR parameter."""
        ex = self.ex
        params = _proc_parameters(program)
        given = args or ()
        if len(given) > len(params):
            raise Diagnostic(
                "SIEM-CALL",
                f"{name}: {len(given)} arguments for {len(params)} parameters of its PROC",
                ex.loc,
            )
        bound: list[tuple[str, str, float]] = []
        results: list[tuple[str, tuple]] = []
        for i, (by_reference, kind, pname) in enumerate(params):
            node = given[i] if i < len(given) else None
            if by_reference:
                target = _target_of(node)
                if target is None:
                    raise Diagnostic(
                        "SIEM-CALL",
                        f"{name}: VAR parameter {pname} needs a variable or R parameter as "
                        "its argument",
                        ex.loc,
                    )
                results.append((pname, target))
                value = self._read(scope, target)
            else:
                value = evaluate(node, scope) if node is not None else 0.0
            bound.append((kind, pname, value))
        return tuple(bound), tuple(results)

    # ------------------------------------------------------------------ statements
    def define_array(self, scope: Variables, kind: str, item: tuple) -> None:
        """``DEF REAL NAME[n, m] = SET(...) / REP(v, count)``: elements in row-major order,
        an omitted SET value 0, REP's value repeated count times (all elements without)."""
        loc = self.ex.loc
        name, dim_nodes, init = item
        dims = []
        for node in dim_nodes:
            d = evaluate(node, scope)
            if d != round(d):
                raise Diagnostic("SIEM-ARRAY", f"{name}: dimension {d:g} is not whole", loc)
            dims.append(int(round(d)))
        if init[0] == "SET":
            values = [0.0 if n is None else evaluate(n, scope) for n in init[1]]
        else:
            value = evaluate(init[1], scope)
            size = 1
            for d in dims:
                size *= max(d, 0)
            count = size if init[2] is None else evaluate(init[2], scope)
            if count != round(count) or count < 0:
                raise Diagnostic("SIEM-ARRAY", f"{name}: REP count {count:g}", loc)
            values = [value] * min(int(count), size + 1)
        scope.define_array(kind, name, tuple(dims), values, loc)

    def statement(self, level: Level, block: Block, index: int) -> None:
        ex = self.ex
        kind = block.kind
        scope = level.scope
        if kind == "GOTO":
            self.jump(level, block.args[0], block.args[1], index)
            if level.index <= index:
                self._repeats_for_ever(level)
        elif kind == "IFGOTO":
            if evaluate(block.args[0], scope):
                self.jump(level, block.args[1], block.args[2], index)
        elif kind in (
            "IF",
            "WHILE",
            "FOR",
            "REPEAT",
            "LOOP",
            "ELSE",
            "ENDIF",
            "ENDWHILE",
            "ENDFOR",
            "UNTIL",
            "ENDLOOP",
        ):
            self.structure(level, block, index)
        elif kind == "DEF":
            kind_name, names = block.args
            for item in names:
                if len(item) == 3:
                    self.define_array(scope, kind_name, item)
                    continue
                name, node = item
                scope.define(
                    kind_name, name, evaluate(node, scope) if node is not None else 0.0, ex.loc
                )
        elif kind == "MSG":
            if block.args[0]:
                ex.emit(canon.Message(block.args[0], source=ex.loc))
        elif kind == "FRAME":
            self.frame(level, block)
        elif kind == "ALARM":
            number = evaluate(block.args[0], scope) if block.args and block.args[0] else 0.0
            raise Diagnostic(
                "SIEM-ALARM", f"the program sets alarm {number:g} (SETAL) and stops", ex.loc
            )
        elif kind == "SETMS":
            self.master_spindle(block, scope)
        elif kind == "CYCLE":
            if self._cycle_file(block.args[0], level):
                self.call(
                    level,
                    Block(
                        block.line, kind="CALL", args=(*block.args[:1], ("num", 1.0), block.args[1])
                    ),
                )
            else:
                run_cycle(ex, block.args[0], block.args[1], scope)
        elif kind == "MCALL":
            head, args = block.args
            if head is None:
                ex.s.mcall = None
            else:
                by_program = not head.startswith("CYCLE") or self._cycle_file(head, level)
                if not by_program:
                    check_cycle(ex, head, args)
                ex.s.mcall = (head, args, by_program)
        elif kind == "CALL":
            self.call(level, block)
        elif kind == "CASE":
            value = evaluate(block.args[0], scope)
            for constant, how, label in block.args[1]:
                if evaluate(constant, scope) == value:
                    self.jump(level, how, label, index)
                    return
            if block.args[2] is not None:
                self.jump(level, block.args[2][0], block.args[2][1], index)
        elif kind == "SECTION":
            self.section(level, block, index)
        elif kind == "RET":
            if len(self.levels) == 1:
                raise Diagnostic("SIEM-RET", "RET in the main program", ex.loc)
            self._return(level, block)
        elif kind == "PROC" and index != _first_code_line(level.program, index):
            raise Diagnostic("SIEM-PROC", "PROC must be the first block of a subprogram", ex.loc)
        elif kind == "PROC" and len(self.levels) == 1 and block.args[1]:
            raise Diagnostic(
                "SIEM-PROC",
                f"PROC {block.args[0]} with parameters run as the main program: its "
                "parameters get their values from a call, and nothing calls it",
                ex.loc,
            )

    def master_spindle(self, block: Block, scope: Variables) -> None:
        """``SETMS(n)`` declares spindle n the master spindle, ``SETMS`` the one of the
        machine data (job planning, "Master spindle"). The IR has one spindle, spindle 1:
        SETMS and SETMS(1) change nothing; another spindle is refused."""
        args = block.args
        number = evaluate(args[0], scope) if args and args[0] is not None else 1.0
        if len(args) > 1 or number != 1:
            raise Diagnostic(
                "SIEM-UNSUPPORTED",
                f"SETMS({number:g}): a master spindle other than spindle 1 (the IR has one "
                "spindle)",
                self.ex.loc,
            )

    def frame(self, level: Level, block: Block) -> None:
        ex = self.ex
        s = ex.s
        values: dict[str, float] = {}
        rpl = None
        for item in block.items:
            assert isinstance(item, Word)  # blocks: a frame takes X Y Z RPL words only
            value = evaluate(item.value, level.scope)
            if item.address == "RPL":
                rpl = value
            else:
                values[item.address] = value
        op = block.args[0]
        if rpl is not None and not op.endswith("ROT"):
            raise Diagnostic("SIEM-FRAME", f"RPL= belongs to ROT/AROT, not {op}", ex.loc)
        if rpl is not None and values:
            raise Diagnostic("SIEM-FRAME", "ROT takes RPL= or axis angles, not both", ex.loc)
        if op.endswith("SCALE") and any(abs(v) < 1e-12 for v in values.values()):
            raise Diagnostic("SIEM-FRAME", "scale factor 0", ex.loc)
        old = s.frame.t
        s.frame = change(s.frame, op, values, rpl, s.plane)
        if s.frame.t != old:
            for i in range(3):
                s.pos[i] += old[i] - s.frame.t[i]
            ex.emit_offsets()

    def section(self, level: Level, block: Block, here: int) -> None:
        """REPEAT / REPEATB: run a section of this program again P times."""
        head, start_label, end_label, passes_node = block.args
        ex = self.ex
        passes = evaluate(passes_node, level.scope)
        if passes < 1 or passes != int(passes):
            raise Diagnostic(
                "SIEM-REPEAT", f"{head} P={passes:g}: the pass count is a whole number >= 1", ex.loc
            )
        program = level.program
        start = _near(program, start_label, here, ex.loc, head == "REPEATB")
        if head == "REPEATB":
            end = start
        elif end_label is None:
            end = here - 1
        else:
            ends = [i for i in program.targets().get(end_label, []) if i >= start]
            if not ends:
                raise Diagnostic(
                    "SIEM-LABEL",
                    f"{head}: end label {end_label} not found after {start_label}",
                    ex.loc,
                )
            end = ends[0]
        if start <= here <= end:
            raise Diagnostic(
                "SIEM-REPEAT", f"{head}: the section {start_label} holds the {head} itself", ex.loc
            )
        if len(level.sections) >= MAX_DEPTH:
            raise Diagnostic("SIEM-REPEAT", f"more than {MAX_DEPTH} nested REPEAT sections", ex.loc)
        construct = f"{head} {start_label} (line {here + 1})"
        level.sections.append(Section(start, end, int(passes) - 1, here + 1, construct))
        self._count(construct, start + 1)
        program.caching = True
        level.index = start

    def _section_end(self, level: Level) -> None:
        """The last line of a repeated section ran: again from its start, or on after it."""
        top = level.sections[-1]
        if top.left > 0:
            top.left -= 1
            self._count(top.construct, top.start + 1)
            level.index = top.start
        else:
            level.sections.pop()
            level.index = top.after

    def jump(self, level: Level, how: str, label: str, here: int) -> None:
        target = level.program.jump(label, how, here, self.ex.loc)
        if target < 0:
            return
        if target <= here:
            self._count(f"{how} {label}", target + 1)
            level.program.caching = True
        level.structures = [o for o in level.structures if o.start < target <= o.end]
        level.index = target

    def _repeats_for_ever(self, level: Level) -> None:
        """An unconditional jump back (GOTOB, ENDLOOP) in the main program arriving with the
        same variables, R parameters, position and modes as before: nothing can leave the
        loop, the control runs it for ever. After :data:`MAX_REPEATS` such passes the reader
        stops with SIEM-LOOP-LIMIT instead of running to the pass limit."""
        if len(self.levels) != 1 or level.sections:
            return
        s = self.ex.s
        state = (
            level.index,
            tuple(sorted(self.ex.r.items())),
            tuple(sorted(level.scope.local.items())),
            tuple((k, tuple(v[2])) for k, v in sorted(level.scope.arrays.items())),
            tuple(round(p, 9) for p in s.pos),
            (s.motion, s.absolute, s.feed, s.work, s.frame, s.tool),
        )
        if self.repeat_guard.endless(state):
            raise Diagnostic(
                "SIEM-LOOP-LIMIT",
                f"the program repeats itself for ever from here ({MAX_REPEATS} passes through "
                "the same state): endless loop",
                self.ex.loc,
            )

    def _count(self, construct: str, target: int = 0) -> None:
        """A loop pass or backward jump to line ``target``: the reader's pass limit, a loop
        waiting on a PLC input, then the shared guard."""
        self.loops += 1
        reads = self.ex.input_reads
        self.waiting = self.waiting + 1 if reads != self.input_mark else 0
        self.input_mark = reads
        if self.waiting > MAX_INPUT_WAIT:
            raise Diagnostic(
                "SIEM-WAIT-INPUT",
                f"{construct}: the loop waits for a PLC input ($A_IN, $A_INA), which a reading "
                "without the machine holds at 0: it would wait for ever",
                self.ex.loc,
            )
        if self.loops > MAX_LOOPS:
            raise Diagnostic(
                "SIEM-LOOP-LIMIT",
                f"more than {MAX_LOOPS} loop passes or backward jumps",
                self.ex.loc,
            )
        self.guard.back(construct, self.ex.loc, target)

    def structure(self, level: Level, block: Block, index: int) -> None:
        ex = self.ex
        kind = block.kind
        scope = level.scope
        program = level.program
        opened = level.structures
        if kind in ("IF", "WHILE", "FOR", "REPEAT", "LOOP"):
            end, other = program.structure(index, ex.loc)
            if kind == "IF":
                if evaluate(block.args[0], scope):
                    opened.append(Open("IF", index, end))
                elif other is not None:
                    opened.append(Open("IF", index, end))
                    level.index = other + 1
                else:
                    level.index = end + 1
            elif kind == "WHILE":
                if evaluate(block.args[0], scope):
                    opened.append(Open("WHILE", index, end))
                else:
                    level.index = end + 1
            elif kind == "FOR":
                target, first, last = block.args
                self._assign(scope, target, evaluate(first, scope))
                stop = evaluate(last, scope)
                if self._read(scope, target) > stop:
                    level.index = end + 1
                else:
                    opened.append(Open("FOR", index, end, (target, stop)))
            else:
                opened.append(Open(kind, index, end))
            return
        want = {
            "ELSE": "IF",
            "ENDIF": "IF",
            "ENDWHILE": "WHILE",
            "ENDFOR": "FOR",
            "UNTIL": "REPEAT",
            "ENDLOOP": "LOOP",
        }[kind]
        if not opened or opened[-1].kind != want or opened[-1].end < index:
            raise Diagnostic("SIEM-STRUCTURE", f"{kind} without {want}", ex.loc)
        top = opened[-1]
        if kind in ("ELSE", "ENDIF"):
            opened.pop()
            level.index = top.end + 1
        elif kind == "ENDWHILE":
            opened.pop()
            self._count(f"WHILE (line {top.start + 1})", top.start + 1)
            level.index = top.start
        elif kind == "ENDFOR":
            target, stop = top.data
            self._assign(scope, target, self._read(scope, target) + 1)
            if self._read(scope, target) <= stop:
                self._count(f"FOR (line {top.start + 1})", top.start + 1)
                level.index = top.start + 1
            else:
                opened.pop()
        elif kind == "UNTIL":
            if evaluate(block.args[0], scope):
                opened.pop()
            else:
                self._count(f"REPEAT (line {top.start + 1})", top.start + 1)
                level.index = top.start + 1
        else:  # ENDLOOP
            self._count(f"LOOP (line {top.start + 1})", top.start + 1)
            level.index = top.start + 1
            self._repeats_for_ever(level)
        program.caching = True

    def _assign(self, scope: Variables, target: tuple, value: float) -> None:
        kind, what = target
        if kind == "R":
            scope.r_set(evaluate(what, scope), value, self.ex.loc)
        else:
            scope.set(what, value, self.ex.loc)

    def _read(self, scope: Variables, target: tuple) -> float:
        kind, what = target
        if kind == "R":
            return scope.r_get(evaluate(what, scope), self.ex.loc)
        return scope.get(what, self.ex.loc)


def _near(program: Program, label: str, here: int, loc: Location, forward: bool) -> int:
    """The line of ``label`` for a section repetition: the nearest before ``here``, else
    (REPEATB) the nearest after it."""
    lines = program.targets().get(label, [])
    before = [i for i in lines if i < here]
    if before:
        return before[-1]
    after = [i for i in lines if i > here]
    if forward and after:
        return after[0]
    raise Diagnostic("SIEM-LABEL", f"section start {label} not found", loc)


def _proc_parameters(program: Program) -> tuple[tuple[bool, str, str], ...]:
    """The parameters of a subprogram's ``PROC`` (its first block), () without one."""
    index = 0
    while program.has_line(index):
        if program.line(index).split(";", 1)[0].strip():
            block = program.block(index)
            return block.args[1] if block.kind == "PROC" else ()
        index += 1
    return ()


def _target_of(node: tuple | None) -> tuple | None:
    """The variable or R parameter an argument names (for a VAR parameter), else None."""
    if node is None:
        return None
    if node[0] == "var":
        return ("V", node[1])
    if node[0] == "num_r":
        return ("R", ("num", float(node[1])))
    if node[0] == "r":
        return ("R", node[1])
    return None


def _first_code_line(program: Program, index: int) -> int:
    for i in range(index + 1):
        text = program.line(i).split(";", 1)[0].strip()
        if text:
            return i
    return index
