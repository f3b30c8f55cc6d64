"""Reference-pulse interpolation (book §3.2-3.3.1): DDA, stairs approximation, direct search.

Integer algorithms that emit one pulse (1 BLU) per axis step; kept for teaching and as
bit-exact references (book tables 3.1, 3.5, 3.6; research/seed-book-interp.md §3.3-3.7).

* :func:`dda_circle`: the hardware DDA of fig. 3.4d with cross-coupled registers, in the
  update order that reproduces table 3.1 (X overflow raises V_y at once; a Y overflow lowers
  V_x from the next iteration; an axis stops after R pulses);
* :func:`dda_line`: the linear DDA (eqs. 3.10/3.11);
* :func:`stairs`: one axis per step from ``D = X^2 + Y^2 - R^2`` (eq. 3.16) and the eight
  rules of table 3.4, with the incremental updates of eqs. 3.19/3.20 (tie ``D = 0`` taken
  as ``D < 0``, as table 3.5 does);
* :func:`direct_search`: also the diagonal step, the candidate with the smallest ``|D|``
  that does not pass the end point (eq. 3.21).

Rows are dictionaries of the books' columns so tests can compare them cell by cell.
"""

from __future__ import annotations

import numpy as np

from kernel.diagnostics import Diagnostic

#: Table 3.4: (quadrant, clockwise) -> (step when D < 0, step when D > 0)
STAIRS_RULES: dict[tuple[int, bool], tuple[tuple[int, int], tuple[int, int]]] = {
    (1, True): ((1, 0), (0, -1)),
    (1, False): ((0, 1), (-1, 0)),
    (2, True): ((0, 1), (1, 0)),
    (2, False): ((-1, 0), (0, -1)),
    (3, True): ((-1, 0), (0, 1)),
    (3, False): ((0, -1), (1, 0)),
    (4, True): ((0, -1), (-1, 0)),
    (4, False): ((1, 0), (0, 1)),
}


def dda_circle(radius: int, bits: int) -> list[dict[str, int]]:
    """Table 3.1: CW quarter circle by two cross-coupled DDAs (``V_x = R``, ``V_y = 0``)."""
    full = 1 << bits
    if not 0 < radius < full:
        raise Diagnostic("PLAN-PULSE", f"radius {radius} does not fit {bits}-bit registers")
    vx, qx, vy, qy = radius, 0, 0, 0
    nx = ny = 0
    rows = [dict(k=0, vx=vx, qx=qx, dsx=0, vy=vy, qy=qy, dsy=0)]
    k = 0
    while nx < radius or ny < radius:
        k += 1
        qx += vx
        dsx = 0
        if qx >= full:
            qx -= full
            if nx < radius:
                dsx, nx = 1, nx + 1
                vy += 1
        qy += vy
        dsy = 0
        if qy >= full:
            qy -= full
            if ny < radius:
                dsy, ny = 1, ny + 1
        rows.append(dict(k=k, vx=vx, qx=qx, dsx=dsx, vy=vy, qy=qy, dsy=dsy))
        if dsy:
            vx -= 1
        if k > 16 * full:
            raise Diagnostic("PLAN-PULSE", "DDA did not converge")
    return rows


def dda_line(a: int, b: int, bits: int) -> np.ndarray:
    """Linear DDA (eqs. 3.10/3.11): pulses of both axes over ``2^bits`` iterations, (N, 2)."""
    full = 1 << bits
    k = np.arange(1, full + 1)
    out = np.empty((full, 2), dtype=np.int64)
    for j, v in enumerate((abs(a), abs(b))):
        acc = k * v
        out[:, j] = acc // full - (acc - v) // full
    out[:, 0] *= 1 if a >= 0 else -1
    out[:, 1] *= 1 if b >= 0 else -1
    return out


def _quadrant(x: int, y: int, dx: int, dy: int) -> int:
    """Quadrant of the arc piece about to be run from (x, y) in direction (dx, dy)."""
    mx, my = x + 0.5 * dx, y + 0.5 * dy
    if mx >= 0 and my >= 0:
        return 1
    if mx < 0 <= my:
        return 2
    return 3 if mx < 0 else 4


