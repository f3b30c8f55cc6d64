"""``cnc check``: lint programs against a machine profile, for people and for CI.

Examples::

    cnc check part.ngc
    cnc check --machine mill.toml --format sarif -o check.sarif programs/*.ngc
    cnc check --jobs 4 --format junit -o check.xml programs/
    cnc check --list-rules
    cnc check --scheduler tcp://head:8786 --results results/ --resume library/

Exit codes (DESIGN.md): 0 no errors, 1 errors in a program, 2 usage or I/O error. One bad
file never stops the batch.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import time
import tomllib
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path
from typing import Any

import click
import numpy as np

from cli.budget import cpu_budget
from cli.deadline import ProgramTimeout, deadline
from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, EXIT_USAGE, guarded
from cli.formats import FORMATS, CheckReport, FileResult, render
from cli.inline import InlineProgram, materialised, renamed
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
    tool_library_option,
    tool_table_option,
    tool_units_option,
)
from cli.outputs import refuse_output, write_output
from cli.programs import (
    STDIN_NAME,
    apply_limits,
    check_input,
    check_input_bulk,
    dialect_option,
    expand,
    jobs_option,
    load_tool_table,
    output_stem,
    regular_input,
    scheduler_option,
    timeout_option,
    tool_table_units,
)
from cli.sim import (
    design_triangles,
    fixtures_of,
    load_tool_library,
    machine_stock_spec,
    stock_field,
    stock_resolution,
)
from cli.stream_out import LineProgress, ResultTable, need_pyarrow, progress_wanted
from kernel.check import RULES, CheckContext, Finding, check_stream, config_from_dict
from kernel.check.config import merge_tables, spindle_range, tool_table_spec
from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, Machine, parse_machine
from kernel.stock import shapes_from_table
from kernel.stock.checkrules import SIM_RULES, SimSetup, sim_findings
from kernel.stock.mesh import top_surface
from kernel.stock.turning import is_bar, parse_bar


@dataclass(frozen=True, slots=True)
class Setup:
    """Everything a worker needs to check a file (picklable)."""

    context: CheckContext
    dialect: str | None = None  # --dialect of G-code input
    verbosity: int = 0  # -v/-q balance: whether a guessed dialect is told on stderr
    timeout: float | None = None  # per-program time limit in seconds (None: none)
    sim: SimSetup | None = None  # --stock: also simulate material removal (CNC9xx)


def _read_toml(path: str) -> dict[str, Any]:
    regular_input(path, "configuration")
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise Diagnostic("CHECK-CONFIG", f"not valid TOML: {exc}", Location(path)) from None


def load_context(
    machine_path: str | None,
    config_path: str | None,
    tool_table: str | None,
    tool_units: str | None = None,
) -> CheckContext:
    """Machine profile + ``[check]`` settings (+ ``[tool.cnc.check]``) + tool table (its
    lengths in ``tool_units`` when given, else as cli.programs.tool_table_units says)."""
    machine: Machine = DEFAULT_MACHINE
    table: dict[str, Any] = {}
    tools_file, tool_units_mm = None, 1.0
    extra: dict[str, Any] = DEFAULT_MACHINE.extra  # its [spindle] range
    if machine_path:
        regular_input(machine_path, "machine profile")
        with open(machine_path, encoding="utf-8") as fh:
            machine = parse_machine(fh.read(), machine_path)
        apply_limits(machine, machine_path)
        extra = machine.extra
        table = dict(extra.get("check", {})) if isinstance(extra.get("check"), dict) else {}
        if "check" in extra and not isinstance(extra["check"], dict):
            raise Diagnostic("CHECK-CONFIG", "[check] must be a table", machine.where.at("check"))
        tools_file, tool_units_mm = tool_table_spec(extra, machine.where)
        if tools_file:
            tools_file = str(Path(machine_path).parent / tools_file)
    if config_path is None and Path("pyproject.toml").is_file():
        config_path = "pyproject.toml"
    source = machine_path
    if config_path:
        doc = _read_toml(config_path)
        top = doc.get("tool", {}).get("cnc", {}).get("check")
        if top is None and "check" in doc and "tool" not in doc:
            top = doc["check"]
        if top is not None:
            if not isinstance(top, dict):
                raise Diagnostic(
                    "CHECK-CONFIG", "[tool.cnc.check] must be a table", Location(config_path)
                )
            table = merge_tables(table, top)
            source = config_path
    config = config_from_dict(table, set(RULES) | set(SIM_RULES), source)
    if tool_table:
        tools_file = tool_table
    tools = load_tool_table(tools_file) if tools_file else None
    if tools_file:
        tool_units_mm = tool_table_units(tools_file, tool_units, tool_units_mm)
    return CheckContext(
        machine=machine,
        config=config,
        tools=tools,
        tool_mm_per_unit=tool_units_mm,
        spindle_range=spindle_range(extra, machine.where),
        default_machine=not machine_path,
    )


_SETUP: Setup | None = None


def _init_worker(setup: Setup) -> None:
    global _SETUP
    _SETUP = setup


def check_file(path: str | InlineProgram, setup: Setup | None = None) -> FileResult:
    """Check one file; program problems become findings, I/O problems ``io_error``, a
    program past ``setup.timeout`` the finding CNC001/CHECK-TIMEOUT. The one task function
    of the local pool (``--jobs``) and of a Dask cluster (``--scheduler``). A program given
    as bytes (:class:`~cli.inline.InlineProgram`) is checked from a scratch file."""
    setup = setup or _SETUP
    assert setup is not None
    if isinstance(path, InlineProgram):
        with materialised(path) as local:
            return renamed(check_file(local, setup), local, path.name)
    t0 = time.perf_counter()
    ctx = setup.context
    try:
        with deadline(setup.timeout), cpu_budget(path):
            seen: list[canon.Command] = []
            if setup.sim is None:  # runs of plain lines judged as the reader's arrays
                bulk, text = check_input_bulk(
                    path,
                    setup.dialect,
                    setup.verbosity,
                    ctx.tools,
                    ctx.tool_mm_per_unit,
                    ctx.machine,
                    bulk=True,
                )
                findings = check_stream(bulk, ctx, path, text)
            else:
                cmds, text = check_input(
                    path,
                    setup.dialect,
                    setup.verbosity,
                    ctx.tools,
                    ctx.tool_mm_per_unit,
                    ctx.machine,
                )
                findings = check_stream(_kept(cmds, seen), ctx, path, text)
            if setup.sim is not None:
                findings = [*findings, *sim_findings(seen, setup.sim, ctx, path)]
    except ProgramTimeout:
        msg = f"stopped at the time limit of {setup.timeout:g} s (--timeout)"
        late = Finding("CNC001", Severity.ERROR, msg, Location(path), "CHECK-TIMEOUT")
        return FileResult(path, (late,), None, time.perf_counter() - t0)
    except Diagnostic as exc:  # LIMIT-TIME
        bug = Finding("CNC001", Severity.ERROR, exc.message, exc.location, exc.code)
        return FileResult(path, (bug,), None, time.perf_counter() - t0)
    except OSError as exc:
        return FileResult(path, (), exc.strerror or str(exc), time.perf_counter() - t0)
    except Exception as exc:  # noqa: BLE001 - a bug must not take the rest of the batch down
        msg = f"internal error while checking ({type(exc).__name__}: {exc}); please report it"
        bug = Finding("CNC001", Severity.ERROR, msg, Location(path), "CHECK-INTERNAL")
        return FileResult(path, (bug,), None, time.perf_counter() - t0)
    return FileResult(path, tuple(findings), None, time.perf_counter() - t0)


def _kept(
    cmds: Iterator[canon.Command], into: list[canon.Command] | None
) -> Iterator[canon.Command]:
    """The commands, also kept in ``into`` (for the simulation after the rules)."""
    for cmd in cmds:
        if into is not None:
            into.append(cmd)
        yield cmd


@dataclass(frozen=True, slots=True)
class SimOptions:
    """``cnc check``'s simulation options: ``--stock``, ``--tools``, ``--design``,
    ``--design-tol`` and ``--fixture``."""

    stock: str | None = None
    library: str | None = None
    design: str | None = None
    design_tol: float = 0.1
    fixtures: tuple[str, ...] = ()


def sim_setup(ctx: CheckContext, opts: SimOptions, machine_path: str | None) -> SimSetup | None:
    """The stock (``--stock`` or the profile's ``[stock]``: a box, a cylinder or a mesh),
    tool shapes (the tool table's flat end mills, replaced by ``--tools``), the design's
    top surface and the fixtures, or None: no simulation."""
    spec = opts.stock or machine_stock_spec(ctx.machine, machine_path)
    if spec is None:
        if opts.design or opts.fixtures:
            raise click.UsageError("--design and --fixture need a stock (--stock or [stock])")
        return None
    lathe = is_bar(spec) or ctx.machine.kind == "lathe"
    tools = ctx.tools
    shapes = shapes_from_table(tools, ctx.tool_mm_per_unit, lathe) if tools else {}
    if opts.library:
        shapes.update(load_tool_library(opts.library))
    res = stock_resolution(ctx.machine, machine_path)
    if lathe:
        where = Location(None if opts.stock else machine_path)
        if not is_bar(spec):
            raise Diagnostic(
                "SIM-STOCK", "a lathe's programs are simulated on a bar: bar:R,Z0,Z1", where
            )
        if opts.design or opts.fixtures:
            raise click.UsageError("--design and --fixture are for milling (a box stock)")
        return SimSetup(parse_bar(spec, where), shapes, float(res))
    hf = stock_field(spec, float(res), None if opts.stock else machine_path)
    design_top = None
    if opts.design:
        design_top = top_surface(design_triangles(opts.design, 0.1 * float(res)), hf)
    return SimSetup(
        hf.box,
        shapes,
        float(res),
        stock_top=hf.h if not np.all(hf.h == hf.box.z1) else None,
        design_top=design_top,
        design_tol=opts.design_tol,
        fixtures=fixtures_of(opts.fixtures, ctx.machine, machine_path, float(res)),
    )


def _check_one(path: str) -> FileResult:
    return check_file(path)


def _size(path: str) -> int:
    try:
        return os.stat(path).st_size
    except OSError:
        return 0


def _largest_first(paths: list[str]) -> list[int]:
    """Indices of ``paths``, largest file first (longest-processing-time-first), so one
    long program does not leave the other workers idle at the end."""
    return sorted(range(len(paths)), key=lambda i: -_size(paths[i]))


def iter_checks(
    paths: list[str], setup: Setup, jobs: int, scheduler: str | None = None
) -> Iterator[tuple[int, FileResult]]:
    """Check ``paths`` and yield ``(index, result)`` as each program finishes: on the Dask
    scheduler at ``scheduler`` (``local:N``: a LocalCluster), else with ``jobs`` worker
    processes (1: in this process). Every path yields exactly once."""
    if scheduler:
        from cli import fleet  # Dask only when asked for: plain start-up stays fast

        with fleet.connect(scheduler) as client:
            yield from fleet.map_stream(
                client, check_file, paths, setup, _lost, _largest_first(paths)
            )
        return
    if jobs <= 1 or len(paths) <= 1:
        for i, p in enumerate(paths):
            yield i, check_file(p, setup)
        return
    jobs = min(jobs, len(paths))
    order = _largest_first(paths)
    chunk = max(1, min(16, len(paths) // (jobs * 16)))
    with ProcessPoolExecutor(jobs, initializer=_init_worker, initargs=(setup,)) as pool:
        done = pool.map(_check_one, [paths[i] for i in order], chunksize=chunk)
        yield from zip(order, done, strict=True)


def _lost(path: str | InlineProgram, exc: BaseException) -> FileResult:
    """The row of a program the cluster gave up on (its workers kept dying)."""
    path = path.name if isinstance(path, InlineProgram) else path
    msg = f"the cluster could not check it ({type(exc).__name__}: {exc})"
    bug = Finding("CNC001", Severity.ERROR, msg, Location(path), "CLUSTER-TASK")
    return FileResult(path, (bug,))


def run_checks(
    paths: list[str], setup: Setup, jobs: int, scheduler: str | None = None
) -> list[FileResult]:
    """Check ``paths`` (see :func:`iter_checks`); input order kept."""
    by_index = dict(iter_checks(paths, setup, jobs, scheduler))
    return [by_index[i] for i in range(len(paths))]


class ResultStore:
    """``--results DIR``: one JSON file per program, written as its result arrives, so a
    batch that stops part-way can go on with ``--resume``."""

    def __init__(self, directory: str, inputs: list[str | None]) -> None:
        self.directory = directory
        os.makedirs(directory, exist_ok=True)
        # a result is stale when older than the profile, configuration or tool table
        self.newest_input = max((os.stat(p).st_mtime for p in inputs if p), default=0.0)

    def path(self, program: str) -> str:
        """``DIR/<stem>-<hash of the absolute path>.json``: one name per program."""
        key = hashlib.sha1(os.path.abspath(program).encode()).hexdigest()[:16]
        return os.path.join(self.directory, f"{output_stem(program)}-{key}.json")

    def load(self, program: str) -> FileResult | None:
        """The stored result of ``program`` if newer than it and than the profile."""
        target = self.path(program)
        try:
            stamp = os.stat(target).st_mtime
            if stamp <= max(os.stat(program).st_mtime, self.newest_input):
                return None
            with open(target, encoding="utf-8") as fh:
                doc = json.load(fh)
        except (OSError, ValueError):
            return None
        if doc.get("program") != os.path.abspath(program):
            return None
        return FileResult(
            program,
            tuple(Finding.from_dict(f) for f in doc["findings"]),
            doc.get("io_error"),
            float(doc.get("seconds", 0.0)),
        )

    def save(self, result: FileResult) -> None:
        """Write ``result`` atomically (a half-written file is never taken for a result)."""
        target = self.path(result.file)
        doc = {
            "program": os.path.abspath(result.file),
            "findings": [f.to_dict() for f in result.findings],
            "io_error": result.io_error,
            "seconds": result.seconds,
        }
        tmp = f"{target}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(doc, fh)
        os.replace(tmp, target)


def _check_all(
    paths: list[str],
    setup: Setup,
    jobs: int,
    scheduler: str | None,
    results_dir: str | None,
    resume: bool,
    *profile: str | None,
    table: str | None = None,
) -> list[FileResult]:
    """Every program's result in input order: resumed ones from ``results_dir``, the others
    checked (stored there as each arrives when ``results_dir`` is given). Each result, resumed
    or not, is also a row of the Parquet ``table`` as it arrives; progress goes to stderr."""
    store = ResultStore(results_dir, list(profile)) if results_dir else None
    results: list[FileResult | None] = [None] * len(paths)
    if store is not None and resume:
        for i, p in enumerate(paths):
            results[i] = store.load(p)
    rows = ResultTable(table) if table else None
    for r in results:
        if rows is not None and r is not None:
            rows.add(r)
    todo = [i for i, r in enumerate(results) if r is None]
    progress = LineProgress(len(todo), enabled=progress_wanted(len(todo), setup.verbosity))
    try:
        for j, res in iter_checks([paths[i] for i in todo], setup, jobs, scheduler):
            results[todo[j]] = res
            if store is not None:
                store.save(res)
            if rows is not None:
                rows.add(res)
            progress.advance()
    finally:
        progress.close()
        if rows is not None:
            rows.close()
    return [r for r in results if r is not None]


def _version() -> str:
    try:
        return metadata.version("cnc-toolchain")
    except metadata.PackageNotFoundError:
        return "0"


def _list_rules(ctx: CheckContext) -> str:
    lines = []
    for r in (*RULES.values(), *SIM_RULES.values()):
        sev = ctx.config.severity(r.id, r.severity, r.default_enabled)
        state = sev.value if sev else "off"
        lines.append(f"{r.id}  {r.name:32s} {state:8s} {r.summary}")
    return "\n".join(lines) + "\n"


@click.command("check")
@program_argument("files", nargs=-1, dir_okay=True)
@machine_option(help="Machine profile (TOML); its [check], [spindle] and [tools] tables apply.")
@click.option(
    "--config",
    "config_path",
    type=click.Path(exists=True, dir_okay=False),
    help="pyproject-style TOML with a [tool.cnc.check] table "
    "(default: ./pyproject.toml if present).",
)
@tool_table_option(help="Tool table (LinuxCNC .tbl or NIST tool file); overrides the profile's.")
@tool_units_option()
@click.option(
    "--format",
    "-f",
    "fmt",
    type=click.Choice(FORMATS),
    default="text",
    show_default=True,
    help="Output format.",
)
@dialect_option
@jobs_option
@output_option(help="Write the report to this file instead of standard output.")
@force_option(help="Replace the -o report file if it exists.")
@fail_on_option
@scheduler_option
@timeout_option
@click.option(
    "--results",
    "results_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="Also keep each program's result in DIR (one JSON per program), for --resume.",
)
@click.option(
    "--resume",
    is_flag=True,
    help="Skip programs whose --results file is newer than the program and the profile.",
)
@click.option(
    "--table",
    type=click.Path(dir_okay=False, writable=True),
    default=None,
    help="Also write every program's result as a row of this Parquet table, in row groups "
    "as results arrive (needs pyarrow; for large batches).",
)
@click.option("--list-rules", is_flag=True, help="List the rules with their effective severity.")
@click.option(
    "--stock",
    default=None,
    help="Also simulate material removal on this stock, box:X0,Y0,Z0,X1,Y1,Z1, "
    "cyl:CX,CY,R,Z0,Z1 or an STL/STEP file (rules CNC901-CNC908).",
)
@tool_library_option(help="Tool library (TOML) with the tools' shapes for the simulation.")
@design_option(
    help="Design model (STL, or STEP with cadquery): with --stock, report gouges and "
    "material left (CNC906, CNC907)."
)
@design_tol_option()
@click.option(
    "--fixture",
    "fixture_specs",
    multiple=True,
    help="A fixture for the simulation: box:..., cyl:... or an STL/STEP file (repeatable; CNC908).",
)
@guarded
def command(
    files: tuple[str, ...],
    machine_path: str | None,
    config_path: str | None,
    tool_table: str | None,
    tool_units: str | None,
    fmt: str,
    dialect: str,
    jobs: int,
    output: str | None,
    force: bool,
    scheduler: str | None,
    timeout: float,
    results_dir: str | None,
    resume: bool,
    table: str | None,
    list_rules: bool,
    fail_on: str,
    stock: str | None,
    library: str | None,
    design: str | None,
    design_tol: float,
    fixture_specs: tuple[str, ...],
) -> None:
    """Lint and verify programs without simulating them.

    FILES are G-code, canonical text or canonical JSON-lines programs (the kind is detected
    from the content) or directories of them. Rules and their ids are listed by
    --list-rules and documented in docs/check-rules.md.

    \b
    Examples:
      cnc check part.ngc
      cnc check -m mill.toml -f sarif -o check.sarif programs/
      cnc check -j 4 -f junit -o check.xml *.ngc
      cnc check --scheduler local:2 --results res/ --resume programs/
    """
    ctx = load_context(machine_path, config_path, tool_table, tool_units)
    if list_rules:
        click.echo(_list_rules(ctx), nl=False)
        return
    if not files:
        raise click.UsageError("no FILES given (see --help)")
    if resume and not results_dir:
        raise click.UsageError("--resume needs --results DIR (where the results are kept)")
    paths = expand(files)
    if STDIN_NAME in paths:  # standard input is read here, not by worker processes
        if scheduler:
            raise click.UsageError("a program on standard input (-) cannot go to --scheduler")
        jobs = 1
    if output:
        inputs = (*paths, machine_path or "", config_path or "", tool_table or "")
        refuse_output(output, force, inputs, "report file")
    if table:
        need_pyarrow(table)
        refuse_output(table, force, paths, "table")
    if jobs == 0:
        jobs = os.cpu_count() or 1
    t0 = time.perf_counter()
    opts = SimOptions(stock, library, design, design_tol, fixture_specs)
    sim = sim_setup(ctx, opts, machine_path)
    setup = Setup(ctx, dialect, verbosity(), timeout or None, sim)
    results = _check_all(
        paths,
        setup,
        jobs,
        scheduler,
        results_dir,
        resume,
        machine_path,
        config_path,
        tool_table,
        table=table,
    )
    rules = tuple(
        (r, ctx.config.severity(r.id, r.severity, r.default_enabled))
        for r in (*RULES.values(), *(SIM_RULES.values() if sim else ()))
    )
    report = CheckReport(
        tuple(results), rules, ctx.machine.name, _version(), time.perf_counter() - t0
    )
    color = (
        output is None and fmt == "text" and sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    )
    text = render(report, fmt, color=color, verbosity=verbosity())
    if output:
        write_output(output, text)
    else:
        click.echo(text, nl=False)
    if report.io_errors:
        sys.exit(EXIT_USAGE)
    failed = any(report.total(sev) for sev in Severity if failing(sev, fail_on))
    sys.exit(EXIT_PROGRAM_ERROR if failed else EXIT_OK)
