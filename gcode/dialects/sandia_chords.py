"""Arcs as ``MoveTo`` chords for the Sandia generic language, vectorised.

The generic language has no arcs (seed 003 Figure 3; research/seed-sandia-full.md §5.4), so
each ``ARC_FEED`` becomes chords: ``n = ceil(sweep / step)`` equal angular steps with
``step = 2 acos(1 - tol / r)``, the largest angle whose sagitta ``r (1 - cos(step / 2))``
is the tolerance (at least two chords; the helix axis moves with the swept angle, NISTIR
5970 §3.6.1). The same chords as :func:`gcode.approximate.ellipse_chords` gives for a
circle, computed in closed form with numpy, and formatted a whole arc at a time: one
``%`` operation and one regular expression for all of its numbers instead of a call per
number (a 200,000-line CAM program becomes about 2.3 million chord lines).
"""

from __future__ import annotations

import functools
import math
import re
from itertools import compress
from operator import eq

import numpy as np

from kernel import canon


@functools.cache
def _zeros(places: int) -> re.Pattern[str]:
    """Up to ``places - 1`` zeros ending a number (before a blank or the line end)."""
    return re.compile(f"0{{1,{places - 1}}}(?=[ \\n])")


def circle_chords(
    start: tuple[float, float],
    end: tuple[float, float],
    centre: tuple[float, float],
    rotation: int,
    tolerance: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(first, second, swept fraction) at each chord end, and the largest sagitta.

    The last point is the arc's end point itself; ``rotation`` is signed turns (> 0
    counterclockwise, NISTIR 5970 §3.6.1), never 0.
    """
    cx, cy = centre
    r = math.hypot(start[0] - cx, start[1] - cy)
    a0 = math.atan2(start[1] - cy, start[0] - cx)
    sign = 1.0 if rotation > 0 else -1.0
    sweep = (sign * (math.atan2(end[1] - cy, end[0] - cx) - a0)) % (2 * math.pi)
    if sweep <= 1e-12:
        sweep = 2 * math.pi
    sweep += 2 * math.pi * (abs(rotation) - 1)
    step = 2 * math.acos(max(-1.0, 1 - tolerance / r)) if tolerance < r else math.pi / 2
    n = max(2, math.ceil(sweep / step))
    frac = np.arange(1, n + 1) / n
    t = a0 + (sign * sweep) * frac
    first = cx + r * np.cos(t)
    second = cy + r * np.sin(t)
    first[-1], second[-1] = end
    return first, second, frac, r * (1 - math.cos(sweep / n / 2))


def format_many(values: np.ndarray, places: int) -> list[str]:
    """Each value as :class:`gcode.emit_state.Formatter` writes it with at least one decimal.

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
        lines = [f"MoveTo X={a} Y={b} Z={c}" for a, b, c in zip(xs, ys, zs, strict=True)]  # type: ignore[arg-type]
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
    commands: list, axes: tuple[int, int, int], start: tuple[float, float, float], tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Chord end points of a run of ``STRAIGHT_FEED`` and ``ARC_FEED`` commands, at once.

    ``axes``: indexes of the plane's (first, second, normal) axes in (x, y, z); ``start``:
    the position before the run. Returns (points (N, 3) in x y z, chords per command, the
    largest sagitta per command): a line is one point; an arc is :func:`circle_chords`'s
    chords, computed for all arcs of the run together.
    """
    i1, i2, i3 = axes
    k = len(commands)
    ends = np.empty((k, 3))
    arc = np.zeros(k, dtype=bool)
    centre = np.zeros((k, 2))
    rotation = np.ones(k)
    for j, c in enumerate(commands):
        if type(c) is canon.StraightFeed:
            ends[j] = (c.x, c.y, c.z)
        else:
            ends[j, i1], ends[j, i2], ends[j, i3] = c.first_end, c.second_end, c.axis_end_point
            centre[j] = (c.first_axis, c.second_axis)
            rotation[j] = c.rotation
            arc[j] = True
    starts = np.vstack([np.array(start)[None, :], ends[:-1]])
    df, ds = starts[:, i1] - centre[:, 0], starts[:, i2] - centre[:, 1]
    r = np.hypot(df, ds)
    a0 = np.arctan2(ds, df)
    sign = np.where(rotation > 0, 1.0, -1.0)
    a1 = np.arctan2(ends[:, i2] - centre[:, 1], ends[:, i1] - centre[:, 0])
    sweep = (sign * (a1 - a0)) % (2 * math.pi)
    sweep = np.where(sweep <= 1e-12, 2 * math.pi, sweep) + 2 * math.pi * (np.abs(rotation) - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.where(tol < r, 2 * np.arccos(np.maximum(-1.0, 1 - tol / r)), math.pi / 2)
    counts = np.where(arc, np.maximum(2, np.ceil(sweep / step)), 1).astype(np.int64)
    sag = np.where(arc, r * (1 - np.cos(sweep / counts / 2)), 0.0)
    owner = np.repeat(np.arange(k), counts)
    last = np.cumsum(counts) - 1
    frac = (np.arange(len(owner)) - (last - counts + 1)[owner] + 1) / counts[owner]
    t = a0[owner] + (sign * sweep)[owner] * frac
    pts = np.empty((len(owner), 3))
    pts[:, i1] = centre[owner, 0] + r[owner] * np.cos(t)
    pts[:, i2] = centre[owner, 1] + r[owner] * np.sin(t)
    n0 = starts[owner, i3]
    pts[:, i3] = n0 + (ends[owner, i3] - n0) * frac
    pts[last] = ends  # every command ends exactly on its end point (helix axis too)
    lines = ~arc[owner]
    pts[lines] = ends[owner[lines]]
    return pts, counts, sag


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
