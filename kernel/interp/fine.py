"""Fine interpolation (book §3.4 and §6.2.4): rough periods split into position periods.

* linear (eq. 3.72): ``a(j) = p(i) / N`` for the ``N = t_ipo / t_pos`` position periods of
  rough period ``i``;
* moving average (eq. 3.73, ``N`` even):
  ``b(j) = sum_{k=-N/2+1}^{N/2} a(j-k) / N``, ``b'(j) = sum_{k=-N/2}^{N/2-1} a(j-k) / N``,
  ``b''(j) = (b(j) + b'(j)) / 2`` (table 3.9; the text's "Eq. 3.72" there means 3.73).

Both conserve the pulse total. :func:`fine_positions` applies them to sampled positions
(one row per rough period) to give positions at the position-control period.
"""

from __future__ import annotations

import numpy as np

from kernel.diagnostics import Diagnostic


def fine_linear(pulses: np.ndarray, n: int) -> np.ndarray:
    """Eq. 3.72: each rough-period amount spread evenly over ``n`` fine periods."""
    if n < 1:
        raise Diagnostic("PLAN-FINE", f"fine interpolation ratio {n} must be >= 1")
    p = np.asarray(pulses, dtype=float)
    return np.repeat(p / n, n, axis=0)


def fine_moving_average(a: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 3.73: ``(b, b', b'')`` for the fine amounts ``a`` (index j as in table 3.9).

    ``a`` is taken as zero outside its range; the outputs have the length of ``a``.
    """
    if n < 2 or n % 2:
        raise Diagnostic("PLAN-FINE", f"moving-average fine interpolation needs an even N, got {n}")
    a = np.asarray(a, dtype=float)
    m = a.shape[0]
    h = n // 2
    pad = np.concatenate([np.zeros((n, *a.shape[1:])), a, np.zeros((n, *a.shape[1:]))])
    c = np.concatenate([np.zeros((1, *a.shape[1:])), np.cumsum(pad, axis=0)])
    j = np.arange(m) + n  # position of a(j) in pad

    def window(lo: int, hi: int) -> np.ndarray:  # sum of a(j - k), k = lo..hi
        return c[j - lo + 1] - c[j - hi]

    b = window(-h + 1, h) / n
    bp = window(-h, h - 1) / n
    return b, bp, 0.5 * (b + bp)


def fine_positions(position: np.ndarray, n: int, method: str = "linear") -> np.ndarray:
    """Positions every ``t_ipo / n`` from positions every ``t_ipo`` (rows), by the increments.

    The first row is kept; each following rough increment is split by :func:`fine_linear`
    and, for ``method="moving_average"``, smoothed by ``b''`` of eq. 3.73 (which looks
    ``n/2`` periods ahead, so that output starts ``n/2`` fine periods earlier and ends as
    many later). The total displacement is kept, so the end point is exact.
    """
    pos = np.asarray(position, dtype=float)
    inc = np.diff(pos, axis=0)
    a = fine_linear(inc, n)
    if method == "moving_average":  # b'' reaches n/2 periods ahead: pad both ends
        z = np.zeros((n // 2, *a.shape[1:]))
        a = fine_moving_average(np.concatenate([z, a, z]), n)[2]
    elif method != "linear":
        raise Diagnostic("PLAN-FINE", f"unknown fine interpolation {method!r}")
    return np.concatenate([pos[:1], pos[:1] + np.cumsum(a, axis=0)])
