"""What ``cnc run --html`` adds to a program's page besides the JSON report: the backplot,
the program's text for the listing, the cut part when the profile has a ``[stock]`` box
(with ``--design``: coloured by its deviation from the design, :func:`design_part`), and
plotly.js written once beside the pages of a batch.

The drawing itself is kernel.report.backplot (pure); here the program's language, its text
and the profile are read.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass

import numpy as np

from cli.formats.html_report import PLOTLY_FILE, plotly_js
from cli.outputs import refuse_output, replacing
from cli.programs import program_language
from cli.sim import machine_stock, machine_stock_spec, stock_field
from gcode.registry import REGISTRY, canonical_name
from kernel.check import CheckContext, Finding
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.machine import Machine
from kernel.path.segments import Path
from kernel.report.backplot import (
    Backplot,
    Box,
    Mark,
    Surface,
    build_backplot,
    is_lathe,
    surface_grid,
    tool_changes,
)
from kernel.stock import HeightField, SimResult, shapes_from_table, simulate_removal
from kernel.stock.checkrules import as_check
from kernel.stock.design import Deviation, compare_design
from kernel.stock.mesh import top_surface
from kernel.stock.turning import is_bar

#: the dialects whose X words are diameters (the IR's x is the radius)
_DIAMETER_DIALECTS = frozenset(e.name for e in REGISTRY if e.lathe)
#: G7 (RS274/NGC lathe diameter mode) as a word of the program
_G7 = re.compile(r"(?<![A-Z0-9.#\[])G0*7(?![0-9.])", re.IGNORECASE)
#: cells a side of the height field simulated for the page (the surface is drawn from it)
STOCK_CELLS = 160
#: the largest program text read for the listing (bytes)
SOURCE_BYTES = 32_000_000


def read_source(program: str) -> str | None:
    """The program's text for the listing (None when it cannot be read)."""
    try:
        with open(program, "rb") as fh:
            data = fh.read(SOURCE_BYTES)
    except OSError:
        return None
    return data.decode("utf-8", errors="replace").replace("\r\n", "\n").replace("\r", "\n")


def _diameter(language: str, source: str | None) -> bool:
    """X words are diameters: a lathe dialect, or RS274/NGC's G7 in the program (outside
    comments)."""
    if language in _DIAMETER_DIALECTS:
        return True
    if source is None or language in ("canon", "jsonl", "part21"):
        return False
    text = re.sub(r"\([^)\n]*\)|;[^\n]*", "", source)
    return _G7.search(text) is not None


def _limits(machine: Machine) -> Box | None:
    """The machine's X, Y, Z travel as a box, when all three are finite."""
    try:
        axes = [machine.axis(n) for n in ("x", "y", "z")]
    except KeyError:
        return None
    lo = tuple(a.min for a in axes)
    hi = tuple(a.max for a in axes)
    if not all(math.isfinite(v) for v in (*lo, *hi)):
        return None
    return Box((lo[0], lo[1], lo[2]), (hi[0], hi[1], hi[2]))


@dataclass(frozen=True, slots=True)
class Design:
    """``cnc run --design``: the design's triangles (read once for the batch), the
    deviation accepted (``--design-tol``, mm) and the grid of the comparison (the profile's
    ``[stock] resolution``, as ``cnc check`` simulates)."""

    triangles: np.ndarray
    tol: float
    resolution: float


@dataclass(frozen=True, slots=True)
class DesignedPart:
    """The program's cut part compared with the design: the final height field, the
    deviation and the simulation with its ``SIM-GOUGE``/``SIM-LEFTOVER`` findings."""

    hf: HeightField
    deviation: Deviation
    result: SimResult
    tol: float

    def findings(self, ctx: CheckContext) -> list[Finding]:
        """The design findings as check findings (CNC906, CNC907) at the configured
        severities, listed in the report like the other findings."""
        design = [f for f in self.result.findings if f.code in ("SIM-GOUGE", "SIM-LEFTOVER")]
        return as_check(SimResult(0.0, 0, design), ctx)

    def marks(self) -> tuple[Mark, ...]:
        """The worst gouge and the worst material left beyond the tolerance, on the part."""
        out = []
        hf = self.hf
        for f in self.result.findings:
            if f.code not in ("SIM-GOUGE", "SIM-LEFTOVER") or f.x is None or f.y is None:
                continue
            i = min(max(int((f.x - hf.box.x0) / hf.dx), 0), hf.nx - 1)
            j = min(max(int((f.y - hf.box.y0) / hf.dy), 0), hf.ny - 1)
            gouge = f.code == "SIM-GOUGE"
            value = -(f.value or 0.0) if gouge else (f.value or 0.0)
            what = "worst gouge" if gouge else "worst material left"
            label = f"{what} {abs(value):.3f} mm"
            out.append(Mark(label, f.x, f.y, float(hf.h[j, i]), value, f.location.line or 0))
        return tuple(out)


