"""``cnc convert IN --from D --to D [-o OUT]``: move a program between controls via the IR.

The input is read by its dialect's reader (:mod:`gcode.readers`), from canonical text
(``--from canon``) or from the IR's JSON lines (``--from jsonl``); ``--from auto`` tells
canonical text and JSON lines by content and a Siemens program by its suffix. The
output streams to ``-o OUT`` (written to a temporary file and renamed, so a refused
conversion leaves no partial file) or to standard output. An existing OUT is never
replaced without ``--force``. A *loss* (the converted program would make the machine do
something else: spindle, coolant, tools, offsets, feed mode, stops, motion beyond the
tolerance; gcode.write.report) is an error: nothing is written and the exit code is 1,
unless ``--allow-loss CODE`` accepts it. Every other difference is a note, printed once per
kind with its first source line and count and, with ``--report R.json``, written as JSON.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn, cast

import click

from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded
from cli.errors import report as report_error
from cli.excerpt import render_record
from cli.main import verbosity
from cli.options import tool_table_option
from cli.outputs import refuse_output, write_output
from cli.programs import expand, is_pattern, stdin_text
from cli.verify import Recorder, Verification, reader_options, verified_output
from gcode.registry import (
    ALIASES,
    DEFAULT_INPUT,
    INPUTS,
    NAMES,
    REGISTRY,
    get_dialect,
    reader_name,
    suffix_summary,
)
from gcode.write.report import LOSS_CODES, Change, ConversionReport, Group, group
from gcode.write.spec import Dialect
from gcode.write.writer import ARC_FORMATS, CYCLE_MODES, WriterOptions, write_text
from kernel.diagnostics import Diagnostic, DiagnosticRecord, Location, Severity
from kernel.ir import canon


def read_canon(path: str, report: ConversionReport) -> Iterator[canon.Command]:
    """Canonical text as IR; commands the IR does not know are dropped and reported."""
    with open(path, encoding="utf-8") as fh:
        for tc in canon.read_text(fh, path):
            if tc.name in canon.LINUXCNC_ONLY and tc.name not in (
                "SET_FEED_MODE",
                "SET_SPINDLE_MODE",
                "SET_NAIVECAM_TOLERANCE",
            ):
                continue
            try:
                yield canon.parse_command(tc, path)
            except Diagnostic as exc:
                if exc.code != "CANON-UNKNOWN":
                    raise
                report.add(
                    Change("CONV-UNSUPPORTED", "dropped", exc.message, Location(path, tc.line, 1))
                )


def read_jsonl(path: str) -> Iterator[canon.Command]:
    """The JSON-lines form of the IR (``kernel.ir.canon.to_jsonl``), one command per line."""
    with open(path, encoding="utf-8") as fh:
        for number, line in enumerate(fh, 1):
            if not line.strip():
                continue
            try:
                yield canon.from_json(json.loads(line))
            except (ValueError, TypeError, AttributeError) as exc:
                raise Diagnostic(
                    "CANON-SYNTAX", f"not an IR JSON line: {exc}", Location(path, number, 1)
                ) from None


def read_program(
    path: str,
    dialect: str,
    tool_table: str | None,
    report: ConversionReport,
    cycle_marks: bool = False,
    keep_cutter_comp: bool = False,
) -> Iterator[canon.Command]:
    """The program at ``path`` as IR, read by the reader of ``dialect`` (gcode.readers);
    ``cycle_marks`` brackets canned-cycle expansions for a writer that keeps them, and
    ``keep_cutter_comp`` leaves G41/G42 to the target (gcode.ngc.comp.keep)."""
    from cli.programs import load_tool_table

    if dialect == "canon":
        return read_canon(path, report)
    if dialect == "jsonl":
        return read_jsonl(path)
    if dialect == "stepnc":
        from stepnc.to_canon import canon_from_file

        return iter(canon_from_file(path, tool_file=tool_table, mode="default"))
    from gcode.ngc.interpreter import InterpreterOptions
    from gcode.readers import read_chunks

    table = load_tool_table(tool_table) if tool_table else None
    here = str(Path(path).resolve().parent)
    options = InterpreterOptions(
        tool_table=table,
        search_path=(here,),
        cycle_marks=cycle_marks,
        keep_cutter_comp=keep_cutter_comp,
        register_marks=True,  # G43 H n kept as a register (gcode.core.register_marks)
    )
    # RS274/NGC comes as commands and fast-lane runs of plain lines and arcs
    # (gcode.ngc.lane.fastlane.Run, read as cnc canon reads it), which write_text takes in
    # bulk; gcode.readers types that stream as objects
    arcs = dialect == "rs274ngc"
    return cast(Iterator[canon.Command], read_chunks(path, dialect, options, arcs=arcs))


#: ``--from`` values that name a kind of file rather than a G-code dialect
KINDS = {"canon": "canon", "jsonl": "jsonl", "part21": "stepnc"}


def source_language(path: str, dialect: str) -> str:
    """``--from`` made concrete: ``auto`` is canonical text, JSON lines or STEP-NC Part 21
    by content, a Siemens program by its suffix, else RS274/NGC; an alias becomes its
    dialect's name. A file that is not of the kind named is refused (``CONV-INPUT``)."""
    from cli.programs import detect_kind, program_dialect, read_head

    kind = KINDS.get(detect_kind(read_head(path)))
    if dialect == "auto" and kind:
        return kind
    if dialect in KINDS.values():
        if kind != dialect:
            raise Diagnostic(
                "CONV-INPUT",
                f"not a {dialect} file (its content reads as {kind or 'G-code'}); "
                "use --from auto to tell by content",
                Location(path),
            )
        return dialect
    return reader_name(program_dialect(path, dialect))


