"""Comments that are more than comments: ``(MSG, ...)`` and ``(DEBUG, ...)`` (LinuxCNC).

Only the last comment of a line is kept (LinuxCNC's block holds one comment). ``MSG``
becomes ``MESSAGE`` with the text after the comma; ``DEBUG`` too, with ``#n`` and
``#<name>`` replaced by their values (``%f``, a value within 1e-6 of zero as ``0.000000`` as
LinuxCNC's ``convert_param_comment`` prints it, or ``######`` when undefined), while parameter
5599 is positive (LinuxCNC's DEBUG flag, ``DEBUG_LEVEL_FLAG``; the RS274/NGC interpreter
starts it at 1); ``PRINT`` and
``LOG*`` go to the operator's terminal or a log file and give no canonical command; any
other comment is a ``COMMENT``.
"""

from __future__ import annotations

import re

from gcode.core.params import Parameters
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

_PARAM_RE = re.compile(r"#(?:<([^>]*)>|(\d+))")
DEBUG_FLAG = 5599  # (DEBUG,) comments print only while this parameter is positive
_SILENT = ("print,", "logopen,", "logappend,", "logclose", "log,", "probeopen", "probeclose")


#: LinuxCNC's ``TOLERANCE_EQUAL``: a value this close to zero is printed as zero (no ``-0``)
_ZERO = 1e-6


def _shown(value: float) -> str:
    return f"{0.0 if abs(value) < _ZERO else value:f}"


def _substitute(text: str, params: Parameters, loc: Location) -> str:
    def repl(m: re.Match[str]) -> str:
        try:
            if m.group(1) is not None:
                name = "".join(m.group(1).split()).lower()
                return _shown(params.named(name, loc))
            return _shown(params.numbered(float(m.group(2)), loc))
        except Diagnostic:
            return "######"

    return _PARAM_RE.sub(repl, text)


def comment_commands(text: str, params: Parameters, loc: Location) -> list[canon.Command]:
    """The canonical commands for one (the last) comment of a line."""
    head = text.lstrip().lower()
    if head.startswith("msg,"):
        return [canon.Message(text.lstrip()[4:], source=loc)]
    if head.startswith("debug,"):
        if params.values[DEBUG_FLAG] <= 0.0:
            return []
        return [canon.Message(_substitute(text.lstrip()[6:], params, loc), source=loc)]
    if head.startswith(_SILENT):
        return []
    return [canon.Comment(text, source=loc)]
