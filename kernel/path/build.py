"""IR -> path: a flat, columnar segment table in machine units (mm, deg, s).

DESIGN.md, *The kernel*: everything downstream is vectorised over this table. One row per
motion (line, arc or helix) or *hold* (dwell, tool change, spindle orientation, program
stop: barriers where the path speed must be zero). Positions are machine coordinates: the
program's work coordinates plus ``SET_ORIGIN_OFFSETS`` (or LinuxCNC's ``SET_G92_OFFSET``,
``SET_XY_ROTATION`` and ``SET_G5X_OFFSET``, applied in that order as rs274 does), lengths in
mm whatever the program's units (NISTIR 5970 §2.3.8), rotary axes in degrees. LinuxCNC's
``RIGID_TAP`` becomes two spindle-synchronised lines (in, and back out) with stops.

Feed rules (NISTIR 5970 §2.1.2.5 and §3.5.1, book ch. 2.3.3): the path parameter ``s`` is
the XYZ length of a move (along the helix for helical arcs); a move of rotary axes only is
measured in degrees and its feed read in degrees per minute. Inverse-time feed (G93) makes
the move last ``1/F`` minutes; feed per revolution (G95, and spindle-synchronised motion)
multiplies by the spindle speed. Traverses run as fast as the axes and the traverse rate
allow.

Arcs are kept exact: a centre, the unit vectors ``e1`` (centre to start) and ``e2``
(``normal x e1``), start and end radius (a slight spiral if the program's radii differ), the
signed sweep about ``normal`` and the displacement along it (helix). NURBS feeds are
tessellated by :mod:`kernel.interp.nurbs` into lines within the chord tolerance (book §3.5.3).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

import kernel.ir.canon as canon
from kernel.machine import Machine
from kernel.path.blend import blend_corners
from kernel.path.builder import PathBuilder
from kernel.path.segments import (
    FEED,
    LINE,
    MIN_LENGTH,
    SEGMENT_DTYPE,
    Path,
)


def build_path(
    commands: Iterable[canon.Command], machine: Machine, file: str | None = None
) -> Path:
    """Convert canonical commands to a :class:`Path` (raises ``PLAN-*`` diagnostics).

    Corners under a ``G64 P`` tolerance are already rounded (kernel.path.blend), so the rows
    are those the planner and the samples' ``segment`` indices refer to.
    """
    b = PathBuilder(machine, file)
    b.feed_all(commands)
    return blend_corners(Path(b.table(), file))


def lines_table(
    start: np.ndarray,
    points: np.ndarray,
    feed: float,
    category: int = FEED,
    line: np.ndarray | None = None,
) -> Path:
    """A path of straight lines through ``points`` (n x k, k <= 6) from ``start``, vectorised.

    Used by benchmarks and tests that build large programs without going through the IR.
    """
    n, k = points.shape
    p = np.zeros((n + 1, 6))
    p[0, : len(start)] = start
    p[1:, :k] = points
    d = p[1:] - p[:-1]
    length = np.linalg.norm(d[:, :3], axis=1)
    keep = length > MIN_LENGTH
    d, length = d[keep], length[keep]
    seg = np.zeros(int(keep.sum()), SEGMENT_DTYPE)
    starts, ends = p[:-1][keep], p[1:][keep]
    seg["kind"] = LINE
    seg["category"] = category
    seg["start"], seg["end"], seg["length"] = starts, ends, length
    u = d / length[:, None]
    seg["u_start"] = u
    seg["u_end"] = u
    seg["feed"] = feed
    seg["source"] = np.flatnonzero(keep)
    seg["line"] = line[keep] if line is not None else np.flatnonzero(keep) + 1
    return Path(seg)


__all__ = ["build_path", "lines_table"]
