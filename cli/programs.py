"""Open a program of any supported kind as a stream of canonical commands.

The kind is detected by content, not by extension: canonical text (ours or LinuxCNC
``rs274`` output, a line like ``    1 N..... STRAIGHT_FEED(...)``), canonical JSON lines
(``{"cmd": ...}``), ISO 10303-21 (``ISO-10303-21;``: STEP-NC, through stepnc.to_canon) or
else RS274/NGC G-code (through gcode.ngc.interpreter).
Errors of the program itself arrive as :class:`~kernel.diagnostics.Diagnostic` from the
generator, after the commands before them (as rs274 stops at its first error).
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

import click

import kernel.limits as limits
from gcode.registry import ALIASES, DEFAULT_INPUT, INPUTS, dialect_for_suffix, suffix_summary
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, Machine, parse_machine
from kernel.tooltable import ToolTable, read_tool_table

KINDS = ("gcode", "canon", "jsonl", "part21")
_PART21 = re.compile(r"^\s*ISO-10303-21\s*;", re.M)
_CANON_LINE = re.compile(r"^\s*(?:\d+\s+N[.\d]*\s+)?[A-Z][A-Z0-9_]*\(.*\)\s*$")


def detect_kind(head: str) -> str:
    """Classify a program by its first meaningful line (Part 21 may open with comments)."""
    if _PART21.search(head):
        return "part21"
    for line in head.splitlines():
        s = line.strip()
        if not s:
            continue
        if s.upper().startswith("ISO-10303-21"):
            return "part21"
        if s.startswith("{"):
            return "jsonl"
        if _CANON_LINE.match(s) and not s.startswith(("(", ";", "%")):
            return "canon"
        return "gcode"
    return "gcode"


def read_head(path: str, size: int = 16384) -> str:
    """The first ``size`` bytes as text; ``CHECK-BINARY`` if the file is not text."""
    with open(path, "rb") as fh:
        data = fh.read(size)
    if b"\0" in data:
        raise Diagnostic("CHECK-BINARY", "not a text file (NUL bytes)", Location(path))
    return data.decode("utf-8", errors="replace")


def _jsonl(path: str) -> Iterator[canon.Command]:
    with open(path, encoding="utf-8", errors="replace") as fh:
        for n, line in enumerate(fh, 1):
            if not line.strip():
                continue
            loc = Location(path, n, 1)
            try:
                obj = json.loads(line)
                cmd = canon.from_json(obj)
            except (ValueError, TypeError) as exc:
                raise Diagnostic("CANON-JSON", f"bad JSON-lines command: {exc}", loc) from None
            yield cmd if cmd.source is not None else _with_source(cmd, loc)


def _with_source(cmd: canon.Command, loc: Location) -> canon.Command:
    object.__setattr__(cmd, "source", loc)
    return cmd


def _canon_text(path: str) -> Iterator[canon.Command]:
    with open(path, encoding="utf-8", errors="replace") as fh:
        yield from canon.read_commands(fh, path, keep_linuxcnc=True)


def inch_tool_table(tools: ToolTable, mm_per_unit: float) -> ToolTable:
    """The table with lengths in inches, the unit rs274 (and gcode.ngc.interpreter) reads tool
    tables in; ``mm_per_unit`` is the unit of ``tools`` (25.4: already inches)."""
    if mm_per_unit == 25.4:
        return tools
    k = mm_per_unit / 25.4
    out = ToolTable()
    for n, t in tools.tools.items():
        off = tuple(v * k if i in (0, 1, 2, 6, 7, 8) else v for i, v in enumerate(t.offset))
        out.tools[n] = replace(t, offset=off, diameter=t.diameter * k)
    return out


def program_dialect(path: str, dialect: str | None) -> str:
    """The dialect a G-code file is read in: ``dialect`` when given (not ``auto``), else
    the one its suffix names (Siemens ``.mpf``/``.spf``), else RS274/NGC."""
    if dialect and dialect != "auto":
        return dialect
    return dialect_for_suffix(Path(path).suffix)


def _gcode(
    path: str, tools: ToolTable | None, mm_per_unit: float, dialect: str | None = None
) -> Iterator[canon.Command]:
    if tools is not None:
        tools = inch_tool_table(tools, mm_per_unit)
    from gcode.ngc.interpreter import InterpreterOptions
    from gcode.readers import read

    search = (str(Path(path).resolve().parent),)
    options = InterpreterOptions(tool_table=tools, search_path=search)
    yield from read(path, program_dialect(path, dialect), options)


def _part21(path: str) -> Iterator[canon.Command]:
    """ISO 14649 through :func:`stepnc.to_canon.canon_from_file` (standard start-up state)."""
    from stepnc.to_canon import canon_from_file

    yield from canon_from_file(path, mode="default")


def program_commands(
    path: str,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
    dialect: str | None = None,
) -> Iterator[canon.Command]:
    """Stream the canonical commands of the program at ``path`` (kind detected by content);
    ``tools`` (lengths in units of ``tool_mm_per_unit`` mm) go to the G-code reader of
    ``dialect`` (:func:`program_dialect`)."""
    kind = detect_kind(read_head(path))
    if kind == "canon":
        yield from _canon_text(path)
    elif kind == "jsonl":
        yield from _jsonl(path)
    elif kind == "part21":
        yield from _part21(path)
    else:
        yield from _gcode(path, tools, tool_mm_per_unit, dialect)


#: ``--dialect`` of the commands that read programs (canon, check, run, plan, trace)
dialect_option = click.option(
    "--dialect",
    "-d",
    default="auto",
    show_default=True,
    type=click.Choice(["auto", *INPUTS, *ALIASES], case_sensitive=False),
    help=f"Language of G-code input: {', '.join(INPUTS)}; auto: by suffix ({suffix_summary()}), "
    f"else {DEFAULT_INPUT}. Canonical text, JSON lines and Part 21 are recognised by content "
    "whatever this says.",
)

#: ``--jobs/-j`` of the batch commands (check, run)
jobs_option = click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=0),
    default=1,
    show_default=True,
    help="Worker processes (0: one per CPU).",
)


def load_machine(path: str | None) -> Machine:
    """The machine profile at ``path`` (TOML), or the built-in 3-axis mill for None."""
    if path is None:
        return DEFAULT_MACHINE
    with open(path, encoding="utf-8") as fh:
        machine = parse_machine(fh.read(), path)
    apply_limits(machine, path)
    return machine


def apply_limits(machine: Machine, path: str | None) -> None:
    """The profile's ``[limits]`` table into :mod:`kernel.limits` (``LIMIT-CONFIG`` when it
    is not a table of numbers); ``--limit`` on the command line, set earlier, wins."""
    table = machine.extra.get("limits")
    if table is None:
        return
    if not isinstance(table, dict) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in table.values()
    ):
        raise Diagnostic("LIMIT-CONFIG", "[limits] must be a table of numbers", Location(path))
    given = click.get_current_context(silent=True)
    root = given.find_root().params.get("limit_values", ()) if given else ()
    named = {str(item).partition("=")[0].strip() for item in root}
    try:
        limits.configure(**{k: float(v) for k, v in table.items() if k not in named})
    except Diagnostic as exc:
        raise Diagnostic(exc.code, exc.message, Location(path)) from None


def load_tool_table(path: str) -> ToolTable:
    """A tool table file: LinuxCNC ``.tbl`` or NIST tool file (``TOOL-*`` diagnostics)."""
    with open(path, encoding="utf-8", errors="replace") as fh:
        return read_tool_table(fh.readlines(), path)
