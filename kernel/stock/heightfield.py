"""The Z-map: a grid of cell-centre columns of material, and one tool swept along one line.

Each cell (i, j) holds the height of the material column at its centre, from the stock's
bottom ``z0`` up to ``h[j, i]``. A tool moving along a line removes, at every cell, what lies
above the lowest point of the swept tool over that cell (:func:`line_envelope`), computed in
closed form and vectorised over the cells of the move's bounding box:

- flat end mill of radius R: the tool's end is a disc at the tip; the lowest tip height
  over the parameters t in [0, 1] where the cell is within R of the tip in XY. Those t are an
  interval (a quadratic inequality in t) and z is linear in t, so the minimum is at one of
  its ends.
- ball end mill of radius R: the swept ball is a capsule around the segment of ball centres;
  the lowest point of a vertical line inside it is on one of the end spheres or on the
  capsule's cylinder where the contact parameter lies in [0, 1] (a quadratic in z).

Error bound of the grid: a cell stands for its centre's column, so the removed volume is
exact up to the cells the swept outline crosses: at most (outline length) x (cell diagonal /
2) x (depth) (see docs/simulation.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic, Location

#: the most cells a height field may have (memory: 8 bytes a cell, 400 MB)
MAX_CELLS = 50_000_000


@dataclass(frozen=True, slots=True)
class StockBox:
    """An axis-aligned block of material in machine coordinates (mm), or with ``radius`` > 0
    the upright cylinder of that radius inscribed in it (a turned blank on a mill)."""

    x0: float
    y0: float
    z0: float
    x1: float
    y1: float
    z1: float
    radius: float = 0.0

    @property
    def volume(self) -> float:
        if self.radius > 0:
            return math.pi * self.radius**2 * (self.z1 - self.z0)
        return (self.x1 - self.x0) * (self.y1 - self.y0) * (self.z1 - self.z0)


def parse_stock(text: str, where: Location | None = None) -> StockBox:
    """``box:X0,Y0,Z0,X1,Y1,Z1`` or ``cyl:CX,CY,R,Z0,Z1`` (an upright cylinder) ->
    :class:`StockBox` (``SIM-STOCK`` otherwise)."""
    kind, _, rest = text.partition(":")
    kind = kind.strip().lower()
    try:
        values = [float(v) for v in rest.split(",")]
    except ValueError:
        values = []
    if not all(map(math.isfinite, values)):
        values = []
    if kind == "cyl" and len(values) == 5:
        cx, cy, r, z0, z1 = values
        if not (r > 0 and z1 > z0):
            raise Diagnostic("SIM-STOCK", f"stock {text!r}: R > 0 and Z1 > Z0 needed", where)
        return StockBox(cx - r, cy - r, z0, cx + r, cy + r, z1, r)
    if kind != "box" or len(values) != 6:
        raise Diagnostic(
            "SIM-STOCK", f"stock {text!r} is not box:X0,Y0,Z0,X1,Y1,Z1 or cyl:CX,CY,R,Z0,Z1", where
        )
    box = StockBox(*values)
    if not (box.x1 > box.x0 and box.y1 > box.y0 and box.z1 > box.z0):
        raise Diagnostic("SIM-STOCK", f"stock {text!r}: each max must exceed its min", where)
    return box


class HeightField:
    """The stock box as a grid of material columns at ``resolution`` mm (cells are square
    up to the box's size being fitted by a whole number of them)."""

    def __init__(self, box: StockBox, resolution: float) -> None:
        if not resolution > 0:
            raise Diagnostic("SIM-GRID", f"resolution {resolution} must be > 0")
        nx = max(1, round((box.x1 - box.x0) / resolution))
        ny = max(1, round((box.y1 - box.y0) / resolution))
        if nx * ny > MAX_CELLS:
            raise Diagnostic(
                "SIM-GRID",
                f"{nx} x {ny} cells is more than {MAX_CELLS}: use a coarser --resolution",
            )
        self.box = box
        self.nx, self.ny = nx, ny
        self.dx = (box.x1 - box.x0) / nx
        self.dy = (box.y1 - box.y0) / ny
        self.xs = box.x0 + (np.arange(nx) + 0.5) * self.dx
        self.ys = box.y0 + (np.arange(ny) + 0.5) * self.dy
        self.h = np.full((ny, nx), box.z1, dtype=np.float64)
        if box.radius > 0:  # a cylinder: no material outside its circle
            cx, cy = 0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1)
            out = np.hypot(self.xs[None, :] - cx, self.ys[:, None] - cy) > box.radius
            self.h[out] = box.z0

    @property
    def cell_area(self) -> float:
        return self.dx * self.dy

    def volume(self) -> float:
        """Material left (mm³)."""
        return float(np.sum(self.h - self.box.z0) * self.cell_area)

    def window(
        self, xmin: float, xmax: float, ymin: float, ymax: float
    ) -> tuple[slice, slice] | None:
        """Rows and columns whose centres lie in the rectangle, or None when none does."""
        b = self.box
        i0 = max(0, math.ceil((xmin - b.x0) / self.dx - 0.5))
        i1 = min(self.nx - 1, math.floor((xmax - b.x0) / self.dx - 0.5))
        j0 = max(0, math.ceil((ymin - b.y0) / self.dy - 0.5))
        j1 = min(self.ny - 1, math.floor((ymax - b.y0) / self.dy - 0.5))
        if i1 < i0 or j1 < j0:
            return None
        return slice(j0, j1 + 1), slice(i0, i1 + 1)


