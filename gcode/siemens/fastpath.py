"""The CAM hot path: a block of plain words (``N10 G1 X1.5 Y-2 F100``, ``G2 X.. CR=..``)
is read by two regular expressions straight into (address, value, column) triples,
skipping tokens and parse trees. Anything else (expressions, keywords, comments, ``EX``
numbers) returns None and goes through :mod:`gcode.siemens.blocks`, which also reports
the errors: the two paths read a plain block identically.
"""

from __future__ import annotations

import re

from gcode.siemens.lexer import MAX_NUMBER

_NUM = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)"
_LINE = re.compile(
    rf"[ \t]*(?:N\d+[ \t]+)?(?:(?:[ABCDFGIJKMSTXYZ]{_NUM}|(?:CR|AR|TURN)={_NUM})(?:[ \t]+|$))+",
    re.ASCII,
)
_ITEM = re.compile(rf"([A-Z]+)=?({_NUM})", re.ASCII)


def plain_words(line: str) -> list[tuple[str, float, int]] | None:
    """The words of a plain block, or None when the block needs the full parser."""
    if not _LINE.fullmatch(line):
        up = line.upper()
        if up == line or not _LINE.fullmatch(up):
            return None
        line = up
    out = []
    for m in _ITEM.finditer(line):
        value = float(m.group(2))
        if abs(value) > MAX_NUMBER:
            return None
        if m.group(1) != "N":
            out.append((m.group(1), value, m.start() + 1))
    return out