def design_part(
    commands: list[canon.Command], ctx: CheckContext, program: str, design: Design
) -> DesignedPart | None:
    """Simulate ``commands`` on the profile's ``[stock]`` at ``design.resolution`` (tools
    as flat end mills of the tool table's diameters) and compare the result with the design
    (kernel.stock.design: the same rules as ``cnc check --design``); None without a
    ``[stock]`` or on a lathe."""
    spec = machine_stock_spec(ctx.machine, None)
    if spec is None or is_bar(spec) or ctx.machine.kind == "lathe":
        return None
    hf = stock_field(spec, design.resolution)  # a mesh stock: its top surface, as cnc check
    shapes = shapes_from_table(ctx.tools, ctx.tool_mm_per_unit) if ctx.tools else {}
    result = simulate_removal(commands, hf, shapes, track_moves=True)
    deviation = compare_design(hf, top_surface(design.triangles, hf), result, design.tol, program)
    return DesignedPart(hf, deviation, result, design.tol)


def program_view(
    commands: list[canon.Command],
    path: Path,
    ctx: CheckContext,
    program: str,
    dialect: str | None,
    source: str | None,
    part: DesignedPart | None = None,
) -> tuple[Backplot, Surface | None]:
    """The backplot of ``program`` and, when the profile has a ``[stock]`` box, the cut part
    (a height field of at most :data:`STOCK_CELLS` cells a side, tools as flat end mills of
    the tool table's diameters); with a design's ``part`` (:func:`design_part`), that part's
    surface coloured by its deviation from the design, the worst values marked."""
    machine = ctx.machine
    try:
        language = program_language(program, dialect, -1, machine.kind == "lathe")
    except Diagnostic:
        language = "rs274ngc"
    language = (
        canonical_name(language) if language not in ("canon", "jsonl", "part21") else language
    )
    lathe = language in _DIAMETER_DIALECTS or is_lathe(commands, path, machine.kind)
    stock = machine_stock(machine, None)
    box = Box((stock.x0, stock.y0, stock.z0), (stock.x1, stock.y1, stock.z1)) if stock else None
    view = build_backplot(
        path,
        tool_changes(commands),
        lathe=lathe,
        diameter=lathe and _diameter(language, source),
        stock=box,
        limits=_limits(machine),
    )
    surface = None
    if stock is not None and not lathe and part is not None:
        dev, b = part.deviation, part.hf.box
        surface = surface_grid(
            b.x0,
            b.y0,
            b.x1,
            b.y1,
            part.hf.h,
            STOCK_CELLS,
            dev.dev,
            part.tol,
            part.marks(),
        )
    elif stock is not None and not lathe:
        step = max(stock.x1 - stock.x0, stock.y1 - stock.y0) / STOCK_CELLS
        hf = HeightField(stock, step)
        shapes = shapes_from_table(ctx.tools, ctx.tool_mm_per_unit) if ctx.tools else {}
        simulate_removal(commands, hf, shapes)
        surface = surface_grid(stock.x0, stock.y0, stock.x1, stock.y1, hf.h)
    return view, surface


def write_library(out_dir: str, force: bool, inputs: list[str]) -> str:
    """``DIR/plotly.min.js`` for the pages of a batch, written once: an identical file is
    kept, a different one is replaced only with ``force`` (``IO-EXISTS`` otherwise), and a
    program of the batch is never overwritten. Returns the name the pages load."""
    target = os.path.join(out_dir, PLOTLY_FILE)
    text = plotly_js()
    refuse_output(target, True, inputs, "plotly.js")  # never a program of the batch
    if os.path.lexists(target) and not os.path.islink(target) and os.path.isfile(target):
        try:
            with open(target, encoding="utf-8") as fh:
                if fh.read() == text:
                    return PLOTLY_FILE
        except (OSError, UnicodeDecodeError):
            pass
    if os.path.lexists(target) and not force:
        raise Diagnostic(
            "IO-EXISTS",
            "a different plotly.min.js is there; use --force to replace it, or another -o"
            " directory",
            Location(target),
        )
    os.makedirs(out_dir, exist_ok=True)
    with replacing(target) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
    return PLOTLY_FILE
