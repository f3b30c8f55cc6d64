"""The whole pipeline for one program, as ``cnc run`` executes it per file.

interpret -> check (kernel.check) -> path -> look-ahead plan -> interpolation -> measure ->
acc/dec after interpolation and servo simulation (kernel.report.trace) -> a JSON report, and a
trace file on request. Problems of the program end the pipeline for that file with a
diagnostic in its report; they never escape to stop a batch.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from cli.budget import cpu_budget
from cli.deadline import ProgramTimeout, deadline
from cli.outputs import open_output, refuse_output, replacing
from cli.programs import check_input, output_stem
from cli.times import times_doc
from kernel.check import CheckContext, Finding, check_stream
from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir import canon
from kernel.report.breakdown import Stretches

if TYPE_CHECKING:  # the page's types: the modules load only with --html or --design
    from cli.report_view import Design, DesignedPart
    from kernel.path.segments import Path
    from kernel.report.backplot import Backplot, Surface

REPORT_SCHEMA = "cnc-run-report"
REPORT_VERSION = 1


@dataclass(frozen=True, slots=True)
class RunOptions:
    """Where reports go, whether traces are written (``trace_format``: csv or npz) and
    whether a self-contained HTML page with plots accompanies each JSON report."""

    out_dir: str
    trace_format: str | None = None
    force: bool = True
    html: bool = False
    dialect: str | None = None  # --dialect of G-code input
    verbosity: int = 0  # -v/-q balance: whether a guessed dialect is told on stderr
    timeout: float | None = None  # per-program time limit in seconds (None: none)
    html_library: str = "inline"  # plotly.js in each page, or the relative file they load
    design: Design | None = None  # --design: compare the cut part with it (needs [stock])


@dataclass(slots=True)
class Page:
    """What the HTML page shows beyond the JSON report: the trace charts (PNG plots by title
    where a caller still gives them), the backplot
    and the cut part (kernel.report.backplot), and a note when the view could not be made."""

    images: dict[str, bytes] = field(default_factory=dict)
    charts: list[dict[str, Any]] = field(default_factory=list)  # kernel.report.charts
    backplot: Backplot | None = None
    surface: Surface | None = None
    source: str | None = None  # the program's text, for the listing
    note: str = ""
    part: DesignedPart | None = None  # --design: the cut part against the design


@dataclass(slots=True)
class RunResult:
    """What the summary table shows for one file; the full report is on disk."""

    file: str
    status: str = "ok"  # ok, findings (check errors), error (stopped), io-error
    cycle_time: float = 0.0
    samples: int = 0
    following_error: float = 0.0  # mm, worst axis
    contour_error: float = 0.0  # mm
    errors: int = 0
    warnings: int = 0
    notes: int = 0
    message: str = ""
    report: str = ""
    seconds: float = 0.0
    notes: int = 0
    worst: str = ""  # the most severe finding or diagnostic, one line ("" when clean)
    measured: bool = False  # planned and measured: cycle_time is the program's
    stages: dict[str, float] = field(default_factory=dict)  # wall seconds per stage


def worst_finding(findings: list[Finding]) -> str:
    """The first finding of the highest severity, formatted (``""`` when there is none)."""
    for sev in (Severity.ERROR, Severity.WARNING, Severity.NOTE):
        first = next((f for f in findings if f.severity == sev), None)
        if first is not None:
            return first.format()
    return ""


def _stem(path: str) -> str:
    return output_stem(path)


def report_names(programs: list[str]) -> dict[str, str]:
    """Output name per program: its file stem, with ``_2``, ``_3``... when stems repeat
    (``a/part.ngc`` and ``b/part.ngc`` must not overwrite each other's reports)."""
    seen: dict[str, int] = {}
    out = {}
    for p in programs:
        stem = _stem(p)
        seen[stem] = seen.get(stem, 0) + 1
        out[p] = stem if seen[stem] == 1 else f"{stem}_{seen[stem]}"
    return out


def _simulate(
    commands: list[canon.Command],
    program: str,
    name: str,
    ctx: CheckContext,
    opts: RunOptions,
    progress: Callable[[int, int], None] | None,
    res: RunResult,
    doc: dict[str, Any],
    page: Page,
) -> None:
    """Plan, interpolate, measure and servo-simulate; fill ``res``, ``doc`` (and ``page``
    with the backplot and plots when an HTML report is wanted)."""
    from kernel import simulate
    from kernel.report.trace import column_dtypes, columns

    t0 = time.perf_counter()
    stretches = Stretches()
    result = simulate(stretches.watch(commands), ctx.machine, program)
    if opts.html:
        _view(commands, result.path, ctx, program, opts, page)
    samples = result.samples
    m = result.measure()
    doc["measure"] = m.to_dict()
    doc["times"] = times_doc(result.plan, stretches, program)
    res.cycle_time, res.samples, res.measured = m.cycle.total, m.samples, True
    t1 = time.perf_counter()
    res.stages["plan"] = t1 - t0
    trace = result.servo()
    with ExitStack() as stack:  # the trace is renamed into place once complete
        writer = None
        if opts.trace_format:
            from kernel.report.trace_writers import open_writer

            tpath = os.path.join(opts.out_dir, f"{name}_trace.{opts.trace_format}")
            refuse_output(tpath, opts.force, (program,))
            spool = stack.enter_context(replacing(tpath))
            writer = open_writer(
                opts.trace_format,
                spool,
                columns(samples.axes),
                True,
                trace.rows,
                column_dtypes(samples.axes),
            )
            doc["trace"] = tpath
        total, done = trace.rows, 0
        data = None
        if opts.html:
            from kernel.report.charts import PlotData

            data = PlotData(samples.axes, total_rows=total)
        try:
            for table in trace.chunks():
                done += len(table["t"])
                if writer is not None:
                    writer.write(table)
                if data is not None:
                    data.add(table)
                if progress is not None:
                    progress(done, total)
        finally:
            if writer is not None:
                writer.close()
    doc["servo"] = trace.errors.to_dict()
    fe = [abs(float(p.value)) for p in trace.errors.following.values()]
    res.following_error = max(fe, default=0.0)
    res.contour_error = abs(float(trace.errors.contour.value))
    t2 = time.perf_counter()
    res.stages["servo"] = t2 - t1
    if data is not None and len(data.column("t")):
        from kernel.report.charts import chart_specs

        page.charts = chart_specs(data)
        res.stages["plots"] = time.perf_counter() - t2


def _design_findings(
    commands: list[canon.Command],
    program: str,
    ctx: CheckContext,
    design: Design,
    doc: dict[str, Any],
    page: Page,
) -> list[Finding]:
    """``--design``: the cut part against the design (cli.report_view.design_part), its
    worst values in ``doc["design"]`` and its findings (CNC906, CNC907) to list with the
    check's; a program the simulation refuses is a CNC001 finding, as in ``cnc check``."""
    from cli.report_view import design_part

    try:
        part = design_part(commands, ctx, program, design)
    except Diagnostic as exc:
        return [Finding("CNC001", Severity.ERROR, exc.message, exc.location, exc.code)]
    if part is None:
        return []
    page.part = part
    doc["design"] = part.deviation.to_dict()
    return part.findings(ctx)


def _view(
    commands: list[canon.Command],
    path: Path,
    ctx: CheckContext,
    program: str,
    opts: RunOptions,
    page: Page,
) -> None:
    """The page's backplot and cut part (cli.report_view); a failure there is told on the
    page and never changes the program's status."""
    from cli.report_view import program_view

    try:
        page.backplot, page.surface = program_view(
            commands, path, ctx, program, opts.dialect, page.source, page.part
        )
    except Diagnostic as diag:
        page.note = f"No backplot: {diag}"
    except Exception as exc:  # noqa: BLE001 - the report must still be written
        page.note = f"No backplot: internal error ({type(exc).__name__}: {exc}); please report it"


def run_task(item: tuple[str, str], setup: tuple[CheckContext, RunOptions]) -> RunResult:
    """``run_program(path, ctx, opts, name=name)`` for ``item = (path, name)``: the one task
    function of ``cnc run``'s local pool (``--jobs``) and of a Dask cluster
    (``--scheduler``)."""
    path, name = item
    ctx, opts = setup
    return run_program(path, ctx, opts, name=name)


def run_program(
    program: str,
    ctx: CheckContext,
    opts: RunOptions,
    progress: Callable[[int, int], None] | None = None,
    name: str | None = None,
) -> RunResult:
    """Run ``program`` through the pipeline and write ``DIR/<name>.report.json`` (``name``
    defaults to the file stem); never raises for problems of the program
    (``progress(done, total)`` follows the servo simulation). A program past
    ``opts.timeout`` stops with the diagnostic RUN-TIMEOUT in its report; one that uses up
    its CPU budget (``--limit seconds=N``) is an error (LIMIT-TIME); the batch goes on."""
    t0 = time.perf_counter()
    name = name or _stem(program)
    try:
        with deadline(opts.timeout), cpu_budget(program):
            return _run_program(program, ctx, opts, progress, name, t0)
    except ProgramTimeout:
        diag = Diagnostic(
            "RUN-TIMEOUT",
            f"stopped at the time limit of {opts.timeout:g} s (--timeout)",
            Location(program),
        )
        res = RunResult(program, report=os.path.join(opts.out_dir, f"{name}.report.json"))
        res.status, res.message = "error", str(diag)
        res.worst = res.message
        res.seconds = time.perf_counter() - t0
        doc = {
            "schema": REPORT_SCHEMA,
            "version": REPORT_VERSION,
            "program": program,
            "machine": ctx.machine.name,
            "status": res.status,
            "diagnostics": [diag.record.to_dict()],
            "findings": [],
            "seconds": round(res.seconds, 6),
        }
        with open_output(res.report) as fh:
            json.dump(doc, fh, indent=2)
        return res
    except Diagnostic as diag:  # LIMIT-TIME
        return RunResult(program, status="error", message=str(diag), worst=str(diag))


def _run_program(
    program: str,
    ctx: CheckContext,
    opts: RunOptions,
    progress: Callable[[int, int], None] | None,
    name: str,
    t0: float,
) -> RunResult:
    """The pipeline of :func:`run_program` without the time limit."""
    res = RunResult(program, report=os.path.join(opts.out_dir, f"{name}.report.json"))
    doc: dict[str, Any] = {
        "schema": REPORT_SCHEMA,
        "version": REPORT_VERSION,
        "program": program,
        "machine": ctx.machine.name,
        "status": "ok",
        "diagnostics": [],
        "findings": [],
    }
    commands: list[canon.Command] = []
    page = Page()
    if opts.html:
        from cli.report_view import read_source

        page.source = read_source(program)

    def recording(stream: Iterator[canon.Command]) -> Iterator[canon.Command]:
        for cmd in stream:  # check the stream, keep it for the planner
            commands.append(cmd)
            yield cmd

    try:
        stream, text = check_input(
            program, opts.dialect, opts.verbosity, ctx.tools, ctx.tool_mm_per_unit, ctx.machine
        )
        findings: list[Finding] = check_stream(recording(stream), ctx, program, text)
    except OSError as exc:
        code = "IO-OPEN" if isinstance(exc, (FileNotFoundError, PermissionError)) else "IO-ERROR"
        res.status, res.message = "io-error", f"{program}: error[{code}]: {exc.strerror or exc}"
        res.worst = res.message
        res.seconds = time.perf_counter() - t0
        return res
    except Exception as exc:  # noqa: BLE001 - a bug must not take the rest of the batch down
        msg = f"internal error while checking ({type(exc).__name__}: {exc}); please report it"
        findings = [Finding("CNC001", Severity.ERROR, msg, Location(program), "CHECK-INTERNAL")]
    if opts.design is not None and not any(f.rule == "CNC001" for f in findings):
        findings += _design_findings(commands, program, ctx, opts.design, doc, page)
    doc["findings"] = [f.to_dict() for f in findings]
    res.stages["check"] = time.perf_counter() - t0
    res.errors = sum(1 for f in findings if f.severity == Severity.ERROR)
    res.warnings = sum(1 for f in findings if f.severity == Severity.WARNING)
    res.notes = sum(1 for f in findings if f.severity == Severity.NOTE)
    res.worst = worst_finding(findings)
    stop = next((f for f in findings if f.rule == "CNC001"), None)
    if stop is not None:  # the program cannot be interpreted to its end: nothing to run
        res.status, res.message = "error", stop.format()
    else:
        if res.errors:
            res.status = "findings"
            res.message = next(f.format() for f in findings if f.severity == Severity.ERROR)
        try:
            _simulate(commands, program, name, ctx, opts, progress, res, doc, page)
        except Diagnostic as diag:
            doc["diagnostics"].append(diag.record.to_dict())
            res.status, res.message = "error", str(diag)
        except Exception as exc:  # noqa: BLE001 - as above, for the planner and the servo stage
            diag = Diagnostic(
                "RUN-INTERNAL",
                f"internal error while simulating ({type(exc).__name__}: {exc}); please report it",
                Location(program),
            )
            doc["diagnostics"].append(diag.record.to_dict())
            res.status, res.message = "error", str(diag)
    doc["status"] = res.status
    if res.status == "error":
        res.worst = res.message
    res.seconds = time.perf_counter() - t0
    doc["seconds"] = round(res.seconds, 6)
    t1 = time.perf_counter()
    with open_output(res.report) as fh:
        json.dump(doc, fh, indent=2, default=_json_default)
    t2 = time.perf_counter()
    res.stages["report"] = t2 - t1
    if opts.html:
        from cli.formats.html_report import render_html

        record = json.loads(json.dumps(doc, default=_json_default))
        html = render_html(
            record,
            page.images,
            page.backplot,
            page.source,
            page.surface,
            opts.html_library,
            page.note,
            page.charts,
        )
        with open_output(os.path.join(opts.out_dir, f"{name}.report.html")) as fh:
            fh.write(html)
        res.stages["html"] = time.perf_counter() - t2
    return res


def _json_default(v: object) -> object:
    try:
        return float(v)  # numpy scalars
    except (TypeError, ValueError):
        return str(v)
