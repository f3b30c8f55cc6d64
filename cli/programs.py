"""Open a program of any supported kind as a stream of canonical commands.

The kind is detected by content, not by extension: canonical text (ours or LinuxCNC
``rs274`` output, a line like ``    1 N..... STRAIGHT_FEED(...)``), canonical JSON lines
(``{"cmd": ...}``), ISO 10303-21 (``ISO-10303-21;``: STEP-NC, through stepnc.to_canon) or
else RS274/NGC G-code (through gcode.ngc.interpreter).
Errors of the program itself arrive as :class:`~kernel.diagnostics.Diagnostic` from the
generator, after the commands before them (as rs274 stops at its first error).
"""

from __future__ import annotations

import glob
import importlib.util
import io
import json
import os
import re
import stat
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

import kernel.limits as limits
from cli.main import verbosity as current_verbosity
from cli.options import STDIN_META, STDIN_NAME, read_stdin
from cli.options import dialect_option as dialect_option  # the commands import it from here
from gcode.detect import Guess
from gcode.readers import read, read_chunks, read_text, text_findings
from gcode.registry import DEFAULT_INPUT, guess_dialect
from kernel.diagnostics import Diagnostic, DiagnosticRecord, Location, Severity
from kernel.ir import canon
from kernel.tooltable import ToolTable, header_units, read_tool_table

if TYPE_CHECKING:
    from kernel.check.batch import Moves
    from kernel.machine import Machine

KINDS = ("gcode", "canon", "jsonl", "part21")
#: the files a folder given to ``cnc check`` or ``cnc convert`` contributes
PROGRAM_SUFFIXES = (
    ".ngc",
    ".nc",
    ".gcode",
    ".tap",
    ".mpf",
    ".spf",
    ".canon",
    ".jsonl",
    ".stp",
    ".p21",
)


def expand(files: tuple[str, ...]) -> list[str]:
    """The programs named by ``files``: files as given; a directory's programs (sorted,
    recursively, by :data:`PROGRAM_SUFFIXES`); a pattern the shell did not expand (quoted,
    ``*``, ``?``, ``[...]``, ``**`` recursive) expanded here. A directory without programs
    and a pattern matching nothing are usage errors (exit 2): a batch that checks nothing
    must not pass. A missing plain file stays in the list (its row says it cannot be read)."""
    out: list[str] = []
    for f in files:
        p = Path(f)
        if f == STDIN_NAME:
            out.append(f)
        elif p.is_dir():
            found = _programs_in(p)
            if not found:
                raise click.UsageError(
                    f"{f}: no programs in this directory (looked for {', '.join(PROGRAM_SUFFIXES)})"
                )
            out.extend(found)
        elif is_pattern(f):
            matches = sorted(glob.glob(f, recursive=True))
            found = [
                q for m in matches for q in (_programs_in(Path(m)) if Path(m).is_dir() else [m])
            ]
            if not found:
                raise click.UsageError(f"{f}: no file matches this pattern")
            out.extend(found)
        else:
            out.append(f)
    return out


def is_pattern(given: str) -> bool:
    """Whether ``given`` is a pattern for :func:`expand` to match (no file has that name)."""
    return glob.has_magic(given) and not Path(given).exists()


def _programs_in(folder: Path) -> list[str]:
    """The programs below ``folder``, sorted."""
    return [
        str(q)
        for q in sorted(folder.rglob("*"))
        if q.suffix.lower() in PROGRAM_SUFFIXES and q.is_file()
    ]


def stdin_text() -> str:
    """Standard input as text: what the program argument read for ``-`` in this invocation
    (cli.options.program_argument), else read now, once per invocation."""
    ctx = click.get_current_context(silent=True)
    if ctx is not None and STDIN_META in ctx.meta:
        return str(ctx.meta[STDIN_META])
    text = read_stdin()
    if ctx is not None:
        ctx.meta[STDIN_META] = text
    return text


def is_stdin(path: str) -> bool:
    """Whether ``path`` is the program read from standard input."""
    return path == STDIN_NAME


