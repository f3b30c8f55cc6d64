"""Grbl 1.1's planner as a planner strategy (``[controller] model = "grbl"``).

Re-derived from the behaviour of Grbl 1.1h (github.com/gnea/grbl, GPL-3.0; read, not
copied) and checked against grbl-sim built from it (tests/data/grbl_sim):

* **Arcs as lines** (motion_control.c ``mc_arc``): an arc of radius ``r`` and sweep ``phi``
  becomes ``floor(|phi r / 2| / sqrt(tol (2 r - tol)))`` equal chords (``$12`` arc
  tolerance, ``[controller] arc_tolerance``), a helix' axial travel shared evenly; fewer
  than one chord is one line.
* **Block limits** (planner.c ``plan_buffer_line``, ``limit_value_by_axis_maximum``): a
  block's acceleration and rapid rate are the largest whose every axis share stays within
  its ``$12x`` / ``$11x`` limit; its nominal speed is the feed, never above the rapid rate.
* **Junction deviation** (planner.c ``plan_buffer_line``): the junction speed is
  ``v^2 = a_j delta sin(theta/2) / (1 - sin(theta/2))`` with ``theta`` the angle between
  the moves' directions (``cos theta = -u1.u2``), ``delta`` the junction deviation (``$11``,
  ``[controller] junction_deviation``) and ``a_j`` the acceleration along the difference of
  the two directions; a straight continuation runs through at speed, a reversal stops; never
  above either block's nominal speed.
* **Forward and reverse passes** (planner.c ``planner_recalculate``) over the 16-block
  buffer (``BLOCK_BUFFER_SIZE``, one kept free): the last block in the buffer ends at rest.
* **Stops** at every buffer synchronisation (dwell, spindle, coolant, program end): the
  path's holds.

The program is taken as streamed by an ideal sender, so Grbl starts each cycle with its
planner full (the goldens' lockstep harness, tests/data/grbl_sim/README.md). A real sender on
a 115200-baud link makes Grbl start moving with one block in view, which slows the first
moves of a program of tiny segments.
"""

from __future__ import annotations

import numpy as np

import kernel.limits as limits
from kernel.diagnostics import Location
from kernel.machine import Machine
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, HOLD, LINE, Path
from kernel.plan.planner import Plan, commanded_feed, lookahead, ratio_min, trapezoids

BLOCK_BUFFER = 16  # config.h BLOCK_BUFFER_SIZE on the AVR
_TINY = 1e-12
_COS_STRAIGHT = 0.999999  # planner.c: straight continuation / reversal thresholds


def arc_chords(radius: np.ndarray, sweep: np.ndarray, tolerance: float) -> np.ndarray:
    """motion_control.c ``mc_arc``: how many chords an arc becomes (at least one)."""
    r = np.asarray(radius, float)
    q = tolerance * (2.0 * r - tolerance)
    den = np.sqrt(np.where(q > 0, q, 1.0))
    count = np.floor(np.abs(0.5 * np.asarray(sweep, float) * r) / den)
    return np.where(q > 0, np.maximum(count, 1), 1).astype(np.int64)


def _check_chords(path: Path, arc: np.ndarray, radius: np.ndarray, tolerance: float) -> None:
    """``LIMIT-COUNT`` at the first arc that would become more than ``kernel.limits``'
    ``arc_chords`` chords (an arc of a million turns, or of radius 1e99: each chord is a row
    of the segment table, 367 bytes)."""
    seg = path.segments
    q = tolerance * (2.0 * radius - tolerance)
    with np.errstate(all="ignore"):
        chords = np.abs(0.5 * seg["sweep"][arc] * radius) / np.sqrt(np.where(q > 0, q, 1.0))
    limit = limits.current().arc_chords
    over = ~(np.floor(chords) <= limit)  # NaN and inf are over
    if over.any():
        i = int(np.argmax(over))
        raise limits.count_error(
            "chords of one arc (Grbl's arc segments)",
            float(chords[i]),
            limit,
            "arc_chords",
            Location(path.file, int(seg["line"][arc[i]])),
        )


