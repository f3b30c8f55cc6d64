"""``cnc plan PROG``: plan and sample a program, print its cycle time and limit hits.

``PROG`` is G-code (through the interpreter) or canonical text (``*.canon``). The machine
is ``--machine M.toml`` or the built-in default mill.
"""

from __future__ import annotations

import json

import click
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cli.errors import guarded
from cli.main import verbosity
from cli.options import machine_option, program_argument, tool_table_option, tool_units_option
from cli.programs import dialect_option, machine_tools, program_commands
from cli.times import print_shares, shares, summed_shares, times_object
from kernel.machine import CONTROLLER_MODELS, Machine, with_controller
from kernel.report.breakdown import Share, Stretches
from kernel.report.clock import clock, fixed
from kernel.report.compare import LineTimes, Stretch, stretches_of
from kernel.report.measure import Report, per_period_peaks
from kernel.simulation import measure_program, plan_and_measure
from kernel.stream import measure_streamed, streams
from kernel.stream_scurve import measure_scurve, smoothed, smoothing_reach_of
from kernel.tooltable import ToolTable


def run(
    program: str,
    machine: Machine,
    dialect: str | None = None,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
) -> Report:
    """Plan, sample and measure ``program`` (the command's work, without printing);
    ``tools`` (lengths in units of ``tool_mm_per_unit`` mm) go to the G-code reader."""
    commands = program_commands(program, tools, tool_mm_per_unit, dialect, machine=machine)
    if streams(machine):
        return measure_streamed(commands, machine, program).report
    if smoothed(machine):
        d0 = _reach(program, machine, dialect, tools, tool_mm_per_unit)
        return measure_scurve(commands, machine, d0, program).report
    return measure_program(commands, machine, program)


def _reach(
    program: str,
    machine: Machine,
    dialect: str | None,
    tools: ToolTable | None,
    tool_mm_per_unit: float,
    on_machine: bool = True,
) -> float:
    """The S-curve smoothing reach of ``program`` (kernel.stream_scurve): a first pass over
    it, which tells nothing (the second pass tells what there is to tell)."""
    fitted = machine if on_machine else None
    again = program_commands(program, tools, tool_mm_per_unit, dialect, -1, fitted)
    return smoothing_reach_of(again, machine, program)


def run_with_times(
    program: str,
    machine: Machine,
    dialect: str | None = None,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
) -> tuple[Report, float, list[Share], list[Share]]:
    """:func:`run`, with the cycle time and the time per tool and per operation
    (cli.times). A model kernel.stream plans is planned window by window (memory does not
    grow with the program); the others whole."""
    stretches = Stretches()
    commands = program_commands(program, tools, tool_mm_per_unit, dialect, machine=machine)
    watched = stretches.watch(commands)
    if streams(machine) or smoothed(machine):
        if streams(machine):
            got = measure_streamed(watched, machine, program, stretches.tools, stretches.operations)
        else:
            d0 = _reach(program, machine, dialect, tools, tool_mm_per_unit)
            got = measure_scurve(
                watched, machine, d0, program, stretches.tools, stretches.operations
            )
        assert got.tools is not None and got.operations is not None
        per_tool, ops = summed_shares(got.tools, got.operations, stretches, program)
        return got.report, got.total_time, per_tool, ops
    plan, report = plan_and_measure(watched, machine, program)
    per_tool, ops = shares(plan, stretches, program)
    return report, plan.total_time, per_tool, ops


def compare(
    program: str,
    machine: Machine,
    models: list[str],
    dialect: str | None = None,
    tools: ToolTable | None = None,
    tool_mm_per_unit: float = 1.0,
) -> tuple[dict[str, Report], list[Stretch]]:
    """Plan ``program`` with each controller model: their reports and the stretches of
    source lines where their times differ most (kernel.report.compare). Each model is
    planned window by window (kernel.stream, kernel.stream_scurve), so memory holds one
    window of one model's plan and the models' times per source line (compact arrays)."""
    reports: dict[str, Report] = {}
    times: dict[str, LineTimes] = {}
    for name in models:
        model = with_controller(machine, model=name)
        commands = program_commands(program, tools, tool_mm_per_unit, dialect)
        times[name] = lines = LineTimes()
        if streams(model):
            got = measure_streamed(commands, model, program, watch=lines.add)
        elif smoothed(model):
            d0 = _reach(program, model, dialect, tools, tool_mm_per_unit, False)
            got = measure_scurve(commands, model, d0, program, watch=lines.add)
        else:  # every model streams; a new one is planned whole until it does
            plan, report = plan_and_measure(commands, model, program)
            lines.add(plan)
            reports[name] = report
            continue
        reports[name] = got.report
    return reports, stretches_of(times, window=5, count=5)


def _models(value: str) -> list[str]:
    names = [v.strip() for v in value.split(",") if v.strip()]
    bad = [v for v in names if v not in CONTROLLER_MODELS]
    if bad or not names:
        raise click.BadParameter(
            f"{', '.join(bad) or 'nothing'}: models are {', '.join(CONTROLLER_MODELS)}"
        )
    return list(dict.fromkeys(names))


