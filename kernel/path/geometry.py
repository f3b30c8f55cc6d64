"""Points and derivatives along path segments, vectorised over (segment, parameter) pairs.

For a segment row and a local path parameter ``s`` (0..length) :func:`evaluate` returns the
position and the first three derivatives with respect to ``s`` for all six axes. Axis
velocity, acceleration and jerk follow by the chain rule from the path speed ``v``,
acceleration ``a`` and jerk ``j`` (kernel.interp.interpolate):

    x' = p1 v,   x'' = p1 a + p2 v^2,   x''' = p1 j + 3 p2 v a + p3 v^3

Arcs (helices, slight spirals) use ``p(l) = c + rho(l) w(psi) + axial l n`` with
``psi = sweep l``, ``w = cos(psi) e1 + sin(psi) e2``, ``rho = r0 + (r1 - r0) l`` and
``l = s/length``. With a sampled-data circle method (kernel.interp.circle) the arc is replaced by
the method's polygon (book §3.3.2 rough interpolation; the chords are then traversed like
lines, book §6.3.3 ``CircularIPO_Pre``), ending exactly at the programmed end point.
"""

from __future__ import annotations

import math

import numpy as np

import kernel.interp.circle as circle
from kernel.path.segments import ARC, LINE


def arc_tangent(seg: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """d position / ds of arc rows at fraction ``lam`` (XYZ part; rotary left zero)."""
    out = np.zeros((len(seg), 6))
    _, d1, _, _ = _arc(_gather(seg, np.arange(len(seg))), lam)
    out[:, :3] = d1
    return out


def _arc(seg: dict[str, np.ndarray], lam: np.ndarray) -> tuple[np.ndarray, ...]:
    sweep = seg["sweep"][:, None]
    r0 = seg["radius"][:, None]
    dr = (seg["radius_end"] - seg["radius"])[:, None]
    length = seg["length"][:, None]
    e1, e2, n = seg["e1"], seg["e2"], seg["normal"]
    lam = lam[:, None]
    psi = sweep * lam
    c, s = np.cos(psi), np.sin(psi)
    w = c * e1 + s * e2
    wp = -s * e1 + c * e2
    rho = r0 + dr * lam
    ax = seg["axial"][:, None]
    pos = seg["centre"] + rho * w + ax * lam * n
    d1 = (dr * w + rho * sweep * wp + ax * n) / length
    d2 = (2 * dr * sweep * wp - rho * sweep**2 * w) / length**2
    d3 = (-3 * dr * sweep**2 * w - rho * sweep**3 * wp) / length**3
    return pos, d1, d2, d3


_ARC_FIELDS = (
    "sweep",
    "radius",
    "radius_end",
    "length",
    "e1",
    "e2",
    "normal",
    "centre",
    "axial",
    "start",
    "end",
    "u_start",
)


def _gather(
    table: np.ndarray, idx: np.ndarray, cache: dict[str, np.ndarray] | None = None
) -> dict[str, np.ndarray]:
    """The arc fields of rows ``idx`` (from the contiguous copies in ``cache`` when it has
    them, :func:`arc_cache`: a gather from a contiguous array instead of a strided field)."""
    if cache is not None and "sweep" in cache:
        return {f: cache[f].take(idx, axis=0) for f in _ARC_FIELDS}
    return {f: table[f][idx] for f in _ARC_FIELDS}


def arc_cache(table: np.ndarray) -> dict[str, np.ndarray]:
    """Contiguous copies of the fields arc evaluation reads (for :func:`evaluate`'s
    ``cache``, added to :func:`line_cache`'s; speed only, the same numbers)."""
    return {f: np.ascontiguousarray(table[f]) for f in _ARC_FIELDS}


def _polygon(
    table: np.ndarray, idx: np.ndarray, lam: np.ndarray, method: str, tolerance: float
) -> tuple[np.ndarray, np.ndarray]:
    """The circle method's chords (constant speed along each), per (segment, lam)."""
    pos = np.empty((len(idx), 3))
    d1 = np.empty((len(idx), 3))
    for key in np.unique(idx):
        m = idx == key
        row = table[key]
        r0 = float(row["radius"])
        sweep = float(row["sweep"])
        if method == "improved_tustin":
            v = circle.tustin_band(r0, sweep, tolerance)
        else:
            n, alpha = circle.steps_for_sweep(method, sweep, r0 / tolerance)
            v = circle.vertices(method, r0, alpha, np.arange(n + 1))
        n = len(v) - 1
        frac = np.arange(n + 1) / n
        e1, e2 = row["e1"], math.copysign(1.0, sweep) * row["e2"]
        pts = (
            row["centre"]
            + v[:, :1] * e1
            + v[:, 1:] * e2
            + frac[:, None] * float(row["axial"]) * row["normal"]
        )
        pts[-1] = row["end"][:3]
        # traverse the polygon by its own length, scaled to the arc's path parameter
        chords = np.diff(pts, axis=0)
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(chords, axis=1))])
        target = lam[m] * cum[-1]
        i = np.clip(np.searchsorted(cum, target, "right") - 1, 0, n - 1)
        seglen = np.maximum(cum[i + 1] - cum[i], 1e-300)
        f = ((target - cum[i]) / seglen)[:, None]
        pos[m] = pts[i] + f * chords[i]
        d1[m] = chords[i] / seglen[:, None] * (cum[-1] / float(row["length"]))
    return pos, d1


