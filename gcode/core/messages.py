"""Comments that are more than comments: ``(MSG, ...)`` and ``(DEBUG, ...)`` (LinuxCNC).

Only the last comment of a line is kept (LinuxCNC's block holds one comment). ``MSG``
becomes ``MESSAGE`` with the text after the comma; ``DEBUG`` too, with ``#n`` and
``#<name>`` replaced by their values (``%f``, ``%d``/``%f``/``%.Nf`` formats, a value within
1e-4 of zero as zero, or ``######`` when undefined), while parameter 5599 is positive
(LinuxCNC's DEBUG flag, ``DEBUG_LEVEL_FLAG``; the RS274/NGC interpreter starts it at 1);
``ABORT`` stops the program with its text as the error; ``PRINT`` and
``LOG*`` go to the operator's terminal or a log file and give no canonical command; any
other comment is a ``COMMENT``.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from gcode.core.params import Parameters
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

DEBUG_FLAG = 5599  # (DEBUG,) comments print only while this parameter is positive
ZERO = 1e-4  # a value closer to 0 prints as 0 (rs274 compares with its TOLERANCE_EQUAL)
_SILENT = ("print,", "logopen,", "logappend,", "logclose", "log,", "probeopen", "probeclose")
_NUMBER = re.compile(r"\d+")
_FORMAT = re.compile(r"%(d|f|\.\d(?=f))")  # %d, %f, %.Nf (N one digit)


def _value(params: Parameters, name: str | None, number: int | None, loc: Location) -> float | None:
    """A parameter's value, or None when it is undefined (or its number out of range)."""
    try:
        if name is not None:
            return params.named(name, loc)
        return params.numbered(float(number or 0), loc)
    except Diagnostic:
        return None


def _substitute(text: str, params: Parameters, loc: Location) -> str:
    """``text`` with each ``#n`` and ``#<name>`` replaced by its value, as LinuxCNC 2.9 does.

    A value is printed with six decimals until a format ``%d`` (none), ``%f`` (four) or
    ``%.Nf`` (N, one digit) changes it for the rest of the text; an undefined parameter
    prints ``######``. Of a ``%.`` starting no format only the ``.`` is kept (as rs274);
    another ``%`` is kept, and so is a ``#`` starting no parameter or an unclosed ``#<``.
    """
    out: list[str] = []
    decimals = 6
    i, n = 0, len(text)
    while i < n:
        ch = text[i]
        if ch == "%":
            m = _FORMAT.match(text, i)
            if m is not None:
                code = m.group(1)
                decimals = 0 if code == "d" else 4 if code == "f" else int(code[1])
                i = m.end() + (1 if code.startswith(".") else 0)
            elif text.startswith("%.", i):
                out.append(".")
                i += 2
            else:
                out.append("%")
                i += 1
            continue
        number = _NUMBER.match(text, i + 1) if ch == "#" else None
        close = text.find(">", i) if text.startswith("#<", i) else -1
        if number is not None:
            value = _value(params, None, int(number.group()), loc)
            i = number.end()
        elif close > 0:
            value = _value(params, "".join(text[i + 2 : close].split()).lower(), None, loc)
            i = close + 1
        else:
            out.append(ch)
            i += 1
            continue
        if value is None:
            out.append("######")
        else:
            out.append(f"{0.0 if abs(value) < ZERO else value:.{decimals}f}")
    return "".join(out)


def comment_commands(
    text: str,
    params: Parameters,
    loc: Location,
    print_sink: Callable[[str], None] | None = None,
) -> list[canon.Command]:
    """The canonical commands for one (the last) comment of a line; a ``PRINT`` text goes to
    ``print_sink`` (when given) with its parameters replaced, as rs274 prints it."""
    head = text.lstrip().lower()
    if print_sink is not None and head.startswith("print,"):
        print_sink(_substitute(text.lstrip()[6:], params, loc))
        return []
    if head.startswith("msg,"):
        return [canon.Message(text.lstrip()[4:], source=loc)]
    if head.startswith("debug,"):
        if params.values[DEBUG_FLAG] <= 0.0:
            return []
        return [canon.Message(_substitute(text.lstrip()[6:], params, loc), source=loc)]
    if head.startswith("abort,"):
        message = _substitute(text.lstrip()[6:], params, loc)
        raise Diagnostic("NGC-ABORT", f"program aborted: {message.strip()}", loc)
    if head.startswith(_SILENT):
        return []
    return [canon.Comment(text, source=loc)]
