"""Readers: one per input dialect, each turning a program into canonical commands.

A reader is a module with ``interpret(path, options)`` and ``interpret_text(text, name,
options)`` (the contract of :mod:`gcode.ngc.interpreter`), both returning a generator of
:class:`kernel.ir.canon.Command` that raises :class:`~kernel.diagnostics.Diagnostic` at the
first error of the program. RS274/NGC is read by :mod:`gcode.ngc.interpreter`; every other
dialect has its reader in its own package, named in :mod:`gcode.registry`. The modules are imported
only when a program of their dialect is read.
"""

from __future__ import annotations

import io
import os
from collections.abc import Iterator
from typing import TYPE_CHECKING

from gcode.registry import reader_module, reader_name
from kernel.diagnostics import Diagnostic, Location

if TYPE_CHECKING:  # the interpreter is imported with the first program read
    from gcode.ngc.interpreter import InterpreterOptions
    from kernel.ir import canon


def read(
    path: str | os.PathLike[str], dialect: str, options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the program at ``path`` written in ``dialect``."""
    try:
        module = reader_module(dialect)
    except Diagnostic as exc:  # name the program the choice of dialect was made for
        raise Diagnostic(exc.code, exc.message, Location(os.fspath(path))) from None
    return module.interpret(path, options or _default_options())


def read_chunks(
    path: str | os.PathLike[str],
    dialect: str,
    options: InterpreterOptions | None = None,
    *,
    arcs: bool = False,
) -> Iterator[object]:
    """Like :func:`read`, but an RS274/NGC program's runs of plain lines come as
    :class:`gcode.ngc.lane.fastlane.Run` arrays (``interpret_chunks``), for a writer that takes
    them in bulk (gcode.write.writer.write_text). With ``arcs``, for a consumer of IR
    commands (the convert check, cnc check), the runs may hold arcs, and every reader with a
    fast lane (``interpret_chunks``: Grbl, NIST v3, Mach3, the Fanuc and Haas mills) gives its
    runs; without, other dialects give commands only."""
    if reader_name(dialect) == "rs274ngc":
        from gcode.ngc.interpreter import interpret_chunks

        return interpret_chunks(path, options or _default_options(), arcs=arcs)
    if arcs:
        module = reader_module(dialect)
        chunks = getattr(module, "interpret_chunks", None)
        if chunks is not None:
            return chunks(path, options or _default_options(), arcs=True)
    return read(path, dialect, options)


def read_text(
    text: str, dialect: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a program given as text (``name`` is used in locations)."""
    module = reader_module(dialect)
    return module.interpret_text(text, name, options or _default_options())


#: dialects whose controls count a length without a decimal point in least input increments
#: (parameter No. 3401#0 = 0), and whether the program is a lathe's
_INCREMENTS: dict[str, bool] = {
    "fanuc": False,
    "haas": False,
    "fanuc_lathe": True,
    "haas_lathe": True,
}


def text_findings(
    path: str | os.PathLike[str], dialect: str, text: str | None = None
) -> list[tuple[str, str, Location]]:
    """What ``cnc check``'s text rules find in the program at ``path`` read as ``dialect``
    (``text``: the program itself, when it is not a file, named ``path``):
    (rule, message, location) for kernel.check.check_stream. CNC050: the first length or
    angle without a decimal point of a Fanuc-family program, with the count of the others."""
    lathe = _INCREMENTS.get(reader_name(dialect))
    if lathe is None:
        return []
    from gcode.fanuc.decimal_point import bare_numbers

    name = os.fspath(path)
    opened = open if text is None else None  # a file, or the text given
    with (
        io.StringIO(text) if opened is None else opened(name, encoding="utf-8", errors="replace")
    ) as fh:
        found = bare_numbers(fh, lathe)
        first = next(found, None)
        if first is None:
            return []
        more = sum(1 for _ in found)
    return [("CNC050", first.message(more), Location(name, first.line, first.column))]


def _default_options() -> InterpreterOptions:
    from gcode.ngc.interpreter import InterpreterOptions

    return InterpreterOptions()
