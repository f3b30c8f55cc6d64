"""Compiled sliding minimum (numba) for the windowed look-ahead of large programs.

:func:`kernel.plan.planner.lookahead` with a window (a controller model's optimisation
depth: LinuxCNC's 50 segments) takes, for every junction, the minimum of the next
``window - 1`` values; :func:`kernel.plan.planner.range_min` does it with a sparse table
of ``log2(window)`` levels, each a pass over the program. This loop does it in one pass
(a monotonic queue). A minimum is one of the values, so the result is the same bit for
bit (tests/test_plan_kernels.py). Compiled once and cached next to this file
(``cache=True``); used where the caller has loaded numba anyway (the LinuxCNC model's
compiled join loops).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def window_min(x: np.ndarray, width: int) -> np.ndarray:
    """``min(x[i + 1 : min(i + width, n) + 1])`` for ``i`` in ``0 .. n - 1`` (``n =
    len(x) - 1``; inf where the range is empty). ``x`` must hold no NaN."""
    n = x.size - 1
    out = np.full(max(n, 0), np.inf)
    if width < 1 or n < 1:
        return out
    queue = np.empty(n, dtype=np.int64)  # indices, their values rising from head to tail
    head = 0
    tail = 0
    for i in range(n - 1, -1, -1):
        j = i + 1
        while tail > head and x[queue[tail - 1]] >= x[j]:
            tail -= 1
        queue[tail] = j
        tail += 1
        while queue[head] > i + width:
            head += 1
        out[i] = x[queue[head]]
    return out