def _allowed_losses(values: tuple[str, ...]) -> frozenset[str]:
    """``--allow-loss`` values (repeatable, comma-separated) as loss codes; ``CONV-`` may be
    left off. A code that is not a loss is a ValueError saying so."""
    codes: set[str] = set()
    for value in values:
        for part in value.split(","):
            name = part.strip().upper()
            if not name:
                continue
            code = name if name.startswith("CONV-") else "CONV-" + name
            if code not in LOSS_CODES:
                known = ", ".join(sorted(LOSS_CODES))
                raise ValueError(f"--allow-loss {part.strip()}: not a loss code ({known})")
            codes.add(code)
    return frozenset(codes)


def _usage(message: str, source: str) -> NoReturn:
    """A bad option value: the located ``CONV-OPTION`` error at the program it was given
    for, and the usage exit code (2)."""
    report_error(Diagnostic("CONV-OPTION", message, Location(source)))
    sys.exit(EXIT_USAGE)


def _echo_groups(groups: list[Group], severity: Severity, prefix: str, source: str) -> None:
    """One line per kind of entry: its first source line, and how many there are (a summary:
    the source excerpt under each only with ``-v``; errors that stop a conversion always
    show theirs)."""
    level = verbosity()
    for g in groups:
        more = f" ({g.count} times, first here)" if g.count > 1 else ""
        rec = DiagnosticRecord(
            g.first.code,
            f"{prefix}{g.first.kind}: {g.first.message}{more}",
            g.first.source or Location(source),
            severity,
        )
        click.echo(render_record(rec, level) if level > 0 else rec.format(), err=True)