def output_stem(path: str) -> str:
    """The stem output files of ``path`` are named after (``stdin`` for standard input)."""
    return "stdin" if is_stdin(path) else Path(path).stem


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


def regular_input(path: str, what: str = "program") -> None:
    """``IO-OPEN`` when ``path`` exists but is not a regular file (standard input aside): a
    FIFO blocks the run until something writes to it, ``/dev/zero`` never ends, a directory
    is no program. A path that does not exist is left to the open that follows."""
    if is_stdin(path):
        return
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return
    if stat.S_ISREG(mode):
        return
    kind = (
        "a directory"
        if stat.S_ISDIR(mode)
        else "a FIFO (named pipe)"
        if stat.S_ISFIFO(mode)
        else "a device"
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
        else "not a regular file"
    )
    raise Diagnostic("IO-OPEN", f"cannot read {what}: {path} is {kind}", Location(path))


def read_head(path: str, size: int = 16384) -> str:
    """The first ``size`` bytes as text; ``CHECK-BINARY`` if the file is not text."""
    if is_stdin(path):
        data = stdin_text()[:size].encode("utf-8", errors="replace")
    else:
        regular_input(path)
        with open(path, "rb") as fh:
            data = fh.read(size)
    nul = data.find(b"\0")
    if nul >= 0:
        # located at the first NUL (its column counts bytes)
        line = data.count(b"\n", 0, nul) + 1
        col = nul - data.rfind(b"\n", 0, nul)
        raise Diagnostic("CHECK-BINARY", "not a text file (NUL bytes)", Location(path, line, col))
    return data.decode("utf-8", errors="replace")


def _jsonl(path: str) -> Iterator[canon.Command]:
    with _open_text(path) as fh:
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
    with _open_text(path) as fh:
        yield from canon.read_commands(fh, path, keep_linuxcnc=True)


def _open_text(path: str) -> io.TextIOBase:
    """The program at ``path`` (or standard input) open for reading text."""
    if is_stdin(path):
        return io.StringIO(stdin_text())
    regular_input(path)
    return open(path, encoding="utf-8", errors="replace")  # noqa: SIM115 - the caller closes


def inch_tool_table(tools: ToolTable, mm_per_unit: float) -> ToolTable:
    """The table with lengths in inches, the unit rs274 (and gcode.ngc.interpreter) reads tool
    tables in; ``mm_per_unit`` is the unit of ``tools`` (25.4: already inches)."""
    return _scaled(tools, mm_per_unit / 25.4)


def metric_tool_table(tools: ToolTable, mm_per_unit: float) -> ToolTable:
    """The table with lengths in millimetres (``mm_per_unit``: the unit of ``tools``)."""
    return _scaled(tools, mm_per_unit)


def _scaled(tools: ToolTable, k: float) -> ToolTable:
    """``tools`` with every length (X Y Z U V W offsets, diameter) times ``k``."""
    if k == 1.0:
        return tools
    out = ToolTable()
    for n, t in tools.tools.items():
        off = tuple(v * k if i in (0, 1, 2, 6, 7, 8) else v for i, v in enumerate(t.offset))
        out.tools[n] = replace(t, offset=off, diameter=t.diameter * k)
    return out


def guess_message(path: str, guess: Guess) -> DiagnosticRecord:
    """The one line telling which dialect ``--dialect auto`` chose for ``path`` and why:
    a note, or a warning when suffix and content disagree or another dialect fits too."""
    text = f"read as {guess.dialect} ({guess.reason})"
    code, severity = "DIALECT-GUESS", Severity.NOTE
    if guess.conflict:
        text, code, severity = guess.conflict, "DIALECT-CONFLICT", Severity.WARNING
    if guess.plausible:
        text += f"; also plausible: {'; '.join(guess.plausible)}"
        code, severity = "DIALECT-AMBIGUOUS", Severity.WARNING
    if severity is Severity.WARNING:
        text += "; give --dialect to choose"
    return DiagnosticRecord(code, text, Location(path), severity)