def line_cache(table: np.ndarray, cols: list[int]) -> dict[str, np.ndarray]:
    """Contiguous copies of the columns line sampling needs (``cols`` of the six axes)."""
    return {
        "kind": np.ascontiguousarray(table["kind"]),
        "length": np.ascontiguousarray(table["length"]),
        "start": np.ascontiguousarray(table["start"][:, cols]),
        "u": np.ascontiguousarray(table["u_start"][:, cols]),
    }


def evaluate(
    table: np.ndarray,
    idx: np.ndarray,
    s: np.ndarray,
    circle_method: str = "exact",
    tolerance: float = 0.001,
    cols: list[int] | None = None,
    cache: dict[str, np.ndarray] | None = None,
) -> tuple[np.ndarray, ...]:
    """Geometry of segments ``table[idx]`` at local path parameter ``s``.

    Returns ``(pos, d1, curved, d2, d3)``: position and d/ds for every query (columns
    ``cols`` of the six axes, all by default), and d2/ds2, d3/ds3 only for the queries
    ``curved`` (indices into the queries) that lie on exactly sampled arcs; elsewhere
    they are zero. ``cache`` is :func:`line_cache` of the table (speed only).
    """
    cols = list(range(6)) if cols is None else list(cols)
    if cache is None:
        cache = line_cache(table, cols)
    n = len(idx)
    kind = cache["kind"][idx]
    line = kind == LINE
    curved = np.zeros(0, dtype=np.int64)
    d2c = d3c = np.zeros((0, len(cols)))
    if line.all():
        u = cache["u"].take(idx, axis=0)
        p = cache["start"].take(idx, axis=0)
        p += np.clip(s, 0.0, None)[:, None] * u
        return p, u, curved, d2c, d3c
    arc = kind == ARC
    if circle_method == "exact" and max(cols) < 3 and arc.all():
        # arcs only, XYZ only (a batch of arc samples): no masks, no rotary columns
        sa = _gather(table, idx, cache)
        la = np.clip(s / sa["length"], 0.0, 1.0)
        p, a1, a2, a3 = _arc(sa, la)
        done = np.flatnonzero(la >= 1.0)
        if done.size:
            p[done] = sa["end"][done, :3]
        return p[:, cols], a1[:, cols], np.arange(n), a2[:, cols], a3[:, cols]
    pos = np.empty((n, 6))
    d1 = np.zeros((n, 6))
    if arc.any():
        ai = idx[arc]
        sa = _gather(table, ai, cache)
        la = np.clip(s[arc] / sa["length"], 0.0, 1.0)
        rot = sa["start"][:, 3:] + la[:, None] * (sa["end"][:, 3:] - sa["start"][:, 3:])
        if circle_method == "exact":
            p, a1, a2, a3 = _arc(sa, la)
            curved = np.flatnonzero(arc)
            d2 = np.zeros((len(ai), 6))
            d3 = np.zeros((len(ai), 6))
            d2[:, :3], d3[:, :3] = a2, a3
            d2c, d3c = d2[:, cols], d3[:, cols]
        else:
            p, a1 = _polygon(table, ai, la, circle_method, tolerance)
        pos[arc, :3], pos[arc, 3:] = p, rot
        d1[arc, :3] = a1
        d1[arc, 3:] = sa["u_start"][:, 3:]
        done = la >= 1.0
        if done.any():
            pos[np.flatnonzero(arc)[done]] = sa["end"][done]
    if line.any():
        li = idx[line]
        sl = np.clip(s[line], 0.0, table["length"][li])
        u = table["u_start"][li]
        pos[line] = table["start"][li] + sl[:, None] * u
        d1[line] = u
    hold = ~(line | arc)
    if hold.any():
        pos[hold] = table["start"][idx[hold]]
    return pos[:, cols], d1[:, cols], curved, d2c, d3c
