"""The servo trace as charts for the ``cnc run --html`` page, drawn by the page's plotly.js.

:class:`PlotData` keeps a decimated copy of the streamed trace tables (at most
``max_points`` rows: every k-th row, and each chunk's rows of largest error). For the page,
:func:`chart_specs` turns it into plain data: per axis, position and velocity (commanded
against actual) and the following error over time; and the XY path, actual coloured by
contour error. Arrays travel as base64 little-endian float32, as the backplot's do
(cli/formats/assets/report.js draws them). Drawing in the browser costs the run nothing
(matplotlib PNGs cost several times the servo simulation); ``cnc trace --plot`` still
writes PNG files (kernel.report.plots).
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

ROTARY = frozenset("abc")


@dataclass
class PlotData:
    """Decimated trace columns for plotting."""

    axes: tuple[str, ...]
    total_rows: int
    max_points: int = 5_000
    cols: dict[str, list[np.ndarray]] = field(default_factory=dict)

    @property
    def stride(self) -> int:
        return max(1, math.ceil(self.total_rows / self.max_points))

    def add(self, table: dict[str, np.ndarray]) -> None:
        n = len(table["t"])
        if n == 0:
            return
        t0 = int(round(table["t"][0] / (table["t"][1] - table["t"][0]))) if n > 1 else 0
        keep = np.flatnonzero((np.arange(n) + t0) % self.stride == 0)
        peaks = [int(np.nanargmax(np.abs(table[f"{a}_following_error"]))) for a in self.axes]
        ce = table["contour_error"]
        if np.isfinite(ce).any():
            peaks.append(int(np.nanargmax(ce)))
        keep = np.union1d(keep, peaks)
        for name, col in table.items():
            self.cols.setdefault(name, []).append(np.asarray(col)[keep])

    def column(self, name: str) -> np.ndarray:
        parts = self.cols.get(name)
        return np.concatenate(parts) if parts else np.zeros(0)


def units(axis: str) -> tuple[str, str]:
    """Position and velocity units of an axis: degrees for A, B, C, else millimetres."""
    return ("deg", "deg/s") if axis in ROTARY else ("mm", "mm/s")


def error_scale(axis: str, error: np.ndarray) -> tuple[float, str]:
    """Following errors in µm when they stay under 1 mm on a linear axis, else as given."""
    pu = units(axis)[0]
    if axis in ROTARY or np.nanmax(np.abs(error), initial=0.0) >= 1.0:
        return 1.0, pu
    return 1000.0, "µm"


def _f32(values: np.ndarray) -> str:
    """Base64 of little-endian float32 (NaN where not finite)."""
    a = np.asarray(values, dtype="<f4")
    return base64.b64encode(np.where(np.isfinite(a), a, np.nan).astype("<f4").tobytes()).decode()


def chart_specs(data: PlotData) -> list[dict[str, Any]]:
    """The page's charts: the XY path (when X and Y move) and one chart per axis."""
    t = data.column("t")
    if not t.size:
        return []
    out: list[dict[str, Any]] = []
    if "x" in data.axes and "y" in data.axes:
        ce = data.column("contour_error") * 1000.0
        worst = int(np.nanargmax(ce)) if np.isfinite(ce).any() else -1
        x_a, y_a = data.column("x_act_pos"), data.column("y_act_pos")
        out.append(
            {
                "kind": "xy",
                "title": "XY path: commanded, and actual coloured by contour error",
                "x_cmd": _f32(data.column("x_cmd_pos")),
                "y_cmd": _f32(data.column("y_cmd_pos")),
                "x_act": _f32(x_a),
                "y_act": _f32(y_a),
                "error": _f32(ce),
                "error_label": "contour error [µm]",
                "worst": [float(x_a[worst]), float(y_a[worst]), float(ce[worst])]
                if worst >= 0
                else None,
            }
        )
    for a in data.axes:
        pu, vu = units(a)
        fe = data.column(f"{a}_following_error")
        scale, eu = error_scale(a, fe)
        out.append(
            {
                "kind": "axis",
                "title": f"axis {a.upper()}: commanded (dashed) and actual",
                "t": _f32(t),
                "rows": [
                    {
                        "label": f"position [{pu}]",
                        "cmd": _f32(data.column(f"{a}_cmd_pos")),
                        "act": _f32(data.column(f"{a}_act_pos")),
                    },
                    {
                        "label": f"velocity [{vu}]",
                        "cmd": _f32(data.column(f"{a}_cmd_vel")),
                        "act": _f32(data.column(f"{a}_act_vel")),
                    },
                    {"label": f"following error [{eu}]", "act": _f32(fe * scale)},
                ],
            }
        )
    return out


__all__ = ["ROTARY", "PlotData", "chart_specs", "error_scale", "units"]
