"""``cnc trace PROG -o DIR``: simulate a program through acc/dec and servo, write traces.

Writes ``DIR/<name>_trace.<csv|npz|parquet>`` (columns in docs/traces.md),
``DIR/<name>_summary.json`` (largest following and contour errors and where), and with
``--plot`` ``DIR/<name>_<axis>.png`` per axis and ``DIR/<name>_xy.png``. Existing files are
never replaced without ``--force``.
"""

from __future__ import annotations

import json
import os

import click

from cli.errors import guarded
from cli.options import (
    force_option,
    machine_option,
    output_option,
    program_argument,
    tool_library_option,
    tool_table_option,
    tool_units_option,
)
from cli.outputs import open_output, refuse_output, replacing
from cli.programs import dialect_option, machine_tools, output_stem, program_commands
from kernel.diagnostics import Diagnostic, Location


@click.command(name="trace")
@program_argument(exists=True)
@output_option(
    "out_dir",
    file_okay=False,
    dir_okay=True,
    required=True,
    help="directory for traces and plots (created if missing)",
)
@machine_option("machine_file", help="machine profile (TOML); default: built-in 3-axis mill")
@tool_table_option(help="tool table (LinuxCNC .tbl or NIST tool file); overrides the profile's")
@tool_units_option()
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "npz", "parquet"]),
    default="csv",
    show_default=True,
    help="trace file format",
)
@click.option("--plot", is_flag=True, help="also write PNG plots per axis and of the XY path")
@force_option(help="replace existing output files")
@click.option(
    "--chunk",
    type=click.IntRange(min=1),
    default=65_536,
    show_default=True,
    help="rows simulated and written at a time (bounds memory)",
)
@click.option(
    "--stock",
    default=None,
    help="stock as box:X0,Y0,Z0,X1,Y1,Z1, cyl:... or an STL/STEP file (as cnc sim): add the "
    "removed_mm3 and mrr_mm3_s columns from a height-field simulation",
)
@tool_library_option(
    help="tool library (TOML) with the tools' shapes for --stock (docs/simulation.md)"
)
@click.option(
    "--resolution",
    type=click.FloatRange(min=0.0, min_open=True),
    default=0.5,
    show_default=True,
    help="grid cell size of the --stock simulation (mm)",
)
@dialect_option
@guarded
def command(
    program: str,
    out_dir: str,
    machine_file: str | None,
    tool_table: str | None,
    tool_units: str | None,
    fmt: str,
    plot: bool,
    force: bool,
    chunk: int,
    stock: str | None,
    library: str | None,
    resolution: float,
    dialect: str,
) -> None:
    """Simulate PROGRAM through acc/dec and the servo loops; write per-axis traces to DIR.

    Also writes DIR/<name>_summary.json (largest following and contour errors, where they
    happen) and, with --plot, PNG plots per axis and of the XY path.

    \b
    Examples:
      cnc trace part.ngc -o traces --plot
      cnc trace part.ngc -o traces --format npz --machine mill.toml
      cnc trace part.ngc -o traces --stock box:0,0,-20,100,80,0 --tools lib.toml
    """
    import numpy as np

    from cli.programs import metric_tool_table
    from cli.sim import stock_field, tool_shapes
    from kernel import simulate
    from kernel.report.trace import REMOVAL, XYZ, column_dtypes, columns
    from kernel.report.trace_writers import open_writer
    from kernel.stock import simulate_removal
    from kernel.stock.removal import RemovalMeter
    from kernel.stock.turning import is_bar

    machine, tools, tool_mm = machine_tools(machine_file, tool_table, tool_units)
    stem = output_stem(program)
    trace_path = os.path.join(out_dir, f"{stem}_trace.{fmt}")
    summary_path = os.path.join(out_dir, f"{stem}_summary.json")
    plot_paths = {a: os.path.join(out_dir, f"{stem}_{a}.png") for a in machine.axis_names}
    xy_path = os.path.join(out_dir, f"{stem}_xy.png")
    targets = [trace_path, summary_path]
    if plot:
        targets += [*plot_paths.values(), xy_path]
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise Diagnostic("IO-NOT-DIR", "output path is not a directory", Location(out_dir))
    for t in targets:
        refuse_output(t, force, (program, machine_file or "", tool_table or ""))
    if fmt == "parquet":  # fail before the simulation, not after it
        from importlib.util import find_spec

        if find_spec("pyarrow") is None:
            raise Diagnostic(
                "IO-PARQUET",
                "Parquet output needs pyarrow, which is not installed; use --format csv or npz",
                Location(trace_path),
            )
    if stock is not None and is_bar(stock):
        raise click.UsageError("--stock for the removal columns is a milling stock, not a bar")
    hf = stock_field(stock, resolution) if stock is not None else None
    commands = list(program_commands(program, tools, tool_mm, dialect, machine=machine))
    result = simulate(commands, machine, program)
    samples = result.samples
    trace = result.servo(chunk)
    meter = None
    if hf is not None:
        metric = metric_tool_table(tools, tool_mm) if tools else None
        shapes = tool_shapes(metric, library, ())
        removal = simulate_removal(commands, hf, shapes, track_volume=True)
        meter = RemovalMeter(
            removal.move_volumes or {}, result.path.segments, trace.commanded().period
        )
    os.makedirs(out_dir, exist_ok=True)
    names = columns(samples.axes, meter is not None)
    data = None
    if plot:
        from kernel.report.plots import PlotData

        data = PlotData(samples.axes, total_rows=trace.rows)
    rows = 0
    with replacing(trace_path) as tmp:
        dtypes = column_dtypes(samples.axes, meter is not None)
        writer = open_writer(fmt, tmp, names, True, trace.rows, dtypes)
        try:
            for table in trace.chunks():
                if meter is not None:
                    xyz = np.column_stack([table[f"{a}_cmd_pos"] for a in XYZ])
                    table[REMOVAL[0]], table[REMOVAL[1]] = meter.step(table["segment"], xyz)
                writer.write(table)
                rows += len(table["t"])
                if data is not None:
                    data.add(table)
        finally:
            writer.close()
    summary = {
        "program": program,
        "machine": machine.name,
        "rows": rows,
        "trace": trace_path,
        **trace.errors.to_dict(),
    }
    predicted = trace.predicted()
    if predicted is not None:
        summary["predicted"] = predicted
    with open_output(summary_path) as fh:
        json.dump(summary, fh, indent=2)
    written = [trace_path, summary_path]
    if data is not None:
        written += _plots(data, samples.axes, plot_paths, xy_path, stem)
    ce = trace.errors.contour
    click.echo(
        f"{rows} rows; max contour error {ce.value * 1000:.3f} µm "
        f"at {program}:{ce.line} (t = {ce.time:.3f} s)"
    )
    for a, p in trace.errors.following.items():
        unit = "deg" if a in ("a", "b", "c") else "mm"
        click.echo(
            f"  {a.upper()}: max following error {p.value:+.6f} {unit} at {program}:{p.line}"
        )
    for w in written:
        click.echo(f"wrote {w}")


def _plots(
    data: object, axes: tuple[str, ...], plot_paths: dict[str, str], xy_path: str, stem: str
) -> list[str]:
    import matplotlib.pyplot as plt

    from kernel.report.plots import PlotData, axis_figure, path_figure

    assert isinstance(data, PlotData)
    out = []
    for a in axes:
        fig = axis_figure(data, a, f"{stem}: axis {a.upper()}, commanded vs actual")
        with replacing(plot_paths[a]) as tmp:
            fig.savefig(tmp)
        plt.close(fig)
        out.append(plot_paths[a])
    if "x" in axes and "y" in axes:
        fig = path_figure(data, f"{stem}: XY path, actual coloured by contour error")
        with replacing(xy_path) as tmp:
            fig.savefig(tmp)
        plt.close(fig)
        out.append(xy_path)
    return out