@click.command("convert")
@click.argument("sources", nargs=-1, required=True, type=click.Path())
@click.option(
    "--from",
    "-d",
    "--dialect",
    "src",
    default="auto",
    show_default=True,
    type=click.Choice(
        ["auto", "canon", "jsonl", "stepnc", *INPUTS, *ALIASES], case_sensitive=False
    ),
    help="input language, also spelled -d/--dialect as in the other commands (auto: "
    "canonical text, JSON lines and STEP-NC by content, "
    f"{suffix_summary()} by suffix, else {DEFAULT_INPUT})",
)
@click.option(
    "--to",
    "dst",
    required=True,
    type=click.Choice([*NAMES, *ALIASES], case_sensitive=False),
    help="output dialect",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(),
    help="output file (else stdout); with several SOURCES or a directory, the folder that "
    "receives one output per input, named with the target's suffix",
)
@click.option("--force", is_flag=True, help="replace an existing output or report file")
@click.option(
    "--arc-format",
    type=click.Choice(ARC_FORMATS),
    default="ijk",
    show_default=True,
    help="IJK incremental centres, absolute centres, or R",
)
@click.option("--units", type=click.Choice(["mm", "inch"]), help="output units (else the input's)")
@click.option(
    "--line-numbers", type=int, default=0, show_default=True, help="N-word increment (0: none)"
)
@click.option("--decimals", type=int, help="decimal places (else the dialect's)")
@click.option("--max-line-length", type=int, help="longest block (else the dialect's limit)")
@click.option("--header", "header", multiple=True, help="header line (repeatable)")
@click.option("--footer", "footer", multiple=True, help="footer line (repeatable)")
@click.option("--no-frame", is_flag=True, help="no header/footer at all")
@click.option(
    "--on-missing",
    type=click.Choice(["approximate", "refuse"]),
    default="approximate",
    show_default=True,
    help="a construct the target lacks: approximate writes curves as arcs or lines within "
    "--tolerance and reports the rest (losses are errors unless --allow-loss names them); "
    "refuse stops at the first such construct, approximations included",
)
@click.option(
    "--allow-loss",
    "allow_loss",
    multiple=True,
    metavar="CODE[,CODE...]",
    help="accept these losses (CONV-SPINDLE, CONV-COOLANT, CONV-TOOL-CHANGE, ...; repeatable "
    "or comma-separated): the program is written and the report lists them",
)
@click.option(
    "--tolerance",
    type=float,
    default=0.001,
    show_default=True,
    help="approximation tolerance (output length units)",
)
@click.option(
    "--cycles",
    type=click.Choice(CYCLE_MODES),
    default="keep",
    show_default=True,
    help="drilling cycles (G73 G81-G83 G85 G89) as cycle blocks where the target has "
    "them, or expanded into moves",
)
@click.option(
    "--cutter-comp",
    type=click.Choice(["keep", "apply"]),
    default="keep",
    show_default=True,
    help="G41/G42 kept with the programmed path where the target has cutter compensation "
    "(LinuxCNC by value, Fanuc/Haas with the radius set by G10 L12), or applied here",
)
@click.option("--no-comments", is_flag=True, help="drop comments")
@tool_table_option(help="LinuxCNC .tbl or NIST tool file for the interpreter")
@click.option(
    "--write-tool-table",
    is_flag=True,
    help="write the machine's tool table where the program sets it (G10 L1) or the target "
    "takes a length only through it (G10 L10; lengths from --tool-table); without it such "
    "a program is refused and G43 H n is kept as a register",
)
@click.option(
    "--no-verify",
    is_flag=True,
    help="do not read the output back and compare it with the source (kernel.ir.equivalence)",
)
@click.option(
    "--report",
    "report_path",
    type=click.Path(dir_okay=False),
    help="write the conversion report as JSON (several SOURCES: one report per file, in a list)",
)
@guarded
def command(
    sources: tuple[str, ...],
    src: str,
    dst: str,
    output: str | None,
    force: bool,
    arc_format: str,
    units: str | None,
    line_numbers: int,
    decimals: int | None,
    max_line_length: int | None,
    header: tuple[str, ...],
    footer: tuple[str, ...],
    no_frame: bool,
    on_missing: str,
    tolerance: float,
    cycles: str,
    cutter_comp: str,
    no_comments: bool,
    tool_table: str | None,
    write_tool_table: bool,
    no_verify: bool,
    report_path: str | None,
    allow_loss: tuple[str, ...],
) -> None:
    """Convert SOURCES from one control's language to another's through the canonical IR.

    A loss (what the target cannot say changes what the machine does: spindle, coolant,
    tool change or length, offsets, units, feed mode, compensation, stops, outputs, motion
    beyond --tolerance) is an error: exit 1 and nothing written, unless --allow-loss names
    its code. Other differences (curves as arcs or lines within --tolerance, expanded
    cycles, comments) are notes, once per kind with the first source line and a count
    (all of them with --report as JSON). --on-missing refuse stops at the first construct
    the target lacks, approximations within the tolerance included.

    \b
    Examples:
      cnc convert part.ngc --to fanuc -o part.nc
      cnc convert part.ngc --to grbl --arc-format r --units mm -o part.gcode
      cnc convert part.canon --from canon --to rs274ngc --line-numbers 10
      cnc convert programs/ --to siemens840d -o converted/

    SOURCES are files or directories (their programs, recursively, as `cnc check` takes
    them). With more than one program, -o names a folder: each program is converted on its
    own into it (a subfolder's programs into the same subfolder), with the target's suffix,
    and a status line says what became of it. A program that fails writes no file and the
    others go on; the exit code is 1 when one failed (2 when one could not be read or its
    output exists without --force).
    """
    target = get_dialect(dst)
    if tolerance <= 0 or (decimals is not None and not 0 <= decimals <= 9):
        _usage("tolerance must be > 0 and decimals within 0..9", sources[0])
    try:
        allowed = _allowed_losses(allow_loss)
    except ValueError as exc:
        _usage(str(exc), sources[0])
    opts = WriterOptions(
        arc_format=arc_format,
        units=units,
        line_numbers=line_numbers,
        decimals=decimals,
        header=() if no_frame else (header or None),
        footer=() if no_frame else (footer or None),
        max_line_length=max_line_length,
        on_missing=on_missing,
        tolerance=tolerance,
        comments=not no_comments,
        cycles=cycles,
        write_tool_table=write_tool_table,
        write_tool_lengths=write_tool_table and tool_table is not None,
    )
    job = Job(
        src.lower(),
        target,
        opts,
        allowed,
        tool_table,
        cutter_comp == "keep" and target.has_cutter_comp,
        not no_verify,
        force,
    )
    if "-" in sources:
        if len(sources) > 1:
            _usage("a program on standard input (-) is converted on its own", "-")
        # the reader and the read-back verification work on files: a scratch copy of the
        # program on standard input, named ``stdin``, its dialect from --from or its content
        with tempfile.TemporaryDirectory(prefix="cnc-convert-") as scratch:
            path = os.path.join(scratch, "stdin")
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(stdin_text())
            sys.exit(_convert_one(path, output, report_path, job))
    if len(sources) == 1 and not os.path.isdir(sources[0]) and not is_pattern(sources[0]):
        sys.exit(_convert_one(sources[0], output, report_path, job))
    sys.exit(convert_many(sources, output, report_path, job))


