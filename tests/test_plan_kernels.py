"""The compiled sliding minimum of the windowed look-ahead (kernel.plan.plan_kernels) gives
the sparse table's minima (kernel.plan.planner.range_min) and the same junction speeds."""

from __future__ import annotations

import numpy as np
import pytest

from kernel.plan.plan_kernels import window_min
from kernel.plan.planner import lookahead, range_min


@pytest.mark.parametrize("width", [0, 1, 2, 3, 49, 200])
@pytest.mark.parametrize("n", [1, 2, 5, 120])
def test_window_min_is_the_range_minimum(n: int, width: int) -> None:
    rng = np.random.default_rng(n * 1000 + width)
    # ties and plateaus as well as distinct values
    x = np.round(rng.uniform(0.0, 5.0, n + 1), 1 if width % 2 else 6)
    i = np.arange(n)
    ref = range_min(x, i + 1, np.minimum(i + width, n))
    assert np.array_equal(window_min(x, width), ref)


@pytest.mark.parametrize("window", [1, 2, 50])
def test_compiled_windowed_lookahead_is_the_same(window: int) -> None:
    rng = np.random.default_rng(window)
    n = 3000
    length = rng.uniform(0.01, 2.0, n)
    cap = rng.uniform(0.0, 80.0, n + 1)
    cap[rng.integers(0, n + 1, 300)] = 0.0  # stops
    accel = rng.uniform(100.0, 2000.0, n)
    ours = lookahead(length, cap, accel, None, window, True)
    ref = lookahead(length, cap, accel, None, window)
    assert np.array_equal(ours.view(np.uint64), ref.view(np.uint64))
