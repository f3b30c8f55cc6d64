"""``cnc plan PROG``: plan and sample a program, print its cycle time and limit hits.

``PROG`` is G-code (through the interpreter) or canonical text (``*.canon``). The machine
is ``--machine M.toml`` or the built-in default mill.
"""

from __future__ import annotations

import json

import click
from rich.console import Console
from rich.table import Table

from cli.errors import guarded
from cli.programs import dialect_option, load_machine, program_commands
from kernel.machine import Machine
from kernel.report.measure import Report
from kernel.simulation import measure_program


def run(program: str, machine: Machine, dialect: str | None = None) -> Report:
    """Plan, sample and measure ``program`` (the command's work, without printing)."""
    return measure_program(program_commands(program, dialect=dialect), machine, program)


def _text(report: Report, program: str, console: Console) -> None:
    c = report.cycle
    t = Table(title=f"cycle time: {program}")
    t.add_column("activity")
    t.add_column("time [s]", justify="right")
    t.add_column("share", justify="right")
    for name, val in (
        ("cutting", c.cutting),
        ("rapid", c.rapid),
        ("dwell", c.dwell),
        ("tool change", c.tool_change),
        ("other stops", c.other),
        ("total", c.total),
    ):
        share = f"{100 * val / c.total:.1f} %" if c.total > 0 else "-"
        t.add_row(name, f"{val:.3f}", share)
    console.print(t)
    console.print(
        f"path: feed {report.feed_length:.3f} mm, rapid {report.rapid_length:.3f} mm; "
        f"{report.segments} segments, {report.samples} samples; "
        f"chord error {report.chord_error * 1000:.3f} µm"
    )
    p = Table(title="peak axis values")
    p.add_column("axis")
    p.add_column("velocity [mm/s]", justify="right")
    p.add_column("acceleration [mm/s²]", justify="right")
    p.add_column("jerk [mm/s³]", justify="right")
    for a in report.peak_velocity:
        p.add_row(
            a.upper(),
            f"{report.peak_velocity[a]:.3f}",
            f"{report.peak_acceleration[a]:.3f}",
            f"{report.peak_jerk[a]:.1f}",
        )
    console.print(p)
    if not report.hits:
        console.print("no limit hits")
        return
    h = Table(title=f"limit hits ({report.hits_total})")
    for col in ("line", "time [s]", "axis", "limit", "value", "bound", "samples"):
        h.add_column(col)
    for hit in report.hits:
        h.add_row(
            f"{program}:{hit.line}",
            f"{hit.time:.3f}",
            hit.axis.upper(),
            hit.kind,
            f"{hit.value:.4f}",
            f"{hit.limit:.4f}",
            str(hit.samples),
        )
    console.print(h)


@click.command(name="plan")
@click.argument("program", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--machine",
    "machine_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="machine profile (TOML); default: built-in 3-axis mill",
)
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
@dialect_option
@guarded
def command(program: str, machine_file: str | None, fmt: str, dialect: str) -> None:
    """Plan PROGRAM: cycle-time breakdown, path lengths, peak axis values, limit hits.

    PROGRAM is G-code, STEP-NC, canonical text or JSON lines (told apart by content).

    \b
    Examples:
      cnc plan part.ngc
      cnc plan part.ngc --machine mill.toml --format json > plan.json
      cnc plan ex1.stp
    """
    report = run(program, load_machine(machine_file), dialect)
    if fmt == "json":
        click.echo(json.dumps({"program": program, **report.to_dict()}, indent=2))
    else:
        _text(report, program, Console())
