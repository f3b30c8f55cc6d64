"""Equivalence of an IR and its re-reading through a language without arcs (Sandia generic).

The Sandia writer (gcode/write/sandia.py) replaces every ``ARC_FEED`` and ``NURBS_FEED``
by ``MoveTo`` chords within a tolerance and drops what the language cannot state (spindle,
coolant, dwell, stops; each recorded in its conversion report). :func:`compare` checks a
re-read IR (``back``) against the original (``ref``) on what the language carries:

* every motion in order, each seeing the same feed, length units and tool;
  traverses, feeds and probes with the same end points within 1e-4 (tests/canon_equiv.py);
* each curve replaced by ``pieces`` straight feeds (the count the writer reported, in
  order) that end exactly on the curve's end point and stay on it: for arcs, in closed form,
  every vertex on the (possibly spiral) circle and on the helix at its swept angle, the
  sweep monotonic and equal to the arc's, every chord's sagitta within the tolerance;
  for NURBS, the two-sided distance between the chords and the curve sampled densely;
* the same tool changes and program end.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence

import numpy as np

from gcode.write import approximate
from gcode.write.state import clamped_uniform_knots
from kernel.ir import canon
from tests.canon_equiv import TOLERANCE

#: rounding of the written numbers (5 decimals) on both coordinates of a vertex
ROUNDING = 2e-5
#: plane -> indexes of (first, second, normal) in (x, y, z)
AXES = {canon.Plane.XY: (0, 1, 2), canon.Plane.YZ: (1, 2, 0), canon.Plane.XZ: (2, 0, 1)}
CURVES = (canon.ArcFeed, canon.NurbsFeed, canon.EllipseFeed)
EVENTS = (canon.ChangeTool, canon.ProgramEnd)


def _items(commands: Iterable[canon.Command]) -> Iterator[tuple]:
    """(command, (feed, units, tool), start xyz, plane) for each motion and event."""
    feed, units, tool = 0.0, None, 0
    plane = canon.Plane.XY
    pos = [0.0, 0.0, 0.0]
    for c in commands:
        if isinstance(c, canon.SetFeedRate):
            feed = c.rate
        elif isinstance(c, canon.UseLengthUnits):
            if units is not None and units != c.units:
                pos = [v * units.mm_per_unit / c.units.mm_per_unit for v in pos]
            units = c.units
        elif isinstance(c, canon.SelectPlane):
            plane = c.plane
        elif isinstance(c, canon.ChangeTool):
            tool = c.name or c.slot
            yield c, None, tuple(pos), plane
        elif isinstance(c, canon.ProgramEnd):
            yield c, None, tuple(pos), plane
        elif isinstance(c, canon.StraightTraverse | canon.StraightFeed | canon.StraightProbe):
            yield c, (feed, units, tool), tuple(pos), plane
            pos = [c.x, c.y, c.z]
        elif isinstance(c, CURVES):
            yield c, (feed, units, tool), tuple(pos), plane
            pos = list(_curve_end(c, pos, plane))


def _curve_end(c: canon.Command, start: Sequence[float], plane: canon.Plane) -> list[float]:
    i1, i2, i3 = AXES[plane]
    end = list(start)
    if isinstance(c, canon.NurbsFeed):
        end[i1], end[i2] = c.points[-1][0], c.points[-1][1]
    else:
        end[i1], end[i2], end[i3] = c.first_end, c.second_end, c.axis_end_point  # type: ignore[attr-defined]
    return end


def _state_diff(a: tuple, b: tuple) -> str | None:
    if abs(a[0] - b[0]) > TOLERANCE:
        return f"feed {a[0]} != {b[0]}"
    if a[1] != b[1] or a[2] != b[2]:
        return f"units/tool {a[1:]} != {b[1:]}"
    return None


def compare(
    back: Iterable[canon.Command],
    ref: Iterable[canon.Command],
    pieces: Sequence[int],
    tolerance: float,
) -> list[str]:
    """Differences between ``back`` and ``ref`` (``[]``: equivalent within the chords)."""
    b_items = list(_items(back))
    out: list[str] = []
    j = k = 0
    for n, (cmd, state, start, plane) in enumerate(_items(ref)):
        if isinstance(cmd, CURVES):
            if k >= len(pieces):
                return [*out, f"item {n}: more curves than the writer reported"]
            count, k = pieces[k], k + 1
            chunk = b_items[j : j + count]
            j += count
            if len(chunk) < count or any(not isinstance(b[0], canon.StraightFeed) for b in chunk):
                return [*out, f"item {n}: {cmd.NAME} not followed by {count} straight feeds"]
            for b in chunk:
                diff = _state_diff(b[1], state)
                if diff:
                    out.append(f"item {n}: chord of {cmd.NAME} sees {diff}")
            vertices = np.array([[b[0].x, b[0].y, b[0].z] for b in chunk])
            out += [f"item {n}: {e}" for e in _curve_diff(cmd, start, plane, vertices, tolerance)]
            continue
        if j >= len(b_items):
            return [*out, f"item {n}: {cmd.NAME} missing"]
        b, j = b_items[j], j + 1
        if b[0].NAME != cmd.NAME:
            return [*out, f"item {n}: {b[0].NAME} vs {cmd.NAME}"]
        if state is None:
            if b[0].args() != cmd.args():
                out.append(f"item {n}: {b[0].to_text()} vs {cmd.to_text()}")
            continue
        for name in ("x", "y", "z", "a", "b", "c"):
            if abs(getattr(b[0], name) - getattr(cmd, name)) > TOLERANCE:
                out.append(f"item {n}: {cmd.NAME} {name} {getattr(b[0], name)}")
        diff = _state_diff(b[1], state)
        if diff:
            out.append(f"item {n}: {cmd.NAME} sees {diff}")
    if j != len(b_items):
        out.append(f"{len(b_items) - j} more motions/events read back")
    if k != len(pieces):
        out.append(f"{len(pieces) - k} reported curves not found")
    return out[:8]


def _curve_diff(
    c: canon.Command, start: Sequence[float], plane: canon.Plane, v: np.ndarray, tol: float
) -> list[str]:
    end = _curve_end(c, start, plane)
    if np.max(np.abs(v[-1] - end)) > TOLERANCE:
        return [f"last chord ends at {v[-1].tolist()}, not {end}"]
    if isinstance(c, canon.ArcFeed):
        return _arc_diff(c, start, plane, v, tol)
    if isinstance(c, canon.NurbsFeed):
        return _nurbs_diff(c, start, plane, v, tol)
    return [f"{c.NAME}: no check written"]


def _arc_diff(
    c: canon.ArcFeed, start: Sequence[float], plane: canon.Plane, v: np.ndarray, tol: float
) -> list[str]:
    """Closed form: vertices on the helix, monotonic sweep equal to the arc's, sagittas."""
    i1, i2, i3 = AXES[plane]
    if c.rotation == 0:
        return [] if len(v) == 1 else ["an arc of 0 turns is one chord"]
    cx, cy = c.first_axis, c.second_axis
    sign = 1.0 if c.rotation > 0 else -1.0
    a0 = math.atan2(start[i2] - cy, start[i1] - cx)
    a1 = math.atan2(c.second_end - cy, c.first_end - cx)
    sweep = (sign * (a1 - a0)) % (2 * math.pi)
    if sweep <= 1e-12:  # the IR's full turn, as the planner reads it (kernel/path/builder.py)
        sweep = 2 * math.pi
    sweep += 2 * math.pi * (abs(c.rotation) - 1)
    r0 = math.hypot(start[i1] - cx, start[i2] - cy)
    r1 = math.hypot(c.first_end - cx, c.second_end - cy)
    pts = np.vstack([np.array(start)[None, :], v])
    ang = np.arctan2(pts[:, i2] - cy, pts[:, i1] - cx)
    steps = (sign * np.diff(ang)) % (2 * math.pi)
    s = np.concatenate([[0.0], np.cumsum(steps)])
    out = []
    if abs(s[-1] - sweep) > 1e-6 * max(1.0, sweep) and abs(s[-1] - sweep) * r0 > TOLERANCE:
        out.append(f"chords sweep {s[-1]:.6f} rad, the arc {sweep:.6f}")
    if np.any(steps >= math.pi):
        out.append("a chord spans half a circle or more")
    frac = s / s[-1]
    radius = r0 + (r1 - r0) * frac
    rho = np.hypot(pts[:, i1] - cx, pts[:, i2] - cy)
    radial = np.abs(rho - radius)
    if radial.max() > tol + ROUNDING:
        out.append(f"vertex {int(radial.argmax())} off the circle by {radial.max():.2e}")
    helix = start[i3] + (c.axis_end_point - start[i3]) * frac
    # a rounded vertex's angle is uncertain by ROUNDING / r: so is its share of the helix
    slack = abs(c.axis_end_point - start[i3]) * ROUNDING / max(min(r0, r1), 1e-9) / s[-1]
    if np.max(np.abs(pts[:, i3] - helix)) > TOLERANCE + slack:
        out.append("a vertex is off the helix")
    r_mid = 0.5 * (radius[:-1] + radius[1:])
    sag = r_mid * (1 - np.cos(np.minimum(steps, math.pi) / 2))
    worst = sag + np.maximum(radial[:-1], radial[1:])
    if worst.max() > tol + ROUNDING:
        out.append(f"chord {int(worst.argmax())} deviates {worst.max():.2e} > {tol}")
    return out


