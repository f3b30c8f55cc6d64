"""Lengths and angles written without a decimal point in a Fanuc or Haas program (CNC050).

With the Fanuc default (parameter No. 3401#0 DPI = 0; Haas the same) a number without a
decimal point counts least input increments: ``X100`` is 0.1 mm in G21 (IS-B, 0.001 mm)
and 0.0100 in in G20 (0.0001 in), ``B90`` 0.09 degree, ``G04 X5`` 0.005 s. The reader
(gcode/fanuc/words.py) reads them so; this pass points at each one in the text, because a
programmer who wrote ``X100`` almost always meant 100 mm.

Only the addresses the increment rule scales are judged (docs/readers/fanuc.md,
"Numbers"): X Y Z U V W I J K R Q, A B C and the corner words ,C ,R. Words that are
integers by their meaning never are: G M N O P (dwell ms, program and sequence numbers) T
D H L S F E, and per code ``G51`` P I J K (magnification), a milling cycle's K (repeat
count), the lathe cycles' P and Q (``G70``-``G73`` sequence numbers; ``G74``-``G76`` P and
Q are written without a point by definition), ``G73`` R (number of divisions) and
``G06.2`` K R P (knots, weights, order). Zero is the same either way, and values from
``#`` variables and ``[...]`` expressions carry their own value.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from gcode.fanuc.lexer import parse_line
from gcode.fanuc.words import ANGLES, CYCLES
from kernel.diagnostics import Diagnostic

#: addresses whose point-less value counts increments (E, the thread lead, is left out:
#: it is written with a point by every post and G187 E is a tolerance)
JUDGED = frozenset("XYZUVWIJKRQ") | ANGLES | {",C", ",R"}  # and the corner lengths
#: lathe cycles (round(G*10)): G70-G76
LATHE_CYCLES = frozenset({700, 710, 720, 730, 740, 750, 760})


@dataclass(frozen=True, slots=True)
class BareNumber:
    """One word without a decimal point: where, as written, and what the control reads."""

    line: int
    column: int
    word: str  # as written, e.g. "X100"
    value: float  # what the control reads, in ``unit``
    unit: str  # mm, in, deg or s

    def message(self, more: int = 0) -> str:
        """The finding's text (``more``: further such words in the program)."""
        integer = self.word.lstrip(",")[1:]
        read = f"{self.value:.4f}".rstrip("0").rstrip(".")
        text = (
            f"{self.word} has no decimal point: the control reads {read} {self.unit} "
            f"(least input increments, parameter No. 3401#0 = 0); write {self.word}. "
            f"for {integer} {self.unit}"
        )
        if more:
            text += f" (and {more} more word{'s' * (more > 1)} without a decimal point)"
        return text


def bare_numbers(lines: Iterable[str], lathe: bool = False) -> Iterator[BareNumber]:
    """Each judged word without a decimal point in a program's lines (mill or ``lathe``).

    A line the lexer refuses is skipped: the reader reports it with its own code.
    """
    inch = False
    cycle = False  # a milling canned cycle is modal until G80 or a G0-G3
    for n, raw in enumerate(lines, 1):
        try:
            blk = parse_line(raw, n)
        except Diagnostic:
            continue
        if blk.kind != "words" or not blk.words:
            continue
        gset = {round(v * 10) for k, v, _ in blk.words if k == "G" and isinstance(v, int | float)}
        if 200 in gset:
            inch = True
        elif 210 in gset:
            inch = False
        if gset & {0, 10, 20, 30, 800}:
            cycle = False
        if gset & CYCLES and not lathe:
            cycle = True
        skip: set[str] = set()
        if 510 in gset:
            skip |= set("PIJK")
        if cycle and not lathe:
            skip.add("K")
        if lathe and gset & LATHE_CYCLES:
            skip |= {"P", "Q"}
            if 730 in gset:
                skip.add("R")
        if 62 in gset:  # G06.2 NURBS
            skip |= set("KRP")
        for letter, value, index in blk.words:
            if type(value) is not int or value == 0 or letter not in JUDGED or letter in skip:
                continue
            yield _bare(blk.line, blk.column(index), letter, value, inch, gset)


def _bare(
    line: int, column: int, letter: str, value: int, inch: bool, gset: set[int]
) -> BareNumber:
    word = f"{letter}{value}"
    if 40 in gset and letter in "XU":  # G04 dwell: 0.001 s
        return BareNumber(line, column, word, value * 0.001, "s")
    if letter in ANGLES or (680 in gset and letter == "R"):  # G68 R: 0.001 degree
        return BareNumber(line, column, word, value * 0.001, "deg")
    if inch:
        return BareNumber(line, column, word, value * 0.0001, "in")
    return BareNumber(line, column, word, value * 0.001, "mm")
