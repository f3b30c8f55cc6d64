"""Several planners on one program: where their cycle times part (``cnc plan --compare``).

Each model's plan gives a time per source line (the durations of the segments the line
made, blend arcs counted with the line they lead into). A *stretch* is a run of ``window``
consecutive source lines that move; the stretches reported are those where the models'
times differ most (largest minus smallest model time over the stretch), none overlapping.
"""

from __future__ import annotations

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


def differing_stretches(
    times: dict[str, dict[int, float]], window: int = 10, count: int = 3
) -> list[Stretch]:
    """The ``count`` non-overlapping stretches of ``window`` lines where the models differ
    most, largest spread first (stretches with no difference are left out)."""
    names = list(times)
    lines = sorted(set().union(*(t.keys() for t in times.values())))
    if not lines or not names:
        return []
    table = np.array([[times[m].get(k, 0.0) for k in lines] for m in names])
    w = max(1, min(window, len(lines)))
    csum = np.concatenate([np.zeros((len(names), 1)), np.cumsum(table, axis=1)], axis=1)
    sums = csum[:, w:] - csum[:, :-w]  # (models, starts)
    spread = sums.max(axis=0) - sums.min(axis=0)
    taken = np.zeros(len(lines), dtype=bool)
    out: list[Stretch] = []
    for start in np.argsort(-spread, kind="stable"):
        if len(out) >= count or spread[start] <= 1e-9:
            break
        if taken[start : start + w].any():
            continue
        taken[start : start + w] = True
        out.append(
            Stretch(
                lines[start],
                lines[start + w - 1],
                {m: float(sums[i, start]) for i, m in enumerate(names)},
            )
        )
    return out


__all__ = ["Stretch", "differing_stretches", "line_times"]
