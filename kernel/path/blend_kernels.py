"""Compiled blend-arc insertion (numba), for large segment tables.

:func:`kernel.path.blend.insert_blend_arcs` puts a blend arc after each corner row and
trims the two lines; with numpy that is a dozen gathers and scatters over the packed
367-byte rows (a structured copy goes field by field), a third of the LinuxCNC model's plan
time on a 200,000-segment program (issue 16, bench/bench_plan.py). These loops make the
same table in one pass over the rows: each row copied once, the arcs' fields (computed by
numpy in :mod:`kernel.path.blend`, as before) written in place, the trims with the same
subtractions in the same order, so the table is the same bit for bit
(tests/test_blend_kernels.py). Compiled once and cached next to this file
(``cache=True``); :mod:`kernel.plan.models.linuxcnc` uses them where it uses its compiled
join loops (kernel.plan.models.lcnc_joins), which load numba anyway.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from kernel.path.segments import ARC, LINE


@njit(cache=True)
def kept_rows(
    kind: np.ndarray, length: np.ndarray, corners: np.ndarray, d: np.ndarray, min_length: float
) -> np.ndarray:
    """Which rows of the blended table (the ``len(kind) + len(corners)`` rows, an arc
    after each corner row) are not lines trimmed to ``min_length`` or less; a line loses
    ``d`` at the corner after it, then ``d`` at the corner before it (the order of
    :func:`kernel.path.blend.kept_after_blending`)."""
    n = kind.size
    k = corners.size
    keep = np.ones(n + k, dtype=np.bool_)
    c = 0
    j = 0
    for i in range(n):
        ln = length[i]
        ends = c < k and corners[c] == i
        if ends:
            ln -= d[c]
        if c > 0 and corners[c - 1] == i - 1:
            ln -= d[c - 1]
        keep[j] = not (kind[i] == LINE and ln <= min_length)
        j += 1
        if ends:
            j += 1  # the arc: never dropped
            c += 1
    return keep


@njit(cache=True)
def fill_blended(
    seg: np.ndarray,
    out: np.ndarray,
    corners: np.ndarray,
    keep: np.ndarray,
    d: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    centre: np.ndarray,
    normal: np.ndarray,
    e1: np.ndarray,
    e2: np.ndarray,
    radius: np.ndarray,
    theta: np.ndarray,
    v1: np.ndarray,
    v2: np.ndarray,
    feed: np.ndarray,
) -> int:
    """Write into ``out`` the rows of ``seg`` with arc ``c`` after row ``corners[c]``,
    only the rows ``keep`` marks (of the ``len(seg) + len(corners)``); returns how many.
    Arc ``c``: from ``start[c]`` to ``end[c]`` about ``centre[c]`` (``radius``, sweep
    ``theta``, plane ``normal``, ``e1``, ``e2``), tangents ``v1``, ``v2``, ``feed``; the
    other five axes, the blend tolerance of the corner row and the source and line of the
    row after it. The lines beside it end at ``start[c]`` and start at ``end[c]``, each
    ``d[c]`` shorter."""
    n = seg.size
    k = corners.size
    c = 0
    j = 0  # rows written
    p = 0  # row of the blended table
    for i in range(n):
        ends = c < k and corners[c] == i
        if keep[p]:
            out[j] = seg[i]
            row = out[j]
            if ends:
                for a in range(3):
                    row.end[a] = start[c, a]
                row.length -= d[c]
            if c > 0 and corners[c - 1] == i - 1:
                for a in range(3):
                    row.start[a] = end[c - 1, a]
                row.length -= d[c - 1]
            j += 1
        p += 1
        if ends:
            if keep[p]:
                arc = out[j]
                src = seg[i]
                nxt = seg[i + 1]
                arc.kind = ARC
                arc.category = src.category
                for a in range(6):
                    arc.start[a] = src.end[a]
                    arc.end[a] = src.end[a]
                    arc.u_start[a] = 0.0
                    arc.u_end[a] = 0.0
                for a in range(3):
                    arc.start[a] = start[c, a]
                    arc.end[a] = end[c, a]
                    arc.u_start[a] = v1[c, a]
                    arc.u_end[a] = v2[c, a]
                    arc.centre[a] = centre[c, a]
                    arc.normal[a] = normal[c, a]
                    arc.e1[a] = e1[c, a]
                    arc.e2[a] = e2[c, a]
                arc.length = radius[c] * theta[c]
                arc.radius = radius[c]
                arc.radius_end = radius[c]
                arc.sweep = theta[c]
                arc.axial = 0.0
                arc.feed = feed[c]
                arc.duration = 0.0
                arc.exact_stop = False
                arc.blend = src.blend
                arc.source = nxt.source
                arc.line = nxt.line
                j += 1
            p += 1
            c += 1
    return j


@njit(cache=True)
def gather_xyz(x: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``x[rows, :3]`` as a new contiguous array (``x``: a field of the packed table, whose
    rows numpy's fancy indexing copies element by element)."""
    out = np.empty((rows.size, 3))
    for i in range(rows.size):
        r = rows[i]
        for c in range(3):
            out[i, c] = x[r, c]
    return out
