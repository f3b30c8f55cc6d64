"""Speed caps at curvature discontinuities for jerk-limited (S-curve) motion.

Along the path an axis moves with (kernel.path.geometry, chain rule)

    x_i'' = p1_i a + p2_i v^2,    x_i''' = p1_i j + 3 p2_i v a + p3_i v^3

where ``p1, p2, p3`` are the first three derivatives of the position with respect to the
path parameter and ``v, a, j`` the path speed, acceleration and jerk. The S-curve profile of
kernel.plan.planner keeps ``v`` and ``a`` continuous, but where two segments meet the geometry
changes at once: at a line -> arc joint ``p2`` jumps from 0 to the arc's curvature vector
(``|p2| = 1/R``), at an arc -> line, arc -> arc (other radius, plane, direction) or a helix
joint likewise. The axis acceleration then steps by ``dA_i = |dp2_i| v^2`` within one
interpolation period ``T``: to the axis this is a jerk ``|dp2_i| v^2 / T`` on top of the
smooth motion's (a true step: without bound as ``T -> 0``). The S-curve of kernel.plan.planner
smooths the motion *along* the path (the ADCBI reading of the book's S filter, §4.2 eq. 4.6
corrected to ``H_L H_L``), so unlike per-axis ADCAI filtering it cannot round this step
away without leaving the path; the speed at the joint must be low enough instead.

Cap (own derivation; the book has no jerk-limited ADCBI, research/seed-book-motion.md §8):
the step over one period is held to a share ``k`` of the axis jerk limit,

    |dp2_i| v^2 <= k J_i T   =>   v <= min_i sqrt(k J_i T / |dp2_i|)

with ``k = 1/2`` (:data:`STEP_SHARE`): the other half is the budget of the smoothed path
motion, whose plain acceleration phases run at jerk ``J/2`` (kernel.plan.planner, S-curve). For a
tangent line -> arc joint of radius ``R`` with an in-plane axis carrying ``cos(phi)`` of the
normal this is ``v <= sqrt(k J T R / |cos phi|)``. It is the jerk analogue of the book's two
rules for the same joints: eq. 4.86 (the arc feed ``F^2/R`` held to an allowable
acceleration, "the worst shock is at the arc -> line transition", §4.3.2.12) and the
per-axis corner rule eq. 4.91, which allows a velocity step ``dV_m`` per period, i.e. a
bounded acceleration over one period; here the acceleration step per period is bounded, so
the jerk over one period is. Like the book's ``DetermineVelocityBetweenLC/CL/CC`` (§6.3,
research §3.4) the cap is a junction speed, taken with the others by the look-ahead.
Non-tangent joints keep their velocity step (the corner rule); only the curvature part of
their acceleration step is capped here. The jerk inside an arc (``v^3/R^2`` and ``3 v a/R``
terms) is capped per segment by kernel.plan.planner.segment_limits.

The planner applies the cap only in S-curve mode, lowering the caps within ``T_f v`` of the
joint (:func:`erode_joint_caps`) so that the smoothed speed at the joint is no higher.
Segment caps are per segment, so the path builder cuts the lines next to such joints
``T_f v`` from them (:func:`cut_for_machine`): only that stretch is slowed.
"""

from __future__ import annotations

import numpy as np

from kernel.machine import Machine, filter_time
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, HOLD, LINE, MIN_LENGTH, Path

#: share of the axis jerk limit given to the acceleration step at a curvature joint
STEP_SHARE = 0.5


