"""The dialect registry: one row per language, the single table every lookup is made from.

A row names the dialect, its aliases, the file suffixes that identify its programs for
``--dialect auto``, the module holding its :class:`~gcode.write.spec.Dialect` (what its writer
may write; absent for an input-only language) and the module reading it (``interpret(path,
options)`` and ``interpret_text(text, name, options)``, imported only when a program of the
dialect is read). The CLI's ``--dialect``, ``--from`` and ``--to`` choices and their help are
generated from it. Adding a dialect is one package under ``gcode/`` plus one row here
(docs/architecture.md).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING

from gcode import detect
from gcode.detect import Hint
from kernel.diagnostics import Diagnostic

if TYPE_CHECKING:  # the writers' vocabulary: loaded with a dialect's module, not at start-up
    from gcode.write.spec import Dialect


@dataclass(frozen=True)
class DialectEntry:
    """One language: its canonical name and where its writer data and reader live."""

    name: str
    #: module with ``DIALECT`` (the writer's vocabulary); None for an input-only language
    dialect: str | None
    #: module with ``interpret`` and ``interpret_text``; None for an output-only language
    reader: str | None
    aliases: tuple[str, ...] = ()
    #: program suffixes (lower case) that name this dialect for ``--dialect auto``
    suffixes: tuple[str, ...] = ()
    #: what in a program's text points to this dialect for ``--dialect auto`` (gcode.detect)
    hints: tuple[Hint, ...] = ()
    #: a lathe's dialect: preferred by ``--dialect auto`` when the machine profile is a lathe
    lathe: bool = False


#: Every language, writers' order (the order of ``--to`` and of error messages).
REGISTRY: tuple[DialectEntry, ...] = (
    DialectEntry(
        "rs274ngc",
        "gcode.ngc.dialect",
        "gcode.ngc.interpreter",
        ("ngc", "linuxcnc"),
        (".ngc",),
        detect.RS274NGC,
    ),
    DialectEntry("nist_v3", "gcode.nist_v3.dialect", "gcode.nist_v3.reader", ("nist",)),
    DialectEntry(
        "fanuc",
        "gcode.fanuc.dialect",
        "gcode.fanuc.reader",
        hints=detect.FANUC_FAMILY + detect.FANUC_NAME + detect.MILL,
    ),
    DialectEntry(
        "fanuc_lathe",
        "gcode.fanuc_lathe.dialect",
        "gcode.fanuc_lathe.reader",
        hints=detect.FANUC_FAMILY + detect.FANUC_NAME + detect.LATHE,
        lathe=True,
    ),
    DialectEntry("grbl", "gcode.grbl.dialect", "gcode.grbl.reader", hints=detect.GRBL),
    DialectEntry(
        "haas",
        "gcode.haas.dialect",
        "gcode.haas.reader",
        hints=detect.FANUC_FAMILY + detect.MILL + detect.HAAS + detect.HAAS_MILL,
    ),
    DialectEntry(
        "haas_lathe",
        "gcode.haas_lathe.dialect",
        "gcode.haas_lathe.reader",
        hints=detect.FANUC_FAMILY + detect.LATHE + detect.HAAS + detect.HAAS_LATHE,
        lathe=True,
    ),
    DialectEntry(
        "siemens840d",
        "gcode.siemens.dialect",
        "gcode.siemens.reader",
        ("siemens", "840d"),
        (".mpf", ".spf"),
        detect.SIEMENS,
    ),
    DialectEntry("mach3", "gcode.mach3.dialect", "gcode.mach3.reader", (), (".tap",)),
    DialectEntry(
        "sandia", "gcode.sandia.dialect", "gcode.sandia.reader", ("generic",), hints=detect.SANDIA
    ),
)
_BY_NAME = {entry.name: entry for entry in REGISTRY}

#: the dialects a program can be written in
NAMES: tuple[str, ...] = tuple(e.name for e in REGISTRY if e.dialect is not None)
#: alias -> canonical name
ALIASES: dict[str, str] = {alias: e.name for e in REGISTRY for alias in e.aliases}
#: canonical name -> the module reading it
READER_MODULES: dict[str, str] = {e.name: e.reader for e in REGISTRY if e.reader is not None}
#: every name a program can be read in
INPUTS: tuple[str, ...] = tuple(READER_MODULES)
#: program suffix -> the dialect it names (``--dialect auto``)
SUFFIXES: dict[str, str] = {suffix: e.name for e in REGISTRY for suffix in e.suffixes}
#: what ``--dialect auto`` reads a program of no known suffix as
DEFAULT_INPUT = "rs274ngc"
#: (dialect, content hints) of every readable dialect in registry order (``--dialect auto``)
HINTS: tuple[tuple[str, tuple[Hint, ...]], ...] = tuple(
    (e.name, e.hints) for e in REGISTRY if e.reader is not None
)
#: the same when the machine profile is a lathe: a lathe's dialect gets the profile's word
LATHE_HINTS: tuple[tuple[str, tuple[Hint, ...]], ...] = tuple(
    (e.name, e.hints + ((detect.LATHE_PROFILE,) if e.lathe else ()))
    for e in REGISTRY
    if e.reader is not None
)


def canonical_name(name: str) -> str:
    """The canonical name of a dialect name or alias (``CONV-DIALECT`` if unknown)."""
    key = ALIASES.get(name.lower(), name.lower())
    if key not in _BY_NAME:
        raise Diagnostic("CONV-DIALECT", f"unknown dialect {name!r}; known: {', '.join(NAMES)}")
    return key


def get_dialect(name: str) -> Dialect:
    """The dialect called ``name`` (or an alias); ``CONV-DIALECT`` if there is none."""
    module = _BY_NAME[canonical_name(name)].dialect
    if module is None:
        raise Diagnostic("CONV-DIALECT", f"unknown dialect {name!r}; known: {', '.join(NAMES)}")
    dialect: Dialect = importlib.import_module(module).DIALECT
    return dialect


def suffix_summary() -> str:
    """The suffixes ``--dialect auto`` recognises, for help texts (``.mpf/.spf siemens840d``)."""
    return ", ".join(f"{'/'.join(e.suffixes)} {e.name}" for e in REGISTRY if e.suffixes)


def dialect_for_suffix(suffix: str) -> str:
    """The input dialect a program suffix names, else :data:`DEFAULT_INPUT`."""
    return SUFFIXES.get(suffix.lower(), DEFAULT_INPUT)


def guess_dialect(head: str, suffix: str, lathe: bool = False) -> detect.Guess:
    """The dialect ``--dialect auto`` reads a program in, from its first kilobytes
    (``head``) and its file suffix, with the reasons (:func:`gcode.detect.guess`); on a
    ``lathe`` (the machine profile's kind) a lathe's dialect wins a close call."""
    return detect.guess(head, suffix, LATHE_HINTS if lathe else HINTS, SUFFIXES, DEFAULT_INPUT)


def reader_name(dialect: str) -> str:
    """The canonical name of an input language (a dialect name or alias)."""
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
    except ModuleNotFoundError as exc:  # the reader (or its package) is not installed
        if exc.name is None or not (module == exc.name or module.startswith(exc.name + ".")):
            raise  # something the reader itself needs is missing: a real error
        raise Diagnostic("CONV-READER", f"no reader for {name} programs") from None


def readable() -> tuple[str, ...]:
    """The writable dialects that have a reader installed."""
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