def _nurbs_diff(
    c: canon.NurbsFeed, start: Sequence[float], plane: canon.Plane, v: np.ndarray, tol: float
) -> list[str]:
    """Two-sided distance between the chord polyline and the curve sampled at 4,000 points."""
    i1, i2, i3 = AXES[plane]
    pts = np.array(c.points, dtype=float)
    knots = np.array(c.knots or clamped_uniform_knots(len(pts), c.order), dtype=float)
    curve = approximate.nurbs_evaluate(c.order, pts, knots, np.linspace(knots[0], knots[-1], 4000))
    poly = np.vstack([[start[i1], start[i2]], v[:, [i1, i2]]])
    out = []
    if np.max(np.abs(v[:, i3] - start[i3])) > TOLERANCE:
        out.append("a NURBS chord leaves the plane")
    step = float(np.max(np.hypot(*np.diff(curve, axis=0).T)))
    slack = ROUNDING + step * step  # sampling of the curve: sagitta of its sample chords
    d_curve = _distance(curve, poly)
    d_poly = _distance(np.vstack([poly, 0.5 * (poly[1:] + poly[:-1])]), curve)
    if max(d_curve, d_poly) > tol + slack:
        out.append(f"chords and curve {max(d_curve, d_poly):.2e} apart > {tol}")
    return out


def _distance(points: np.ndarray, polyline: np.ndarray) -> float:
    """Largest distance from ``points`` to the polyline (vectorised point-segment)."""
    a, b = polyline[:-1], polyline[1:]
    d = b - a
    ll = np.maximum((d * d).sum(axis=1), 1e-30)
    worst = 0.0
    for chunk in np.array_split(points, max(1, len(points) // 512)):
        rel = chunk[:, None, :] - a[None, :, :]
        t = np.clip((rel * d[None]).sum(axis=2) / ll[None], 0.0, 1.0)
        near = a[None] + t[..., None] * d[None]
        dist = np.hypot(*(chunk[:, None, :] - near).transpose(2, 0, 1)).min(axis=1)
        worst = max(worst, float(dist.max()))
    return worst