def program_dialect(
    path: str,
    dialect: str | None,
    verbosity: int | None = None,
    head: str | None = None,
    lathe: bool = False,
) -> str:
    """The dialect a G-code file is read in: ``dialect`` when given (not ``auto``), else
    the one its content and suffix point to (gcode.detect; ``.mpf`` is Siemens, ``.ngc``
    RS274/NGC, content wins over a generic suffix), else RS274/NGC.

    The guess is said on stderr, one line (quiet under ``-q``; a plain RS274/NGC program
    only under ``-v``). ``verbosity`` is the ``-v``/``-q`` balance (default: the current
    command's), ``head`` the program's first bytes when already read, ``lathe`` whether the
    machine profile is a lathe (a lathe's dialect then wins a close call)."""
    if dialect and dialect != "auto":
        return dialect
    if head is None:
        head = read_head(path)
    guess = guess_dialect(head, Path(path).suffix, lathe)
    level = current_verbosity() if verbosity is None else verbosity
    doubt = bool(guess.conflict or guess.plausible)
    if level > 0 or (level == 0 and (doubt or guess.dialect != DEFAULT_INPUT)):
        click.echo(guess_message(path, guess).format(), err=True)
    return guess.dialect


def _gcode(
    path: str, tools: ToolTable | None, mm_per_unit: float, dialect: str, bulk: bool = False
) -> Iterator[canon.Command | Moves]:
    if tools is not None:
        tools = inch_tool_table(tools, mm_per_unit)
    from gcode.ngc.interpreter import InterpreterOptions

    search = (str(Path(path).resolve().parent),)  # standard input: the working directory
    options = InterpreterOptions(tool_table=tools, search_path=search)
    if is_stdin(path):
        yield from read_text(stdin_text(), dialect, path, options)
    elif bulk:
        for item in read_chunks(path, dialect, options, arcs=True):
            yield item if isinstance(item, canon.Command) else _moves(item, path)
    else:
        yield from read(path, dialect, options)


def _moves(run: object, path: str) -> Moves:
    """A run of the RS274/NGC fast lane (gcode.ngc.lane.fastlane.Run) as the checker's
    :class:`~kernel.check.batch.Moves` (the same events, as arrays)."""
    import numpy as np  # a bulk run comes from the fast lane, which has loaded numpy

    from gcode.ngc.lane import fastlane
    from kernel.check.batch import ARC, FEED, SET_FEED, TRAVERSE, Moves

    assert isinstance(run, fastlane.Run), run
    codes = np.zeros(4, dtype=np.int64)
    codes[[fastlane.TRAVERSE, fastlane.FEED_MOVE, fastlane.SET_FEED, fastlane.ARC]] = (
        TRAVERSE,
        FEED,
        SET_FEED,
        ARC,
    )
    return Moves(codes[run.kind], run.position, run.feed, run.line, run.arc, path)


def _part21(path: str, machine: Machine | None) -> Iterator[canon.Command]:
    """ISO 14649 through :func:`stepnc.to_canon.canon_from_file` (standard start-up state,
    its retract height kept within ``machine``'s Z travel)."""
    from stepnc.model import load_text
    from stepnc.to_canon import canon_from_file, canon_from_model

    z_max = None
    if machine is not None and "z" in machine.axis_names:
        z_max = machine.axis("z").max
    if is_stdin(path):
        yield from canon_from_model(load_text(stdin_text(), path), mode="default", z_max=z_max)
    else:
        yield from canon_from_file(path, mode="default", z_max=z_max)


def program_language(
    path: str, dialect: str | None, verbosity: int | None = None, lathe: bool = False
) -> str:
    """What the program at ``path`` is: ``canon``, ``jsonl`` or ``part21`` by content, else
    the G-code dialect it is read in (:func:`program_dialect`)."""
    head = read_head(path)
    kind = detect_kind(head)
    return kind if kind != "gcode" else program_dialect(path, dialect, verbosity, head, lathe)


