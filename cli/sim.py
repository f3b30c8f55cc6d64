"""``cnc sim``: material removal on a height field, and what it finds (rapid into stock,
plunge with a tool that does not cut at its centre, cut deeper than the flutes).

Exit codes follow ``cnc check``: 0 no error finding, 1 an error finding or an error in the
program, 2 usage or I/O error.
"""

from __future__ import annotations

import io
import json
import os

import click
import numpy as np

from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, guarded
from cli.excerpt import render
from cli.main import verbosity
from cli.options import (
    force_option,
    machine_option,
    output_option,
    program_argument,
    tool_table_option,
    tool_units_option,
)
from cli.outputs import refuse_output
from cli.programs import (
    dialect_option,
    load_machine,
    load_tools,
    metric_tool_table,
    output_stem,
    program_commands,
)
from kernel.diagnostics import Diagnostic, Location
from kernel.machine import Machine
from kernel.stock import (
    HeightField,
    SimResult,
    StockBox,
    ToolShape,
    parse_stock,
    parse_tool_spec,
    shapes_from_table,
    simulate_removal,
)
from kernel.stock.mesh import stl_bytes, stock_mesh


def machine_stock(machine: Machine, where: str | None) -> StockBox | None:
    """``[stock] box = [X0, Y0, Z0, X1, Y1, Z1]`` of the machine profile, if any."""
    table = machine.extra.get("stock")
    if table is None:
        return None
    box = table.get("box") if isinstance(table, dict) else None
    if not isinstance(box, list):
        raise Diagnostic(
            "SIM-STOCK", "[stock] needs box = [X0, Y0, Z0, X1, Y1, Z1]", Location(where)
        )
    return parse_stock("box:" + ",".join(str(v) for v in box), Location(where))


def height_png(hf: HeightField, title: str) -> bytes:
    """The final height field as a colour map, PNG bytes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    b = hf.box
    fig, ax = plt.subplots(figsize=(7, 6))
    im = ax.imshow(
        hf.h, origin="lower", extent=(b.x0, b.x1, b.y0, b.y1), cmap="viridis", aspect="equal"
    )
    fig.colorbar(im, ax=ax, label="Z (mm)")
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y (mm)")
    ax.set_title(title)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    plt.close(fig)
    return buf.getvalue()


def _text(program: str, res: SimResult, hf: HeightField) -> str:
    lines = [
        f"{program}: removed_volume {res.removed_volume:.3f} mm3 over {res.moves} moves "
        f"({hf.nx} x {hf.ny} cells of {hf.dx:g} x {hf.dy:g} mm)"
    ]
    for f in res.findings:
        header = f"{f.location}: {f.severity.value}[{f.code}]: {f.message}"
        lines.append(render(header, f.location, f.code, None, verbosity()))
    return "\n".join(lines)


@click.command(name="sim")
@program_argument(exists=True)
@click.option("--stock", default=None, help="stock as box:X0,Y0,Z0,X1,Y1,Z1 (mm, machine)")
@tool_table_option(help="LinuxCNC .tbl or NIST tool file: flat end mills of its diameters")
@tool_units_option()
@click.option(
    "--tool",
    "tool_specs",
    multiple=True,
    help="tool shape N=flat|ball:DIAMETER[,flute=L][,nocentre] (repeatable; 0: the default)",
)
@click.option(
    "--resolution",
    type=click.FloatRange(min=0.0, min_open=True),
    default=0.5,
    show_default=True,
    help="grid cell size (mm)",
)
@click.option(
    "--chord-tol",
    type=click.FloatRange(min=0.0, min_open=True),
    default=0.005,
    show_default=True,
    help="arcs are swept as chords within this (mm)",
)
@machine_option(
    "machine_file", help="machine profile (TOML); its [stock] box is used without --stock"
)
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
@output_option(
    "out_dir",
    file_okay=False,
    dir_okay=True,
    default=None,
    help="write <name>_height.npy, <name>_height.png and <name>_stock.stl here",
)
@force_option(help="replace existing output files")
@dialect_option
@guarded
def command(
    program: str,
    stock: str | None,
    tool_table: str | None,
    tool_units: str | None,
    tool_specs: tuple[str, ...],
    resolution: float,
    chord_tol: float,
    machine_file: str | None,
    fmt: str,
    out_dir: str | None,
    force: bool,
    dialect: str | None,
) -> None:
    """Simulate 3-axis material removal of PROGRAM on a height field.

    Prints the removed volume (mm³) and the findings; exits 1 on an error finding.

    \b
    Examples:
      cnc sim part.ngc --stock box:0,0,-20,100,80,0 --resolution 0.2
      cnc sim part.ngc --machine mill.toml -t tools.tbl --tool 2=ball:6 -o out
    """
    machine = load_machine(machine_file)
    box = parse_stock(stock, Location(None)) if stock else machine_stock(machine, machine_file)
    if box is None:
        raise click.UsageError("no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or [stock] box")
    table, tool_mm = load_tools(tool_table, tool_units)
    shapes: dict[int, ToolShape] = {}
    if table:
        shapes = shapes_from_table(metric_tool_table(table, tool_mm))
    for spec in tool_specs:
        number, shape = parse_tool_spec(spec)
        shapes[number] = shape
    stem = output_stem(program)
    targets: list[str] = []
    if out_dir is not None:
        if os.path.exists(out_dir) and not os.path.isdir(out_dir):
            raise Diagnostic("IO-NOT-DIR", "output path is not a directory", Location(out_dir))
        targets = [
            os.path.join(out_dir, f"{stem}_{s}") for s in ("height.npy", "height.png", "stock.stl")
        ]
        for t in targets:
            refuse_output(t, force, (program,))
    hf = HeightField(box, resolution)
    commands = program_commands(program, table, tool_mm, dialect, machine=machine)
    res = simulate_removal(commands, hf, shapes, chord_tol)
    if fmt == "json":
        out = {
            "program": program,
            "removed_volume": res.removed_volume,
            "moves": res.moves,
            "cells": [hf.nx, hf.ny],
            "findings": [f.to_dict() for f in res.findings],
        }
        click.echo(json.dumps(out, indent=2))
    else:
        click.echo(_text(program, res, hf))
    if out_dir is not None:
        os.makedirs(out_dir, exist_ok=True)
        np.save(targets[0], hf.h)
        with open(targets[1], "wb") as fh:
            fh.write(height_png(hf, f"{stem}: stock height after the program"))
        verts, faces = stock_mesh(hf)
        with open(targets[2], "wb") as fh:
            fh.write(stl_bytes(verts, faces))
    raise SystemExit(EXIT_PROGRAM_ERROR if res.errors else EXIT_OK)
