"""The builder's light rows and straight runs (kernel.path.builder) -> the segment table
(kernel.path.segments), vectorised: all runs converted as whole columns, then lengths, tangents,
feeds and the ``PLAN-AXIS`` / ``PLAN-FEED`` checks on plain columns.
"""

from __future__ import annotations

from itertools import chain
from operator import attrgetter
from typing import NamedTuple

import numpy as np

import kernel.ir.canon as canon
from kernel.diagnostics import Diagnostic, Location
from kernel.interp.bulk import bulk_array
from kernel.machine import AXIS_NAMES, Machine
from kernel.path.geometry import arc_tangent
from kernel.path.segments import ARC, FEED, HOLD, LINE, MIN_LENGTH, RAPID, SEGMENT_DTYPE


# ------------------------------------------------------------------ rows of the builder
class ArcRecord(NamedTuple):
    """The exact-arc columns of one arc row (kernel.path.segments.SEGMENT_DTYPE names), mm."""

    centre: np.ndarray  # 3
    normal: np.ndarray  # 3, unit
    e1: np.ndarray  # 3, unit, centre to start
    e2: np.ndarray  # 3, normal x e1
    radius: float  # at the start
    radius_end: float
    sweep: float  # signed, rad
    axial: float  # along the normal (helix)
    length: float  # path parameter s


class Row(NamedTuple):
    """One motion or hold of the builder (kernel.path.builder), before vectorising: its
    segment-table fields plus the modal rates its feed is computed from."""

    kind: int  # LINE, ARC, HOLD
    category: int  # FEED, RAPID, ...
    start: tuple[float, ...]  # machine position, 6 axes
    end: tuple[float, ...]
    rate: float  # programmed feed (or traverse) rate, program units
    feed_mode: int  # 0 per minute, 1 inverse time, 2 per revolution
    mm: float  # mm per program unit
    spindle: float  # spindle speed, rpm
    synch: float  # feed per revolution of spindle-synchronised motion (0: none)
    override: float  # feed override factor in force
    exact_stop: bool
    blend: float  # G64 P tolerance, mm
    source: int  # IR index
    line: int  # source line (0: unknown)
    duration: float  # holds: seconds
    arc: ArcRecord | None


class StraightRun(NamedTuple):
    """Consecutive STRAIGHT_FEED / STRAIGHT_TRAVERSE commands under one modal state (the
    bulk of CAM output), converted to rows by :func:`merged_columns` all runs at once."""

    commands: list[canon.Command]
    first: int  # IR index of commands[0]
    start: tuple[float, ...]  # machine position before the run
    scale: tuple[float, ...]  # mm per program unit, then the G92 offset (6 axes)
    frame: tuple[float, ...]  # XY rotation (rad), its cos and sin, then the G5x offset
    framed: bool  # a rotation or a G5x offset is in force
    rates: tuple[float, ...]  # feed, traverse, feed mode, mm, spindle, synch, override, blend
    exact_stop: bool


_XYZABC = attrgetter("x", "y", "z", "a", "b", "c")
_SOURCE_LINE = attrgetter("source.line")
_CATEGORY = {canon.StraightFeed: FEED, canon.StraightTraverse: RAPID}


def _source_line(cmd: canon.Command) -> int:
    return cmd.source.line if cmd.source is not None else 0


def _lines(cmds: list[canon.Command]) -> np.ndarray:
    """The source line of each command (0: unknown)."""
    try:
        return np.fromiter(map(_SOURCE_LINE, cmds), np.int32, len(cmds))
    except AttributeError:  # some command without a source
        return np.fromiter(map(_source_line, cmds), np.int32, len(cmds))


