"""Turning: the stock as a revolved 2-D section, cut by a lathe insert (docs/simulation.md).

The stock is a bar about the Z axis (:class:`Bar`); its section is a **radius profile**
(:class:`TurnedProfile`): a grid of cells along Z, each holding the radius of the material
at its centre. Lathe programs work in the XZ plane with X the radius (the IR's X is always
the radius, whatever the program's diameter mode).

The insert (a :class:`~kernel.stock.tools.ToolShape` of kind ``insert``) is, in the (Z, X)
section, a rounded rectangle of width W along Z whose two lower corners have the nose
radius rn, standing on the side of +X (its holder goes up in X): an outside turning or
grooving tool cutting towards the axis. The programmed point is its imaginary tip: the
corner of its bounding box at the lowest X and lowest Z (so a straight pass at X = R turns
the diameter 2R exactly, and a facing pass at Z = z faces exactly there).

This is the milling height field turned on its side: X is the height, Z the one grid axis,
and the insert a 2-D bull nose of diameter W. Over a cell at distance rho from the insert's
centre line, its lowest X above the tip is f(rho) = 0 for rho <= W/2 - rn and
rn - sqrt(rn^2 - (rho - W/2 + rn)^2) up to W/2, convex and non-decreasing; along a line
move, g(t) = x0 + t dx + f(|s - t dz|) is convex where the cell is under the insert, so its
least value is at an end of that interval or where g'(t) = 0: f'(rho) = +-dx/dz, which on
the rounded corner is rho = W/2 - rn + rn k / sqrt(1 + k^2) (k = +-dx/dz >= 0). Exact, in
closed form, vectorised over the cells. Arcs are cut into chords within the chord
tolerance first, as for milling.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.stock.heightfield import MAX_CELLS
from kernel.stock.simulate import (
    RAPID_EPS,
    RULES,
    SimFinding,
    SimResult,
    ToolUse,
    add_air_cutting,
    machine_moves,
)
from kernel.stock.tools import INSERT_WIDTH, ToolShape

#: the insert used while no tool is loaded and for a tool given no shape: sharp, 6 mm wide
DEFAULT_INSERT = ToolShape("insert", 0.0, width=INSERT_WIDTH)


@dataclass(frozen=True, slots=True)
class Bar:
    """A round bar about the Z axis: ``radius`` (mm), from ``z0`` (the chuck's side) to
    ``z1``."""

    radius: float
    z0: float
    z1: float

    @property
    def volume(self) -> float:
        return math.pi * self.radius**2 * (self.z1 - self.z0)


def parse_bar(text: str, where: Location | None = None) -> Bar:
    """``bar:R,Z0,Z1`` -> :class:`Bar` (``SIM-STOCK`` otherwise)."""
    kind, _, rest = text.partition(":")
    try:
        values = [float(v) for v in rest.split(",")]
    except ValueError:
        values = []
    if kind.strip().lower() != "bar" or len(values) != 3 or not all(map(math.isfinite, values)):
        raise Diagnostic("SIM-STOCK", f"stock {text!r} is not bar:R,Z0,Z1", where)
    bar = Bar(*values)
    if not (bar.radius > 0 and bar.z1 > bar.z0):
        raise Diagnostic("SIM-STOCK", f"stock {text!r}: R > 0 and Z1 > Z0 needed", where)
    return bar


def is_bar(text: str) -> bool:
    """A ``--stock`` spec for the turning profile."""
    return text.strip().lower().startswith("bar:")


class TurnedProfile:
    """The bar's radius over cells along Z at ``resolution`` mm (fitted to its length)."""

    def __init__(self, bar: Bar, resolution: float) -> None:
        if not resolution > 0:
            raise Diagnostic("SIM-GRID", f"resolution {resolution} must be > 0")
        nz = max(1, round((bar.z1 - bar.z0) / resolution))
        if nz > MAX_CELLS:
            raise Diagnostic(
                "SIM-GRID", f"{nz} cells is more than {MAX_CELLS}: use a coarser --resolution"
            )
        self.bar = bar
        self.nz = nz
        self.dz = (bar.z1 - bar.z0) / nz
        self.zs = bar.z0 + (np.arange(nz) + 0.5) * self.dz
        self.r = np.full(nz, bar.radius, dtype=np.float64)

    def volume(self) -> float:
        """Material left (mm³): the revolved cells."""
        return float(math.pi * np.sum(self.r * self.r) * self.dz)

    def window(self, zmin: float, zmax: float) -> slice | None:
        """Cells whose centres lie in [zmin, zmax], or None."""
        k0 = max(0, math.ceil((zmin - self.bar.z0) / self.dz - 0.5))
        k1 = min(self.nz - 1, math.floor((zmax - self.bar.z0) / self.dz - 0.5))
        return slice(k0, k1 + 1) if k1 >= k0 else None


def insert_envelope(
    s: np.ndarray, dz: float, dx: float, x0: float, width: float, nose: float
) -> np.ndarray:
    """Lowest X of an insert (``width`` along Z, ``nose`` radius) swept by (dz, dx) from tip
    height ``x0``, over cells at Z offsets ``s`` from its centre line at the start; +inf
    where the insert never covers the cell (module docstring)."""
    half = 0.5 * width
    flat = half - nose

    def f(rho: np.ndarray) -> np.ndarray:
        e = np.clip(rho - flat, 0.0, nose)
        return nose - np.sqrt(np.maximum(nose * nose - e * e, 0.0))

    if abs(dz) <= 1e-12:
        rho = np.abs(s)
        return np.where(rho <= half, x0 + min(0.0, dx) + f(rho), np.inf)
    lo = (s - half) / dz
    hi = (s + half) / dz
    t1 = np.clip(np.minimum(lo, hi), 0.0, 1.0)
    t2 = np.clip(np.maximum(lo, hi), 0.0, 1.0)
    ok = (np.minimum(lo, hi) <= 1.0) & (np.maximum(lo, hi) >= 0.0)

    def g(t: np.ndarray) -> np.ndarray:
        return x0 + t * dx + f(np.minimum(np.abs(s - t * dz), half))

    best = np.minimum(g(t1), g(t2))
    for side in (1.0, -1.0):
        k = side * dx / dz
        if k >= 0.0:
            rho = flat + nose * k / math.sqrt(1.0 + k * k)
            ts = (s - side * rho) / dz
            best = np.minimum(best, g(np.clip(ts, t1, t2)))
    return np.where(ok, best, np.inf)


def _insert_of(tool: ToolShape, number: int, where: Location) -> ToolShape:
    if tool.kind != "insert":
        raise Diagnostic(
            "SIM-UNSUPPORTED",
            f"tool {number} is a {tool.kind} milling tool: turning needs a lathe insert "
            '(type = "insert", nose_radius, width)',
            where,
        )
    return tool


def simulate_turning(
    commands: Iterable[canon.Command],
    prof: TurnedProfile,
    tools: dict[int, ToolShape],
    chord_tol: float = 0.005,
) -> SimResult:
    """Sweep every move of a lathe program through ``prof`` (changed in place) with the
    inserts by number (tool 0's shape, or :data:`DEFAULT_INSERT`, for the others) and
    report the removed volume, each tool's share and the findings: ``SIM-RAPID-IN-STOCK``
    and ``SIM-AIR-CUTTING``. A move off the XZ plane (Y changes) is ``SIM-UNSUPPORTED``."""
    start = prof.volume()
    result = SimResult(0.0, 0)
    index: dict[tuple[str, int | None], int] = {}
    fallback = tools.get(0, DEFAULT_INSERT)
    first_use: dict[int, Location] = {}
    current, mark = -1, start
    top = prof.bar.radius

    def settle() -> None:
        nonlocal mark
        if current >= 0:
            now = prof.volume()
            result.tools[current].removed_volume += mark - now
            mark = now

    for cmd, rapid, number, pts in machine_moves(commands, chord_tol):
        loc = cmd.source or Location()
        tool = _insert_of(tools.get(number, fallback), number, loc)
        if np.ptp(pts[:, 1]) > 1e-9:
            raise Diagnostic("SIM-UNSUPPORTED", "a Y move in a turning program", loc)
        if number != current:
            settle()
            current = number
        use = result.tools.setdefault(number, ToolUse())
        first_use.setdefault(number, loc)
        result.moves += 1
        for k in range(len(pts) - 1):
            (x0, _, z0), (x1, _, z1) = pts[k], pts[k + 1]
            seg = math.hypot(x1 - x0, z1 - z0)
            if not rapid:
                use.feed_length += seg
            win = prof.window(min(z0, z1), max(z0, z1) + tool.width)
            if win is None or min(x0, x1) >= top:
                use.air_length += 0.0 if rapid else seg
                continue
            s = prof.zs[win] - (z0 + 0.5 * tool.width)
            env = insert_envelope(s, z1 - z0, x1 - x0, x0, tool.width, tool.corner_radius)
            r = prof.r[win]
            cut = (env < r - RAPID_EPS) & (r > RAPID_EPS)
            if not cut.any():
                use.air_length += 0.0 if rapid else seg
                continue
            if rapid:
                depth = np.where(cut, r - env, 0.0)
                j = int(np.argmax(depth))
                worst = float(min(depth[j], r[j]))
                zw = float(prof.zs[win][j])
                f = SimFinding(
                    "SIM-RAPID-IN-STOCK",
                    RULES["SIM-RAPID-IN-STOCK"],
                    f"rapid move into material {worst:.3f} mm deep at Z{zw:.3f} "
                    f"(radius {float(r[j]):.3f})",
                    loc,
                    worst,
                    x=float(max(env[j], 0.0)),
                    z=zw,
                )
                key = index.get(("SIM-RAPID-IN-STOCK", loc.line))
                if key is None:
                    index[("SIM-RAPID-IN-STOCK", loc.line)] = len(result.findings)
                    result.findings.append(f)
                elif worst > (result.findings[key].value or 0.0):
                    result.findings[key] = f
            np.minimum(r, np.maximum(env, 0.0), out=r)
    settle()
    add_air_cutting(result, first_use)
    result.removed_volume = start - prof.volume()
    return result


def revolved_mesh(prof: TurnedProfile, segments: int = 96) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of the turned part: the profile revolved about Z in ``segments``
    steps (a ring through each cell centre, the end rings moved to the bar's faces) and
    closed by a fan at each end; faces counter-clockwise seen from outside."""
    n, m = prof.nz, segments
    z = prof.zs.copy()
    z[0], z[-1] = prof.bar.z0, prof.bar.z1
    th = np.linspace(0.0, 2.0 * math.pi, m, endpoint=False)
    ring = np.stack(
        [
            np.outer(prof.r, np.cos(th)).ravel(),
            np.outer(prof.r, np.sin(th)).ravel(),
            np.repeat(z, m),
        ],
        axis=1,
    )
    ends = np.array([[0.0, 0.0, prof.bar.z0], [0.0, 0.0, prof.bar.z1]])
    verts = np.vstack([ring, ends])
    j = np.arange(m)
    jn = (j + 1) % m
    k = np.arange(n - 1)[:, None]
    a, b = (k * m + j).ravel(), (k * m + jn).ravel()
    c, d = ((k + 1) * m + jn).ravel(), ((k + 1) * m + j).ravel()
    side = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    lo, hi = n * m, n * m + 1
    bottom = np.column_stack([np.full(m, lo), jn, j])
    top = np.column_stack([np.full(m, hi), (n - 1) * m + j, (n - 1) * m + jn])
    return verts, np.concatenate([side, bottom, top]).astype(np.int64)


def profile_csv(prof: TurnedProfile) -> str:
    """The final profile as CSV: each cell's Z, radius and diameter (mm)."""
    rows = ["z,radius,diameter"]
    rows += [f"{z:.6f},{r:.6f},{2 * r:.6f}" for z, r in zip(prof.zs, prof.r, strict=True)]
    return "\n".join(rows) + "\n"