def curvature_ends(seg: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``d2 position / ds2`` (XYZ) at the start and at the end of the segments ``rows``
    (zero for lines and holds; exact arcs whatever the sampled-data circle method)."""
    start = np.zeros((len(rows), 3))
    end = np.zeros((len(rows), 3))
    arc = np.flatnonzero(seg["kind"][rows] == ARC)
    if arc.size:
        sub = seg[rows[arc]]  # only the arcs: evaluate caches columns of its table
        idx, cols = np.arange(arc.size), [0, 1, 2]
        _, _, c0, d2_0, _ = evaluate(sub, idx, np.zeros(idx.size), "exact", 1.0, cols)
        _, _, c1, d2_1, _ = evaluate(sub, idx, sub["length"].copy(), "exact", 1.0, cols)
        start[arc[c0]] = d2_0
        end[arc[c1]] = d2_1
    return start, end


def curvature_steps(seg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Junctions (indices ``i``: between segment ``i`` and ``i+1``) next to an arc, and the
    per-axis step ``|p2(start of i+1) - p2(end of i)|`` there (XYZ, 1/mm)."""
    n = len(seg)
    arcs = np.flatnonzero(seg["kind"] == ARC)
    if n < 2 or not arcs.size:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    junction = np.unique(np.concatenate([arcs - 1, arcs]))
    junction = junction[(junction >= 0) & (junction < n - 1)]
    rows = np.unique(np.concatenate([junction, junction + 1]))
    start, end = curvature_ends(seg, rows)
    before = end[np.searchsorted(rows, junction)]
    after = start[np.searchsorted(rows, junction + 1)]
    return junction, np.abs(after - before)


def curvature_joint_caps(
    seg: np.ndarray, jerk: np.ndarray, period: float, share: float = STEP_SHARE
) -> np.ndarray:
    """Speed cap at each of the ``n - 1`` inner junctions: ``min_i sqrt(k J_i T / |dp2_i|)``
    (inf where the curvature does not change). ``jerk``: the XYZ axis jerk limits."""
    n = len(seg)
    out = np.full(max(n - 1, 0), np.inf)
    junction, step = curvature_steps(seg)
    if not junction.size:
        return out
    budget = share * np.asarray(jerk, dtype=float)[:3] * period
    with np.errstate(divide="ignore"):
        v2 = np.where(step > 1e-12, budget / np.where(step > 1e-12, step, 1.0), np.inf)
    out[junction] = np.sqrt(v2.min(axis=1))
    return out


def erode_joint_caps(
    s: np.ndarray, cap: np.ndarray, jcap: np.ndarray, v_joint: np.ndarray, tf: float
) -> tuple[np.ndarray, np.ndarray]:
    """Segment and junction caps lowered to ``v_joint[i]`` within ``T_f v_joint[i]`` of
    inner junction ``i + 1`` (path positions ``s``, n + 1; ``v_joint`` inf: no cap).

    The S-curve speed at path position ``p`` is the trapezoid's averaged over the last
    ``T_f``; if the trapezoid runs at most ``v`` within ``T_f v`` of ``p`` on both sides, the
    window (shorter than ``T_f v`` on either side of ``p``) sees no more than ``v``, so the
    joint is crossed at most at ``v``. Only that stretch is slowed, not the whole reach of
    the planner's general erosion (which uses the fastest speed around).
    """
    k = np.flatnonzero(np.isfinite(v_joint))
    if not k.size:
        return cap, jcap
    cap, jcap = cap.copy(), jcap.copy()
    v = v_joint[k]
    at = s[k + 1]
    lo, hi = at - tf * v, at + tf * v
    # segments overlapping (lo, hi), s_i < hi and s_i+1 > lo (one merely touching it ends
    # or starts at a junction capped by the overlapping neighbour); junctions in [lo, hi]
    for values, first, last in (
        (cap, np.searchsorted(s[1:], lo, "right"), np.searchsorted(s[:-1], hi, "left") - 1),
        (jcap, np.searchsorted(s, lo, "left"), np.searchsorted(s, hi, "right") - 1),
    ):
        count = np.maximum(last - first + 1, 0)
        idx = np.repeat(first - np.cumsum(count) + count, count) + np.arange(count.sum())
        np.minimum.at(values, idx, np.repeat(v, count))
    return cap, jcap


def split_lines_at_joints(path: Path, v_joint: np.ndarray, tf: float) -> tuple[Path, np.ndarray]:
    """A copy of ``path`` whose lines next to a capped curvature joint are cut ``T_f v`` from
    it (``v_joint``: the n - 1 inner junction caps, inf where none), so that only that
    stretch is slowed by :func:`erode_joint_caps` (segment caps are per segment); the rest
    of the line keeps its speed and decelerates to the cut like to any junction. Pieces
    keep their line's row (source, feed, ...); the cut is collinear, so it costs no corner
    speed. Lines shorter than twice the stretch are left whole. Returns the new path and
    ``v_joint`` for its junctions (inf at the cuts and at joints that are stops anyway)."""
    seg = path.segments
    kind = seg["kind"]
    # a joint that is a stop anyway (G61, a dwell or other hold) needs no cap
    stop = seg["exact_stop"][:-1] | (kind[:-1] == HOLD) | (kind[1:] == HOLD)
    v_joint = np.where(stop, np.inf, v_joint)
    k = np.flatnonzero(np.isfinite(v_joint))
    if not k.size or tf <= 0:
        return path, v_joint
    d = tf * v_joint[k]
    length = seg["length"]
    line = kind == LINE
    rows = np.concatenate([k, k + 1])  # the line ending at the joint, the one starting there
    at = np.concatenate([length[k] - d, d])
    ok = line[rows] & (length[rows] > 2 * np.concatenate([d, d])) & (at > MIN_LENGTH)
    rows, at = rows[ok], at[ok]
    if not rows.size:
        return path, v_joint
    order = np.lexsort((at, rows))
    rows, at = rows[order], at[order]
    # a line cut at both ends keeps both cuts (each at most half its length from its end)
    pieces = np.bincount(rows, minlength=len(seg)) + 1
    raw = np.dtype((np.void, seg.dtype.itemsize))  # rows as bytes: a plain memory copy
    out = np.repeat(seg.view(raw), pieces).view(seg.dtype)
    first = np.cumsum(pieces) - pieces  # new index of each old row's first piece
    cut_index = first[rows] + (np.arange(rows.size) - np.searchsorted(rows, rows, "left"))
    u = seg["u_start"][rows]
    point = seg["start"][rows] + at[:, None] * u
    out["end"][cut_index] = point
    out["start"][cut_index + 1] = point
    out["exact_stop"][cut_index] = False  # a stop (G61) belongs to the line's real end
    # lengths from the cut positions along each line
    s_from = np.zeros(len(out))
    s_to = np.repeat(length, pieces)
    s_to[cut_index] = at
    s_from[cut_index + 1] = at
    out["length"] = s_to - s_from
    v_new = np.full(len(out) - 1, np.inf)
    v_new[first[1:] - 1] = v_joint  # old junction i: after the last piece of row i
    return Path(out, path.file), v_new


def cut_for_machine(path: Path, machine: Machine) -> Path:
    """:func:`split_lines_at_joints` with the joint caps of ``machine`` (S-curve only; the
    path unchanged otherwise). kernel.path.builder applies it when it builds a path for a
    machine, so the planner (which never changes a built path's rows: the samples' segment
    indices refer to them) slows only the stretch next to each joint."""
    ctl = machine.controller
    if ctl.accdec != "scurve" or len(path) < 2:
        return path
    jerk = np.array(machine.limit_vector("jerk"))
    v = curvature_joint_caps(path.segments, jerk, ctl.interpolation_period)
    return split_lines_at_joints(path, v, filter_time(machine))[0]


__all__ = [
    "STEP_SHARE",
    "cut_for_machine",
    "curvature_ends",
    "curvature_joint_caps",
    "curvature_steps",
    "erode_joint_caps",
    "split_lines_at_joints",
]
