"""``cnc sim``: material removal on a height field, and what it finds (rapid into stock,
plunge with a tool that does not cut at its centre, cut deeper than the flutes).

Exit codes follow ``cnc check``: 0 no error finding, 1 an error finding or an error in the
program, 2 usage or I/O error.
"""

from __future__ import annotations

import io
import json
import os
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass

import click
import numpy as np

from cli.errors import EXIT_OK, EXIT_PROGRAM_ERROR, guarded
from cli.excerpt import render
from cli.main import verbosity
from cli.options import (
    design_option,
    design_tol_option,
    force_option,
    machine_option,
    output_option,
    program_argument,
    tool_library_option,
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
    program_language,
    regular_input,
)
from gcode.registry import REGISTRY
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.machine import Machine
from kernel.stock import (
    HeightField,
    SimResult,
    StockBox,
    ToolShape,
    library_from_toml,
    parse_stock,
    parse_tool_spec,
    shapes_from_table,
    simulate_removal,
)
from kernel.stock.design import Deviation, compare_design
from kernel.stock.mesh import read_stl, stl_bytes, stock_mesh, top_surface
from kernel.stock.solids import (
    Fixture,
    fixture_from_box,
    fixture_from_mesh,
    mesh_box,
    mesh_field,
)
from kernel.stock.turning import (
    TurnedProfile,
    is_bar,
    parse_bar,
    profile_csv,
    revolved_mesh,
    simulate_turning,
)
from kernel.tooltable import ToolTable

#: file suffixes of a stock, fixture or design given as a mesh
MESH_SUFFIXES = (".stl", ".step", ".stp")


def is_mesh(spec: str) -> bool:
    """A stock or fixture spec naming an STL or STEP file (not box:/cyl:)."""
    return os.path.splitext(spec)[1].lower() in MESH_SUFFIXES


def _profile_table(machine: Machine, key: str) -> object:
    return machine.extra.get(key)


def _spec_of(table: object, what: str, where: str | None, code: str) -> str:
    """A profile table's ``box = [...]``, ``cylinder = [...]`` or ``file = "..."`` (relative
    to the profile) as a ``--stock``/``--fixture`` spec."""
    if isinstance(table, dict):
        if isinstance(table.get("bar"), list):
            return "bar:" + ",".join(str(v) for v in table["bar"])
        if isinstance(table.get("cylinder"), list):
            return "cyl:" + ",".join(str(v) for v in table["cylinder"])
        if isinstance(table.get("box"), list):
            return "box:" + ",".join(str(v) for v in table["box"])
        if isinstance(table.get("file"), str):
            base = os.path.dirname(where) if where else ""
            return os.path.join(base, table["file"])
    raise Diagnostic(
        code,
        f"{what} needs box = [X0, Y0, Z0, X1, Y1, Z1], cylinder = [CX, CY, R, Z0, Z1], "
        'bar = [R, Z0, Z1] or file = "part.stl|part.step"',
        Location(where),
    )


def machine_stock_spec(machine: Machine, where: str | None) -> str | None:
    """The machine profile's ``[stock]`` as a ``--stock`` spec, if it has one."""
    table = _profile_table(machine, "stock")
    if table is None:
        return None
    return _spec_of(table, "[stock]", where, "SIM-STOCK")


def machine_stock(machine: Machine, where: str | None) -> StockBox | None:
    """``[stock] box = [X0, Y0, Z0, X1, Y1, Z1]`` or ``cylinder = [CX, CY, R, Z0, Z1]`` of
    the machine profile, if any (a mesh stock: its bounding box; a lathe's bar: None)."""
    spec = machine_stock_spec(machine, where)
    if spec is None or is_bar(spec):
        return None
    if is_mesh(spec):
        return mesh_box(mesh_triangles(spec, 0.01, "SIM-STOCK"), "SIM-STOCK", spec)
    return parse_stock(spec, Location(where))