def stairs(x0: int, y0: int, xf: int, yf: int, clockwise: bool = True) -> list[dict[str, int]]:
    """Stairs approximation from (x0, y0) to (xf, yf) about the origin (table 3.5 rows).

    Columns: ``step, D, dx, dy, rem_x, rem_y, x, y``; ``dx``/``dy`` are the book's
    incremental terms ``2X+1`` and ``-2Y+1`` (the D change of the next +X / -Y step).
    """
    r2 = x0 * x0 + y0 * y0
    x, y = x0, y0
    d = 0
    rows = [
        dict(
            step=0, D=d, dx=2 * x + 1, dy=-2 * y + 1, rem_x=abs(xf - x), rem_y=abs(yf - y), x=x, y=y
        )
    ]
    step = 0
    while (x, y) != (xf, yf):
        step += 1
        q = _quadrant(x, y, int(np.sign(xf - x)), int(np.sign(yf - y)))
        inside, outside = STAIRS_RULES[(q, clockwise)]
        sx, sy = inside if d <= 0 else outside
        if (sx and x == xf) or (sy and y == yf):  # never pass the end coordinate
            sx, sy = (0, int(np.sign(yf - y))) if sx else (int(np.sign(xf - x)), 0)
        x, y = x + sx, y + sy
        d = x * x + y * y - r2
        rows.append(
            dict(
                step=step,
                D=d,
                dx=2 * x + 1,
                dy=-2 * y + 1,
                rem_x=abs(xf - x),
                rem_y=abs(yf - y),
                x=x,
                y=y,
            )
        )
        if step > 4 * (abs(x0) + abs(y0) + abs(xf) + abs(yf)) + 8:
            raise Diagnostic("PLAN-PULSE", "stairs approximation did not reach the end point")
    return rows


def direct_search(
    x0: int, y0: int, xf: int, yf: int, clockwise: bool = True
) -> list[dict[str, int | None]]:
    """Direct search (book §3.3.1.3, table 3.6 rows).

    Columns ``step, D, D1, D2, D3, dx, dy, rem_x, rem_y, x, y``: ``D1..D3`` are the
    candidates (stairs inside step, stairs outside step, both together) evaluated from the
    previous point, ``None`` where a candidate would pass the end point.
    """
    r2 = x0 * x0 + y0 * y0
    x, y, d = x0, y0, 0

    def row(step: int, cands: tuple[int | None, ...]) -> dict[str, int | None]:
        return dict(
            step=step,
            D=d,
            D1=cands[0],
            D2=cands[1],
            D3=cands[2],
            dx=2 * x + 1,
            dy=-2 * y + 1,
            rem_x=abs(xf - x),
            rem_y=abs(yf - y),
            x=x,
            y=y,
        )

    rows = [row(0, (None, None, None))]
    step = 0
    while (x, y) != (xf, yf):
        step += 1
        q = _quadrant(x, y, int(np.sign(xf - x)), int(np.sign(yf - y)))
        a, b = STAIRS_RULES[(q, clockwise)]
        moves = (a, b, (a[0] + b[0], a[1] + b[1]))
        cands: list[int | None] = []
        for sx, sy in moves:
            nx, ny = x + sx, y + sy
            passes = (sx and (nx - xf) * (x - xf) < 0) or (sy and (ny - yf) * (y - yf) < 0)
            passes = passes or (sx != 0 and x == xf) or (sy != 0 and y == yf)
            cands.append(None if passes else nx * nx + ny * ny - r2)
        ok = {i: c for i, c in enumerate(cands) if c is not None}
        if not ok:
            raise Diagnostic("PLAN-PULSE", "direct search has no admissible step")
        best = min(ok, key=lambda i: abs(ok[i]))
        x, y = x + moves[best][0], y + moves[best][1]
        d = int(ok[best])
        rows.append(row(step, tuple(cands)))
        if step > 4 * (abs(x0) + abs(y0) + abs(xf) + abs(yf)) + 8:
            raise Diagnostic("PLAN-PULSE", "direct search did not reach the end point")
    return rows
