"""Arcs as ``MoveTo`` chords for the Sandia generic language, vectorised.

The generic language has no arcs (seed 003 Figure 3; research/seed-sandia-full.md §5.4), so
each ``ARC_FEED`` becomes chords: ``n = ceil(sweep / step)`` equal angular steps with
``step = 2 acos(1 - tol / r)``, the largest angle whose sagitta ``r (1 - cos(step / 2))``
is the tolerance (at least two chords; the helix axis moves with the swept angle, NISTIR
5970 §3.6.1). The same chords as :func:`kernel.path.ellipse.ellipse_chords` gives for a
circle, computed in closed form with numpy for a whole queue of moves
(gcode.write.sandia.SandiaWriter.flush_moves), and formatted at once: one ``%``
operation and one regular expression for all of their numbers instead of a call per
number (the compiled formatter of :mod:`gcode.ngc.lane.fastlane` takes over in a large program,
where a 200,000-line CAM program becomes millions of chord lines).
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from itertools import compress
from operator import eq

import numpy as np

import kernel.limits as limits
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweeps


@dataclass(frozen=True, slots=True)
class ArcRows:
    """Arcs of a fast-lane run queued as arrays, not commands: ``rows[i]`` holds an arc's
    in-plane end, centre, signed turns and end on the normal axis, as ``ARC_FEED`` takes
    them (gcode.ngc.lane.fastlane.Run.arc), ``line[i]`` its source line in ``file``."""

    rows: np.ndarray
    line: np.ndarray
    file: str | None


def _arc_location(owners: list[list[canon.ArcFeed] | ArcRows], i: int) -> Location:
    """Where the ``i``-th arc of :func:`batch_points`' table came from (its blocks' owners:
    the arcs' commands, or a fast-lane run's rows)."""
    for owner in owners:
        size = len(owner.rows) if isinstance(owner, ArcRows) else len(owner)
        if i < size:
            if isinstance(owner, ArcRows):
                return Location(owner.file, int(owner.line[i]))
            return owner[i].source or Location(None)
        i -= size
    return Location(None)


@functools.cache
def _zeros(places: int) -> re.Pattern[str]:
    """Up to ``places - 1`` zeros ending a number (before a blank or the line end)."""
    return re.compile(f"0{{1,{places - 1}}}(?=[ \\n])")


def format_many(values: np.ndarray, places: int) -> list[str]:
    """Each value as :class:`gcode.write.state.Formatter` writes it with at least one decimal.

    ``places`` >= 1: ``f"{v:.{places}f}"`` without its trailing zeros past the first decimal,
    and no sign on zero (``-0.0`` -> ``0.0``).
    """
    n = len(values)
    if not n:
        return []
    text = (f"%.{places}f\n" * n) % tuple(values.tolist())
    if places > 1:  # up to places - 1 trailing zeros: the first decimal stays
        text = _zeros(places).sub("", text)
    if "-0.0\n" in text:  # only a zero prints as -0.0 once the trailing zeros are gone
        text = "\n" + text
        text = text.replace("\n-0.0\n", "\n0.0\n").replace("\n-0.0\n", "\n0.0\n")[1:]
    return text[:-1].split("\n")


def move_lines(
    xs: list[str] | None,
    ys: list[str] | None,
    zs: list[str] | None,
    last: list[str | None],
) -> list[str]:
    """``MoveTo`` lines writing each axis only when its text changes (modal-minimal).

    ``xs``/``ys``/``zs`` are the texts of each axis per point (None: the axis keeps the
    text in ``last``, which must then hold one); ``last`` holds the texts written last
    (None: written on the first line) and is updated in place. A line where nothing
    changes repeats X, as the writer's single moves do.

    The text an axis had at the previous point is the one written last (an unchanged text
    is simply not repeated), so every line is decided by its point and the one before: all
    lines are built as if every axis changed, then the few where one did not are redone.
    """
    given = [(k, v, i) for i, (k, v) in enumerate((("X", xs), ("Y", ys), ("Z", zs))) if v]
    if not given:
        return []
    if len(given) == 3:
        (_, v1, _), (_, v2, _), (_, v3, _) = given  # X, Y, Z
        lines = [f"MoveTo X={a} Y={b} Z={c}" for a, b, c in zip(v1, v2, v3, strict=True)]
    elif len(given) == 2:
        (k1, v1, _), (k2, v2, _) = given
        lines = [f"MoveTo {k1}={a} {k2}={b}" for a, b in zip(v1, v2, strict=True)]
    else:
        k1, v1, _ = given[0]
        lines = [f"MoveTo {k1}={a}" for a in v1]
    n = len(lines)
    same: set[int] = set()
    for _, v, i in given:
        if v[0] == last[i]:
            same.add(0)
        same.update(compress(range(1, n), map(eq, v[1:], v[:-1])))
    for j in same:
        words = [f"{k}={v[j]}" for k, v, i in given if v[j] != (v[j - 1] if j else last[i])]
        lines[j] = "MoveTo " + (" ".join(words) or f"X={xs[j] if xs else last[0]}")
    for _, v, i in given:
        last[i] = v[-1]
    return lines


def batch_points(
    items: list, axes: tuple[int, int, int], start: tuple[float, float, float], tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[int]]:
    """Chord end points of a run of straight feeds and arcs, at once.

    ``items`` holds ``STRAIGHT_FEED`` and ``ARC_FEED`` commands, (k, 3) arrays of the x y z
    end points of k straight feeds (the fast lane's) and :class:`ArcRows`; ``axes``:
    indexes of the plane's (first, second, normal) axes in (x, y, z); ``start``: the
    position before the run.
    Returns (points (N, 3) in x y z, chords per move, the largest sagitta per move, the
    first move of each item): a line is one point; an arc is ``n`` chords of equal angle,
    the module's rule, computed for all arcs of the run together.
    """
    i1, i2, i3 = axes
    pieces: list[np.ndarray] = []
    rows: list[int] = []
    loose: list[tuple[float, float, float]] = []  # end points of commands, in order
    arcs: list[tuple[int, float, float, float]] = []  # (move, centre first, second, turns)
    blocks: list[np.ndarray] = []  # the same as arrays, before ``arcs``
    # each block's arcs: their commands, or the run's rows (where a limit is reported)
    owners: list[list[canon.ArcFeed] | ArcRows] = []
    arc_cmds: list[canon.ArcFeed] = []  # the commands of ``arcs``
    k = 0
    end = [0.0, 0.0, 0.0]
    for item in items:
        rows.append(k)
        kind = type(item)
        if kind is np.ndarray:
            if loose:
                pieces.append(np.array(loose, dtype=np.float64))
                loose = []
            pieces.append(item)
            k += len(item)
            continue
        if kind is ArcRows:
            if loose:
                pieces.append(np.array(loose, dtype=np.float64))
                loose = []
            if arcs:
                blocks.append(np.array(arcs, dtype=np.float64))
                owners.append(arc_cmds)
                arcs, arc_cmds = [], []
            data = item.rows
            m = len(data)
            ends = np.empty((m, 3))
            ends[:, i1], ends[:, i2], ends[:, i3] = data[:, 0], data[:, 1], data[:, 5]
            pieces.append(ends)
            block = np.empty((m, 4))
            block[:, 0] = np.arange(k, k + m)
            block[:, 1:] = data[:, 2:5]
            blocks.append(block)
            owners.append(item)
            k += m
            continue
        if kind is canon.StraightFeed:
            loose.append((item.x, item.y, item.z))
        else:
            end[i1], end[i2], end[i3] = item.first_end, item.second_end, item.axis_end_point
            loose.append((end[0], end[1], end[2]))
            arcs.append((k, item.first_axis, item.second_axis, item.rotation))
            arc_cmds.append(item)
        k += 1
    if loose:
        pieces.append(np.array(loose, dtype=np.float64))
    ends = pieces[0] if len(pieces) == 1 else np.concatenate(pieces)
    counts = np.ones(k, dtype=np.int64)
    sag = np.zeros(k)
    if arcs:
        blocks.append(np.array(arcs, dtype=np.float64))
        owners.append(arc_cmds)
    if not blocks:  # straight feeds only: their end points
        return ends, counts, sag, rows
    table = blocks[0] if len(blocks) == 1 else np.concatenate(blocks)
    at = table[:, 0].astype(np.int64)
    centre, rotation = table[:, 1:3], table[:, 3]
    arc_end = ends[at]
    arc_start = ends[np.maximum(at - 1, 0)]
    if at[0] == 0:
        arc_start[0] = start
    df, ds = arc_start[:, i1] - centre[:, 0], arc_start[:, i2] - centre[:, 1]
    r = np.hypot(df, ds)
    a0 = np.arctan2(ds, df)
    sign = np.where(rotation > 0, 1.0, -1.0)
    a1 = np.arctan2(arc_end[:, i2] - centre[:, 1], arc_end[:, i1] - centre[:, 0])
    sweep = np.abs(arc_sweeps(a0, a1, rotation))
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.where(tol < r, 2 * np.arccos(np.maximum(-1.0, 1 - tol / r)), math.pi / 2)
    with np.errstate(divide="ignore", invalid="ignore"):  # a step of 0: a radius of 1e99
        wanted = np.maximum(2, np.ceil(sweep / step))
    over = ~(wanted <= limits.current().arc_chords)  # a million turns, a radius of 1e99
    if over.any():
        i = int(np.argmax(over))
        raise limits.count_error(
            "chords of one arc (MoveTo lines)",
            float(wanted[i]),
            limits.current().arc_chords,
            "arc_chords",
            _arc_location(owners, i),
        )
    n = wanted.astype(np.int64)
    counts[at] = n
    sag[at] = r * (1 - np.cos(sweep / n / 2))
    owner = np.repeat(np.arange(len(at)), n)
    last = np.cumsum(n) - 1
    frac = (np.arange(len(owner)) - (last - n + 1)[owner] + 1) / n[owner]
    t = a0[owner] + (sign * sweep)[owner] * frac
    chords = np.empty((len(owner), 3))
    chords[:, i1] = centre[owner, 0] + r[owner] * np.cos(t)
    chords[:, i2] = centre[owner, 1] + r[owner] * np.sin(t)
    n0 = arc_start[owner, i3]
    chords[:, i3] = n0 + (arc_end[owner, i3] - n0) * frac
    chords[last] = arc_end  # every arc ends exactly on its end point (helix axis too)
    first = np.cumsum(counts) - counts  # the first point of each move
    pts = np.empty((int(first[-1] + counts[-1]), 3))
    straight = np.ones(k, dtype=bool)
    straight[at] = False
    pts[first[straight]] = ends[straight]
    pts[np.repeat(first[at], n) + np.arange(len(owner)) - np.repeat(last - n + 1, n)] = chords
    return pts, counts, sag, rows


def plane_lines(
    first: tuple[str, np.ndarray], second: tuple[str, np.ndarray], places: int, last: list[str]
) -> list[str]:
    """``MoveTo`` lines of points moving in two axes (the third keeps its text), at once.

    One ``%`` operation writes every line with both words and one regular expression takes
    the trailing zeros off (a number always keeps its first decimal). Lines where a word may
    repeat the previous line's (values less than 1.5 units of the last place apart, and the
    first line against ``last``) are then rebuilt by the rule of :func:`move_lines`.
    ``last``: the texts written last per X, Y, Z, all set; updated in place.
    """
    (k1, v1), (k2, v2) = first, second
    n = len(v1)
    template = f"MoveTo {k1}=%.{places}f {k2}=%.{places}f\n"
    text = (template * n) % tuple(np.column_stack((v1, v2)).ravel().tolist())
    if places > 1:  # up to places - 1 trailing zeros: the first decimal stays
        text = _zeros(places).sub("", text)
    if "=-0.0" in text:
        text = text.replace("=-0.0 ", "=0.0 ").replace("=-0.0\n", "=0.0\n")
    lines = text[:-1].split("\n")
    unit = 1.5 * 10.0**-places
    near = (np.abs(np.diff(v1)) < unit) | (np.abs(np.diff(v2)) < unit)
    check = [0, *(np.flatnonzero(near) + 1).tolist()]
    index = "XYZ"
    full = {j: lines[j] for j in check} | {j - 1: lines[j - 1] for j in check if j}
    for j in check:
        now = full[j].split(" ")[1:]
        if j:
            before = full[j - 1].split(" ")[1:]
        else:
            before = [f"{k}={last[index.index(k)]}" for k in (k1, k2)]
        words = [w for w, b in zip(now, before, strict=True) if w != b]
        if not words:
            words = [w for w in now if w.startswith("X=")] or [f"X={last[0]}"]
        lines[j] = "MoveTo " + " ".join(words)
    tail = full.get(n - 1, lines[-1]).split(" ")[1:]  # the last line, before any rebuild
    for w in tail:
        last[index.index(w[0])] = w[2:]
    return lines
