"""O-word control flow (LinuxCNC): sub/endsub/call/return, if/elseif/else/endif,
while/endwhile, do/while, repeat/endrepeat, break/continue; and M98/M99 programs.

The program is read as a stream (:mod:`gcode.core.program`): a false branch or a skipped loop
is passed over by reading forward to the matching O-word; a loop or a call jumps by byte
offset, as LinuxCNC does. Subroutines are found in the table of those already defined, then
as ``<name>.ngc`` on the search path, then by reading forward in the current file.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from typing import Protocol

from gcode.core.expr import evaluate
from gcode.core.lexer import Block, OWord
from gcode.core.loopguard import LoopGuard
from gcode.core.params import Parameters
from gcode.core.program import Position, ProgramFile, find_subroutine_file
from gcode.core.state import SavedModes
from kernel.diagnostics import Diagnostic, Location

MAX_CALL_DEPTH = 64
#: a line a forward search must see besides O-words: a closing ``%`` ends the search there
_PERCENT_LINE = re.compile(rb"^\s*%")


@dataclass(slots=True)
class _Control:
    kind: str  # if, while, do, repeat
    name: str
    head: Position  # while: the while line; do/repeat: the first body line
    count: int = 0
    taken: bool = False


@dataclass(slots=True)
class _Call:
    name: str
    file: ProgramFile
    back: Position
    controls: int
    saved_state: SavedModes | None = None
    autorestore: bool = False
    extra: dict[str, object] = field(default_factory=dict)


class FlowHost(Protocol):
    """What :class:`Flow` needs of the interpreter that owns it."""

    params: Parameters
    loc: Location

    def execute_line(self, block: Block) -> bool:
        """Execute one non-O-word line; True when the program ended."""
        ...

    def finish_percent(self) -> None:
        """The closing ``%`` was read."""
        ...

    def restore_modes(self, saved: SavedModes) -> None:
        """Restore the modes an M73 subroutine saved (at its return)."""
        ...


class Flow:
    """Where the interpreter reads next, and the O-word stacks."""

    def __init__(
        self, host: FlowHost, search_path: tuple[str, ...] = (), guard: LoopGuard | None = None
    ) -> None:
        self.host = host
        self.guard = guard if guard is not None else LoopGuard()
        self.search_path = search_path
        self.file: ProgramFile
        self.main: ProgramFile
        self.files: dict[str, ProgramFile] = {}
        self.subs: dict[str, tuple[ProgramFile, Position]] = {}
        self.ahead: set[str] = set()  # subroutines found by reading ahead of a call
        #: M98 programs (a bare "O<number>" line) found so far: number -> the line after it
        self.programs: dict[str, tuple[ProgramFile, Position]] = {}
        #: where each label first opened a control structure (file, name) -> line
        self.labels: dict[tuple[str, str], Position] = {}
        self.controls: list[_Control] = []
        self.calls: list[_Call] = []
        self.return_value = 0.0
        self.value_returned = False
        self.percent = False
        self.seen_line = False
        self.ended = False

    @property
    def call_level(self) -> int:
        return len(self.calls)

    def start(self, main: ProgramFile) -> None:
        self.main = self.file = main
        self.files[os.path.abspath(main.path)] = main

    def close(self) -> None:
        for f in self.files.values():
            f.close()

    # ------------------------------------------------------------------ reading
    def next_block(self, floor: int = 0) -> Block | None:
        """The next line to execute (O-word lines are handled here), None at the end, or
        once an O-word returns below call level ``floor`` (a lathe cycle reading its
        profile subroutine stops there)."""
        while True:
            f = self.file
            f.caching = bool(self.controls or self.calls)
            block = f.next_block()
            if block is None:
                return None
            self.guard.blocks += 1
            if block.percent:
                if not self.seen_line:
                    self.percent = True
                    self.seen_line = True
                    continue
                if not self.percent:
                    raise Diagnostic(
                        "NGC-BAD-CHARACTER",
                        "bad character '%' used (the program did not start with %)",
                        Location(f.path, block.line, block.text.index("%") + 1),
                    )
                self.ended = True
                self.host.finish_percent()
                return None
            if not self.seen_line and not block.empty:
                self.seen_line = True
            if block.oword is not None:
                if not block.oword.keyword:  # a bare program number "O123": ignored
                    self._check_bare(block, block.oword)
                    continue
                # rs274 2.9 runs no comment of an O-word line: (MSG,...) there prints nothing
                self.oword(block)
                if self.call_level < floor:
                    return None
                continue
            return block

    def end_of_file(self) -> None:
        if self.ended:
            return
        f = self.file
        loc = Location(f.path, max(f.last_nonblank, 1), 1)
        if self.calls:
            raise Diagnostic("NGC-OWORD-EOF", "file ended inside a subroutine", loc)
        if self.percent:
            raise Diagnostic("NGC-NO-PERCENT", "file ended with no percent sign", loc)
        raise Diagnostic(
            "NGC-NO-END", "file ended with no percent sign or program end (M2, M30)", loc
        )

    # ------------------------------------------------------------------ O-words
    def _loc(self, block: Block, ow: OWord) -> Location:
        return Location(self.file.path, block.line, ow.column)

    def _name(self, ow: OWord, loc: Location) -> str:
        if isinstance(ow.name, str):
            return ow.name
        v = evaluate(ow.name, self.host.params, loc)
        return str(int(round(v)))

    def _cond(self, ow: OWord, loc: Location) -> float:
        return evaluate(ow.args[0], self.host.params, loc)

    def oword(self, block: Block) -> None:
        ow = block.oword
        assert ow is not None
        loc = self._loc(block, ow)
        self.host.loc = loc
        name = self._name(ow, loc)
        kw = ow.keyword
        getattr(self, "_kw_" + kw)(block, ow, name, loc)

    def _label_error(self, block: Block, loc: Location) -> Diagnostic:
        return Diagnostic(
            "NGC-OWORD-UNEXPECTED",
            f"undefined O-word label: '{block.text.strip()}'",
            loc,
        )

    def _in_m98(self) -> bool:
        """Whether the innermost call is an M98 program (not an ``O... call``)."""
        return bool(self.calls) and "m98" in self.calls[-1].extra

    def _check_bare(self, block: Block, ow: OWord) -> None:
        """A bare ``O...`` line (an M98 program) is not a subroutine ``O... call`` enters."""
        if self.calls and not self._in_m98():
            raise Diagnostic(
                "NGC-OWORD-STYLE",
                "Fanuc-style 'O....' program must be called with M98, not 'O.... call'",
                Location(self.file.path, block.line, ow.column),
            )

    def _stop(self, b: Block, name: str, keywords: tuple[str, ...], loc: Location) -> None:
        """A ``%`` line met by a forward search: the closing one (any but the file's first
        line, which opens it) ends the search with an error there, as rs274 2.9 does."""
        if b.line > 1:
            raise Diagnostic(
                "NGC-OWORD-PERCENT",
                f"the closing % reached seeking O-word o<{name}> {'/'.join(keywords)} "
                f"(from line {loc.line})",
                Location(self.file.path, b.line, 1),
            )

    def _skip_to(
        self,
        name: str,
        keywords: tuple[str, ...],
        loc: Location,
        defining: bool = False,
        calling: bool = False,
    ) -> tuple[Block, OWord]:
        """Read forward to the next O-word ``name`` with one of ``keywords``.

        As LinuxCNC: a closing ``%`` ends the search; skipping a subroutine's definition
        (``defining``) another ``sub`` is an error; seeking a subroutine to call
        (``calling``) the bare ``O<name>`` of an M98 program is.
        """
        while True:
            b = self.file.next_oword_block(_PERCENT_LINE)
            if b is not None and b.oword is None:
                self._stop(b, name, keywords, loc)
                continue
            if b is None:  # rs274 reports this at the end of the file
                f = self.file
                raise Diagnostic(
                    "NGC-OWORD-EOF",
                    f"end of file seeking O-word o<{name}> {'/'.join(keywords)} "
                    f"(from line {loc.line})",
                    Location(f.path, max(f.last_nonblank, 1), 1),
                )
            ow = b.oword
            assert ow is not None
            if defining and ow.keyword == "sub":
                raise Diagnostic(
                    "NGC-OWORD-NESTED",
                    "nested subroutine definition",
                    Location(self.file.path, b.line, ow.column),
                )
            if calling and not ow.keyword and self._try_name(ow) == name:
                raise Diagnostic(
                    "NGC-OWORD-STYLE",
                    "Fanuc-style 'O....' program must be called with M98, not 'O.... call'",
                    Location(self.file.path, b.line, ow.column),
                )
            if ow.keyword in keywords:
                n = ow.name if isinstance(ow.name, str) else self._try_name(ow)
                if n == name:
                    return b, ow

    def _try_name(self, ow: OWord) -> str | None:
        if isinstance(ow.name, str):
            return ow.name
        try:
            return self._name(ow, Location(self.file.path, self.file.line, ow.column))
        except Diagnostic:
            return None

    # sub / endsub / return / call
    def _kw_sub(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        here = self.file.tell()
        if name in self.ahead and self.subs.get(name) == (self.file, here):
            raise Diagnostic(
                "NGC-OWORD-SUB-LOCATION", f"sub o<{name}> found in illegal location", loc
            )
        if self._in_m98():
            raise Diagnostic(
                "NGC-OWORD-STYLE", "'O.... sub' subroutine must be called with 'O.... call'", loc
            )
        self.subs[name] = (self.file, here)
        self._skip_to(name, ("endsub",), loc, defining=True)

    def _leave(self, block: Block, ow: OWord, loc: Location) -> None:
        if not self.calls:
            raise Diagnostic(
                "NGC-OWORD-NOT-IN-SUB",
                f"not in a subroutine definition: '{block.text.strip()}'",
                loc,
            )
        if self._in_m98():
            raise Diagnostic(
                "NGC-OWORD-STYLE", "Fanuc-style 'O....' program must end with M99", loc
            )
        # a return without a value clears #<_value> (LinuxCNC 2.9, interp_read.cc read_o)
        self.return_value = evaluate(ow.args[0], self.host.params, loc) if ow.args else 0.0
        self.value_returned = bool(ow.args)
        call = self.calls.pop()
        del self.controls[call.controls :]
        self.host.params.leave()
        if call.autorestore and call.saved_state is not None:
            self.host.restore_modes(call.saved_state)
        self.file = call.file
        self.file.seek(call.back)

    def _kw_endsub(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self._leave(block, ow, loc)

    def _kw_return(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self._leave(block, ow, loc)

    def _kw_call(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self.call(name, [evaluate(a, self.host.params, loc) for a in ow.args], loc)

    def call(self, name: str, args: list[float], loc: Location) -> None:
        """Enter subroutine ``name`` with ``args`` (``o<name> call``); its lines come next."""
        if len(self.calls) >= MAX_CALL_DEPTH:
            raise Diagnostic("NGC-OWORD-DEPTH", "too many nested subroutine calls", loc)
        back = self.file.tell()
        caller = self.file
        target = self.subs.get(name)
        if target is None:
            target = self._find(name, loc)
        self.calls.append(_Call(name, caller, back, len(self.controls)))
        self.return_value = 0.0  # a bare return leaves #<_value> 0 (rs274)
        self.value_returned = False
        self.host.params.enter(args)
        self.file = target[0]
        self.file.seek(target[1])

    def _find(self, name: str, loc: Location) -> tuple[ProgramFile, Position]:
        here = os.path.dirname(os.path.abspath(self.main.path))
        path = find_subroutine_file(name, list(self.search_path), here)
        if path is not None:
            key = os.path.abspath(path)
            pf = self.files.get(key)
            if pf is None:
                pf = self.files[key] = ProgramFile(path)
            pf.seek(Position(pf.path, 0, 0))
            saved, self.file = self.file, pf
            try:
                self._skip_to(name, ("sub",), loc, calling=True)
            finally:
                self.file = saved
            self.subs[name] = (pf, pf.tell())
            return self.subs[name]
        # a subroutine defined further down in this file
        start = self.file.tell()
        try:
            self._skip_to(name, ("sub",), loc, calling=True)
        except Diagnostic as exc:
            self.file.seek(start)
            if exc.code != "NGC-OWORD-EOF":
                raise
            raise Diagnostic(
                "NGC-OWORD-UNDEFINED", f"subroutine o<{name}> not defined", loc
            ) from None
        self.subs[name] = (self.file, self.file.tell())
        self.ahead.add(name)
        self.file.seek(start)
        return self.subs[name]

    # M98 / M99: programs "O<number>" ... "M99" (LinuxCNC 2.9 runs them stand-alone)
    def m98(self, number: float, repeats: float, loc: Location) -> None:
        """``M98 P<number> L<repeats>``: run program O<number> that many times (L0: none).

        As rs274 2.9: the program is the line ``O<number>`` found by reading forward in the
        current file (then remembered); it has its own named locals but shares #1-#30 with
        the caller; its ``M99`` returns to the line after the M98.
        """
        for value, word in ((number, "P"), (repeats, "L")):
            if abs(value - round(value)) > 1e-4:
                raise Diagnostic("NGC-M98-NOT-INTEGER", f"M98 {word} value is not an integer", loc)
        count = int(round(repeats))
        if count <= 0:
            return
        if len(self.calls) >= MAX_CALL_DEPTH:
            raise Diagnostic("NGC-OWORD-DEPTH", "too many nested subroutine calls", loc)
        name = str(int(round(number)))
        target = self.programs.get(name)
        if target is None:
            target = self._find_program(name, loc)
        call = _Call(name, self.file, self.file.tell(), len(self.controls))
        call.extra["m98"] = (target, count - 1)
        self.calls.append(call)
        self.host.params.enter_shared()
        self.file = target[0]
        self.file.seek(target[1])

    def m99(self, loc: Location) -> bool:
        """``M99``: the end of an M98 program (again from its start while repeats remain);
        False outside any call (the caller then ends the program, as rs274 2.9 does)."""
        if not self.calls:
            return False
        if not self._in_m98():
            raise Diagnostic(
                "NGC-OWORD-STYLE",
                "'O.... endsub' or 'O.... return' must end an 'O.... sub' subroutine, not M99",
                loc,
            )
        self.return_value, self.value_returned = 0.0, False  # as a return with no value
        call = self.calls[-1]
        repeat = call.extra.get("m98")
        del self.controls[call.controls :]
        if isinstance(repeat, tuple) and repeat[1] > 0:
            target, left = repeat
            call.extra["m98"] = (target, left - 1)
            self.file = target[0]
            self.file.seek(target[1])
            return True
        self.calls.pop()
        self.host.params.leave()
        if call.autorestore and call.saved_state is not None:
            self.host.restore_modes(call.saved_state)
        self.file = call.file
        self.file.seek(call.back)
        return True

    def _find_program(self, name: str, loc: Location) -> tuple[ProgramFile, Position]:
        """The line after ``O<name>`` (a bare program number), read forward from here."""
        start = self.file.tell()
        while True:
            b = self.file.next_oword_block(_PERCENT_LINE)
            if b is not None and b.oword is None:
                self._stop(b, f"O{name}", ("",), loc)
                continue
            if b is None:
                end = Location(self.file.path, max(self.file.last_nonblank, 1), 1)
                self.file.seek(start)
                raise Diagnostic(  # rs274 reports it at the end of the file
                    "NGC-OWORD-UNDEFINED",
                    f"end of file seeking program O{name} (M98 at line {loc.line} reads forward)",
                    end,
                )
            ow = b.oword
            assert ow is not None
            if ow.keyword == "sub" and self._try_name(ow) == name:
                raise Diagnostic(
                    "NGC-OWORD-STYLE",
                    "'O.... sub' subroutine must be called with 'O.... call', not M98",
                    Location(self.file.path, b.line, ow.column),
                )
            if not ow.keyword and not isinstance(ow.name, str) and self._try_name(ow) == name:
                break
        self.programs[name] = (self.file, self.file.tell())
        self.file.seek(start)
        return self.programs[name]

    # if / elseif / else / endif
    def _check_unique(self, block: Block, name: str, loc: Location) -> None:
        """A label opens control structures at one line only, and one at a time (LinuxCNC)."""
        here = self.file.current()
        key = (self.file.path, name)
        first = self.labels.setdefault(key, here)
        if first.offset != here.offset:
            raise Diagnostic(
                "NGC-OWORD-DUPLICATE",
                f"duplicate O-word label: '{block.text.strip()}' - defined in line "
                f"{first.line + 1}",
                loc,
            )
        other = self._top(("if", "while", "do", "repeat"), name)
        if other is not None:
            raise Diagnostic(
                "NGC-OWORD-DUPLICATE",
                f"duplicate O-word label - already defined in line {other.head.line + 1}: "
                f"'{block.text.strip()}'",
                loc,
            )

    def _kw_if(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self._check_unique(block, name, loc)
        ctl = _Control("if", name, self.file.current())
        self.controls.append(ctl)
        if self._cond(ow, loc):
            ctl.taken = True
            return
        self._next_branch(ctl, loc)

    def _next_branch(self, ctl: _Control, loc: Location) -> None:
        while True:
            b, ow = self._skip_to(ctl.name, ("elseif", "else", "endif"), loc)
            bloc = Location(self.file.path, b.line, ow.column)
            if ow.keyword == "endif":
                self.controls.pop()
                return
            if ow.keyword == "else" or self._cond(ow, bloc):
                ctl.taken = True
                return

    def _top(self, kinds: tuple[str, ...], name: str) -> _Control | None:
        base = self.calls[-1].controls if self.calls else 0
        for ctl in reversed(self.controls[base:]):
            if ctl.name == name and ctl.kind in kinds:
                return ctl
        return None

    def _kw_elseif(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("if",), name)
        if ctl is None:
            raise self._label_error(block, loc)
        if ow.args:  # rs274 still evaluates the condition (errors count)
            self._cond(ow, loc)
        self._skip_to(name, ("endif",), loc)
        self._pop(ctl)

    _kw_else = _kw_elseif

    def _kw_endif(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("if",), name)
        if ctl is None:
            raise self._label_error(block, loc)
        self._pop(ctl)

    def _pop(self, ctl: _Control) -> None:
        i = len(self.controls) - 1
        while i >= 0 and self.controls[i] is not ctl:
            i -= 1
        del self.controls[i:]

    # loops
    def _kw_while(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("do", "while"), name)
        if ctl is not None and ctl.kind == "do":
            if self._cond(ow, loc):
                self._back(ctl, loc)
                self.file.seek(ctl.head)
            else:
                self._pop(ctl)
            return
        here = self.file.current()
        if ctl is None or ctl.head.offset != here.offset:
            self._check_unique(block, name, loc)
            ctl = _Control("while", name, here)
            self.controls.append(ctl)
        if not self._cond(ow, loc):
            self._skip_to(name, ("endwhile",), loc)
            self._pop(ctl)

    def _kw_endwhile(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("while",), name)
        if ctl is None:
            raise self._label_error(block, loc)
        self._back(ctl, loc)
        self.file.seek(ctl.head)

    def _back(self, ctl: _Control, loc: Location) -> None:
        """A loop going back to its head: the shared loop guard's check."""
        line = ctl.head.line + 1 if ctl.kind == "while" else ctl.head.line
        self.guard.back(f"o{ctl.name} {ctl.kind} (line {line})", loc, line)

    def _kw_do(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self._check_unique(block, name, loc)
        self.controls.append(_Control("do", name, self.file.tell()))

    def _kw_repeat(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        self._check_unique(block, name, loc)
        n = int(round(self._cond(ow, loc)))
        ctl = _Control("repeat", name, self.file.tell(), count=n)
        self.controls.append(ctl)
        if n <= 0:
            self._skip_to(name, ("endrepeat",), loc)
            self._pop(ctl)

    def _kw_endrepeat(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("repeat",), name)
        if ctl is None:
            raise self._label_error(block, loc)
        ctl.count -= 1
        if ctl.count > 0:
            self._back(ctl, loc)
            self.file.seek(ctl.head)
        else:
            self._pop(ctl)

    def _kw_break(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("while", "do", "repeat"), name)
        if ctl is None:
            raise self._label_error(block, loc)
        end = {"while": ("endwhile",), "do": ("while",), "repeat": ("endrepeat",)}[ctl.kind]
        self._skip_to(name, end, loc)
        self._pop(ctl)

    def _kw_continue(self, block: Block, ow: OWord, name: str, loc: Location) -> None:
        ctl = self._top(("while", "do", "repeat"), name)
        if ctl is None:
            raise self._label_error(block, loc)
        del self.controls[self.controls.index(ctl) + 1 :]  # leave the inner ifs
        if ctl.kind == "while":
            self._back(ctl, loc)
            self.file.seek(ctl.head)
        elif ctl.kind == "repeat":
            self._kw_endrepeat(block, ow, name, loc)
        else:
            b, w = self._skip_to(name, ("while",), loc)
            self._kw_while(b, w, name, Location(self.file.path, b.line, w.column))