def _compare_text(
    reports: dict[str, Report], stretches: list[Stretch], program: str, console: Console
) -> None:
    names = list(reports)
    first = reports[names[0]].cycle.total
    _title(f"cycle time by controller model: {program}", console)
    t = Table()
    t.add_column("model")
    t.add_column("total \\[m:s]", justify="right")
    t.add_column("total \\[s]", justify="right")
    t.add_column(f"/ {names[0]}", justify="right")
    t.add_column("cutting \\[s]", justify="right")
    t.add_column("rapid \\[s]", justify="right")
    for name, rep in reports.items():
        ratio = fixed(rep.cycle.total / first) if first > 0 else "-"
        t.add_row(
            name,
            clock(rep.cycle.total),
            fixed(rep.cycle.total),
            ratio,
            fixed(rep.cycle.cutting),
            fixed(rep.cycle.rapid),
        )
    console.print(t)
    if not stretches:
        console.print("the models' times do not differ")
        return
    d = Table(title="where they differ most")
    d.add_column("source lines")
    for name in names:
        d.add_column(f"{escape(name)} \\[s]", justify="right")
    d.add_column("spread \\[s]", justify="right")
    for st in stretches:
        d.add_row(
            f"{st.first}-{st.last}",
            *(fixed(st.times[n]) for n in names),
            fixed(st.spread),
        )
    console.print(d)


_UNITS = {"velocity": "mm/s", "acceleration": "mm/s²", "jerk": "mm/s³", "travel": "mm"}


def _title(text: str, console: Console) -> None:
    """A heading printed as one line the terminal may wrap but rich never breaks (a table
    title would wrap in the middle of a long file name)."""
    console.print(escape(text), soft_wrap=True, highlight=False)


def _text(
    report: Report,
    program: str,
    console: Console,
    tools: list[Share],
    ops: list[Share],
    per_period: bool = False,
) -> None:
    """The plan as text: times as m:ss, units in every header, detail under ``-v``;
    ``per_period``: the peaks are those of the positions commanded every servo period."""
    c = report.cycle
    _title(f"cycle time of {program}: {clock(c.total)} ({fixed(c.total)} s)", console)
    t = Table()
    t.add_column("activity")
    t.add_column("time \\[m:s]", justify="right")
    t.add_column("time \\[s]", justify="right")
    t.add_column("share \\[%]", justify="right")
    for name, val in (
        ("cutting", c.cutting),
        ("rapid", c.rapid),
        ("dwell", c.dwell),
        ("tool change", c.tool_change),
        ("other stops", c.other),
        ("total", c.total),
    ):
        share = fixed(100 * val / c.total, 1) if c.total > 0 else "-"
        t.add_row(name, clock(val), fixed(val), share)
    console.print(t)
    print_shares(tools, ops, console)
    console.print(
        f"path: feed {fixed(report.feed_length)} mm, rapid {fixed(report.rapid_length)} mm; "
        f"{report.segments} segments",
        highlight=False,
    )
    if verbosity() > 0:
        console.print(
            f"{report.samples} samples; chord error {fixed(report.chord_error * 1000)} µm",
            highlight=False,
        )
    p = Table(title="peak axis values" + (" (per servo period)" if per_period else ""))
    p.add_column("axis")
    p.add_column("velocity \\[mm/s]", justify="right")
    p.add_column("acceleration \\[mm/s²]", justify="right")
    p.add_column("jerk \\[mm/s³]", justify="right")
    for a in report.peak_velocity:
        p.add_row(
            a.upper(),
            fixed(report.peak_velocity[a]),
            fixed(report.peak_acceleration[a]),
            fixed(report.peak_jerk[a], 1),
        )
    console.print(p)
    if not report.hits:
        console.print("no limit hits")
        return
    _title(f"limit hits ({report.hits_total}) of {program}", console)
    h = Table()
    for col in ("line", "time [s]", "axis", "limit", "value", "bound", "unit", "samples"):
        h.add_column(escape(col))
    for hit in report.hits:
        h.add_row(
            str(hit.line),
            fixed(hit.time),
            hit.axis.upper(),
            hit.kind,
            fixed(hit.value, 4),
            fixed(hit.limit, 4),
            _UNITS.get(hit.kind, ""),
            str(hit.samples),
        )
    console.print(h)


@click.command(name="plan")
@program_argument(exists=True)
@machine_option("machine_file", help="machine profile (TOML); default: built-in 3-axis mill")
@tool_table_option(help="tool table (LinuxCNC .tbl or NIST tool file); overrides the profile's")
@tool_units_option()
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
@click.option(
    "--compare",
    "compare_models",
    default=None,
    metavar="MODELS",
    help="plan with several controller models (comma list of "
    + ", ".join(CONTROLLER_MODELS)
    + ") and show their cycle times side by side and where they differ most",
)
@dialect_option
@guarded
def command(
    program: str,
    machine_file: str | None,
    tool_table: str | None,
    tool_units: str | None,
    fmt: str,
    dialect: str,
    compare_models: str | None,
) -> None:
    """Plan PROGRAM: cycle-time breakdown, path lengths, peak axis values, limit hits.

    PROGRAM is G-code, STEP-NC, canonical text or JSON lines (told apart by content).

    \b
    Examples:
      cnc plan part.ngc
      cnc plan part.ngc --machine mill.toml --format json > plan.json
      cnc plan ex1.stp
      cnc plan part.ngc --compare linuxcnc,grbl,book
    """
    machine, tools, tool_mm = machine_tools(machine_file, tool_table, tool_units)
    if compare_models is not None:
        models = _models(compare_models)
        reports, stretches = compare(program, machine, models, dialect, tools, tool_mm)
        if fmt == "json":
            doc = {
                "program": program,
                "models": {n: r.to_dict() for n, r in reports.items()},
                "stretches": [
                    {"first_line": s.first, "last_line": s.last, "times": s.times}
                    for s in stretches
                ],
            }
            click.echo(json.dumps(doc, indent=2))
        else:
            _compare_text(reports, stretches, program, Console())
        return
    report, cycle, per_tool, ops = run_with_times(program, machine, dialect, tools, tool_mm)
    if fmt == "json":
        times = times_object(cycle, per_tool, ops)
        click.echo(json.dumps({"program": program, **report.to_dict(), "times": times}, indent=2))
    else:
        _text(report, program, Console(), per_tool, ops, per_period_peaks(machine))