def program_commands(
    path: str,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
    dialect: str | None = None,
    verbosity: int | None = None,
    machine: Machine | None = None,
) -> Iterator[canon.Command]:
    """Stream the canonical commands of the program at ``path`` (kind detected by content);
    ``tools`` (lengths in units of ``tool_mm_per_unit`` mm) go to the G-code reader of
    ``dialect`` (:func:`program_dialect`; ``verbosity`` says whether a guess is told).
    ``machine``: a lathe tips a close dialect call to the lathe readers, and a STEP-NC
    start state is fitted to its travel."""
    lathe = machine is not None and machine.kind == "lathe"
    language = program_language(path, dialect, verbosity, lathe)
    cmds = language_commands(path, language, tools, tool_mm_per_unit, machine)
    yield from cast(Iterator[canon.Command], cmds)  # no bulk: commands only


#: a finding a front end made from a program's text: (rule, message, location)
TextFinding = tuple[str, str, Location]


def check_input(
    path: str,
    dialect: str | None,
    verbosity: int | None,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
    machine: Machine | None = None,
) -> tuple[Iterator[canon.Command], list[TextFinding]]:
    """What ``cnc check`` and ``cnc run`` judge of ``path`` (:func:`check_input_bulk`
    without its arrays)."""
    cmds, text = check_input_bulk(path, dialect, verbosity, tools, tool_mm_per_unit, machine)
    return cast(Iterator[canon.Command], cmds), text


def check_input_bulk(
    path: str,
    dialect: str | None,
    verbosity: int | None,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
    machine: Machine | None = None,
    bulk: bool = False,
) -> tuple[Iterator[canon.Command | Moves], list[TextFinding]]:
    """What ``cnc check`` and ``cnc run`` judge of ``path``: its canonical commands and the
    findings of the rules judged on its text (CNC050, gcode.readers.text_findings). A file
    that cannot be read as a program gives a stream that stops at once with its diagnostic,
    so it becomes a finding like the program's own errors. ``bulk``: runs of plain lines
    as arrays (:func:`language_commands`)."""
    lathe = machine is not None and machine.kind == "lathe"
    try:
        language = program_language(path, dialect, verbosity, lathe)
    except Diagnostic as diag:
        return _failing(diag), []
    cmds = language_commands(path, language, tools, tool_mm_per_unit, machine, bulk)
    if language in KINDS:
        return cmds, []
    return cmds, text_findings(path, language, stdin_text() if is_stdin(path) else None)


def _failing(diag: Diagnostic) -> Iterator[canon.Command]:
    """A stream that stops at once with ``diag`` (check_stream makes it a finding)."""
    raise diag
    yield  # a generator


def language_commands(
    path: str,
    language: str,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
    machine: Machine | None = None,
    bulk: bool = False,
) -> Iterator[canon.Command | Moves]:
    """The canonical commands of ``path`` read as ``language`` (:func:`program_language`);
    with ``bulk``, an RS274/NGC program's runs of plain lines as
    :class:`~kernel.check.batch.Moves` arrays."""
    if language == "canon":
        yield from _canon_text(path)
    elif language == "jsonl":
        yield from _jsonl(path)
    elif language == "part21":
        yield from _part21(path, machine)
    else:
        yield from _gcode(path, tools, tool_mm_per_unit, language, bulk)


#: ``--jobs/-j`` of the batch commands (check, run)
def _scheduler(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
    """Refuse a malformed ``local:N`` and a missing Dask before any work (usage errors)."""
    if value is None:
        return None
    if value.startswith("local:"):
        n = value[len("local:") :]
        if not n.isdigit() or int(n) < 1:
            raise click.BadParameter(f"'{value}': use local:N with N >= 1 workers")
    if importlib.util.find_spec("distributed") is None:
        raise click.BadParameter(
            "needs Dask: pip install 'cnc-toolchain[cluster]' (see docs/cluster.md)"
        )
    return value


scheduler_option = click.option(
    "--scheduler",
    metavar="ADDRESS",
    default=None,
    callback=_scheduler,
    help="Work on a Dask cluster: a scheduler address (tcp://host:8786) or local:N for N "
    "local worker processes. Workers read the programs by path (docs/cluster.md).",
)

DEFAULT_TIMEOUT = 600.0  # s: --timeout's default, far above any real program's time

#: ``--timeout`` of the batch commands (check, run)
timeout_option = click.option(
    "--timeout",
    type=click.FloatRange(min=0),
    default=DEFAULT_TIMEOUT,
    show_default=True,
    help="Per-program time limit in seconds (0: none); a program past it is one failed row.",
)

jobs_option = click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=0),
    default=1,
    show_default=True,
    help="Worker processes (0: one per CPU).",
)


