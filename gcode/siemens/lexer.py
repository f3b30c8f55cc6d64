"""Siemens 840D block text -> tokens (SINUMERIK 840D sl programming manual, fundamentals,
"Block structure": words of an address letter and a value, ``ADDRESS=expression``,
keywords, ``;`` comments, ``"..."`` strings).

Code is case-insensitive and upper-cased here; strings keep their case. A letter directly
followed by a signed number (``X-10.5``, ``G1``, ``M30``) is one *word* token; any other
identifier (``CR``, ``R1``, ``CYCLE81``, ``IF``) is a *name* token.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from kernel.diagnostics import Diagnostic, Location

WORD, NAME, NUM, STR, OP = "word", "name", "num", "str", "op"
#: largest number a program may write: no part program needs more, and refusing larger
#: ones keeps the arithmetic finite (the 840D's REAL range is wider)
MAX_NUMBER = 1e15

_NUMBER = r"(?:\d+(?:\.\d*)?|\.\d+)(?:EX[+-]?\d+)?"
_TOKEN = re.compile(
    rf"""
    (?P<ws>[ \t]+)
  | (?P<word>[A-Z][+-]?{_NUMBER})(?![_0-9.$])(?!\s*=(?!=))
  | (?P<name>[A-Z_$][A-Z0-9_$]*)
  | (?P<num>{_NUMBER})
  | (?P<str>"[^"]*")
  | (?P<op>==|<>|<=|>=|<<|[-+*/()=<>,:\[\]])
    """,
    re.VERBOSE | re.ASCII,  # \d is 0-9 only: "１" is no digit of a program
)


@dataclass(frozen=True, slots=True)
class Token:
    kind: str
    text: str  # upper case (strings: as written, without quotes)
    col: int  # 1-based column
    value: float = 0.0  # numbers and words

    @property
    def letter(self) -> str:
        return self.text[0]


def number(text: str, loc: Location | None = None) -> float:
    """A number with Siemens' ``EX`` exponent (``1.5EX3`` = 1500); finite or SIEM-NUMBER."""
    mant, _, exp = text.partition("EX")
    try:
        value = float(mant) * 10.0 ** int(exp) if exp else float(mant)
    except OverflowError:
        value = math.inf
    if not math.isfinite(value) or abs(value) > MAX_NUMBER:
        raise Diagnostic("SIEM-NUMBER", f"number {text} out of range", loc)
    return value


def tokenize(line: str, file: str | None, lineno: int) -> tuple[list[Token], str | None]:
    """The tokens of one line and its ``;`` comment (None when it has none)."""
    comment = None
    code = line
    if ";" in line or '"' in line:
        code, comment = _split_comment(line)
    up = code.upper()
    if len(up) != len(code):  # "ß" -> "SS": keep columns, such letters are errors anyway
        up = "".join(c.upper() if len(c.upper()) == 1 else c for c in code)
    tokens: list[Token] = []
    pos, end = 0, len(up)
    match = _TOKEN.match
    while pos < end:
        m = match(up, pos)
        if m is None:
            raise Diagnostic(
                "SIEM-CHARACTER",
                f"unexpected character {code[pos]!r}",
                Location(file, lineno, pos + 1),
            )
        kind = m.lastgroup
        text = m.group()
        if kind == "word":
            value = number(text[1:], Location(file, lineno, pos + 1))
            tokens.append(Token(WORD, text, pos + 1, value))
        elif kind == "num":
            tokens.append(Token(NUM, text, pos + 1, number(text, Location(file, lineno, pos + 1))))
        elif kind == "str":
            tokens.append(Token(STR, code[pos + 1 : m.end() - 1], pos + 1))
        elif kind != "ws":
            tokens.append(Token(kind or "", text, pos + 1))  # every alternative is named
        pos = m.end()
    return tokens, comment


def _split_comment(line: str) -> tuple[str, str | None]:
    """Code and comment of a line: the first ``;`` outside a string starts the comment."""
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == ";" and not quoted:
            return line[:i], line[i + 1 :].strip()
    return line, None
