"""The bull-nose end mill's sweep in compiled code (numba), for
:func:`kernel.stock.heightfield.bull_envelope`: the stationary point of the end's height
along a move, cell by cell. A module of its own so that numba loads with the first bull
nose swept, not with every command that imports the stock (``cnc check`` without
``--stock``)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: precision of the bull nose's stationary point: within 2^-16 of [t1, t2], whose length
#: along the move is at most the diameter (9e-5 mm for 6 mm); the height's error (g' = 0
#: there) is about f'' / 2 times that squared (< 1e-7 mm)
BULL_STEPS = 16


@njit(cache=True, error_model="numpy")  # IEEE division: inf past the rim
def bull_end(rho: float, a: float, rc: float) -> float:
    """Height of the bull nose's end above its tip at ``rho`` from the axis."""
    e = min(max(rho - a, 0.0), rc)
    return rc - math.sqrt(rc * rc - e * e)


@njit(cache=True, error_model="numpy")  # IEEE division: inf past the rim
def bull_slope(rho: float, rp: float, ddz: float, a: float, rc: float) -> float:
    """g'(t) from the distance ``rho`` to the axis and its rate ``rp`` = rho'(t)."""
    e = min(max(rho - a, 0.0), rc)
    return ddz + e / math.sqrt(max(rc * rc - e * e, 1e-300)) * rp


@njit(cache=True, error_model="numpy")  # IEEE division: inf past the rim
def bull_root(
    x: float,
    y: float,
    xd: float,
    lo: float,
    hi: float,
    ddx: float,
    ddy: float,
    ddz: float,
    a: float,
    rc: float,
) -> float:
    """The t in [lo, hi] where g' (negative at lo, positive at hi, increasing) vanishes:
    Newton's method on g' with g'' = f''(rho) rho'^2 + f'(rho) (L^2 - rho'^2) / rho, kept
    inside the shrinking bracket: a step that leaves it, or does not halve the step before,
    bisects instead (and so does the flat end, where g'' = 0), until the bracket or the
    step is below 2^-:data:`BULL_STEPS` of the first bracket."""
    l2 = ddx * ddx + ddy * ddy
    tol = (hi - lo) * 2.0**-BULL_STEPS
    t = 0.5 * (lo + hi)
    last = hi - lo  # the step before the last: a Newton step must halve it
    for _ in range(4 * BULL_STEPS):
        px, py = x - t * ddx, y - t * ddy
        rho = max(math.sqrt(px * px + py * py), 1e-300)
        e = min(max(rho - a, 0.0), rc)
        den = max(rc * rc - e * e, 1e-300)
        root = math.sqrt(den)
        fp = e / root
        rp = (t * l2 - xd) / rho
        gp = ddz + fp * rp
        if gp < 0.0:
            lo = t
        else:
            hi = t
        if hi - lo <= tol:
            break
        gpp = 0.0  # on the flat end f' = f'' = 0: bisect
        if rho > a:
            gpp = rc * rc / den / root * rp * rp + fp * (l2 - rp * rp) / rho
        step = gp / gpp if gpp > 0.0 else hi - lo
        nxt = t - step
        if gpp > 0.0 and lo < nxt < hi and 2.0 * abs(step) <= last:
            last = abs(step)
            if last <= 0.5 * tol:
                return nxt
        else:
            nxt = 0.5 * (lo + hi)
            last = hi - lo
        t = nxt
    return t


@njit(cache=True, error_model="numpy")  # IEEE division: inf past the rim
def bull_kernel(
    qx: np.ndarray,
    qy: np.ndarray,
    ddx: float,
    ddy: float,
    ddz: float,
    z0: float,
    radius: float,
    corner: float,
    ceiling: np.ndarray,
    out: np.ndarray,
) -> None:
    """:func:`~kernel.stock.heightfield.bull_envelope` cell by cell into ``out`` (ny, nx):
    ``qx`` is (1 or ny, nx), ``qy`` (ny, 1 or nx), ``ceiling`` (ny, nx), or (0, 0) for
    none."""
    a, rc = radius - corner, corner
    l2 = ddx * ddx + ddy * ddy
    length = math.sqrt(l2)
    ny, nx = out.shape
    row_x, col_y = qx.shape[0] > 1, qy.shape[1] > 1
    has_ceiling = ceiling.shape[0] > 0
    level = abs(ddz) <= 1e-12
    r2 = radius * radius
    for j in range(ny):
        for i in range(nx):
            x = qx[j if row_x else 0, i]
            y = qy[j, i if col_y else 0]
            q2 = x * x + y * y
            if l2 <= 1e-24:
                if q2 <= r2:
                    out[j, i] = z0 + min(0.0, ddz) + bull_end(math.sqrt(q2), a, rc)
                else:
                    out[j, i] = np.inf
                continue
            qd = x * ddx + y * ddy
            disc = qd * qd - l2 * (q2 - r2)
            if disc < 0.0:
                out[j, i] = np.inf
                continue
            root = math.sqrt(disc)
            if qd - root > l2 or qd + root < 0.0:
                out[j, i] = np.inf
                continue
            t1 = min(max((qd - root) / l2, 0.0), 1.0)
            t2 = min(max((qd + root) / l2, 0.0), 1.0)
            if level:  # the lowest end is at the nearest point
                t = min(max(qd / l2, t1), t2)
                px, py = x - t * ddx, y - t * ddy
                out[j, i] = z0 + bull_end(math.sqrt(px * px + py * py), a, rc)
                continue
            px, py = x - t1 * ddx, y - t1 * ddy
            rho1 = math.sqrt(px * px + py * py)
            px, py = x - t2 * ddx, y - t2 * ddy
            rho2 = math.sqrt(px * px + py * py)
            best = min(z0 + t1 * ddz + bull_end(rho1, a, rc), z0 + t2 * ddz + bull_end(rho2, a, rc))
            out[j, i] = best
            if has_ceiling:
                w = abs(x * ddy - y * ddx) / length
                if z0 + min(t1 * ddz, t2 * ddz) + bull_end(w, a, rc) >= ceiling[j, i]:
                    continue  # cannot reach below the material here
            s1 = bull_slope(rho1, (t1 * l2 - qd) / max(rho1, 1e-300), ddz, a, rc)
            if s1 >= 0.0:
                continue
            s2 = bull_slope(rho2, (t2 * l2 - qd) / max(rho2, 1e-300), ddz, a, rc)
            if s2 <= 0.0:
                continue
            if has_ceiling:
                # g is convex: above both end tangents, so its least value is at least
                # where they cross; no cut when that is not below the material
                g1 = z0 + t1 * ddz + bull_end(rho1, a, rc)
                g2 = z0 + t2 * ddz + bull_end(rho2, a, rc)
                step = (g2 - g1 - s2 * (t2 - t1)) / (s1 - s2)
                bound = g1 + s1 * step
                if math.isfinite(bound) and bound >= ceiling[j, i]:
                    continue
            t = bull_root(x, y, qd, t1, t2, ddx, ddy, ddz, a, rc)
            px, py = x - t * ddx, y - t * ddy
            gm = z0 + t * ddz + bull_end(math.sqrt(px * px + py * py), a, rc)
            out[j, i] = min(best, gm)