def _per_row(values: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Per-run values (runs x k) for every row; one broadcast row when all runs agree bit
    for bit (the usual single modal state), which saves a wide temporary."""
    if np.all(values.view(np.uint64) == values[:1].view(np.uint64)):
        return values[:1]
    return np.repeat(values, counts, axis=0)


def _light_columns(rows: list[Row]) -> list[np.ndarray]:
    """The builder's light rows as the 15 row columns (arc records apart)."""
    n = len(rows)
    c = dict(zip(Row._fields, zip(*rows, strict=True), strict=True))  # field -> column
    return [
        np.fromiter(c["kind"], np.int8, n),
        np.fromiter(c["category"], np.int8, n),
        np.fromiter(chain.from_iterable(c["start"]), float, 6 * n).reshape(n, 6),
        np.fromiter(chain.from_iterable(c["end"]), float, 6 * n).reshape(n, 6),
        *(np.fromiter(c[k], float, n) for k in ("rate", "feed_mode", "mm", "spindle")),
        *(np.fromiter(c[k], float, n) for k in ("synch", "override")),
        np.fromiter(c["exact_stop"], bool, n),
        np.fromiter(c["blend"], float, n),
        np.fromiter(c["source"], np.int64, n),
        np.fromiter(c["line"], np.int32, n),
        np.fromiter(c["duration"], float, n),
    ]


def _run_columns(runs: list[StraightRun]) -> tuple[list[np.ndarray], np.ndarray]:
    """All runs as 15 columns, and how many rows each run keeps. The end points are those
    of the builder's command-by-command ``_target`` (same operations, element by element:
    units and G92, then the XY rotation and the G5x offset only where one is in force);
    moves to where the tool already is are dropped, as ``line_to`` does."""
    counts = np.array([len(r.commands) for r in runs])
    cmds = list(chain.from_iterable(r.commands for r in runs))
    m = len(cmds)
    v = np.fromiter(chain.from_iterable(map(_XYZABC, cmds)), float, 6 * m).reshape(m, 6)
    scale = _per_row(np.array([r.scale for r in runs], dtype=float), counts)
    end = np.empty((m, 6))
    end[:, :3] = v[:, :3] * scale[:, :1] + scale[:, 1:4]
    end[:, 3:] = v[:, 3:] + scale[:, 4:]
    if any(r.framed for r in runs):
        frame = _per_row(np.array([r.frame for r in runs], dtype=float), counts)
        turned = frame[:, 0] != 0
        if turned.any():
            x, y, c, sn = end[:, 0].copy(), end[:, 1].copy(), frame[:, 1], frame[:, 2]
            end[:, 0] = np.where(turned, c * x - sn * y, x)
            end[:, 1] = np.where(turned, sn * x + c * y, y)
        framed = np.repeat(np.array([r.framed for r in runs]), counts)
        end = np.where(framed[:, None], end + frame[:, 3:], end)
    first = np.cumsum(counts) - counts
    start = np.empty_like(end)
    start[1:] = end[:-1]
    start[first] = np.array([r.start for r in runs], dtype=float)
    cat = np.fromiter(map(_CATEGORY.__getitem__, map(type, cmds)), np.int8, m)
    line = np.concatenate([_lines(r.commands) for r in runs])
    src = np.arange(m, dtype=np.int64) + np.repeat([r.first for r in runs] - first, counts)
    rates = [np.repeat(c, counts) for c in np.array([r.rates for r in runs], dtype=float).T]
    stop = np.repeat(np.array([r.exact_stop for r in runs]), counts)
    cols = [
        np.full(m, LINE, np.int8),
        cat,
        start,
        end,
        np.where(cat == RAPID, rates[1], rates[0]),
        *rates[2:7],
        stop,
        rates[7],
        src,
        line,
        np.zeros(m),
    ]
    moved = np.any(end != start, axis=1)
    if moved.all():
        return cols, counts
    return [c[moved] for c in cols], np.add.reduceat(moved.astype(np.intp), first)


def merged_columns(
    chunks: list[list[Row] | StraightRun],
) -> tuple[list[np.ndarray], dict[int, ArcRecord]]:
    """The 15 row columns of the builder's chunks (lists of light rows and
    :class:`StraightRun`) in program order, and the arc records by final row index."""
    light: list[Row] = [row for ch in chunks if not isinstance(ch, StraightRun) for row in ch]
    runs = [ch for ch in chunks if isinstance(ch, StraightRun)]
    lcols = _light_columns(light) if light else []
    if not runs:
        return lcols, {i: row.arc for i, row in enumerate(light) if row.arc is not None}
    rcols, kept = _run_columns(runs)
    if not light:
        return rcols, {}
    is_run = np.array([isinstance(ch, StraightRun) for ch in chunks])
    sizes = np.zeros(len(chunks), np.intp)
    sizes[is_run] = kept
    sizes[~is_run] = [len(ch) for ch in chunks if not isinstance(ch, StraightRun)]
    offset = np.cumsum(sizes) - sizes

    def place(sel: np.ndarray) -> np.ndarray:  # final row indices of the selected chunks
        n = sizes[sel]
        return np.arange(n.sum()) + np.repeat(offset[sel] - (np.cumsum(n) - n), n)

    li, ri = place(~is_run), place(is_run)
    total = int(sizes.sum())
    cols = []
    for lc, rc in zip(lcols, rcols, strict=True):
        out = np.empty((total, *lc.shape[1:]), lc.dtype)
        out[li], out[ri] = lc, rc
        cols.append(out)
    recs = {int(li[i]): row.arc for i, row in enumerate(light) if row.arc is not None}
    return cols, recs


def segment_table(
    chunks: list[list[Row] | StraightRun], machine: Machine, file: str | None
) -> np.ndarray:
    """The builder's chunks (kernel.path.builder) vectorised into the segment table:
    lengths, tangents and feeds in mm/s (or deg/s), with the ``PLAN-AXIS`` and
    ``PLAN-FEED`` checks; motions shorter than MIN_LENGTH are dropped.

    Everything is computed on plain columns; the (wide, packed) table is written once per
    field at the end (in a :func:`kernel.interp.bulk.bulk_array`) and never read back."""
    cols, recs = merged_columns(chunks)
    if not cols:
        return np.zeros(0, SEGMENT_DTYPE)
    kind, cat, start, end, rate, mode, mm, spindle, synch, override = cols[:10]
    stop, blend, src, line, duration = cols[10:]
    d = end - start
    lin = np.sqrt(np.einsum("ij,ij->i", d[:, :3], d[:, :3]))
    rotary_only = lin <= MIN_LENGTH
    length = lin.copy()
    if rotary_only.any():
        length[rotary_only] = np.linalg.norm(d[rotary_only, 3:], axis=1)
    ai = np.flatnonzero(kind == ARC)
    arc_cols: dict[str, np.ndarray] = {}
    if ai.size:
        arcs = [recs[i] for i in ai.tolist()]
        arc_cols = {
            key: np.array(values, dtype=float)
            for key, values in zip(ArcRecord._fields, zip(*arcs, strict=True), strict=True)
        }
        length[ai] = arc_cols["length"]
    rotary_only[ai] = False
    length = np.where(kind == HOLD, 0.0, length)
    # axes the machine lacks must not move
    present = np.array([a in machine.axis_names for a in AXIS_NAMES])
    bad = np.flatnonzero(np.any(np.abs(d[:, ~present]) > MIN_LENGTH, axis=1))
    if bad.size:
        i = int(bad[0])
        names = ", ".join(
            AXIS_NAMES[j].upper() for j in np.flatnonzero((np.abs(d[i]) > MIN_LENGTH) & ~present)
        )
        raise Diagnostic(
            "PLAN-AXIS",
            f"the move drives axis {names}, which the machine lacks",
            Location(file, int(line[i]), 1 if line[i] else 0),
        )
    # drop motions too short to matter (the position was carried on anyway)
    keep = (kind == HOLD) | (length > MIN_LENGTH)
    if not keep.all():  # the usual case keeps all: no copies
        kept_arc = keep[ai]
        ai = (np.cumsum(keep) - 1)[ai[kept_arc]]
        arc_cols = {key: v[kept_arc] for key, v in arc_cols.items()}
        kind, cat, start, end, stop, blend, src, line, duration = (
            c[keep] for c in (kind, cat, start, end, stop, blend, src, line, duration)
        )
        d, rotary_only, length = d[keep], rotary_only[keep], length[keep]
        rate, mode, mm = rate[keep], mode[keep], mm[keep]
        spindle, synch, override = spindle[keep], synch[keep], override[keep]
    with np.errstate(invalid="ignore"):
        unit = np.where(rotary_only, 1.0, mm)
        # G93 rates arrive per minute already (kernel.ir.canon.SetFeedMode)
        feed = np.where(mode == 2, rate * unit * spindle / 60.0, rate * unit / 60.0)
        feed = np.where(synch > 0, synch * mm * spindle / 60.0, feed) * override
        rapid = cat == RAPID
        feed = np.where(rapid, rate * unit / 60.0, feed)
    bad = np.flatnonzero((kind != HOLD) & ~rapid & ~(feed > 0))
    if bad.size:
        ln = int(line[bad[0]])
        raise Diagnostic(
            "PLAN-FEED",
            "feed move with a zero feed rate",
            Location(file, ln, 1 if ln else 0),
        )
    safe = np.where(length > 0, length, 1.0)[:, None]
    u = np.where((kind == LINE)[:, None], d / safe, 0.0)
    seg = bulk_array(len(kind), SEGMENT_DTYPE)
    seg["kind"], seg["category"] = kind, cat
    seg["start"], seg["end"] = start, end
    seg["length"] = length
    seg["u_start"], seg["u_end"] = u, u
    seg["feed"] = feed
    seg["duration"] = duration
    seg["exact_stop"] = stop
    seg["blend"] = blend
    seg["source"] = src
    seg["line"] = line
    if ai.size:
        sa = np.zeros(ai.size, SEGMENT_DTYPE)  # the arc rows, for arc_tangent
        for key, v in arc_cols.items():
            sa[key] = v
            seg[key][ai] = v
        us, ue = arc_tangent(sa, np.zeros(ai.size)), arc_tangent(sa, np.ones(ai.size))
        rot = d[ai, 3:] / arc_cols["length"][:, None]
        us[:, 3:], ue[:, 3:] = rot, rot
        seg["u_start"][ai], seg["u_end"][ai] = us, ue
    return seg
