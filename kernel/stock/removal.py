"""Removed volume and removal rate over time: the trace columns ``removed_mm3`` and
``mrr_mm3_s`` (docs/traces.md, docs/simulation.md).

The height-field simulation gives the volume each motion command removed
(``SimResult.move_volumes``, by IR index). The plan gives time: every trace row names the
path segment being commanded, each segment the IR command it came from (``source``). A
command's volume is spread over its segments' rows in proportion to the distance the
commanded tool point travels in each row, so the rate follows the feed: a steady cut
removing A mm² of cross-section at F mm/min removes A·F/60 mm³/s. Pure numpy, streamed in
the trace's chunks.
"""

from __future__ import annotations

import numpy as np


class RemovalMeter:
    """Turns trace chunks into the removed-volume columns: feed :meth:`step` every chunk's
    ``segment`` column and commanded X, Y, Z positions in order."""

    def __init__(self, move_volumes: dict[int, float], segments: np.ndarray, period: float):
        source = np.asarray(segments["source"], np.int64)
        length = np.asarray(segments["length"], float)
        n_cmd = int(source.max()) + 1 if len(source) else 0
        per_cmd = np.bincount(source, weights=length, minlength=n_cmd) if n_cmd else np.zeros(0)
        volume = np.zeros(n_cmd)
        for k, v in move_volumes.items():
            if 0 <= k < n_cmd:
                volume[k] = v
        with np.errstate(divide="ignore", invalid="ignore"):
            dens = np.where(per_cmd > 0, volume / np.where(per_cmd > 0, per_cmd, 1.0), 0.0)
        #: mm³ removed per mm the tool point travels, per path segment
        self.density = dens[source] if len(source) else np.zeros(0)
        self.period = period
        self.removed = 0.0
        self._last: np.ndarray | None = None

    def step(self, segment: np.ndarray, xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(removed_mm3, mrr_mm3_s)`` of one chunk: the cumulative volume at each row and
        the rate over the period ending there."""
        pos = np.asarray(xyz, float)
        if len(pos) == 0:
            return np.zeros(0), np.zeros(0)
        prev = np.vstack([pos[:1] if self._last is None else self._last[None, :], pos[:-1]])
        dist = np.linalg.norm(pos - prev, axis=1)
        seg = np.asarray(segment, np.int64)
        ok = (seg >= 0) & (seg < len(self.density))
        dv = np.where(ok, self.density[np.where(ok, seg, 0)] * dist, 0.0)
        cum = self.removed + np.cumsum(dv)
        self.removed = float(cum[-1])
        self._last = pos[-1].copy()
        return cum, dv / self.period
