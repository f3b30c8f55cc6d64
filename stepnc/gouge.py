"""Gouge check: every cutting move of a workingstep must keep the tool inside the material
the workplan removes (raw workpiece minus finished part), book §11 Fig. 11.24 "Simulator
... checks for gouging"; research/seed-book-stepnc.md §1.14.

The tool is a flat-ended cylinder of its diameter (a drill's cylinder starts one tip length
above the tip, the cone being inside the hole's drill point). Moves are sampled every
``step`` mm; at each sample, points on the tool's bottom circle and on its side up to the
workpiece top are tested. A point gouges when it lies inside the raw block (shrunk by
``tol``) and inside no feature volume (grown by ``tol``).
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweep
from stepnc.model import Model, tool_dimension
from stepnc.prisms import Prism, raw_block
from stepnc.toolpaths.drilling import tip_length
from stepnc.volumes import feature_volumes

_DRILLS = frozenset({"TWIST_DRILL", "CENTER_DRILL", "COUNTERSINK", "TAP"})


@dataclass(frozen=True)
class Gouge:
    workingstep: int
    command: int  # index in the command stream
    point: tuple[float, float, float]


def _samples(start: np.ndarray, cmd: canon.Command, step: float) -> np.ndarray:
    """Tool-tip positions along a move (including its end)."""
    if isinstance(cmd, canon.StraightFeed):
        end = np.array([cmd.x, cmd.y, cmd.z])
        n = max(1, math.ceil(float(np.linalg.norm(end - start)) / step))
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        return start + t * (end - start)
    assert isinstance(cmd, canon.ArcFeed)  # XY plane, NISTIR 5970 §3.5.5
    cx, cy = cmd.first_axis, cmd.second_axis
    a0 = math.atan2(start[1] - cy, start[0] - cx)
    a1 = math.atan2(cmd.second_end - cy, cmd.first_end - cx)
    r0 = math.hypot(start[0] - cx, start[1] - cy)
    r1 = math.hypot(cmd.first_end - cx, cmd.second_end - cy)
    sweep = arc_sweep(a0, a1, cmd.rotation)
    n = max(1, math.ceil(abs(sweep) * max(r0, r1) / step), math.ceil(abs(sweep) / 0.2))
    t = np.linspace(0.0, 1.0, n + 1)
    ang = a0 + sweep * t
    rad = r0 + (r1 - r0) * t
    z = start[2] + (cmd.axis_end_point - start[2]) * t
    return np.column_stack([cx + rad * np.cos(ang), cy + rad * np.sin(ang), z])


def _tool_points(
    tips: np.ndarray, radius: float, lift: float, top: float, ring: int = 16, dz: float = 2.0
) -> np.ndarray:
    ang = np.linspace(0.0, 2 * math.pi, ring, endpoint=False)
    circle = np.column_stack([np.cos(ang), np.sin(ang), np.zeros(ring)]) * radius
    pts = [tips + [0.0, 0.0, lift]] if lift == 0.0 else []
    heights = np.arange(lift, max(lift, top - tips[:, 2].min()) + dz, dz)
    for h in heights:
        base = tips + [0.0, 0.0, h]
        pts.append((base[:, None, :] + circle[None, :, :]).reshape(-1, 3))
    return np.concatenate(pts)


def check(
    model: Model,
    commands: Iterable[canon.Command],
    raw: tuple[float, ...] | None = None,
    step: float = 1.0,
    tol: float = 1e-3,
) -> dict[int, list[Gouge]]:
    """Gouges per workingstep id (an empty list for a clean workingstep)."""
    block = raw_block(model, raw)
    removed = feature_volumes(model)
    top = block.frame.origin[2] + block.z_top
    result: dict[int, list[Gouge]] = defaultdict(list)
    pos = np.zeros(3)
    for i, cmd in enumerate(commands):
        ws = cmd.source.workingstep if cmd.source is not None else None
        if ws is not None:
            result.setdefault(ws, [])
        if isinstance(cmd, (canon.StraightFeed, canon.ArcFeed)) and ws is not None:
            tips = _samples(pos, cmd, step)
            op = model.entity(ws).its_operation
            tool = op.its_tool
            radius = float(tool_dimension(tool).diameter) / 2.0 * (1 - 1e-9)
            lift = tip_length(tool) if tool.its_tool_body.type in _DRILLS else 0.0
            pts = _tool_points(tips, radius, lift, top)
            bad = _gouging(pts, block, removed, tol)
            if bad.any():
                p = pts[int(np.argmax(bad))]
                result[ws].append(Gouge(ws, i, (float(p[0]), float(p[1]), float(p[2]))))
        if isinstance(cmd, (canon.StraightFeed, canon.StraightTraverse)):
            pos = np.array([cmd.x, cmd.y, cmd.z])
        elif isinstance(cmd, canon.ArcFeed):
            pos = np.array([cmd.first_end, cmd.second_end, cmd.axis_end_point])
        elif isinstance(cmd, canon.NurbsFeed) and cmd.points:
            pos = np.array([cmd.points[-1][0], cmd.points[-1][1], pos[2]])
    return dict(result)


def _gouging(pts: np.ndarray, block: Prism, removed: list[Prism], tol: float) -> np.ndarray:
    inside = block.contains(pts, -tol)
    for vol in removed:
        if not inside.any():
            break
        inside &= ~vol.contains(pts, tol)
    return inside