def _convert_one(source: str, output: str | None, report_path: str | None, job: Job) -> int:
    """Convert one program to ``output`` (None: standard output), with its JSON report at
    ``report_path`` when asked; the exit code."""
    if report_path:
        refuse_output(report_path, job.force, (source, job.tool_table or ""), "report")
    outcome = convert_file(source, output, job)
    if report_path:
        _write_json(report_path, outcome.data)
    return EXIT_OK if outcome.converted else EXIT_PROGRAM_ERROR


@dataclass(frozen=True)
class Job:
    """What every program of one ``cnc convert`` is converted with."""

    src: str
    target: Dialect
    opts: WriterOptions
    allowed: frozenset[str]
    tool_table: str | None
    keep_comp: bool
    verify: bool
    force: bool


@dataclass
class Outcome:
    """One program's conversion: converted (and written) or refused, its JSON report."""

    converted: bool
    verified: bool
    data: dict[str, object]


def convert_file(source: str, output: str | None, job: Job) -> Outcome:
    """Convert one program to ``output`` (None: standard output). A loss not accepted is
    printed and the outcome is not converted; an error in the program or its files is a
    Diagnostic; either way nothing is written."""
    if not os.path.exists(source):
        raise Diagnostic("IO-OPEN", f"no such file: {source}", Location(source))
    if os.path.isdir(source):
        raise Diagnostic("IO-OPEN", f"{source} is a folder, not a program", Location(source))
    if output and os.path.isdir(output):
        raise Diagnostic("IO-EXISTS", f"output {output} is a folder", Location(output))
    if output:
        refuse_output(output, job.force, (source, job.tool_table or ""), "output")
    target, opts = job.target, job.opts
    cycles = opts.cycles == "keep"
    src = source_language(source, job.src)
    report = ConversionReport(source_dialect=src, target_dialect=target.name, allowed=job.allowed)
    ir = read_program(source, src, job.tool_table, report, cycles, job.keep_comp)
    check = Verification() if job.verify else None
    recorder = Recorder(ir, source)
    chunks = write_text(recorder if check else ir, target, opts, report, source=source)
    if check:  # the output is read back and compared with the source before it is written
        back = reader_options(source, job.tool_table, cycles, job.keep_comp)
        chunks = verified_output(chunks, recorder, target, back, opts, report, check)
    # the text goes to a temporary file first: a refused conversion leaves no file, and
    # nothing on standard output
    folder = os.path.dirname(os.path.abspath(output)) if output else None
    if folder:
        os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".convert-", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.writelines(chunks)
        data = report.to_dict()
        data["verified"] = bool(check and check.verified)
        data["options"] = {k: v for k, v in vars(opts).items() if not k.startswith("_")}
        refused = report.refused()
        _echo_groups(group(refused), Severity.ERROR, "", source)
        if refused:
            codes = ",".join(sorted({str(c.loss_code) for c in refused}))
            click.echo(
                f"{source}: error[CONV-LOSS]: not converted: the {target.title} program would "
                f"run differently; accept with --allow-loss {codes}",
                err=True,
            )
            return Outcome(False, False, data)
        if output:
            os.replace(tmp, output)
        else:
            with open(tmp, encoding="utf-8") as fh:
                for line in fh:
                    sys.stdout.write(line)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    _echo_groups(group(report.accepted()), Severity.WARNING, "accepted loss, ", source)
    _echo_groups(group(report.notes()), Severity.NOTE, "", source)
    if check and output:  # a program on standard output is followed by nothing
        click.echo(check.summary(source), err=True)
    return Outcome(True, bool(check and check.verified), data)