def stock_resolution(machine: Machine, where: str | None) -> float:
    """The profile's ``[stock] resolution`` (mm, default 0.5): the grid of ``cnc check``'s
    and ``cnc run --design``'s simulation (``SIM-GRID`` when it is not > 0)."""
    table = machine.extra.get("stock")
    res = table.get("resolution", 0.5) if isinstance(table, dict) else 0.5
    if not isinstance(res, int | float) or not res > 0:
        raise Diagnostic(
            "SIM-GRID", "[stock] resolution must be > 0", machine.where.at("stock", "resolution")
        )
    return float(res)


def stock_field(spec: str, resolution: float, where: str | None = None) -> HeightField:
    """The stock's height field: a box or cylinder (``box:``/``cyl:``) or an STL/STEP file
    whose top surface sets each cell's column (docs/simulation.md)."""
    if is_mesh(spec):
        return mesh_field(
            mesh_triangles(spec, 0.1 * resolution, "SIM-STOCK"), resolution, "SIM-STOCK", spec
        )
    return HeightField(parse_stock(spec, Location(where)), resolution)


def fixtures_of(
    specs: tuple[str, ...], machine: Machine, where: str | None, resolution: float
) -> tuple[Fixture, ...]:
    """The profile's ``[[fixture]]`` tables and the ``--fixture`` specs (box:, cyl: or an
    STL/STEP file) as obstacles on grids of ``resolution``."""
    table = _profile_table(machine, "fixture")
    entries: list[tuple[str, str | None]] = []
    if table is not None:
        if not isinstance(table, list):
            raise Diagnostic("SIM-FIXTURE-SPEC", "fixtures are [[fixture]] tables", Location(where))
        for k, t in enumerate(table):
            spec = _spec_of(t, "[[fixture]]", where, "SIM-FIXTURE-SPEC")
            name = t.get("name") if isinstance(t, dict) else None
            entries.append((spec, str(name) if name else f"#{k + 1}"))
    entries += [(spec, None) for spec in specs]
    out = []
    for spec, name in entries:
        label = name or os.path.basename(spec)
        if is_mesh(spec):
            tri = mesh_triangles(spec, 0.1 * resolution, "SIM-FIXTURE-SPEC")
            out.append(fixture_from_mesh(tri, resolution, label))
            continue
        try:
            box = parse_stock(spec, Location(where))
        except Diagnostic as exc:
            raise Diagnostic("SIM-FIXTURE-SPEC", f"fixture: {exc.message}", exc.location) from None
        out.append(fixture_from_box(box, resolution, label))
    return tuple(out)


def load_tool_library(path: str) -> dict[int, ToolShape]:
    """A TOML tool library (``SIM-TOOL`` located at the file when it is not one)."""
    regular_input(path, "tool library")
    try:
        with open(path, "rb") as fh:
            doc = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise Diagnostic("SIM-TOOL", f"not valid TOML: {exc}", Location(path)) from None
    return library_from_toml(doc, path)


def tool_shapes(
    table: ToolTable | None, library: str | None, specs: tuple[str, ...], lathe: bool = False
) -> dict[int, ToolShape]:
    """Tool shapes by number: flat end mills of the tool table's diameters (``lathe``:
    inserts of half those as nose radius), replaced by the library's tools, replaced by
    ``--tool`` specs."""
    shapes: dict[int, ToolShape] = shapes_from_table(table, lathe=lathe) if table else {}
    if library:
        shapes.update(load_tool_library(library))
    for spec in specs:
        number, shape = parse_tool_spec(spec)
        shapes[number] = shape
    return shapes


def design_triangles(path: str, tolerance: float) -> np.ndarray:
    """Triangles (n, 3, 3) of a design model (:func:`mesh_triangles`)."""
    return mesh_triangles(path, tolerance, "SIM-DESIGN")


def mesh_triangles(path: str, tolerance: float, code: str) -> np.ndarray:
    """Triangles (n, 3, 3) of an STL (binary or ASCII) or STEP file (tessellated by
    cadquery, the ``geometry`` extra, within ``tolerance`` mm); ``code`` when it is
    neither or cannot be read."""
    regular_input(path, "solid")
    if os.path.splitext(path)[1].lower() in (".step", ".stp"):
        try:
            import cadquery as cq
        except ImportError:
            raise Diagnostic(
                code, "reading STEP needs cadquery (the geometry extra)", Location(path)
            ) from None
        try:
            shape = cq.importers.importStep(path).val()
        except Exception as exc:  # noqa: BLE001 - OCCT raises its own types
            raise Diagnostic(code, f"not a readable STEP file: {exc}", Location(path)) from None
        verts, faces = shape.tessellate(tolerance)
        pts = np.array([[v.x, v.y, v.z] for v in verts], dtype=np.float64)
        tris = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        return pts[tris]
    with open(path, "rb") as fh:  # OSError: an I/O error (exit 2)
        data = fh.read()
    try:
        return read_stl(data, path)
    except Diagnostic as exc:
        raise Diagnostic(code, exc.message, exc.location) from None


