"""The backplot of a program as display traces: what the HTML report's 3-D view draws.

Pure data, no I/O: :func:`build_backplot` turns the segment table (kernel.path) into one
polyline per (tool, feed or rapid) with, per point, the source line of the move that ends
there and its programmed feed, so a viewer can say ``line 42 · F600`` on hover and find a
line's move when the listing is clicked.

- Moves: lines as their end points, arcs and helices as chords within ``chord_tol`` (at most
  15° apart so a circle looks round); holds (dwells, tool changes) draw nothing.
- Tools: the tool in the spindle is the last ``CHANGE_TOOL`` (or ``M61``'s
  ``CHANGE_TOOL_NUMBER``) before a move's IR command (:func:`tool_changes`).
- Lathe programs (:func:`is_lathe`) are drawn in the ZX plane as 2-D points ``(Z, X)``, X
  doubled when the program gives diameters (the IR's x is always the radius).
- Display budget: beyond ``budget`` points, arcs get fewer chords first (every move's end
  point is still drawn); if the moves alone are more, points on a straight line are merged,
  then points closer than a growing grid step to the one before, until the budget holds.
  :attr:`Backplot.decimated` says so, and how many points the full drawing had.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

import kernel.ir.canon as canon
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, FEED, LINE, PROBE, RAPID, Path

#: points drawn at most (the page stays responsive in a browser)
DISPLAY_BUDGET = 200_000
_MAX_STEP = math.radians(15.0)  # largest angle between two chords of an arc
_MAX_CHORDS = 256  # chords of one arc at most


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned box in machine coordinates (mm): stock or travel limits."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Polyline:
    """One display trace: the moves of one tool of one kind (feed or rapid) in program order
    (``tool`` empty before the program's first tool change).

    ``points`` is (n, 3) for a 3-D view (X, Y, Z) and (n, 2) for a lathe's (Z, X); a row of
    NaN breaks the line. ``lines[i]`` is the source line of the move ending at point i (the
    first point of a piece carries its first move's line), 0 on breaks; ``feeds[i]`` its
    programmed feed in mm/min (0 on rapids and breaks)."""

    tool: str
    rapid: bool
    points: np.ndarray
    lines: np.ndarray
    feeds: np.ndarray


@dataclass(frozen=True, slots=True)
class Backplot:
    """Everything the view draws: traces, and the stock and travel boxes as wireframes.

    ``edges`` are (m, d) point lists with NaN breaks, one per named box, in the view's
    coordinates; ``source_points`` the points of the full drawing, ``points`` those kept."""

    traces: tuple[Polyline, ...]
    lathe: bool
    diameter: bool
    edges: tuple[tuple[str, np.ndarray], ...]
    moves: int
    points: int
    source_points: int

    @property
    def decimated(self) -> bool:
        return self.points < self.source_points

    @property
    def labels(self) -> tuple[str, ...]:
        """Axis names of the view's coordinates."""
        if self.lathe:
            return ("Z", "X (diameter)" if self.diameter else "X (radius)")
        return ("X", "Y", "Z")


def tool_changes(commands: Iterable[canon.Command]) -> list[tuple[int, str]]:
    """``(IR index, tool label)`` of every tool change in ``commands``, in order."""
    out: list[tuple[int, str]] = []
    for i, cmd in enumerate(commands):
        if isinstance(cmd, canon.ChangeTool):
            out.append((i, cmd.name or str(cmd.slot)))
        elif isinstance(cmd, canon.ChangeToolNumber):
            out.append((i, str(cmd.number)))
    return out


def is_lathe(commands: Iterable[canon.Command], path: Path, kind: str = "mill") -> bool:
    """A lathe program: the machine is a lathe, or the program works in the XZ plane
    (G18) and never moves Y."""
    if kind == "lathe":
        return True
    if not any(isinstance(c, canon.SelectPlane) and c.plane == canon.Plane.XZ for c in commands):
        return False
    seg = path.segments
    if not len(seg):
        return False
    y = np.concatenate([seg["start"][:, 1], seg["end"][:, 1]])
    return bool(np.ptp(y) < 1e-9)


def _chords(seg: np.ndarray, arc: np.ndarray, chord_tol: float) -> np.ndarray:
    """Chords per arc row: the chord error within ``chord_tol``, at most 15° apart."""
    r = np.maximum(np.maximum(seg["radius"], seg["radius_end"]), 1e-9)
    ratio = np.clip(1.0 - chord_tol / r, -1.0, 1.0)
    step = np.minimum(2.0 * np.arccos(ratio), _MAX_STEP)
    n = np.ceil(np.abs(seg["sweep"]) / np.maximum(step, 1e-6))
    return np.where(arc, np.clip(n, 1, _MAX_CHORDS), 1).astype(np.int64)


def _project(p: np.ndarray, lathe: bool, diameter: bool) -> np.ndarray:
    """Machine XYZ to the view's coordinates."""
    if not lathe:
        return p
    return np.column_stack([p[:, 2], p[:, 0] * (2.0 if diameter else 1.0)])


def _box_edges(box: Box, lathe: bool, diameter: bool) -> np.ndarray:
    """A box's 12 edges (3-D) or its ZX rectangle (lathe) as one NaN-broken polyline."""
    lo, hi = np.asarray(box.lo, float), np.asarray(box.hi, float)
    nan = np.full(3, np.nan)
    if lathe:
        c = [lo, [hi[0], lo[1], lo[2]], [hi[0], lo[1], hi[2]], [lo[0], lo[1], hi[2]], lo]
        return _project(np.asarray(c, float), True, diameter)
    corner = [np.where([i & 1, i & 2, i & 4], hi, lo) for i in range(8)]
    rows = [corner[0], corner[1], corner[3], corner[2], corner[0], nan]
    rows += [corner[4], corner[5], corner[7], corner[6], corner[4], nan]
    for a in range(4):
        rows += [corner[a], corner[a + 4], nan]
    return np.asarray(rows, float)


def build_backplot(
    path: Path,
    changes: Sequence[tuple[int, str]] = (),
    *,
    lathe: bool = False,
    diameter: bool = False,
    stock: Box | None = None,
    limits: Box | None = None,
    budget: int = DISPLAY_BUDGET,
    chord_tol: float = 0.01,
) -> Backplot:
    """The display traces of ``path`` (see the module's docstring); ``changes`` from
    :func:`tool_changes` of the same IR."""
    seg = path.segments
    motion = np.isin(seg["kind"], (LINE, ARC)) & np.isin(seg["category"], (FEED, RAPID, PROBE))
    mi = np.flatnonzero(motion)
    s = seg[mi]
    edges: list[tuple[str, np.ndarray]] = []
    for name, box in (("stock", stock), ("travel limits", limits)):
        if box is not None:
            edges.append((name, _box_edges(box, lathe, diameter)))
    rapid = s["category"] == RAPID
    labels = list(dict.fromkeys(["", *(t for _, t in changes)]))  # "": before any change
    tool = np.asarray([0, *(labels.index(t) for _, t in changes)], np.int64)
    where = np.searchsorted(np.asarray([i for i, _ in changes], np.int64), s["source"])
    key = tool[where] * 2 + rapid  # one trace per (tool, feed or rapid)
    arc = s["kind"] == ARC
    n = _chords(s, arc, chord_tol)
    first = np.ones(len(s), bool)  # a segment that starts a new piece of its trace
    if len(s) > 1:
        jump = np.linalg.norm(s["start"][1:, :3] - s["end"][:-1, :3], axis=1) > 1e-9
        first[1:] = (key[1:] != key[:-1]) | jump
    last = np.append(first[1:], True)  # a piece ends before the next one starts
    full = int(n.sum() + first.sum() + last.sum())
    fixed = len(s) + int(first.sum() + last.sum())
    if full > budget and arc.any():  # fewer chords first: every move's end stays
        room = max(budget - fixed, 0)
        extra = (n - 1)[arc]
        scale = room / max(int(extra.sum()), 1)
        n[arc] = 1 + np.floor(extra * min(scale, 1.0)).astype(np.int64)
    # rows: [start of piece] + chord points (end last) + [NaN break]
    count = n + first + last
    owner = np.repeat(np.arange(len(s)), count)
    pos_in = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
    start_row = first[owner] & (pos_in == 0)
    brk = last[owner] & (pos_in == count[owner] - 1)
    k = pos_in - first[owner] + 1  # 1..n on chord points
    frac = np.where(start_row, 0.0, np.clip(k / n[owner], 0.0, 1.0))
    length = s["length"][owner]
    pos, *_ = evaluate(s, owner, frac * length, cols=[0, 1, 2])
    ends = ~start_row & ~brk & (k == n[owner])
    pos[ends] = s["end"][owner[ends], :3]  # chords end exactly on the move's end
    pos[brk] = np.nan
    view = _project(pos, lathe, diameter)
    line = np.where(brk, 0, s["line"][owner]).astype(np.int32)
    feed = np.where(rapid[owner] | brk | ~np.isfinite(s["feed"][owner]), 0.0, s["feed"][owner])
    feed = (feed * 60.0).astype(np.float32)
    rowkey = key[owner]
    if len(view) > budget:
        keep = _thin(view, rowkey, brk, budget)
        view, line, feed, rowkey, brk = view[keep], line[keep], feed[keep], rowkey[keep], brk[keep]
    traces = []
    for kv in np.unique(rowkey):
        rows = np.flatnonzero(rowkey == kv)
        if brk[rows[-1]]:
            rows = rows[:-1]  # no trailing break
        traces.append(
            Polyline(labels[int(kv) // 2], bool(kv % 2), view[rows], line[rows], feed[rows])
        )
    drawn = sum(len(t.points) for t in traces)
    whole = full - len(traces)  # the trailing break of each trace is not drawn
    return Backplot(
        tuple(traces),
        lathe,
        diameter,
        tuple(edges),
        len(s),
        drawn,
        max(whole, drawn),
    )


def _thin(view: np.ndarray, key: np.ndarray, brk: np.ndarray, budget: int) -> np.ndarray:
    """Indices of the rows kept so that at most about ``budget`` remain: interior points on a
    straight line are dropped, then points within a grid step of the previous point of the
    same piece (the step doubles until the budget holds). Breaks and piece ends stay."""
    n = len(view)
    fixed = brk.copy()  # breaks, and the points around them, always stay
    fixed[0] = fixed[-1] = True
    fixed[1:] |= brk[:-1]
    fixed[:-1] |= brk[1:]
    fixed[1:] |= key[1:] != key[:-1]
    fixed[:-1] |= key[1:] != key[:-1]
    keep = np.ones(n, bool)
    a, b = view[:-2], view[2:]
    m = view[1:-1]
    d1, d2 = m - a, b - m
    cross = np.linalg.norm(
        np.cross(d1, d2)
        if view.shape[1] == 3
        else (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])[:, None],
        axis=1,
    )
    scale = np.linalg.norm(d1, axis=1) * np.linalg.norm(d2, axis=1)
    straight = (cross <= 1e-9 * scale) & (np.einsum("ij,ij->i", d1, d2) > 0)
    straight &= np.isfinite(cross)
    keep[1:-1] &= ~straight
    keep |= fixed
    if keep.sum() <= budget:
        return np.flatnonzero(keep)
    finite = view[np.isfinite(view).all(axis=1)]
    span = float(np.max(np.ptp(finite, axis=0))) if len(finite) else 1.0
    step = max(span, 1e-6) / 4096.0
    idx = np.flatnonzero(keep)
    while True:
        cell = np.floor(view[idx] / step)
        same = np.zeros(len(idx), bool)
        same[1:] = (cell[1:] == cell[:-1]).all(axis=1) & (key[idx[1:]] == key[idx[:-1]])
        out = idx[~same | fixed[idx]]
        if len(out) <= budget or step > span:
            return out
        step *= 2.0


@dataclass(frozen=True, slots=True)
class Mark:
    """A point the 3-D view marks on the cut part: the worst gouge or material left."""

    label: str
    x: float
    y: float
    z: float
    value: float  # signed deviation (mm): below the design < 0
    line: int  # source line of the move that last cut there (0: none)


@dataclass(frozen=True, slots=True)
class Surface:
    """The cut part as a height field over ``[x0, x1] x [y0, y1]``: ``z[j, i]`` is the top of
    cell (i, j), cells of equal size (kernel.stock's grid, reduced for display).

    With a design: ``dev[j, i]`` is the signed deviation stock − design (mm, NaN where the
    design has no surface) that colours the cell, ``tol`` the accepted deviation and
    ``marks`` the worst gouge and material left."""

    x0: float
    y0: float
    x1: float
    y1: float
    z: np.ndarray
    dev: np.ndarray | None = None
    tol: float = 0.0
    marks: tuple[Mark, ...] = ()


def _blocks(a: np.ndarray, fy: int, fx: int, fill: float) -> np.ndarray:
    """``a`` padded with ``fill`` to whole blocks of ``fy`` x ``fx`` cells, as
    (rows, fy, cols, fx)."""
    ny, nx = a.shape
    pad = np.full((math.ceil(ny / fy) * fy, math.ceil(nx / fx) * fx), fill)
    pad[:ny, :nx] = a
    return pad.reshape(pad.shape[0] // fy, fy, pad.shape[1] // fx, fx)


def surface_grid(
    x0: float,
    y0: float,
    x1: float,
    y1: float,
    heights: np.ndarray,
    cells: int = 160,
    deviation: np.ndarray | None = None,
    tol: float = 0.0,
    marks: tuple[Mark, ...] = (),
) -> Surface:
    """``heights`` (rows along Y) reduced to at most ``cells`` a side for display, each new
    cell the lowest of the cells it merges so that narrow cuts stay visible; the
    ``deviation`` (same grid) reduced to the largest in size of the cells merged, so that
    a narrow gouge stays visible too (NaN only where all are)."""
    h = np.asarray(heights, float)
    dev = None if deviation is None else np.asarray(deviation, float)
    ny, nx = h.shape
    fy, fx = max(1, math.ceil(ny / cells)), max(1, math.ceil(nx / cells))
    if fy > 1 or fx > 1:
        h = _blocks(h, fy, fx, np.inf).min(axis=(1, 3))
        if dev is not None:
            b = _blocks(dev, fy, fx, np.nan)
            flat = b.transpose(0, 2, 1, 3).reshape(b.shape[0], b.shape[2], fy * fx)
            size = np.where(np.isnan(flat), -1.0, np.abs(flat))
            dev = np.take_along_axis(flat, size.argmax(axis=2)[..., None], axis=2)[..., 0]
        # the padded cells reach past the grid: the extents grow with them
        x1 = x0 + (x1 - x0) * h.shape[1] * fx / nx
        y1 = y0 + (y1 - y0) * h.shape[0] * fy / ny
    return Surface(float(x0), float(y0), float(x1), float(y1), h, dev, float(tol), marks)


#: the deviation colours: gouge (below the design), within tolerance, material left
GOUGE_RED = "#b2182b"
NEUTRAL = "#d9dee5"
LEFT_BLUE = "#2166ac"


def deviation_scale(surface: Surface) -> tuple[float, list[tuple[float, str]]]:
    """``(span, colorscale)`` for colouring ``surface.dev`` over ``[-span, span]`` (mm):
    the largest deviation in size, at least twice the tolerance; red below ``-tol``
    (deepest darkest), the neutral grey within ``±tol``, blue above ``+tol``."""
    dev = surface.dev
    finite = dev[np.isfinite(dev)] if dev is not None else np.zeros(0)
    big = float(np.abs(finite).max()) if finite.size else 0.0
    span = max(big, 2.0 * surface.tol, 1e-6)
    band = 0.5 * surface.tol / span  # the tolerance as a share of the colour axis
    lo, hi = 0.5 - band, 0.5 + band
    return span, [
        (0.0, GOUGE_RED),
        (lo, "#f4a582"),
        (lo, NEUTRAL),
        (hi, NEUTRAL),
        (hi, "#92c5de"),
        (1.0, LEFT_BLUE),
    ]
