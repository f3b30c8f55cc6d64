"""Reader of NIST RS274/NGC interpreter v3 programs: RS274/NGC without LinuxCNC's extensions.

The v3 language (NISTIR 6556 §3; research/seed-canon-rs274.md §4-5) is what the
RS274/NGC interpreter reads, minus what LinuxCNC added. Accepted G codes: G0-G4, G10 L2,
G17-G19, G20, G21, G28, G30, G38.2, G40-G43, G49, G53-G59.3, G61, G61.1, G64 (without P/Q),
G80-G89, G90-G92.3, G93, G94, G98, G99; M codes M0-M9, M30, M48, M49, M60; words
A B C D F H I J K L N P Q R S T X Y Z; numbered parameters #1-#5399 with expressions of
the v3 operators (``**``, ``*``, ``/``, ``MOD``, ``+``, ``-``, ``AND``, ``XOR``, ``OR``)
and functions. Refused with ``NIST-UNSUPPORTED`` at the word: O-words, named parameters
``#<...>``, ``EXISTS``, the comparison operators ``EQ``..``LE``, parameters above 5399,
G5.x, G7/G8, G33/G33.1, G38.3-G38.5, G41.1/G42.1, G43.1/G43.2, G52, G64 P/Q, G73, G76,
G90.1/G91.1, G95-G97, G10 L1/L10/L11/L20, M19, M50-M53, M61-M68, M70-M73, M100-M199.
A program ends with M2/M30 or ``%`` as in RS274/NGC.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from gcode.core.lexer import Block
from gcode.core.subset_reader import (
    Vocabulary,
    code_of,
    constant_word,
    expression_nodes,
    read_chunks,
    read_path,
    read_text,
)
from gcode.ngc.interpreter import InterpreterOptions
from kernel.ir import canon

G_CODES = frozenset(
    {0, 10, 20, 30, 40, 100, 170, 180, 190, 200, 210, 280, 300, 382, 400, 410, 420, 430, 490}
    | {530, 540, 550, 560, 570, 580, 590, 591, 592, 593, 610, 611, 640}
    | {800, 810, 820, 830, 840, 850, 860, 870, 880, 890}
    | {900, 910, 920, 921, 922, 923, 930, 940, 980, 990}
)
M_CODES = frozenset({0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 300, 480, 490, 600})
LETTERS = frozenset("abcdfghijklmnpqrstxyz")
OPERATORS = frozenset({"**", "*", "/", "mod", "+", "-", "and", "xor", "or"})
MAX_PARAMETER = 5399


class NistV3(Vocabulary):
    prefix = "NIST"
    title = "NIST RS274/NGC v3"

    def check(self, block: Block, file: str) -> None:
        line = block.line
        if block.oword is not None:
            raise self.refuse("O-words (subroutines and flow control)", file, line, block.col0)
        for _, col in block.comments:
            if block.text[col - 1 : col] == ";":
                raise self.refuse("';' comments (parentheses only)", file, line, col)
        for target, value, col in block.assignments:
            self.check_value(target, file, line, col)
            self.check_value(value, file, line, col)
        for w in block.words:
            if w.letter not in LETTERS:
                raise self.refuse(f"{w.letter.upper()} word", file, line, w.column)
            self.check_value(w.value, file, line, w.column)
            if w.letter not in "gm":
                continue
            code = code_of(w)
            if code is None:
                what = f"{w.letter.upper()} code given by an expression"
                raise self.refuse(what, file, line, w.column)
            if w.letter == "g":
                self.check_g(block, code, w.column, file)
            elif code not in M_CODES:
                raise self.refuse(f"M{w.value:g}", file, line, w.column)

    def check_g(self, block: Block, code: int, column: int, file: str) -> None:
        line = block.line
        if code not in G_CODES:
            raise self.refuse(f"G{code / 10:g}", file, line, column)
        if code == 100 and constant_word(block, "l") != 2.0:
            raise self.refuse("G10 other than G10 L2", file, line, column)
        if code == 640:
            for w in block.words:
                if w.letter in "pq":
                    raise self.refuse(f"G64 {w.letter.upper()} (tolerances)", file, line, w.column)

    def check_value(self, value: object, file: str, line: int, col: int) -> None:
        """Refuse named parameters, EXISTS, comparisons and parameters above #5399."""
        for node in expression_nodes(value):
            kind = node[0]
            if kind == "<":
                raise self.refuse(f"named parameters (#<{node[1]}>)", file, line, col)
            if kind in ("exists", "exists#"):
                raise self.refuse("EXISTS", file, line, col)
            if kind == "b" and node[1] not in OPERATORS:
                raise self.refuse(f"operator {node[1].upper()}", file, line, col)
            if kind == "#" and type(node[1]) is float and not 1 <= node[1] <= MAX_PARAMETER:
                raise self.refuse(f"parameter #{node[1]:g} (v3 has #1-#5399)", file, line, col)


NIST_V3 = NistV3()


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the NIST v3 program at ``path`` (streaming)."""
    return read_path(path, NIST_V3, options)


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the fast lane's runs of a large program as
    :class:`gcode.ngc.lane.fastlane.Run` arrays; ``arcs``: runs may hold arcs."""
    return read_chunks(path, NIST_V3, options, arcs)


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a NIST v3 program given as text."""
    return read_text(text, name, NIST_V3, options)
