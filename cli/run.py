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

import click
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from cli.check import expand, load_context
from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded
from cli.main import verbosity
from cli.outputs import refuse_output
from cli.pipeline import RunOptions, RunResult, report_names, run_program, run_task
from cli.programs import dialect_option, jobs_option, scheduler_option, timeout_option
from cli.stream_out import LineProgress, progress_wanted
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
    return RunResult(item[0], status="error", message=str(diag))


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
    measure, servo = doc.get("measure", {}), doc.get("servo", {})
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
    return res


def _summary(results: list[RunResult], console: Console, seconds: float) -> None:
    t = Table(title=f"cnc run: {len(results)} program{'s' * (len(results) != 1)}")
    for col in (
        "program",
        "status",
        "cycle [s]",
        "samples",
        "follow [µm]",
        "contour [µm]",
        "errors",
        "warnings",
    ):
        t.add_column(col, justify="left" if col in ("program", "status") else "right")
    style = {"ok": "green", "findings": "yellow", "error": "bold red", "io-error": "bold red"}
    for r in results:
        t.add_row(
            os.path.basename(r.file),
            f"[{style[r.status]}]{r.status}[/]",
            f"{r.cycle_time:.3f}",
            str(r.samples),
            f"{r.following_error * 1000:.2f}",
            f"{r.contour_error * 1000:.2f}",
            str(r.errors),
            str(r.warnings),
        )
    console.print(t)
    for r in results:
        if r.message:
            console.print(f"{r.message}", markup=False, highlight=False)
    bad = sum(1 for r in results if r.status != "ok")
    console.print(f"{len(results) - bad} ok, {bad} with problems, {seconds:.1f} s")


@click.command("run")
@click.argument("files", nargs=-1, required=True, type=click.Path(dir_okay=True))
@click.option(
    "--machine",
    "-m",
    "machine_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Machine profile (TOML); default: the built-in 3-axis mill.",
)
@click.option(
    "--output",
    "-o",
    "out_dir",
    type=click.Path(file_okay=False),
    default="cnc-run",
    show_default=True,
    help="Directory for the reports (created if missing).",
)
@jobs_option
@click.option(
    "--html",
    is_flag=True,
    help="Also write DIR/<name>.report.html: plots, cycle time and findings, viewable offline.",
)
@click.option(
    "--traces",
    type=click.Choice(["csv", "npz"]),
    default=None,
    help="Also write each program's per-axis servo trace in this format.",
)
@click.option("--force", is_flag=True, help="Replace reports and traces that already exist.")
@scheduler_option
@timeout_option
@click.option(
    "--resume",
    is_flag=True,
    help="Skip programs whose report in DIR is newer than the program and the profile.",
)
@dialect_option
@guarded
def command(
    files: tuple[str, ...],
    machine_path: str | None,
    out_dir: str,
    jobs: int,
    html: bool,
    traces: str | None,
    force: bool,
    scheduler: str | None,
    timeout: float,
    resume: bool,
    dialect: str,
) -> None:
    """Run programs through the whole pipeline and write a report per program.

    FILES are G-code or canonical programs (detected by content) or directories of them.

    \b
    Examples:
      cnc run part.ngc -o reports/
      cnc run -m mill.toml -j 4 -o reports/ programs/
      cnc run --traces csv -o out/ part.ngc
      cnc run --html -o reports/ part.ngc
      cnc run --scheduler local:2 --resume -o reports/ programs/
    """
    ctx = load_context(machine_path, None, None)
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
    )
    paths = list(dict.fromkeys(expand(files)))  # each program once
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
        if taken:
            more = f" and {len(taken) - 1} more" if len(taken) > 1 else ""
            raise Diagnostic(
                "IO-EXISTS",
                f"report exists{more}; use --force to replace, or another -o directory",
                Location(taken[0]),
            )
    for p in paths:  # an output that is one of the programs is refused even with --force
        for t in _outputs(out_dir, names[p], opts):
            refuse_output(t, True, paths)
    os.makedirs(out_dir, exist_ok=True)
    jobs = (os.cpu_count() or 1) if jobs == 0 else jobs
    console = Console(stderr=True)
    t0 = time.perf_counter()
    todo = [p for p in paths if p not in results]
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    )
    quiet = verbosity() < 0
    live = console.is_terminal and not quiet  # else (a log): a line every N programs
    lines = LineProgress(len(todo), enabled=not live and progress_wanted(len(todo), verbosity()))
    with Progress(*columns, console=console, transient=True, disable=not live) as progress:
        files_task = progress.add_task("programs", total=len(todo))

        def step() -> None:
            progress.advance(files_task)
            lines.advance()

        if scheduler:
            items = [(p, names[p]) for p in todo]
            for i, res in _on_cluster(scheduler, items, ctx, opts):
                results[todo[i]] = res
                step()
        elif jobs <= 1 or len(todo) <= 1:
            for p in todo:
                sub = progress.add_task(f"  {os.path.basename(p)}: servo samples", total=None)

                def tick(done: int, total: int, sub: int = sub) -> None:
                    progress.update(sub, completed=done, total=total)

                results[p] = run_program(p, ctx, opts, tick, names[p])
                progress.remove_task(sub)
                step()
        else:
            with ProcessPoolExecutor(
                min(jobs, len(todo)), initializer=_init, initargs=(ctx, opts)
            ) as pool:
                futures = {pool.submit(_run_one, p, names[p]): p for p in todo}
                for fut in as_completed(futures):
                    results[futures[fut]] = fut.result()
                    step()
    ordered = [results[p] for p in paths]
    out = Console() if sys.stdout.isatty() else Console(width=160)
    _summary(ordered, out, time.perf_counter() - t0)
    if any(r.status == "io-error" for r in ordered):
        sys.exit(EXIT_USAGE)
    sys.exit(EXIT_PROGRAM_ERROR if any(r.status != "ok" for r in ordered) else EXIT_OK)


def _outputs(out_dir: str, name: str, opts: RunOptions) -> list[str]:
    """Every file ``cnc run`` writes for the program reported as ``name``."""
    out = [os.path.join(out_dir, f"{name}.report.json")]
    if opts.html:
        out.append(os.path.join(out_dir, f"{name}.report.html"))
    if opts.trace_format:
        out.append(os.path.join(out_dir, f"{name}_trace.{opts.trace_format}"))
    return out
