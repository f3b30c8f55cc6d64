"""The simulated stock against the design: gouges below its top surface, material left
above it.

The design's top surface is rasterised on the stock's grid (:func:`kernel.stock.mesh.
top_surface`) so both are compared at the same cell centres; cells the design does not
cover are not compared. The deviation is stock minus design: below ``-tol`` is a gouge
(``SIM-GOUGE``, error), above ``+tol`` material left (``SIM-LEFTOVER``, warning). Each is
reported once, at its worst cell, located at the last move that cut that cell (the one
that set its final height, since heights only fall).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Location
from kernel.stock.heightfield import HeightField
from kernel.stock.simulate import RULES, SimFinding, SimResult


@dataclass(frozen=True, slots=True)
class Deviation:
    """Stock minus design per cell (NaN where the design has no surface) and the worst
    gouge and leftover (mm, >= 0) with the area (mm²) beyond the tolerance."""

    dev: np.ndarray
    gouge: float
    gouge_area: float
    leftover: float
    leftover_area: float

    def to_dict(self) -> dict[str, float]:
        return {
            "gouge": self.gouge,
            "gouge_area": self.gouge_area,
            "leftover": self.leftover,
            "leftover_area": self.leftover_area,
        }


def compare_design(
    hf: HeightField, design_top: np.ndarray, result: SimResult, tol: float, program: str | None
) -> Deviation:
    """Compare ``hf`` (after the program) with the rasterised design and append the
    gouge and leftover findings to ``result`` (which needs ``track_moves``)."""
    covered = np.isfinite(design_top)
    dev = np.where(covered, hf.h - np.where(covered, design_top, 0.0), np.nan)
    safe = np.where(covered, dev, 0.0)
    area = hf.cell_area
    out = Deviation(
        dev,
        max(0.0, -float(safe.min(initial=0.0))),
        float(np.count_nonzero(safe < -tol)) * area,
        max(0.0, float(safe.max(initial=0.0))),
        float(np.count_nonzero(safe > tol)) * area,
    )
    for code, sign, worst, what in (
        ("SIM-GOUGE", -1.0, out.gouge, "below"),
        ("SIM-LEFTOVER", 1.0, out.leftover, "above"),
    ):
        if worst <= tol:
            continue
        j, i = np.unravel_index(int(np.argmax(sign * safe)), safe.shape)
        x, y = float(hf.xs[i]), float(hf.ys[j])
        loc = Location(program)
        by = "never cut"
        if result.last_move is not None and result.last_move[j, i] >= 0:
            loc = result.move_locations[int(result.last_move[j, i])]
            by = "last cut by this move"
        cells_area = out.gouge_area if sign < 0 else out.leftover_area
        result.findings.append(
            SimFinding(
                code,
                RULES[code],
                f"stock {worst:.3f} mm {what} the design (tolerance {tol:g} mm; "
                f"{cells_area:.1f} mm² beyond it) at X{x:.3f} Y{y:.3f}, {by}",
                loc,
                worst,
                x,
                y,
            )
        )
    return out
