"""Reader of Mach3 programs: the RS274/NGC interpreter with Mach3's own codes.

Mach3's G-code language is RS274/NGC (its manual follows NIST's) with these differences,
each made here on the block before the RS274/NGC interpreter
(:class:`gcode.ngc.interpreter.Interpreter`) executes it:

* ``G70``/``G71`` are inch/millimetre units, as ``G20``/``G21``; ``G31`` is the straight
  probe, as ``G38.2``.
* ``G51 X~ Y~ Z~ A~ B~ C~`` sets per-axis scale factors (the words are the factors, not
  scaled themselves; an axis not named keeps its factor); ``G50`` sets every factor back
  to 1. The factors multiply the X Y Z A B C, I J (K) and R words of every later block
  as they are read, before anything else uses them; tool and fixture offsets are not
  scaled. An arc under factors that differ in its plane would be an ellipse, which Mach3
  does not allow (``MACH3-SCALE-ARC``); with equal factors R is scaled by that factor.
  One negative factor in the plane mirrors an arc, whose direction Mach3's manual does
  not define: refused too.
* An M code Mach3 does not define (all but M0-M9, M30, M47-M49, M98, M99) runs a user
  macro (``M<n>.m1s``): it is a ``MACHINE_FUNCTION`` event (with the block's P and Q when
  no G code of the block uses them), placed before the block's motion. ``M47`` (repeat
  the program from its first line, without end) is refused (``MACH3-M47``).
* A centre-format arc whose end radius differs from its start radius is run as
  programmed where LinuxCNC would refuse it, up to 5 % of the radius
  (:data:`ARC_RELATIVE`): Mach3 publishes no bound and does not refuse such arcs; a
  larger difference is a wrong program (``NGC-ARC-RADIUS``).
* A program may end without ``M2``/``M30`` or a closing ``%`` (Mach3 stops at the end of
  the file).

Everything else is RS274/NGC as LinuxCNC 2.9 reads it, and gives the same canonical
commands (docs/readers/mach3.md says what was checked against what).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import replace

from gcode.core.codes import Words
from gcode.core.expr import evaluate
from gcode.core.lexer import Block, Word
from gcode.core.machine_functions import machine_function
from gcode.core.program import ProgramFile
from gcode.mach3.dialect import OWN_M_CODES
from gcode.ngc.interpreter import Interpreter, InterpreterOptions
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

#: the largest end-radius difference (a fraction of the start radius) accepted in an arc
ARC_RELATIVE = 0.05
#: Mach3 codes given as the RS274/NGC code that does the same (code * 10)
SAME_AS = {700: 20.0, 710: 21.0, 310: 38.2}
#: the factor (axis index) each scaled letter takes
FACTOR = {"x": 0, "y": 1, "z": 2, "a": 3, "b": 4, "c": 5, "i": 0, "j": 1, "k": 2}
PLANES = {170: (0, 1), 180: (2, 0), 190: (1, 2)}
_PLANE_CODE = {canon.Plane.XY: 170, canon.Plane.XZ: 180, canon.Plane.YZ: 190}
_ARCS = frozenset({20, 30})
_UNSCALED = [1.0] * 6
_ENDS = (*canon.MOTIONS, canon.ProgramStop, canon.OptionalProgramStop, canon.ProgramEnd)
_LENIENT_END = frozenset({"NGC-NO-END", "NGC-NO-PERCENT"})
#: G codes (x10) that use a P or Q word themselves
_PQ_USERS = frozenset({20, 30, 40, 50, 52, 53, 100, 640, 730, 760, 820, 830, 860, 880, 890})


class Mach3Interpreter(Interpreter):
    """The RS274/NGC interpreter with Mach3's codes (module docstring)."""

    def __init__(self, options: InterpreterOptions) -> None:
        super().__init__(replace(options, arc_radius_relative=ARC_RELATIVE))
        self.scale = [1.0] * 6

    def lane_open(self) -> bool:
        """The fast lane takes plain lines only while no scale factor is set: a plain line
        then runs as RS274/NGC (no Mach3 code, no M code, and a centre-format arc the lane
        accepts by LinuxCNC's radius rule is accepted by Mach3's more lenient one too)."""
        return self.scale == _UNSCALED

    def execute_line(self, block: Block) -> bool:
        """Rewrite Mach3's codes of ``block`` and run it (module docstring)."""
        cached = block.cached_words
        if cached is not None and cached.plain:
            if self.scale != [1.0] * 6:
                values = {k: v * self.scale[FACTOR[k]] for k, v in cached.values.items()}
                block = replace(block, cached_words=Words(values=values, plain=True))
            return super().execute_line(block)
        if not block.words:
            return super().execute_line(block)
        block, functions = self._rewrite(block)
        start = len(self.out)
        ended = super().execute_line(block)
        if functions:
            at = next(
                (i for i in range(start, len(self.out)) if isinstance(self.out[i], _ENDS)),
                len(self.out),
            )
            self.out[at:at] = functions
        return ended

    # ------------------------------------------------------------------ one block
    def _where(self, block: Block, column: int) -> Location:
        return Location(self.flow.file.path, block.line, column)

    def _value(self, word: Word, block: Block) -> float:
        v = word.value
        return v if type(v) is float else evaluate(v, self.params, self._where(block, word.column))

    def _rewrite(self, block: Block) -> tuple[Block, list[canon.Command]]:
        """The block as RS274/NGC, and the machine functions its M codes make."""
        kept: list[Word] = []
        macros: list[tuple[int, int]] = []
        scale_set = scale_reset = False
        for w in block.words:
            if w.letter == "g":
                code = round(self._value(w, block) * 10)
                if code in SAME_AS:
                    kept.append(Word("g", SAME_AS[code], w.column))
                    continue
                if code in (500, 510):
                    scale_set, scale_reset = scale_set or code == 510, scale_reset or code == 500
                    continue
            elif w.letter == "m":
                value = self._value(w, block)
                code = round(value)
                if abs(value - code) < 1e-4 and code not in OWN_M_CODES:
                    macros.append((code, w.column))
                    continue
                if code == 47:
                    raise Diagnostic(
                        "MACH3-M47",
                        "M47 repeats the program from its first line without end",
                        self._where(block, w.column),
                    )
            kept.append(w)
        if scale_reset:
            self.scale = [1.0] * 6
        if scale_set:
            kept = self._set_scale(kept, block)
        elif self.scale != [1.0] * 6:
            kept = self._scaled(kept, block)
        takes_pq = bool(macros) and not self._uses_pq(kept, block)
        functions = self._functions(macros, kept, block, takes_pq)
        if takes_pq:
            kept = [w for w in kept if w.letter not in "pq"]
        return replace(block, words=kept, cached_words=None), functions

    def _uses_pq(self, words: list[Word], block: Block) -> bool:
        """A G code of the block takes the block's P and Q words."""
        return any(
            w.letter == "g" and round(self._value(w, block) * 10) in _PQ_USERS for w in words
        )

    def _functions(
        self, macros: list[tuple[int, int]], kept: list[Word], block: Block, takes_pq: bool
    ) -> list[canon.Command]:
        if not macros:
            return []
        values = {}
        if takes_pq:
            values = {w.letter: self._value(w, block) for w in kept if w.letter in "pq"}
        return [
            machine_function(
                code, values.get("p"), values.get("q"), self._where(block, col), "MACH3-M-CODE"
            )
            for code, col in macros
        ]

    def _set_scale(self, words: list[Word], block: Block) -> list[Word]:
        """G51: the axis words are the new factors."""
        kept = []
        for w in words:
            if w.letter in "xyzabc":
                factor = self._value(w, block)
                if factor == 0.0:
                    raise Diagnostic(
                        "MACH3-SCALE-ZERO", "G51 scale factor of 0", self._where(block, w.column)
                    )
                self.scale[FACTOR[w.letter]] = factor
            else:
                kept.append(w)
        return kept

    def _scaled(self, words: list[Word], block: Block) -> list[Word]:
        """The block's words with the scale factors applied."""
        plane = self._block_plane(words, block)
        arc = self._block_motion(words, block) in _ARCS
        f1, f2 = (self.scale[i] for i in PLANES[plane])
        if arc and f1 != f2:
            what = "differ" if abs(f1) != abs(f2) else "mirror the arc (one is negative)"
            raise Diagnostic(
                "MACH3-SCALE-ARC",
                f"scale factors {f1:g} and {f2:g} of the arc's plane {what}: Mach3 makes no "
                "elliptical or mirrored arc",
                self._where(block, words[0].column if words else block.col0),
            )
        out = []
        for w in words:
            if w.letter in FACTOR:
                factor = self.scale[FACTOR[w.letter]]
            elif w.letter == "r":
                factor = f1
            else:
                out.append(w)
                continue
            out.append(Word(w.letter, self._value(w, block) * factor, w.column))
        return out

    def _block_plane(self, words: list[Word], block: Block) -> int:
        for w in words:
            if w.letter == "g":
                code = round(self._value(w, block) * 10)
                if code in PLANES:
                    return code
        return _PLANE_CODE[self.s.plane]

    def _block_motion(self, words: list[Word], block: Block) -> int | None:
        for w in words:
            if w.letter == "g":
                code = round(self._value(w, block) * 10)
                if code in (0, 10, 20, 30, 800) or code >= 730 and code <= 890:
                    return code
        return self.s.motion_mode if any(w.letter in FACTOR for w in words) else None


def _run(pf: ProgramFile, options: InterpreterOptions | None) -> Iterator[canon.Command]:
    try:
        yield from Mach3Interpreter(options or InterpreterOptions()).run(pf)
    except Diagnostic as exc:
        if exc.code not in _LENIENT_END:
            raise


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the Mach3 program at ``path`` (streaming)."""
    return _run(ProgramFile(os.fspath(path)), options)


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the fast lane's runs of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays; ``arcs``: runs may hold arcs."""
    pf = ProgramFile(os.fspath(path))
    try:
        yield from Mach3Interpreter(options or InterpreterOptions()).chunks(pf, arcs)
    except Diagnostic as exc:
        if exc.code not in _LENIENT_END:
            raise


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a Mach3 program given as text."""
    return _run(ProgramFile(name, data=text.encode("utf-8")), options)
