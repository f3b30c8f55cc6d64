"""Trace plots (matplotlib, Agg): one figure per axis and the XY path coloured by contour error.

:class:`~kernel.report.charts.PlotData` collects a decimated copy of the streamed trace
tables (the peaks survive), then :func:`axis_figure` and :func:`path_figure` draw it for
``cnc trace --plot`` (the HTML report draws the same data in the browser,
kernel.report.charts). Figures are
returned, not shown or saved: the CLI saves them.
"""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from kernel.report.charts import PlotData, error_scale, units  # noqa: E402

#: commanded against actual in the axis plots: a wide dashed black line under a thin solid
#: coloured one, so that both show where they coincide
_COMMANDED: dict[str, Any] = {
    "color": "black",
    "ls": (0, (5, 3)),
    "lw": 2.0,
    "alpha": 0.75,
    "zorder": 2,
    "label": "commanded (dashed)",
}
_ACTUAL: dict[str, Any] = {"lw": 1.1, "zorder": 3, "label": "actual"}


def axis_figure(data: PlotData, axis: str, title: str = "") -> Figure:
    """Position, velocity and following error of one axis over time (commanded vs actual)."""
    t = data.column("t")
    pu, vu = units(axis)
    # fixed margins, not a constrained layout: the layout solver took a third of the time
    fig, (ax_p, ax_v, ax_e) = plt.subplots(3, 1, sharex=True, figsize=(10, 8), dpi=110)
    fig.subplots_adjust(left=0.09, right=0.98, top=0.94, bottom=0.07, hspace=0.28)
    # commanded dashed black under the actual in colour: both stay visible where they agree
    ax_p.plot(t, data.column(f"{axis}_cmd_pos"), **_COMMANDED)
    ax_p.plot(t, data.column(f"{axis}_act_pos"), color="tab:blue", **_ACTUAL)
    ax_p.set_ylabel(f"position [{pu}]")
    ax_p.legend(loc="best", fontsize=9)
    ax_v.plot(t, data.column(f"{axis}_cmd_vel"), **_COMMANDED)
    ax_v.plot(t, data.column(f"{axis}_act_vel"), color="tab:orange", **_ACTUAL)
    ax_v.set_ylabel(f"velocity [{vu}]")
    ax_v.legend(loc="best", fontsize=9)
    fe = data.column(f"{axis}_following_error")
    scale, eu = error_scale(axis, fe)
    ax_e.plot(t, fe * scale, color="tab:red", lw=1.0)
    ax_e.axhline(0.0, color="0.3", lw=0.6)
    ax_e.set_ylabel(f"following error [{eu}]")
    ax_e.set_xlabel("time [s]")
    if fe.size:
        i = int(np.nanargmax(np.abs(fe)))
        ax_e.annotate(
            f"max {fe[i] * scale:.4g} {eu}",
            (t[i], fe[i] * scale),
            textcoords="offset points",
            xytext=(8, 8),
            fontsize=9,
        )
    for a in (ax_p, ax_v, ax_e):
        a.grid(True, alpha=0.3)
    fig.suptitle(title or f"axis {axis.upper()}: commanded vs actual", fontsize=12)
    return fig


def path_figure(data: PlotData, title: str = "") -> Figure:
    """The XY path: commanded (grey) and actual, coloured by contour error (µm)."""
    x_c, y_c = data.column("x_cmd_pos"), data.column("y_cmd_pos")
    x_a, y_a = data.column("x_act_pos"), data.column("y_act_pos")
    ce = data.column("contour_error") * 1000.0
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(13, 7), dpi=110, width_ratios=[3, 2])
    fig.subplots_adjust(left=0.06, right=0.97, top=0.92, bottom=0.09, wspace=0.22)
    ax.plot(x_c, y_c, color="0.75", lw=3.0, label="commanded", zorder=1)
    if x_a.size > 1:
        pts = np.column_stack([x_a, y_a]).reshape(-1, 1, 2)
        segs = np.concatenate([pts[:-1], pts[1:]], axis=1)
        val = np.nan_to_num(ce[1:], nan=0.0)
        lc = LineCollection(
            segs, cmap="viridis", linewidths=1.6, zorder=2, label="actual (colour: contour error)"
        )
        lc.set_array(val)
        lc.set_clim(0.0, max(float(val.max(initial=0.0)), 1e-9))
        ax.add_collection(lc)
        cb = fig.colorbar(lc, ax=ax, shrink=0.8)
        cb.set_label("contour error [µm]")
        if np.isfinite(ce).any():
            i = int(np.nanargmax(ce))
            ax.plot([x_a[i]], [y_a[i]], "o", mfc="none", mec="tab:red", ms=12, zorder=3)
            ax.annotate(
                f"max {ce[i]:.3g} µm",
                (x_a[i], y_a[i]),
                textcoords="offset points",
                xytext=(10, -14),
                color="tab:red",
                fontsize=9,
            )
            if ce[i] > 0:
                _zoom(zoom, x_c, y_c, x_a, y_a, val, i, float(ce[i]) / 1000.0)
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=9)
    ax.set_title("whole path", fontsize=11)
    if not zoom.has_data():
        zoom.set_axis_off()
    fig.suptitle(title or "XY path, actual coloured by contour error", fontsize=12)
    return fig


def _zoom(
    ins: plt.Axes,
    x_c: np.ndarray,
    y_c: np.ndarray,
    x_a: np.ndarray,
    y_a: np.ndarray,
    val: np.ndarray,
    i: int,
    err: float,
) -> None:
    """The path magnified around the worst contour error."""
    half = max(6.0 * err, 0.02)
    near = (np.abs(x_c - x_a[i]) < half) & (np.abs(y_c - y_a[i]) < half)
    idx = np.flatnonzero((np.abs(x_a - x_a[i]) < half) & (np.abs(y_a - y_a[i]) < half))
    if idx.size < 2:
        return
    ins.plot(x_c[near], y_c[near], "o", color="0.6", ms=3, label="commanded")
    ins.scatter(
        x_a[idx],
        y_a[idx],
        c=val[np.maximum(idx - 1, 0)],
        cmap="viridis",
        s=14,
        vmin=0.0,
        vmax=max(float(val.max(initial=0.0)), 1e-9),
        label="actual",
        zorder=3,
    )
    ins.plot([x_a[i]], [y_a[i]], "o", mfc="none", mec="tab:red", ms=14, zorder=4)
    ins.set_xlim(x_a[i] - half, x_a[i] + half)
    ins.set_ylim(y_a[i] - half, y_a[i] + half)
    ins.set_aspect("equal")
    ins.set_xlabel("X [mm]")
    ins.set_ylabel("Y [mm]")
    ins.legend(loc="best", fontsize=9)
    ins.grid(True, alpha=0.3)
    ins.set_title(f"worst point, ±{half * 1000:.0f} µm (a dot per servo period)", fontsize=10)
