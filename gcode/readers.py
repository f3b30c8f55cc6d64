"""Readers: one per input dialect, each turning a program into canonical commands.

A reader is a module with ``interpret(path, options)`` and ``interpret_text(text, name,
options)`` (the contract of :mod:`gcode.interpreter`), both returning a generator of
:class:`kernel.canon.Command` that raises :class:`~kernel.diagnostics.Diagnostic` at the
first error of the program. RS274/NGC is read by :mod:`gcode.interpreter`; every other
dialect has its reader in ``gcode/dialects/<name>_reader.py``. The modules are imported
only when a program of their dialect is read.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Iterator
from types import ModuleType
from typing import TYPE_CHECKING

from gcode.dialects import NAMES, get_dialect
from kernel.diagnostics import Diagnostic, Location

if TYPE_CHECKING:  # the interpreter is imported with the first program read
    from gcode.interpreter import InterpreterOptions
    from kernel import canon

#: the module reading each dialect (by its canonical name, gcode.dialects.NAMES)
READER_MODULES: dict[str, str] = {
    "rs274ngc": "gcode.interpreter",
    "nist_v3": "gcode.dialects.nist_v3_reader",
    "grbl": "gcode.dialects.grbl_reader",
    "fanuc": "gcode.dialects.fanuc_reader",
    "haas": "gcode.dialects.haas_reader",
    "siemens840d": "gcode.dialects.siemens840d_reader",
    "sandia": "gcode.dialects.sandia_reader",
    "fanuc_lathe": "gcode.dialects.fanuc_lathe_reader",  # the Fanuc reader in lathe mode
}
#: every name a program can be read in: the dialects and the input-only readers
INPUTS: tuple[str, ...] = tuple(READER_MODULES)


def reader_name(dialect: str) -> str:
    """The canonical name of an input language (a dialect name or alias, or an
    input-only reader such as ``fanuc_lathe``)."""
    key = dialect.lower()
    return key if key in READER_MODULES else get_dialect(key).name


def reader_module(dialect: str) -> ModuleType:
    """The reader of ``dialect`` (a name or alias); ``CONV-READER`` if it has none."""
    name = reader_name(dialect)
    module = READER_MODULES.get(name)
    if module is None:
        raise Diagnostic("CONV-READER", f"no reader for {name} programs")
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name != module:
            raise
        raise Diagnostic("CONV-READER", f"no reader for {name} programs") from None


def readable() -> tuple[str, ...]:
    """The dialects (writable too: gcode.dialects.NAMES) that have a reader installed."""
    names = []
    for name, module in READER_MODULES.items():
        if name not in NAMES:
            continue
        try:
            importlib.import_module(module)
        except ModuleNotFoundError:
            continue
        names.append(name)
    return tuple(names)


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
    path: str | os.PathLike[str], dialect: str, options: InterpreterOptions | None = None
) -> Iterator[object]:
    """Like :func:`read`, but an RS274/NGC program's runs of plain lines come as
    :class:`gcode.fastlane.Run` arrays (``interpret_chunks``), for a writer that takes
    them in bulk (gcode.emit.write_text); other dialects give commands only."""
    if reader_name(dialect) == "rs274ngc":
        from gcode.interpreter import interpret_chunks

        return interpret_chunks(path, options or _default_options())
    return read(path, dialect, options)


def read_text(
    text: str, dialect: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a program given as text (``name`` is used in locations)."""
    module = reader_module(dialect)
    return module.interpret_text(text, name, options or _default_options())


def _default_options() -> InterpreterOptions:
    from gcode.interpreter import InterpreterOptions

    return InterpreterOptions()
