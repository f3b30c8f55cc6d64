"""Readers of RS274/NGC subsets (Grbl 1.1, NIST RS274/NGC v3): a vocabulary check per block.

The RS274/NGC interpreter (:mod:`gcode.ngc.interpreter`) gives the semantics; a
:class:`Vocabulary` refuses, with a located error, every word the subset lacks. The check
runs on each block as the interpreter reads it (the lexer's tokens of that line,
:mod:`gcode.core.lexer`), so reading streams line by line and a refused construct stops the
program at its line, after the commands of the lines before it. Neither subset has O-word
flow (both refuse O-words), so the interpreter reads the file front to back: every line
is checked once, in order. Large files go through the compiled fast lane
(:mod:`gcode.ngc.lane.lane`), which skips plain CAM lines (axis words, F, G0/G1, N) past the block
reader; those lines are checked from their bytes when the lane skips them
(:meth:`Vocabulary.check_plain`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import TYPE_CHECKING

from gcode.core.lexer import Block, Word
from gcode.core.program import ProgramFile
from gcode.ngc.interpreter import Interpreter, InterpreterOptions
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

if TYPE_CHECKING:
    from gcode.ngc.lane.fastlane import Run


class Vocabulary:
    """What a subset accepts; the base class accepts everything (override the hooks)."""

    #: code prefix of the subset's diagnostics, e.g. "GRBL"
    prefix = "SUBSET"
    title = "the subset"
    #: end-of-file errors of RS274/NGC the subset does not make (Grbl: no M2 or % needed)
    lenient_end: frozenset[str] = frozenset()

    def raw_line(self, data: bytes, file: str, line: int) -> bytes:
        """The line as the interpreter should read it (a line may be blanked or refused)."""
        return data

    def check(self, block: Block, file: str) -> None:
        """Raise ``<PREFIX>-UNSUPPORTED`` for a word of ``block`` the subset lacks."""

    def check_plain(self, data: bytes, file: str, first_line: int) -> None:
        """Check plain CAM lines (``data``, starting at ``first_line``) the lane skipped."""

    def options(self, options: InterpreterOptions) -> InterpreterOptions:
        """The interpreter's options for the subset (where its rules differ from rs274's)."""
        return options

    def refuse(self, what: str, file: str, line: int, column: int, code: str = "") -> Diagnostic:
        return Diagnostic(
            code or f"{self.prefix}-UNSUPPORTED",
            f"{self.title} has no {what}",
            Location(file, line, column),
        )


class CheckedProgramFile(ProgramFile):
    """A program file whose every line passes the vocabulary before the interpreter."""

    def __init__(self, path: str, vocabulary: Vocabulary, data: bytes | None = None) -> None:
        super().__init__(path, data)
        self.vocabulary = vocabulary

    def next_raw(self) -> tuple[int, bytes] | None:
        raw = super().next_raw()
        if raw is None:
            return None
        offset, data = raw
        return offset, self.vocabulary.raw_line(data, self.path, self.line)

    def next_block(self) -> Block | None:
        block = super().next_block()
        if block is not None and not block.percent:
            self.vocabulary.check(block, self.path)
        return block

    def seek_to(self, offset: int, line: int) -> None:
        """The fast lane took the lines up to ``offset``: check them from their bytes."""
        if offset > self._offset:
            self._fh.seek(self._offset)
            data = self._fh.read(offset - self._offset)
            self.vocabulary.check_plain(data, self.path, self.line + 1)
        super().seek_to(offset, line)


def interpret_checked(
    pf: CheckedProgramFile, options: InterpreterOptions | None
) -> Iterator[canon.Command]:
    """The interpreter's commands for ``pf``; the subset's lenient end-of-file errors end it."""
    lenient = pf.vocabulary.lenient_end
    try:
        yield from Interpreter(pf.vocabulary.options(options or InterpreterOptions())).run(pf)
    except Diagnostic as exc:
        if exc.code not in lenient:
            raise


def chunks_checked(
    pf: CheckedProgramFile, options: InterpreterOptions | None, arcs: bool
) -> Iterator[canon.Command | Run]:
    """Like :func:`interpret_checked`, with the fast lane's runs of a large file as
    :class:`gcode.ngc.lane.fastlane.Run` arrays (``Interpreter.chunks``)."""
    lenient = pf.vocabulary.lenient_end
    try:
        opts = pf.vocabulary.options(options or InterpreterOptions())
        yield from Interpreter(opts).chunks(pf, arcs)
    except Diagnostic as exc:
        if exc.code not in lenient:
            raise


def read_path(
    path: str | os.PathLike[str], vocabulary: Vocabulary, options: InterpreterOptions | None
) -> Iterator[canon.Command]:
    return interpret_checked(CheckedProgramFile(os.fspath(path), vocabulary), options)


def read_chunks(
    path: str | os.PathLike[str],
    vocabulary: Vocabulary,
    options: InterpreterOptions | None,
    arcs: bool,
) -> Iterator[canon.Command | Run]:
    return chunks_checked(CheckedProgramFile(os.fspath(path), vocabulary), options, arcs)


def read_text(
    text: str, name: str, vocabulary: Vocabulary, options: InterpreterOptions | None
) -> Iterator[canon.Command]:
    pf = CheckedProgramFile(name, vocabulary, data=text.encode("utf-8"))
    return interpret_checked(pf, options)


def code_of(word: Word) -> int | None:
    """A G or M word's code as ``round(value * 10)`` (G38.2 -> 382); None for an expression."""
    v = word.value
    return round(v * 10) if type(v) is float else None


def expression_nodes(value: object) -> Iterator[tuple]:
    """Every node of an unevaluated value (:mod:`gcode.core.lexer` expression tuples)."""
    if isinstance(value, tuple):
        yield value
        for part in value[1:]:
            yield from expression_nodes(part)


def constant_word(block: Block, letter: str) -> float | None:
    """The constant value of ``letter`` in the block (None when absent or an expression)."""
    for w in block.words:
        if w.letter == letter and type(w.value) is float:
            return w.value
    return None