def _map_png(hf: HeightField, grid: np.ndarray, label: str, title: str, **style: object) -> bytes:
    """A grid over the stock's XY rectangle as a colour map with a colour bar, PNG bytes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    b = hf.box
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.set_facecolor("0.85")
    im = ax.imshow(grid, origin="lower", extent=(b.x0, b.x1, b.y0, b.y1), aspect="equal", **style)
    fig.colorbar(im, ax=ax, label=label)
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y (mm)")
    ax.set_title(title)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    plt.close(fig)
    return buf.getvalue()


def deviation_png(hf: HeightField, dev: np.ndarray, tol: float, title: str) -> bytes:
    """Stock minus design as a diverging colour map (blue: gouge, red: material left),
    grey where the design has no surface; PNG bytes."""
    span = max(float(np.nanmax(np.abs(dev))) if np.isfinite(dev).any() else 0.0, 2 * tol)
    grid = np.ma.masked_invalid(dev)
    style = {"cmap": "coolwarm", "vmin": -span, "vmax": span}
    return _map_png(hf, grid, "stock - design (mm)", title, **style)


def height_png(hf: HeightField, title: str) -> bytes:
    """The final height field as a colour map, PNG bytes."""
    return _map_png(hf, hf.h, "Z (mm)", title, cmap="viridis")


def lathe_program(program: str, dialect: str | None, machine: Machine) -> bool:
    """The machine profile is a lathe's, or the program is read in a lathe's dialect."""
    if machine.kind == "lathe":
        return True
    name = program_language(program, dialect, -1)
    return any(e.lathe and e.name == name for e in REGISTRY)


@dataclass(frozen=True, slots=True)
class Turning:
    """``cnc sim`` on a bar (the turning profile): what to simulate and where to write."""

    program: str
    spec: str
    resolution: float
    chord_tol: float
    fmt: str
    out_dir: str | None
    force: bool
    stem: str

    def run(self, commands: Iterable[canon.Command], shapes: dict[int, ToolShape]) -> None:
        """Simulate, print, write ``<stem>_profile.csv``, ``_stock.stl`` (the profile
        revolved) and ``_sim.json`` with ``-o``, and exit as ``cnc check`` does."""
        targets: list[str] = []
        if self.out_dir is not None:
            if os.path.exists(self.out_dir) and not os.path.isdir(self.out_dir):
                raise Diagnostic(
                    "IO-NOT-DIR", "output path is not a directory", Location(self.out_dir)
                )
            targets = [
                os.path.join(self.out_dir, f"{self.stem}_{s}")
                for s in ("profile.csv", "stock.stl", "sim.json")
            ]
            for t in targets:
                refuse_output(t, self.force, (self.program,))
        prof = TurnedProfile(parse_bar(self.spec), self.resolution)
        res = simulate_turning(commands, prof, shapes, self.chord_tol)
        out = {
            "program": self.program,
            "turning": True,
            "removed_volume": res.removed_volume,
            "moves": res.moves,
            "cells": [prof.nz],
            "tools": {str(n): u.to_dict() for n, u in sorted(res.tools.items())},
            "design": None,
            "findings": [f.to_dict() for f in res.findings],
        }
        if self.fmt == "json":
            click.echo(json.dumps(out, indent=2))
        else:
            click.echo(_text(self.program, res, prof, None))
        if self.out_dir is not None:
            os.makedirs(self.out_dir, exist_ok=True)
            with open(targets[0], "w", encoding="utf-8") as fh:
                fh.write(profile_csv(prof))
            with open(targets[1], "wb") as fh:
                fh.write(stl_bytes(*revolved_mesh(prof), name=b"cnc sim turned part"))
            grid = {"z0": prof.bar.z0, "dz": prof.dz}
            files = {"profile": os.path.basename(targets[0])}
            with open(targets[2], "w", encoding="utf-8") as fh:
                json.dump({**out, "grid": grid, "files": files}, fh, indent=2)
        raise SystemExit(EXIT_PROGRAM_ERROR if res.errors else EXIT_OK)


def _text(
    program: str, res: SimResult, hf: HeightField | TurnedProfile, dev: Deviation | None
) -> str:
    if isinstance(hf, TurnedProfile):
        grid = f"turning: {hf.nz} cells of {hf.dz:g} mm along Z"
    else:
        grid = f"{hf.nx} x {hf.ny} cells of {hf.dx:g} x {hf.dy:g} mm"
    lines = [
        f"{program}: removed_volume {res.removed_volume:.3f} mm3 over {res.moves} moves ({grid})"
    ]
    for n, use in sorted(res.tools.items()):
        lines.append(
            f"  tool {n}: removed {use.removed_volume:.3f} mm3, "
            f"feed path {use.feed_length:.1f} mm, {100 * use.air_share:.0f} % in air"
        )
    if dev is not None:
        lines.append(
            f"  design: worst gouge {dev.gouge:.3f} mm, worst material left {dev.leftover:.3f} mm"
        )
    for f in res.findings:
        header = f"{f.location}: {f.severity.value}[{f.code}]: {f.message}"
        lines.append(render(header, f.location, f.code, None, verbosity()))
    return "\n".join(lines)


@click.command(name="sim")
@program_argument(exists=True)
@click.option(
    "--stock",
    default=None,
    help="stock as box:X0,Y0,Z0,X1,Y1,Z1, cyl:CX,CY,R,Z0,Z1 (mm, machine), an STL/STEP file, "
    "or bar:R,Z0,Z1 for turning (a lathe profile or dialect needs a bar)",
)
@click.option(
    "--fixture",
    "fixture_specs",
    multiple=True,
    help="a fixture (obstacle): box:..., cyl:... or an STL/STEP file (repeatable; "
    "also the profile's [[fixture]] tables)",
)
@tool_table_option(help="LinuxCNC .tbl or NIST tool file: flat end mills of its diameters")
@tool_units_option()
@tool_library_option(
    help="tool library (TOML, docs/simulation.md): shapes, flutes, shank and holder"
)
@click.option(
    "--tool",
    "tool_specs",
    multiple=True,
    help="tool shape N=KIND:DIAMETER[,flute=L][,corner=R][,angle=A][,shank=D][,holder=D]"
    "[,nocentre], KIND flat|ball|bull|drill|chamfer, or a lathe insert N=insert:NOSE_RADIUS"
    "[,width=W] (repeatable; 0: the default)",
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
@design_option(help="design model (STL, or STEP with cadquery): report gouges and material left")
@design_tol_option(help="deviation from the design's top surface accepted (mm)")
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
@output_option(
    "out_dir",
    file_okay=False,
    dir_okay=True,
    default=None,
    help="write <name>_height.npy, _height.png, _stock.stl and _sim.json (the summary and the "
    "grid: cell (i, j) centre at x0 + (i + 0.5) dx, y0 + (j + 0.5) dy) here, and "
    "_deviation.npy, _deviation.png with --design",
)
@force_option(help="replace existing output files")
@dialect_option
@guarded
def command(
    program: str,
    stock: str | None,
    fixture_specs: tuple[str, ...],
    tool_table: str | None,
    tool_units: str | None,
    library: str | None,
    tool_specs: tuple[str, ...],
    resolution: float,
    chord_tol: float,
    machine_file: str | None,
    design: str | None,
    design_tol: float,
    fmt: str,
    out_dir: str | None,
    force: bool,
    dialect: str | None,
) -> None:
    """Simulate 3-axis material removal of PROGRAM on a height field, or turning on a
    bar's radius profile (a bar stock, a lathe profile or a lathe dialect).

    Prints the removed volume (mm³) and the findings; exits 1 on an error finding.

    \b
    Examples:
      cnc sim part.ngc --stock box:0,0,-20,100,80,0 --resolution 0.2
      cnc sim part.ngc --machine mill.toml -t tools.tbl --tool 2=ball:6 -o out
      cnc sim shaft.ngc --stock bar:25,-80,1 --tool 1=insert:0.8 -o out
    """
    machine = load_machine(machine_file)
    spec = stock or machine_stock_spec(machine, machine_file)
    if spec is None:
        raise click.UsageError("no stock: give --stock box:X0,Y0,Z0,X1,Y1,Z1 or [stock] box")
    lathe = is_bar(spec) or lathe_program(program, dialect, machine)
    table, tool_mm = load_tools(tool_table, tool_units)
    metric = metric_tool_table(table, tool_mm) if table else None
    shapes = tool_shapes(metric, library, tool_specs, lathe)
    stem = output_stem(program)
    if lathe:
        if not is_bar(spec):
            raise Diagnostic(
                "SIM-STOCK",
                "a lathe program is simulated on a bar: --stock bar:R,Z0,Z1 "
                "(or [stock] bar = [R, Z0, Z1])",
                Location(None if stock else machine_file),
            )
        if design or fixture_specs:
            raise click.UsageError("--design and --fixture are for milling (a box stock)")
        turn = Turning(program, spec, resolution, chord_tol, fmt, out_dir, force, stem)
        turn.run(program_commands(program, table, tool_mm, dialect, machine=machine), shapes)
        return
    targets: list[str] = []
    if out_dir is not None:
        if os.path.exists(out_dir) and not os.path.isdir(out_dir):
            raise Diagnostic("IO-NOT-DIR", "output path is not a directory", Location(out_dir))
        targets = [
            os.path.join(out_dir, f"{stem}_{s}")
            for s in (
                "height.npy",
                "height.png",
                "stock.stl",
                "sim.json",
                "deviation.npy",
                "deviation.png",
            )
        ]
        if design is None:
            targets = targets[:4]
        for t in targets:
            refuse_output(t, force, (program,))
    hf = stock_field(spec, resolution, None if stock else machine_file)
    fixtures = fixtures_of(fixture_specs, machine, machine_file, resolution)
    commands = program_commands(program, table, tool_mm, dialect, machine=machine)
    design_top = top_surface(design_triangles(design, 0.1 * resolution), hf) if design else None
    res = simulate_removal(
        commands, hf, shapes, chord_tol, track_moves=design is not None, fixtures=fixtures
    )
    deviation: Deviation | None = None
    if design_top is not None:
        deviation = compare_design(hf, design_top, res, design_tol, program)
    out = {
        "program": program,
        "removed_volume": res.removed_volume,
        "moves": res.moves,
        "cells": [hf.nx, hf.ny],
        "tools": {str(n): u.to_dict() for n, u in sorted(res.tools.items())},
        "design": deviation.to_dict() if deviation else None,
        "findings": [f.to_dict() for f in res.findings],
    }
    if fmt == "json":
        click.echo(json.dumps(out, indent=2))
    else:
        click.echo(_text(program, res, hf, deviation))
    if out_dir is not None:
        os.makedirs(out_dir, exist_ok=True)
        np.save(targets[0], hf.h)
        with open(targets[1], "wb") as fh:
            fh.write(height_png(hf, f"{stem}: stock height after the program"))
        verts, faces = stock_mesh(hf)
        with open(targets[2], "wb") as fh:
            fh.write(stl_bytes(verts, faces))
        b = hf.box
        grid = {"x0": b.x0, "y0": b.y0, "z0": b.z0, "dx": hf.dx, "dy": hf.dy}
        files = {"height": os.path.basename(targets[0])}
        if deviation is not None:
            files["deviation"] = os.path.basename(targets[4])
        with open(targets[3], "w", encoding="utf-8") as fh:
            json.dump({**out, "grid": grid, "files": files}, fh, indent=2)
        if deviation is not None:
            np.save(targets[4], deviation.dev)
            with open(targets[5], "wb") as fh:
                fh.write(deviation_png(hf, deviation.dev, design_tol, f"{stem}: stock - design"))
    raise SystemExit(EXIT_PROGRAM_ERROR if res.errors else EXIT_OK)