def segment_arcs(path: Path, tolerance: float) -> Path:
    """``path`` with every arc replaced by its Grbl chords (lines)."""
    seg = path.segments
    arc = np.flatnonzero(seg["kind"] == ARC)
    if not arc.size:
        return path
    r = np.minimum(seg["radius"][arc], seg["radius_end"][arc])
    _check_chords(path, arc, r, tolerance)
    count = arc_chords(r, seg["sweep"][arc], tolerance)
    reps = np.ones(len(seg), dtype=np.int64)
    reps[arc] = count
    out = np.repeat(seg, reps)
    first = np.concatenate([[0], np.cumsum(reps)[:-1]])
    # local chord index k within each arc, and the arc rows' positions in ``out``
    owner = np.repeat(np.arange(len(seg)), reps)
    k = np.arange(len(out)) - first[owner]
    is_arc = seg["kind"][owner] == ARC
    rows = np.flatnonzero(is_arc)
    n_of = reps[owner[rows]]
    length = seg["length"][owner[rows]]
    s0 = length * k[rows] / n_of
    s1 = length * (k[rows] + 1) / n_of
    p0, *_ = evaluate(seg, owner[rows], s0)
    p1, *_ = evaluate(seg, owner[rows], s1)
    last = k[rows] == n_of - 1
    p1[last] = seg["end"][owner[rows][last]]
    first_chord = k[rows] == 0
    p0[first_chord] = seg["start"][owner[rows][first_chord]]
    d = p1 - p0
    lin = np.linalg.norm(d[:, :3], axis=1)
    rot = np.linalg.norm(d[:, 3:], axis=1)
    ln = np.where(lin > _TINY, lin, rot)
    u = d / np.maximum(ln, _TINY)[:, None]
    sub = out[rows]
    sub["kind"] = LINE
    sub["start"], sub["end"] = p0, p1
    sub["length"] = ln
    sub["u_start"] = sub["u_end"] = u
    sub["radius"] = sub["radius_end"] = sub["sweep"] = sub["axial"] = 0.0
    out[rows] = sub
    keep = ~((out["kind"] == LINE) & (out["length"] <= 1e-12))
    return Path(out[keep], path.file)


def junction_speed(
    u1: np.ndarray, u2: np.ndarray, accel: np.ndarray, deviation: float
) -> np.ndarray:
    """planner.c: the junction-deviation speed between directions ``u1`` and ``u2`` (rows)."""
    cos = -np.sum(u1 * u2, axis=1)
    diff = u2 - u1
    norm = np.linalg.norm(diff, axis=1)
    unit = diff / np.maximum(norm, _TINY)[:, None]
    a_j = ratio_min(accel, unit)
    sin_half = np.sqrt(np.clip(0.5 * (1.0 - cos), 0.0, 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        v2 = a_j * deviation * sin_half / np.maximum(1.0 - sin_half, _TINY)
    v = np.sqrt(np.maximum(v2, 0.0))
    v = np.where(cos > _COS_STRAIGHT, 0.0, v)
    return np.where(cos < -_COS_STRAIGHT, np.inf, v)


def block_limits(path: Path, machine: Machine) -> tuple[np.ndarray, np.ndarray]:
    """planner.c ``plan_buffer_line``: every block's nominal speed (0 for holds) and
    acceleration, each from its own row (the path already in chords)."""
    seg = path.segments
    vmax = np.array(machine.limit_vector("velocity"))
    amax = np.array(machine.limit_vector("acceleration"))
    moving = seg["kind"] != HOLD
    u = seg["u_start"]
    rapid_rate = ratio_min(vmax, u)
    acc = ratio_min(amax, u)
    feed = commanded_feed(path, machine.controller)
    nominal = np.where(moving, np.minimum(feed, rapid_rate), 0.0)
    return nominal, acc


def junction_caps(seg: np.ndarray, nominal: np.ndarray, machine: Machine) -> np.ndarray:
    """The speed allowed at each junction between consecutive rows of ``seg`` (n - 1):
    junction deviation, never above either block's nominal speed, 0 next to a hold."""
    amax = np.array(machine.limit_vector("acceleration"))
    moving = seg["kind"] != HOLD
    v_j = junction_speed(
        seg["u_end"][:-1], seg["u_start"][1:], amax, machine.controller.junction_deviation
    )
    inner = np.minimum.reduce([v_j, nominal[:-1], nominal[1:]])
    ok = moving[:-1] & moving[1:]
    return np.where(ok, inner, 0.0)


def plan(path: Path, machine: Machine) -> Plan:
    """Plan ``path`` as Grbl 1.1 does (its arcs become chords first)."""
    ctl = machine.controller
    path = segment_arcs(path, ctl.arc_tolerance)
    seg = path.segments
    n = len(seg)
    moving = seg["kind"] != HOLD
    nominal, acc = block_limits(path, machine)
    jcap = np.zeros(n + 1)
    if n > 1:
        jcap[1:-1] = junction_caps(seg, nominal, machine)
    acc_plan = np.where(moving, acc, 0.0)
    window = None if n <= BLOCK_BUFFER - 1 else BLOCK_BUFFER - 1
    length = seg["length"]
    v = lookahead(length, jcap, acc_plan, None, window)
    prof = trapezoids(length, v[:-1], v[1:], nominal, acc_plan)
    duration = np.where(moving, prof.duration, seg["duration"])
    t_start = np.concatenate([[0.0], np.cumsum(duration)[:-1]]) if n else np.zeros(0)
    s = np.concatenate([[0.0], np.cumsum(length)])
    return Plan(path, machine, v, nominal, prof, np.zeros(n), duration, t_start, s[:-1], 0.0)


__all__ = [
    "BLOCK_BUFFER",
    "arc_chords",
    "block_limits",
    "junction_caps",
    "junction_speed",
    "plan",
    "segment_arcs",
]
