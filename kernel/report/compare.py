"""Several planners on one program: where their cycle times part (``cnc plan --compare``).

Each model's plan gives a time per source line (the durations of the segments the line
made, blend arcs counted with the line they lead into). A *stretch* is a run of ``window``
consecutive source lines that move; the stretches reported are those where the models'
times differ most (largest minus smallest model time over the stretch), none overlapping.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from kernel.plan.planner import Plan


@dataclass(frozen=True, slots=True)
class Stretch:
    """Source lines ``first``..``last`` and each model's time over them, s."""

    first: int
    last: int
    times: dict[str, float]

    @property
    def spread(self) -> float:
        """Largest minus smallest model time over the stretch, s."""
        return max(self.times.values()) - min(self.times.values())


def line_times(plan: Plan) -> dict[int, float]:
    """Seconds spent on each source line (0: commands without a line)."""
    seg = plan.path.segments
    lines = seg["line"].astype(np.int64)
    if not len(lines):
        return {}
    keys, inv = np.unique(lines, return_inverse=True)
    sums = np.bincount(inv, weights=plan.duration, minlength=keys.size)
    return {int(k): float(v) for k, v in zip(keys, sums, strict=True)}


class LineTimes:
    """:func:`line_times` of a plan that comes window by window (kernel.stream's ``watch``),
    as compact arrays indexed by source line: 8 bytes of time and 1 of presence per line
    up to the last one seen, whatever the number of rows. Each row's time is added to its
    line's in row order, as :func:`line_times` sums them (the same total, bit for bit)."""

    def __init__(self) -> None:
        self.times = np.zeros(0)
        self.seen = np.zeros(0, dtype=bool)

    def add(self, plan: Plan) -> None:
        """Add the rows of one window of the plan."""
        lines = plan.path.segments["line"].astype(np.int64)
        if not len(lines):
            return
        top = int(lines.max()) + 1
        if top > len(self.times):
            size = max(top, 2 * len(self.times))
            self.times = np.concatenate([self.times, np.zeros(size - len(self.times))])
            self.seen = np.concatenate([self.seen, np.zeros(size - len(self.seen), bool)])
        np.add.at(self.times, lines, plan.duration)
        self.seen[lines] = True


def stretches_of(times: dict[str, LineTimes], window: int = 10, count: int = 3) -> list[Stretch]:
    """:func:`differing_stretches` of the models' :class:`LineTimes` (the same stretches
    and sums), one model's row of the table at a time."""
    size = max((len(t.times) for t in times.values()), default=0)
    seen = np.zeros(size, dtype=bool)
    for t in times.values():
        seen[: len(t.seen)] |= t.seen
    lines = np.flatnonzero(seen)
    del seen

    def row(name: str) -> np.ndarray:
        t = times[name]
        out = np.zeros(lines.size)
        inside = lines < len(t.times)
        out[inside] = t.times[lines[inside]]
        return out

    return _stretches(list(times), lines, row, window, count)


def differing_stretches(
    times: dict[str, dict[int, float]], window: int = 10, count: int = 3
) -> list[Stretch]:
    """The ``count`` non-overlapping stretches of ``window`` lines where the models differ
    most, largest spread first (stretches with no difference are left out)."""
    lines = np.array(sorted(set().union(*(t.keys() for t in times.values()))), dtype=np.int64)

    def row(name: str) -> np.ndarray:
        return np.array([times[name].get(int(k), 0.0) for k in lines], dtype=float)

    return _stretches(list(times), lines, row, window, count)


def _stretches(
    names: list[str],
    lines: np.ndarray,
    row: Callable[[str], np.ndarray],
    window: int,
    count: int,
) -> list[Stretch]:
    """:func:`differing_stretches` of the models' times over ``lines`` (``row``: one
    model's, in the order of ``lines``): the table's window sums are made a model at a
    time, so memory holds a few arrays of the lines' length, not one per model."""
    if not len(lines) or not names:
        return []
    w = max(1, min(window, len(lines)))

    def sums(name: str) -> np.ndarray:
        csum = np.concatenate([[0.0], np.cumsum(row(name))])
        return csum[w:] - csum[:-w]

    high = low = sums(names[0])
    for name in names[1:]:
        s = sums(name)
        high, low = np.maximum(high, s), np.minimum(low, s)
    spread = high - low
    del high, low
    taken = np.zeros(len(lines), dtype=bool)
    starts: list[int] = []
    for start in np.argsort(-spread, kind="stable"):
        if len(starts) >= count or spread[start] <= 1e-9:
            break
        if taken[start : start + w].any():
            continue
        taken[start : start + w] = True
        starts.append(int(start))
    if not starts:
        return []
    picked = {m: sums(m)[starts] for m in names}
    return [
        Stretch(
            int(lines[start]),
            int(lines[start + w - 1]),
            {m: float(picked[m][j]) for m in names},
        )
        for j, start in enumerate(starts)
    ]


__all__ = ["LineTimes", "Stretch", "differing_stretches", "line_times", "stretches_of"]
