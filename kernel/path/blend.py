"""Corner blending for ``G64 P<tolerance>`` (NISTIR 5970 §3.5.3 continuous mode with the
deviation bound LinuxCNC's ``P`` supplies; book §4.2.4 / §4.3: block overlap at corners).

Between two straight feed moves that meet at an angle, with a blending tolerance ``P`` in
force on the first, the corner is replaced by a circular arc tangent to both lines. The
arc's largest distance from the programmed corner is ``e = r (1/cos(theta/2) - 1)`` for a
direction change ``theta`` and radius ``r``; ``r`` is the largest with ``e <= P`` and
tangent length ``r tan(theta/2)`` at most half of either line (so neighbouring blends never
overlap). The tool then passes the corner at the arc's speed (centripetal cap of the
planner) instead of the per-axis corner speed, and never leaves the ``P`` band around the
programmed path. Exact stop (G61), rotary motion, holds and arcs are left unblended.
"""

from __future__ import annotations

import numpy as np

from kernel.interp.bulk import bulk_array
from kernel.path.segments import ARC, LINE, SEGMENT_DTYPE, Path

_MIN_ANGLE = 1e-6
_MIN_RADIUS = 1e-6
# the segment table's float fields from ``start`` to ``duration`` lie back to back: one
# (rows, 43) float block, each field's first column in it
_BLOCK_FIELDS = [
    f for f in SEGMENT_DTYPE.names if SEGMENT_DTYPE.fields[f][1] >= SEGMENT_DTYPE.fields["start"][1]
][: SEGMENT_DTYPE.names.index("duration") - SEGMENT_DTYPE.names.index("start") + 1]
_BLOCK_START = SEGMENT_DTYPE.fields["start"][1]
_BLOCK_COLUMNS = {f: (SEGMENT_DTYPE.fields[f][1] - _BLOCK_START) // 8 for f in _BLOCK_FIELDS}
_BLOCK_WIDTH = (SEGMENT_DTYPE.fields["duration"][1] + 8 - _BLOCK_START) // 8


def _float_block(table: np.ndarray) -> np.ndarray:
    """The fields ``start`` .. ``duration`` of every row of a contiguous segment table as one
    (unaligned) float view (rows, 43): writing a row's floats at once instead of field by
    field (a packed 367-byte row makes each field write a pass over the whole table)."""
    return np.ndarray(
        (len(table), _BLOCK_WIDTH),
        np.float64,
        buffer=table,
        offset=_BLOCK_START,
        strides=(table.dtype.itemsize, 8),
    )


_KIND = SEGMENT_DTYPE.fields["kind"][1]
_CATEGORY = SEGMENT_DTYPE.fields["category"][1]
_TAIL_START = _BLOCK_START + 8 * _BLOCK_WIDTH  # exact_stop, blend, source, line
_TAIL_BYTES = SEGMENT_DTYPE.itemsize - _TAIL_START


def _bytes(table: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Bytes ``lo:hi`` of every row of a contiguous segment table, one item per row."""
    return np.ndarray(
        (len(table),), f"V{hi - lo}", buffer=table, offset=lo, strides=(table.dtype.itemsize,)
    )


def _check_block() -> None:
    """The block really is back-to-back float64 fields (the layout of SEGMENT_DTYPE)."""
    at = _BLOCK_START
    for f in _BLOCK_FIELDS:
        base, offset = SEGMENT_DTYPE.fields[f][:2]
        if offset != at or base.base != np.dtype(np.float64):
            raise TypeError(f"segment field {f} is not in the float block")
        at += base.itemsize
    if SEGMENT_DTYPE.names[:2] != ("kind", "category") or _BLOCK_START != 2:
        raise TypeError("the segment table no longer starts with kind, category")
    tail = SEGMENT_DTYPE.names[SEGMENT_DTYPE.names.index("duration") + 1 :]
    if tail != ("exact_stop", "blend", "source", "line"):
        raise TypeError("the segment table no longer ends with exact_stop .. line")


_check_block()


def blend_corners(path: Path) -> Path:
    """A copy of ``path`` with blend arcs inserted at every eligible line-line corner."""
    seg = path.segments
    n = len(seg)
    if n < 2 or not np.any(seg["blend"] > 0):
        return path
    r = blend_radii(seg)
    corners = np.flatnonzero(r > 0)
    if not corners.size:
        return path
    out = insert_blend_arcs(seg, corners, r[corners])
    # a line shortened from both ends by half its length is gone (not -1e-16 long)
    gone = (out["kind"] == LINE) & (out["length"] <= 1e-12)
    if gone.any():
        out = out[~gone]
    return Path(out, path.file)


def blend_rows(seg: np.ndarray, a: int, b: int) -> np.ndarray:
    """The rows :func:`blend_corners` makes of ``seg``'s rows ``a .. b - 1`` and of the
    corners after them: those rows of the blended table, whatever comes before row
    ``a - 1`` or after row ``b`` (each corner reads its two rows only, each line is trimmed
    by the corners at its two ends). A table planned in windows (kernel.stream) is blended
    so with one row of context on either side."""
    n = len(seg)
    if n < 2 or not np.any(seg["blend"] > 0):
        return seg[a:b]
    r = blend_radii(seg)
    corners = np.flatnonzero(r > 0)
    if not corners.size:
        return seg[a:b]
    out = insert_blend_arcs(seg, corners, r[corners])
    moved, _ = _placed(n, corners)
    part = out[int(moved[a]) : int(moved[b]) if b < n else len(out)]
    gone = (part["kind"] == LINE) & (part["length"] <= 1e-12)
    return part[~gone] if gone.any() else part


def blend_radii(seg: np.ndarray) -> np.ndarray:
    """The blend arc's radius at the corner after each row but the last (0: the corner is
    not blended). A corner's decision reads its two rows only."""
    a, b = seg[:-1], seg[1:]
    u1, u2 = a["u_end"][:, :3], b["u_start"][:, :3]
    cos = np.clip(np.einsum("ij,ij->i", u1, u2), -1.0, 1.0)
    theta = np.arccos(cos)
    ok = (
        (a["kind"] == LINE)
        & (b["kind"] == LINE)
        & (a["blend"] > 0)
        & ~a["exact_stop"]
        & (theta > _MIN_ANGLE)
        & (theta < np.pi - 1e-3)
        & np.all(np.abs(a["u_end"][:, 3:]) == 0, axis=1)
        & np.all(np.abs(b["u_start"][:, 3:]) == 0, axis=1)
        & (a["category"] == b["category"])
    )
    half = np.where(ok, theta / 2, 1.0)
    r_tol = a["blend"] / np.maximum(1 / np.cos(half) - 1, 1e-300)
    r_len = 0.5 * np.minimum(a["length"], b["length"]) / np.tan(half)
    r = np.where(ok, np.minimum(r_tol, r_len), 0.0)
    return np.where(r > _MIN_RADIUS, r, 0.0)


def corner_trims(
    seg: np.ndarray, corners: np.ndarray, r: np.ndarray, compiled: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Directions into and out of each corner, their cosine and angle, and the tangent
    length ``d`` an arc of radius ``r`` takes off both lines (what
    :func:`kept_after_blending` and :func:`insert_blend_arcs` compute first: pass it to
    both as ``trims`` to compute it once). ``compiled``: the directions gathered by
    kernel.path.blend_kernels (the same numbers)."""
    u1, u2 = _xyz(seg["u_end"], corners, compiled), _xyz(seg["u_start"], corners + 1, compiled)
    cos = np.clip(np.einsum("ij,ij->i", u1, u2), -1.0, 1.0)
    theta = np.arccos(cos)
    return u1, u2, cos, theta, r * np.tan(theta / 2)


def _xyz(field: np.ndarray, rows: np.ndarray, compiled: bool) -> np.ndarray:
    """``field[rows, :3]`` of a (rows, 6) field of the table, by numpy or compiled."""
    if not compiled:
        return field[rows, :3]
    from kernel.path.blend_kernels import gather_xyz

    return gather_xyz(field, rows)


def _placed(n: int, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the rows of an ``n``-row table go once an arc follows each corner row, and
    where the arcs go."""
    moved = np.arange(n) + np.searchsorted(corners, np.arange(n), "left")
    return moved, corners + 1 + np.arange(corners.size)


def kept_after_blending(
    seg: np.ndarray,
    corners: np.ndarray,
    r: np.ndarray,
    min_length: float,
    compiled: bool = False,
    trims: tuple[np.ndarray, ...] | None = None,
) -> np.ndarray:
    """Which rows of :func:`insert_blend_arcs`' result are not lines shortened to
    ``min_length`` or less (the same arithmetic as the shortening there). ``compiled``:
    in one compiled pass (kernel.path.blend_kernels, the same result); ``trims``:
    :func:`corner_trims` of the same arguments."""
    _, _, _, theta, d = corner_trims(seg, corners, r) if trims is None else trims
    if compiled:
        from kernel.path.blend_kernels import kept_rows

        return kept_rows(seg["kind"], seg["length"], corners, d, min_length)
    moved, at = _placed(len(seg), corners)
    length = np.empty(len(seg) + corners.size)
    length[moved] = seg["length"]
    length[at] = r * theta
    line = np.zeros(length.size, dtype=bool)
    line[moved] = seg["kind"] == LINE
    length[moved[corners]] -= d
    length[moved[corners + 1]] -= d
    return ~(line & (length <= min_length))


def insert_blend_arcs(
    seg: np.ndarray,
    corners: np.ndarray,
    r: np.ndarray,
    keep: np.ndarray | None = None,
    compiled: bool = False,
    trims: tuple[np.ndarray, ...] | None = None,
    feed: np.ndarray | None = None,
) -> np.ndarray:
    """``seg`` with a tangent arc of radius ``r[k]`` inserted at the corner after each row
    ``corners[k]`` (sorted; both rows lines); the lines are shortened by the arc's tangent
    length. Lines shortened to nothing are kept (zero length): the caller decides, and may
    pass ``keep`` (:func:`kept_after_blending`): only those rows of the result are made.
    ``compiled``: the rows made in one compiled pass (kernel.path.blend_kernels: the same
    table, for large ones); ``trims``: :func:`corner_trims` of the same arguments;
    ``feed``: the arcs' feed (default: the slower of the two moves')."""
    if feed is None:
        feed = np.minimum(seg["feed"][corners], seg["feed"][corners + 1])
    u1, u2, cos, theta, d = corner_trims(seg, corners, r) if trims is None else trims
    c = _xyz(seg["end"], corners, compiled)
    v1, v2 = u1, u2
    start = c - d[:, None] * v1
    end = c + d[:, None] * v2
    inward = v2 - cos[:, None] * v1
    inward /= np.linalg.norm(inward, axis=1)[:, None]
    centre = start + r[:, None] * inward
    normal = np.cross(v1, v2)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    e1 = (start - centre) / r[:, None]
    e2 = np.cross(normal, e1)  # = v1: the arc leaves A along the first line
    if compiled:
        return _insert_compiled(
            seg, corners, keep, d, (start, end, centre, normal, e1, e2, r, theta, v1, v2, feed)
        )
    # the rows moved to their places (row i after the arcs of the corners before it), the
    # arcs in between: one copy of the table, no per-field inserts
    n, k = len(seg), corners.size
    moved, at = _placed(n, corners)
    before, after = moved[corners], moved[corners + 1]
    raw = np.dtype((np.void, seg.dtype.itemsize))  # rows copied as bytes, not field by field
    contiguous = np.ascontiguousarray(seg)
    src = contiguous.view(raw)
    size = n + k
    if keep is not None:  # rows of the result renumbered, the dropped ones left out
        final = np.cumsum(keep) - 1
        size = int(final[-1]) + 1 if final.size else 0
        # a dropped row is copied to a spare row past the end (no gather of the kept ones)
        moved = np.where(keep[moved], final[moved], size)
        at = final[at]
        cut_end, cut_start = keep[before], keep[after]
        before, after = final[before[cut_end]], final[after[cut_start]]
    else:
        cut_end = cut_start = np.ones(k, dtype=bool)
    out = bulk_array(size + 1, seg.dtype)
    out.view(raw)[moved] = src
    # the arcs' float fields as one contiguous block per row, written at once
    f = _float_block(out)
    cols = _BLOCK_COLUMNS
    rows = np.zeros((k, f.shape[1]))
    ends = seg["end"][corners]
    for name in ("start", "end"):
        c0 = cols[name]
        rows[:, c0 : c0 + 6] = ends
        rows[:, c0 : c0 + 3] = start if name == "start" else end
    rows[:, cols["length"]] = r * theta
    for name, value in (("centre", centre), ("normal", normal), ("e1", e1), ("e2", e2)):
        rows[:, cols[name] : cols[name] + 3] = value
    rows[:, cols["radius"]] = r
    rows[:, cols["radius_end"]] = r
    rows[:, cols["sweep"]] = theta
    rows[:, cols["u_start"] : cols["u_start"] + 3] = v1
    rows[:, cols["u_end"] : cols["u_end"] + 3] = v2
    rows[:, cols["feed"]] = feed
    f[at] = rows
    # the fields before the block (kind, category) and after it (exact_stop: False, blend,
    # source, line) as one byte string each per row
    head = np.zeros((k, _BLOCK_START), np.uint8)
    head[:, _KIND] = ARC
    head[:, _CATEGORY] = seg["category"][corners].view(np.uint8)
    _bytes(out, 0, _BLOCK_START)[at] = head.view(f"V{_BLOCK_START}")[:, 0]
    tail = np.zeros((k, _TAIL_BYTES), np.uint8)
    for name, rows_of in (("blend", corners), ("source", corners + 1), ("line", corners + 1)):
        lo = SEGMENT_DTYPE.fields[name][1]
        hi = lo + SEGMENT_DTYPE.fields[name][0].itemsize
        got = _bytes(contiguous, lo, hi)[rows_of]
        tail[:, lo - _TAIL_START : hi - _TAIL_START] = got.view(np.uint8).reshape(k, hi - lo)
    _bytes(out, _TAIL_START, SEGMENT_DTYPE.itemsize)[at] = tail.view(f"V{_TAIL_BYTES}")[:, 0]
    # shorten the lines on both sides
    e0, s0, ln = cols["end"], cols["start"], cols["length"]
    f[before, e0 : e0 + 3] = start[cut_end]
    f[before, ln] -= d[cut_end]
    f[after, s0 : s0 + 3] = end[cut_start]
    f[after, ln] -= d[cut_start]
    return out[:size]


def _insert_compiled(
    seg: np.ndarray,
    corners: np.ndarray,
    keep: np.ndarray | None,
    d: np.ndarray,
    arcs: tuple[np.ndarray, ...],
) -> np.ndarray:
    """:func:`insert_blend_arcs`' table made by kernel.path.blend_kernels from the arcs'
    geometry and feed (``start, end, centre, normal, e1, e2, r, theta, v1, v2, feed``)
    computed above."""
    from kernel.path.blend_kernels import fill_blended

    n, k = len(seg), corners.size
    if keep is None:
        keep = np.ones(n + k, dtype=bool)
    out = bulk_array(int(np.count_nonzero(keep)), seg.dtype)
    made = fill_blended(seg, out, corners, keep, d, *arcs)
    assert made == len(out)
    return out