def flat_envelope(
    qx: np.ndarray, qy: np.ndarray, d: tuple[float, float, float], z0: float, radius: float
) -> np.ndarray:
    """Lowest tip height of a flat end mill over cells at (qx, qy) relative to the start,
    moving by ``d`` from height ``z0``; +inf where the tool never covers the cell."""
    ddx, ddy, ddz = d
    q2 = qx * qx + qy * qy
    r2 = radius * radius
    l2 = ddx * ddx + ddy * ddy
    if l2 <= 1e-24:
        return np.where(q2 <= r2, z0 + min(0.0, ddz), np.inf)
    qd = qx * ddx + qy * ddy
    disc = qd * qd - l2 * (q2 - r2)
    root = np.sqrt(np.maximum(disc, 0.0))
    t1 = np.clip((qd - root) / l2, 0.0, 1.0)
    t2 = np.clip((qd + root) / l2, 0.0, 1.0)
    ok = (disc >= 0.0) & (qd - root <= l2) & (qd + root >= 0.0)
    return np.where(ok, z0 + np.minimum(t1 * ddz, t2 * ddz), np.inf)


def ball_envelope(
    qx: np.ndarray, qy: np.ndarray, d: tuple[float, float, float], z0: float, radius: float
) -> np.ndarray:
    """Lowest point of a ball end mill (tip ``z0`` at the start) swept by ``d`` over cells
    at (qx, qy) relative to the start: the capsule of ball centres; +inf where untouched."""
    ddx, ddy, ddz = d
    r2 = radius * radius
    cz = z0 + radius  # ball centre at the start
    q2 = qx * qx + qy * qy
    e0 = np.where(q2 <= r2, cz - np.sqrt(np.maximum(r2 - q2, 0.0)), np.inf)
    px, py = qx - ddx, qy - ddy
    p2 = px * px + py * py
    e1 = np.where(p2 <= r2, cz + ddz - np.sqrt(np.maximum(r2 - p2, 0.0)), np.inf)
    env = np.minimum(e0, e1)
    length = math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz)
    ux, uy, uz = ddx / max(length, 1e-300), ddy / max(length, 1e-300), ddz / max(length, 1e-300)
    a = ux * ux + uy * uy
    if length <= 1e-12 or a <= 1e-12:
        return env  # no move, or a vertical one: the end spheres are the whole envelope
    # vertical line (qx, qy, z) against the cylinder of radius R around the centre segment
    s0 = qx * ux + qy * uy
    b = -2.0 * s0 * uz
    c = q2 - s0 * s0 - r2
    disc = b * b - 4.0 * a * c
    z = (-b - np.sqrt(np.maximum(disc, 0.0))) / (2.0 * a)  # relative to the start centre
    t = (s0 + z * uz) / length
    hit = (disc >= 0.0) & (t >= 0.0) & (t <= 1.0)
    return np.where(hit, np.minimum(env, cz + z), env)


