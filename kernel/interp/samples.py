"""Sampled motion: the hand-over between interpolation (issue 3) and servo/traces (issue 4).

A :class:`Samples` holds commanded values per axis at a fixed period, as numpy arrays, in
machine units (mm, deg, s). It is plain data: every stage downstream (acc/dec after
interpolation, servo simulation, measurement, traces) takes and returns arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

AXES: tuple[str, ...] = ("x", "y", "z", "a", "b", "c")


@dataclass(frozen=True, slots=True)
class Samples:
    """Commanded motion sampled every ``period`` seconds.

    ``position``, ``velocity``, ``acceleration`` and ``jerk`` have shape ``(n, len(axes))``
    (mm or deg, per second powers). ``segment`` is the index of the path segment each
    sample belongs to (-1 while dwelling or stopped at a barrier; int32 from
    :func:`kernel.interp.interpolate.sample`), ``source_line`` the 1-based program line it came
    from (0 when unknown, int32). ``t[i] == i * period``.
    """

    period: float
    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    segment: np.ndarray
    source_line: np.ndarray
    axes: tuple[str, ...] = AXES[:3]

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def duration(self) -> float:
        return float(self.t[-1]) if len(self) else 0.0
