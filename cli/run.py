"""``cnc run``: the whole pipeline for a batch of programs, with progress and a summary.

Examples::

    cnc run part.ngc -o reports/
    cnc run -m mill.toml -j 4 -o reports/ programs/
    cnc run --traces csv -o out/ part.ngc
    cnc run --scheduler tcp://head:8786 --resume -o reports/ library/

Per program: interpret, check, plan, interpolate, simulate acc/dec and servos; write
``DIR/<name>.report.json`` (schema ``cnc-run-report`` version 1: status, diagnostics, check
findings, the planner's measurements, servo following and contour errors) and with
``--traces`` ``DIR/<name>_trace.<fmt>``. One failing file never stops the batch. Exit codes:
0 all programs ran clean, 1 a program had an error, 2 usage or I/O error.
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import replace

import click
from rich.console import Console

from cli.batch import BatchProgress, batch_files, print_summary, write_batch
from cli.check import expand, load_context
from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded
from cli.formats.html_report import PLOTLY_FILE
from cli.main import verbosity
from cli.options import (
    design_option,
    design_tol_option,
    fail_on_option,
    failing,
    force_option,
    machine_option,
    output_option,
    program_argument,
    tool_table_option,
    tool_units_option,
)
from cli.outputs import exists_message, refuse_output
from cli.pipeline import (
    RunOptions,
    RunResult,
    report_names,
    run_program,
    run_task,
    worst_finding,
)
from cli.programs import (
    STDIN_NAME,
    dialect_option,
    jobs_option,
    scheduler_option,
    timeout_option,
)
from cli.report_view import Design
from cli.sim import design_triangles, machine_stock, stock_resolution
from kernel.check import CheckContext, Finding
from kernel.diagnostics import Diagnostic, Location, Severity

_CTX: tuple[CheckContext, RunOptions] | None = None


def _init(ctx: CheckContext, opts: RunOptions) -> None:
    global _CTX
    _CTX = (ctx, opts)


def _run_one(path: str, name: str) -> RunResult:
    assert _CTX is not None
    return run_task((path, name), _CTX)


def _lost(item: tuple[str, str], exc: BaseException) -> RunResult:
    """The row of a program the cluster gave up on (its workers kept dying)."""
    diag = Diagnostic(
        "CLUSTER-TASK",
        f"the cluster could not run it ({type(exc).__name__}: {exc})",
        Location(item[0]),
    )
    return RunResult(item[0], status="error", message=str(diag), worst=str(diag))


def _on_cluster(
    address: str, items: list[tuple[str, str]], ctx: CheckContext, opts: RunOptions
) -> Iterator[tuple[int, RunResult]]:
    """``(index, result)`` of each program as the Dask cluster at ``address`` finishes it."""
    from cli import fleet  # Dask only when asked for: plain start-up stays fast

    with fleet.connect(address) as client:
        yield from fleet.map_stream(client, run_task, items, (ctx, opts), _lost)


def _resumed(path: str, report: str, newest_input: float) -> RunResult | None:
    """The summary row of ``path`` from its report, if the report is newer than the program
    and the profile (``--resume``); None when it must run again."""
    try:
        stamp = os.stat(report).st_mtime
        if stamp <= max(os.stat(path).st_mtime, newest_input):
            return None
        with open(report, encoding="utf-8") as fh:
            doc = json.load(fh)
    except (OSError, ValueError):
        return None
    if doc.get("program") != path or "status" not in doc:
        return None
    findings = [Finding.from_dict(f) for f in doc.get("findings", [])]
    res = RunResult(path, status=str(doc["status"]), report=report)
    res.errors = sum(1 for f in findings if f.severity == Severity.ERROR)
    res.warnings = sum(1 for f in findings if f.severity == Severity.WARNING)
    res.notes = sum(1 for f in findings if f.severity == Severity.NOTE)
    res.worst = worst_finding(findings)
    measure, servo = doc.get("measure", {}), doc.get("servo", {})
    res.measured = "cycle" in measure
    res.cycle_time = float(measure.get("cycle", {}).get("total", 0.0))
    res.samples = int(measure.get("samples", 0))
    fe = [abs(float(p["value"])) for p in servo.get("following_error", {}).values()]
    res.following_error = max(fe, default=0.0)
    res.contour_error = abs(float(servo.get("contour_error", {}).get("value", 0.0)))
    res.seconds = float(doc.get("seconds", 0.0))
    if res.status != "ok":
        diags = doc.get("diagnostics", [])
        if diags:
            d = diags[0]
            loc = Location(d.get("file"), int(d.get("line") or 0), int(d.get("column") or 0))
            res.message = str(Diagnostic(str(d["code"]), str(d["message"]), loc))
        else:
            stop = next((f for f in findings if f.rule == "CNC001"), None)
            first = stop or next((f for f in findings if f.severity == Severity.ERROR), None)
            res.message = first.format() if first else ""
        if res.status == "error" and res.message:
            res.worst = res.message
    return res


@click.command("run")
@program_argument("files", nargs=-1, required=True, dir_okay=True)
@machine_option()
@tool_table_option(help="Tool table (LinuxCNC .tbl or NIST tool file); overrides the profile's.")
@tool_units_option()
@output_option(
    "out_dir",
    file_okay=False,
    dir_okay=True,
    default="cnc-run",
    show_default=True,
    help="Directory for the reports (created if missing).",
)
@jobs_option
@click.option(
    "--html",
    is_flag=True,
    help="Also write DIR/<name>.report.html: 3-D backplot beside the listing, plots, cycle "
    "time and findings, viewable offline (a batch shares DIR/plotly.min.js).",
)
@click.option(
    "--traces",
    type=click.Choice(["csv", "npz"]),
    default=None,
    help="Also write each program's per-axis servo trace in this format.",
)
@force_option(help="Replace reports and traces that already exist.")
@fail_on_option
@scheduler_option
@timeout_option
@click.option(
    "--resume",
    is_flag=True,
    help="Skip programs whose report in DIR is newer than the program and the profile.",
)
@design_option(
    help="Design model (STL, or STEP with cadquery): compare the cut part of the profile's "
    "[stock] with it, report gouges and material left (CNC906, CNC907) and colour the "
    "--html view by the deviation."
)
@design_tol_option()
@dialect_option
@guarded
def command(
    files: tuple[str, ...],
    machine_path: str | None,
    tool_table: str | None,
    tool_units: str | None,
    out_dir: str,
    jobs: int,
    html: bool,
    traces: str | None,
    force: bool,
    scheduler: str | None,
    timeout: float,
    resume: bool,
    dialect: str,
    fail_on: str,
    design: str | None,
    design_tol: float,
) -> None:
    """Run programs through the whole pipeline and write a report per program.

    FILES are G-code or canonical programs (detected by content) or directories of them.

    \b
    Examples:
      cnc run part.ngc -o reports/
      cnc run -m mill.toml -j 4 -o reports/ programs/
      cnc run --traces csv -o out/ part.ngc
      cnc run --html -o reports/ part.ngc
      cnc run --html -m mill.toml --design part.stl -o reports/ part.ngc
      cnc run --scheduler local:2 --resume -o reports/ programs/
    """
    ctx = load_context(machine_path, None, tool_table, tool_units)
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise Diagnostic("IO-NOT-DIR", "output path is not a directory", Location(out_dir))
    opts = RunOptions(
        out_dir,
        traces,
        html=html,
        force=force or resume,
        dialect=dialect,
        verbosity=verbosity(),
        timeout=timeout or None,
        design=_design(design, design_tol, ctx, machine_path),
    )
    paths = list(dict.fromkeys(expand(files)))  # each program once
    if STDIN_NAME in paths:  # standard input is read here, not by worker processes
        if scheduler:
            raise click.UsageError("a program on standard input (-) cannot go to --scheduler")
        jobs = 1
    if html and len(paths) > 1:  # the pages of a batch share one plotly.js beside them
        opts = replace(opts, html_library=PLOTLY_FILE)
    names = report_names(paths)
    results: dict[str, RunResult] = {}
    if resume:  # a stale or missing report runs again and is replaced
        newest = os.stat(machine_path).st_mtime if machine_path else 0.0
        for p in paths:
            old = _resumed(p, os.path.join(out_dir, f"{names[p]}.report.json"), newest)
            if old is not None:
                results[p] = old
    elif not force:  # refuse before any work, so nothing of an earlier run is lost
        taken = [t for p in paths for t in _outputs(out_dir, names[p], opts) if os.path.lexists(t)]
        taken += [t for t in batch_files(out_dir) if os.path.lexists(t)]
        if taken:
            more = f" and {len(taken) - 1} more" if len(taken) > 1 else ""
            raise Diagnostic(
                "IO-EXISTS",
                exists_message("report", more),
                Location(taken[0]),
            )
    for p in paths:  # an output that is one of the programs is refused even with --force
        for t in _outputs(out_dir, names[p], opts):
            refuse_output(t, True, paths)
    for t in batch_files(out_dir):
        refuse_output(t, True, paths)
    os.makedirs(out_dir, exist_ok=True)
    if opts.html_library != "inline":
        from cli.report_view import write_library

        write_library(out_dir, force, paths)
    jobs = (os.cpu_count() or 1) if jobs == 0 else jobs
    console = Console(stderr=True)
    t0 = time.perf_counter()
    todo = [p for p in paths if p not in results]
    quiet = verbosity() < 0
    with BatchProgress(len(todo), console, quiet) as progress:
        if scheduler:
            items = [(p, names[p]) for p in todo]
            for i, res in _on_cluster(scheduler, items, ctx, opts):
                results[todo[i]] = res
                progress.finished(res)
        elif jobs <= 1 or len(todo) <= 1:
            for p in todo:
                with progress.servo(p) as tick:
                    results[p] = run_program(p, ctx, opts, tick, names[p])
                progress.finished(results[p])
        else:
            with ProcessPoolExecutor(
                min(jobs, len(todo)), initializer=_init, initargs=(ctx, opts)
            ) as pool:
                futures = {pool.submit(_run_one, p, names[p]): p for p in todo}
                for fut in as_completed(futures):
                    results[futures[fut]] = fut.result()
                    progress.finished(results[futures[fut]])
    ordered = [results[p] for p in paths]
    seconds = time.perf_counter() - t0
    write_batch(ordered, out_dir, ctx.machine.name, seconds, html)
    out = Console() if sys.stdout.isatty() else Console(width=160)
    print_summary(ordered, out, seconds)
    if any(r.status == "io-error" for r in ordered):
        sys.exit(EXIT_USAGE)
    sys.exit(EXIT_PROGRAM_ERROR if any(_fails(r, fail_on) for r in ordered) else EXIT_OK)


def _design(
    path: str | None, tol: float, ctx: CheckContext, machine_path: str | None
) -> Design | None:
    """``--design``: the design read once for the batch, on the grid of the profile's
    ``[stock]`` (a milling stock is needed: usage error without one)."""
    if path is None:
        return None
    if ctx.machine.kind == "lathe" or machine_stock(ctx.machine, machine_path) is None:
        raise click.UsageError("--design needs a milling stock: a [stock] box in the profile")
    res = stock_resolution(ctx.machine, machine_path)
    return Design(design_triangles(path, 0.1 * res), tol, res)


def _fails(result: RunResult, fail_on: str) -> bool:
    """Whether ``result`` makes ``cnc run`` exit 1 under ``--fail-on``: a program that
    stopped or has errors always; warnings and notes when ``fail_on`` reaches them."""
    if result.status != "ok":
        return True
    counts = {
        Severity.ERROR: result.errors,
        Severity.WARNING: result.warnings,
        Severity.NOTE: result.notes,
    }
    return any(n and failing(sev, fail_on) for sev, n in counts.items())


def _outputs(out_dir: str, name: str, opts: RunOptions) -> list[str]:
    """Every file ``cnc run`` writes for the program reported as ``name``."""
    out = [os.path.join(out_dir, f"{name}.report.json")]
    if opts.html:
        out.append(os.path.join(out_dir, f"{name}.report.html"))
    if opts.trace_format:
        out.append(os.path.join(out_dir, f"{name}_trace.{opts.trace_format}"))
    return out