def load_machine(path: str | None) -> Machine:
    """The machine profile at ``path`` (TOML), or the built-in 3-axis mill for None.

    ``kernel.machine`` (and its TOML reader) is imported here, not at start-up: ``cnc canon``
    without a profile never needs it."""
    from kernel.machine import DEFAULT_MACHINE, parse_machine

    if path is None:
        return DEFAULT_MACHINE
    regular_input(path, "machine profile")
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
        raise Diagnostic(
            "LIMIT-CONFIG", "[limits] must be a table of numbers", machine.where.at("limits")
        )
    given = click.get_current_context(silent=True)
    root = given.find_root().params.get("limit_values", ()) if given else ()
    named = {str(item).partition("=")[0].strip() for item in root}
    try:
        limits.configure(**{k: float(v) for k, v in table.items() if k not in named})
    except Diagnostic as exc:
        raise Diagnostic(exc.code, exc.message, machine.where.at("limits")) from None


def load_tool_table(path: str) -> ToolTable:
    """A tool table file: LinuxCNC ``.tbl`` or NIST tool file (``TOOL-*`` diagnostics)."""
    regular_input(path, "tool table")
    with open(path, encoding="utf-8", errors="replace") as fh:
        return read_tool_table(fh.readlines(), path)


MM_PER_UNIT = {"mm": 1.0, "inch": 25.4}


def tool_table_units(path: str, given: str | None, fallback: float) -> float:
    """Millimetres per length unit of the tool table at ``path``: ``given`` (``--tool-units``)
    when set, else its header comment (``; units: inch``), else ``fallback`` (the profile's
    ``[tools] units``, or the command's default)."""
    if given is not None:
        return MM_PER_UNIT[given]
    regular_input(path, "tool table")
    with open(path, encoding="utf-8", errors="replace") as fh:
        declared = header_units(fh)
    return MM_PER_UNIT[declared] if declared else fallback


def load_tools(
    path: str | None, given: str | None, fallback: float = 1.0
) -> tuple[ToolTable | None, float]:
    """``-t`` with ``--tool-units``: the table (None without ``path``) and mm per its unit."""
    if path is None:
        return None, fallback
    return load_tool_table(path), tool_table_units(path, given, fallback)


def profile_tools(machine: Machine, path: str) -> tuple[str | None, float]:
    """The profile's ``[tools]`` table: its file (relative to the profile, made a path
    here) and mm per its unit (kernel.check.config.tool_table_spec, imported only for a
    profile: a plain ``cnc canon`` does not load the checker)."""
    from kernel.check.config import tool_table_spec

    file, mm_per_unit = tool_table_spec(machine.extra, machine.where)
    return (str(Path(path).parent / file) if file else None), mm_per_unit


def machine_tools(
    machine_path: str | None, tool_table: str | None, tool_units: str | None
) -> tuple[Machine, ToolTable | None, float]:
    """``-m``, ``-t`` and ``--tool-units`` as every command that plans a program reads
    them: the machine (built-in mill without ``-m``), the tool table (``-t``, else the
    profile's ``[tools]`` file, else none) and mm per its length unit."""
    machine = load_machine(machine_path)
    fallback = 1.0
    if machine_path is not None:
        listed, fallback = profile_tools(machine, machine_path)
        tool_table = tool_table or listed
    tools, mm_per_unit = load_tools(tool_table, tool_units, fallback)
    return machine, tools, mm_per_unit
