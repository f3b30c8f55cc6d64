"""G and M codes of RS274/NGC (LinuxCNC dialect): modal groups and block-level checks.

Codes are kept as integers ``round(value * 10)`` so ``G38.2`` is 382 and ``G1`` is 10,
avoiding float comparisons. The modal groups follow the NIST RS274/NGC v3 report (table 4)
as extended by LinuxCNC; two codes of one group on a line is an error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from kernel.diagnostics import Diagnostic, Location

G_GROUPS: dict[int, int] = {}
for _group, _codes in {
    0: (40, 100, 280, 281, 300, 301, 520, 530, 920, 921, 922, 923),
    1: (
        0,
        10,
        20,
        30,
        50,
        51,
        52,
        53,
        330,
        331,
        382,
        383,
        384,
        385,
        700,  # the lathe cycles G70-G72.2 (gcode.ngc.lathe_cycles)
        710,
        711,
        712,
        720,
        721,
        722,
        730,
        740,
        760,
        800,
        810,
        820,
        830,
        840,
        850,
        860,
        870,
        880,
        890,
    ),
    2: (170, 180, 190, 171, 181, 191),
    3: (900, 910),
    4: (901, 911),
    5: (930, 940, 950),
    6: (200, 210),
    7: (400, 410, 420, 411, 421),
    8: (430, 431, 432, 490),
    10: (980, 990),
    12: (540, 550, 560, 570, 580, 590, 591, 592, 593),
    13: (610, 611, 640),
    14: (960, 970),
    15: (70, 80),
}.items():
    for _c in _codes:
        G_GROUPS[_c] = _group

M_GROUPS: dict[int, int] = {}
for _group, _codes in {
    4: (0, 1, 2, 30, 60, 98, 99),
    6: (6, 61),
    7: (3, 4, 5, 19),
    8: (7, 8, 9),
    9: (48, 49, 50, 51, 52, 53),
    5: (62, 63, 64, 65, 66, 67, 68),
    10: (70, 71, 72, 73),
}.items():
    for _c in _codes:
        M_GROUPS[_c] = _group

#: G codes of group 0 that use axis words (so a motion on the same line cannot).
AXIS_USING_NONMODAL = frozenset({100, 280, 300, 520, 920})
CANNED_CYCLES = frozenset({730, 740, 760, 810, 820, 830, 840, 850, 860, 870, 880, 890})
AXIS_LETTERS = "xyzabcuvw"
#: letters other than G and M that may appear at most once per block
VALUE_LETTERS = "abcdefhijklpqrstuvwxyz"


@dataclass(slots=True)
class Words:
    """The evaluated words of one block, grouped for execution."""

    g: dict[int, int] = field(default_factory=dict)  # group -> code*10
    m: dict[int, int] = field(default_factory=dict)  # group -> code
    values: dict[str, float] = field(default_factory=dict)
    columns: dict[str, int] = field(default_factory=dict)
    #: only axis words X Y Z A B C and no G or M code (the CAM hot path)
    plain: bool = False

    def has_axis(self) -> bool:
        v = self.values
        return any(a in v for a in AXIS_LETTERS) or "@" in v or "^" in v


_WRITTEN = re.compile(r"[A-Za-z][ \t]*[-+]?(?:\d+\.?\d*|\.\d+)")


def as_written(letter: str, value: float, text: str | None, column: int) -> str:
    """The word at ``column`` of the line ``text`` as the user wrote it (``g07.50``), or
    ``G7.5`` made of its value when the text there is not that word (an expression)."""
    if text is not None and column > 0:
        m = _WRITTEN.match(text, column - 1)
        if m is not None and m.group(0)[0].lower() == letter:
            return m.group(0)
    return f"{letter.upper()}{value:g}"


def g_code(value: float, loc: Location, text: str | None = None) -> int:
    """The G code of a G word's value (times ten); ``text``, the word's line, lets an unknown
    code be quoted as written."""
    code = round(value * 10)
    if abs(value * 10 - code) > 1e-3 or code not in G_GROUPS:
        word = as_written("g", value, text, loc.column)
        raise Diagnostic("NGC-UNKNOWN-G", f"unknown G code used: {word}", loc)
    return code


def m_code(value: float, loc: Location, text: str | None = None) -> int:
    """The M code of an M word's value; ``text`` as for :func:`g_code`."""
    code = round(value)
    if abs(value - code) <= 1e-4 and (code in M_GROUPS or 100 <= code <= 199):
        return code
    word = as_written("m", value, text, loc.column)
    raise Diagnostic("NGC-UNKNOWN-M", f"unknown M code used: {word}", loc)


def add_g(words: Words, code: int, loc: Location) -> None:
    group = G_GROUPS[code]
    if group == 1 and group in words.g and 800 in (code, words.g[1]):
        # LinuxCNC accepts G80 beside another motion code and runs the motion
        if code != 800:
            words.g[1] = code
        return
    if group in words.g:
        raise Diagnostic("NGC-G-GROUP-CONFLICT", "two G codes used from same modal group", loc)
    words.g[group] = code


def add_m(words: Words, code: int, loc: Location) -> None:
    group = M_GROUPS.get(code, 10 if code >= 100 else -1)
    if group in words.m:
        raise Diagnostic("NGC-M-GROUP-CONFLICT", "two M codes used from same modal group", loc)
    if len(words.m) >= 4:
        raise Diagnostic("NGC-TOO-MANY-M", "too many M codes on line", loc)
    words.m[group] = code


def add_value(words: Words, letter: str, value: float, loc: Location) -> None:
    if letter in words.values:
        raise Diagnostic("NGC-DUPLICATE-WORD", f"multiple {letter.upper()} words on one line", loc)
    words.values[letter] = value
    words.columns[letter] = loc.column