def _write_json(path: str, data: object) -> None:
    write_output(path, json.dumps(data, indent=2) + "\n")


#: the suffix of a converted program, per target (else the target's first registry suffix,
#: else ``.ngc``)
OUTPUT_SUFFIX = {
    "fanuc": ".nc",
    "fanuc_lathe": ".nc",
    "haas": ".nc",
    "haas_lathe": ".nc",
    "grbl": ".gcode",
    "sandia": ".txt",
}


def output_suffix(target: str) -> str:
    """The suffix a converted program is named with in an output folder."""
    if target in OUTPUT_SUFFIX:
        return OUTPUT_SUFFIX[target]
    entry = next((e for e in REGISTRY if e.name == target), None)
    return entry.suffixes[0] if entry and entry.suffixes else ".ngc"


def planned_outputs(sources: tuple[str, ...], folder: str, target: str) -> list[tuple[str, str]]:
    """(program, its output) for every program named or found in a named folder (as
    ``cnc check`` finds them, cli.check.expand): a folder's programs keep their place
    below it."""
    suffix = output_suffix(target)
    pairs: list[tuple[str, str]] = []
    for given in sources:
        base = Path(given)
        found = expand((given,))  # a folder's programs, a quoted pattern's matches
        for program in found:
            rel = Path(program).relative_to(base) if base.is_dir() else Path(Path(program).name)
            pairs.append((program, str(Path(folder) / rel.with_suffix(suffix))))
    return pairs


def convert_many(
    sources: tuple[str, ...], folder: str | None, report_path: str | None, job: Job
) -> int:
    """Convert each program on its own into ``folder``, a status line each; the exit
    code: 0 all converted, 1 a program failed, 2 a program could not be read or its output
    exists without --force."""
    if not folder:
        _usage("several programs need -o FOLDER to receive their outputs", sources[0])
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise Diagnostic("IO-EXISTS", f"-o {folder} is a file, not a folder", Location(folder))
    if report_path:
        refuse_output(report_path, job.force, (*sources, job.tool_table or ""), "report")
    pairs = planned_outputs(sources, folder, job.target.name)
    if not pairs:
        raise Diagnostic("IO-OPEN", "no programs found", Location(sources[0]))
    taken: dict[str, str] = {}
    failed = io_failed = 0
    reports: list[dict[str, object]] = []
    for program, output in pairs:
        entry: dict[str, object] = {"source": program, "output": output}
        try:
            first = taken.setdefault(str(Path(output).resolve()), program)
            if first != program:
                raise Diagnostic(
                    "IO-EXISTS",
                    f"{output} is the output of {first} too; convert them separately",
                    Location(program),
                )
            outcome = convert_file(program, output, job)
        except Diagnostic as exc:
            report_error(exc)
            io_failed += exc.code.startswith("IO-")
            failed += 1
            click.echo(f"{program}: not converted ({exc.code})", err=True)
            entry.update(status="failed", code=exc.code, message=exc.message)
        else:
            entry.update(outcome.data)
            if outcome.converted:
                state = "verified" if outcome.verified else "not verified"
                click.echo(f"{program}: converted to {output} ({state})", err=True)
                entry["status"] = "converted"
            else:
                failed += 1
                click.echo(f"{program}: not converted (CONV-LOSS)", err=True)
                entry["status"] = "failed"
        reports.append(entry)
    click.echo(
        f"{len(pairs) - failed} of {len(pairs)} programs converted to {job.target.title}",
        err=True,
    )
    if report_path:
        _write_json(report_path, {"files": reports})
    if io_failed:
        return EXIT_USAGE
    return EXIT_PROGRAM_ERROR if failed else EXIT_OK
