"""The segment table: one row per motion or hold, the columnar form of a path that
everything downstream of kernel.path.build (blends, curvature cuts, planner, sampling, measures)
reads. Kinds, categories and the row layout only; kernel.path.build describes the rules that fill
it, kernel.path.columns and kernel.path.builder build it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# segment kinds
LINE, ARC, HOLD = 0, 1, 2
# categories, for the cycle-time breakdown (kernel.report.measure)
FEED, RAPID, PROBE, DWELL, TOOL_CHANGE, ORIENT, STOP, MACHINE_FUNCTION = range(8)
CATEGORY_NAMES = (
    "feed",
    "rapid",
    "probe",
    "dwell",
    "tool_change",
    "orient",
    "stop",
    "machine_function",
)

SEGMENT_DTYPE = np.dtype(
    [
        ("kind", "i1"),
        ("category", "i1"),
        ("start", "f8", 6),
        ("end", "f8", 6),
        ("length", "f8"),  # path parameter s: mm (deg for rotary-only moves)
        ("u_start", "f8", 6),  # d position / ds at the start
        ("u_end", "f8", 6),  # d position / ds at the end
        ("centre", "f8", 3),
        ("normal", "f8", 3),
        ("e1", "f8", 3),
        ("e2", "f8", 3),
        ("radius", "f8"),  # at the start
        ("radius_end", "f8"),
        ("sweep", "f8"),  # signed angle about normal, rad
        ("axial", "f8"),  # displacement along normal (helix), mm
        ("feed", "f8"),  # programmed path speed, units of s per second (inf: traverse)
        ("duration", "f8"),  # holds: seconds
        ("exact_stop", "?"),  # speed must be zero at the end (G61, barrier)
        ("blend", "f8"),  # G64 P tolerance in force, mm (0: none)
        ("source", "i8"),  # index of the IR command
        ("line", "i4"),  # 1-based source line (0: unknown)
    ]
)

MIN_LENGTH = 1e-9  # mm: shorter motions are dropped (the position still moves)


@dataclass(frozen=True, slots=True)
class Path:
    """The segment table plus the file name the ``line`` column refers to."""

    segments: np.ndarray
    file: str | None = None

    def __len__(self) -> int:
        return int(self.segments.shape[0])

    @property
    def end_position(self) -> np.ndarray:
        """Where the program leaves the tool (machine coordinates, 6 axes)."""
        seg = self.segments
        return seg["end"][-1].copy() if len(seg) else np.zeros(6)


__all__ = [
    "ARC",
    "CATEGORY_NAMES",
    "DWELL",
    "FEED",
    "HOLD",
    "LINE",
    "MACHINE_FUNCTION",
    "MIN_LENGTH",
    "ORIENT",
    "PROBE",
    "RAPID",
    "SEGMENT_DTYPE",
    "STOP",
    "TOOL_CHANGE",
    "Path",
]