def _interval(
    qx: np.ndarray, qy: np.ndarray, ddx: float, ddy: float, l2: float, radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(t1, t2, ok, qd): the parameters in [0, 1] where the cell is within ``radius`` of
    the axis in XY form [t1, t2] (where ``ok``); qd = q . d_xy. Needs l2 > 0."""
    qd = qx * ddx + qy * ddy
    disc = qd * qd - l2 * (qx * qx + qy * qy - radius * radius)
    root = np.sqrt(np.maximum(disc, 0.0))
    t1 = np.clip((qd - root) / l2, 0.0, 1.0)
    t2 = np.clip((qd + root) / l2, 0.0, 1.0)
    ok = (disc >= 0.0) & (qd - root <= l2) & (qd + root >= 0.0)
    return t1, t2, ok, qd


def _rho(qx: np.ndarray, qy: np.ndarray, ddx: float, ddy: float, t: np.ndarray) -> np.ndarray:
    """XY distance of the cells from the tool axis at parameter t."""
    return np.hypot(qx - t * ddx, qy - t * ddy)


def cone_envelope(
    qx: np.ndarray,
    qy: np.ndarray,
    d: tuple[float, float, float],
    z0: float,
    radius: float,
    slope: float,
    tip_radius: float = 0.0,
) -> np.ndarray:
    """Lowest point of a drill or chamfer tool swept by ``d`` from tip height ``z0``: the
    end is z = tip + slope * max(0, rho - tip_radius) for rho <= radius; +inf where
    untouched.

    Along the move, rho(t) = |q - t d_xy| is convex in t, so g(t) = z0 + t dz +
    slope * max(0, rho - a) is convex on [t1, t2] (where the cell is under the tool). Its
    minimum is at an end, at a kink (rho = a), or where the cone part is stationary:
    dz + slope * L * u / rho = 0 with u = t L - s the along-move offset and w the
    cross-move distance, i.e. u / rho = c = -dz / (slope L), u = c w / sqrt(1 - c^2)
    (none when |c| >= 1: the cone part is monotone). g is taken at every candidate."""
    ddx, ddy, ddz = d
    l2 = ddx * ddx + ddy * ddy

    def end(rho: np.ndarray) -> np.ndarray:
        return slope * np.maximum(np.minimum(rho, radius) - tip_radius, 0.0)

    if l2 <= 1e-24:
        q = np.hypot(qx, qy)
        return np.where(q <= radius, z0 + min(0.0, ddz) + end(q), np.inf)
    t1, t2, ok, qd = _interval(qx, qy, ddx, ddy, l2, radius)
    length = math.sqrt(l2)

    def g(t: np.ndarray) -> np.ndarray:
        return z0 + t * ddz + end(_rho(qx, qy, ddx, ddy, t))

    best = np.minimum(g(t1), g(t2))
    c = -ddz / (slope * length)
    s = qd / length
    if abs(c) < 1.0:
        w = np.abs(qx * ddy - qy * ddx) / length
        ts = (s + c * w / math.sqrt(1.0 - c * c)) / length
        best = np.minimum(best, g(np.clip(ts, t1, t2)))
    if tip_radius > 0.0:
        a1, a2, _, _ = _interval(qx, qy, ddx, ddy, l2, tip_radius)
        best = np.minimum(best, g(np.clip(a1, t1, t2)))
        best = np.minimum(best, g(np.clip(a2, t1, t2)))
    return np.where(ok, best, np.inf)


def bull_envelope(
    qx: np.ndarray,
    qy: np.ndarray,
    d: tuple[float, float, float],
    z0: float,
    radius: float,
    corner: float,
    ceiling: np.ndarray | None = None,
) -> np.ndarray:
    """Lowest point of a bull-nose end mill (flat end of radius a = radius - corner, a
    torus of tube radius ``corner`` around it) swept by ``d`` from tip height ``z0``; +inf
    where untouched.

    The end's height over the tip at distance rho from the axis is f(rho) = 0 for
    rho <= a and corner - sqrt(corner^2 - (rho - a)^2) beyond: convex and non-decreasing,
    so g(t) = z0 + t dz + f(|q - t d_xy|) is convex on [t1, t2] and its minimum is where
    g'(t) = dz + f'(rho) (t L^2 - q.d) / rho changes sign. On the torus, with
    rho - a = corner sin(phi), that is tan(phi) sqrt(rho^2 - w^2) = (-dz / L) rho: a quartic
    in sin(phi) with no stable closed form, so the root of g' (increasing) is found where
    it changes sign by Newton's method safeguarded by bisection
    (:func:`kernel.stock.bullnose.bull_root`, to 2^-:data:`~kernel.stock.bullnose.BULL_STEPS`
    of the bracket), cell by cell in compiled code (numba). A level move (dz = 0) is exact:
    the lowest f is at the nearest point, t = q.d / L^2 clipped; a vertical move is the
    torus at its lower end.

    With ``ceiling`` (the material's top over the cells), cells the tool cannot reach below
    it are not iterated: there g(t) >= z0 + min(t1 dz, t2 dz) + f(w), w the cell's distance
    from the move's line, or g is above the point where its tangents at t1 and t2 cross
    (g is convex), and the ends' value (returned) is no lower than those bounds."""
    fx, fy = np.broadcast_arrays(np.atleast_2d(qx), np.atleast_2d(qy))
    shape = fx.shape
    x2 = np.atleast_2d(np.asarray(qx, dtype=np.float64))
    y2 = np.atleast_2d(np.asarray(qy, dtype=np.float64))
    if x2.shape[1] != shape[1] or (x2.shape[0] not in (1, shape[0])):
        x2 = np.ascontiguousarray(fx, dtype=np.float64)
    if y2.shape[0] != shape[0] or (y2.shape[1] not in (1, shape[1])):
        y2 = np.ascontiguousarray(fy, dtype=np.float64)
    if ceiling is None:
        ceil = np.empty((0, 0))
    else:
        ceil = np.broadcast_to(np.asarray(ceiling, dtype=np.float64), shape)
    out = np.empty(shape)
    ddx, ddy, ddz = (float(v) for v in d)
    # numba loads with the first bull nose, not with every command that imports the stock
    from kernel.stock.bullnose import bull_kernel

    bull_kernel(x2, y2, ddx, ddy, ddz, float(z0), float(radius), float(corner), ceil, out)
    return out.reshape(np.broadcast_shapes(np.shape(qx), np.shape(qy)))
