"""Acc/dec before interpolation (ADCBI): speed caps, corner speeds, look-ahead, profiles.

Book ch. 4.3-4.4 and 6.3 with the corrections of research/seed-book-motion.md §2-§3:

* per-segment speed caps: programmed feed (x override), each axis' velocity limit projected
  on the segment, centripetal acceleration on arcs (eq. 4.86/4.97 with the performance index
  ``arc_acceleration_ratio`` x axis acceleration), chord error for the interpolation period
  (eq. 4.98, read ``R - E``; the exact sagitta bound for exactly sampled arcs);
* corner speeds between consecutive segments from their end/start tangents (line-line,
  line-arc, arc-line, arc-arc alike, as ``DetermineVelocityBetween..``): the angle rule
  (eq. 4.88) or the per-axis speed-difference rule (eqs. 4.89-4.92, ``Q < 1`` reading);
* look-ahead over ``N`` buffered segments: backward from the window's end at speed zero
  (eqs. 4.93/4.94, fig. 4.33), forward so no segment needs more acceleration than it has
  (eqs. 4.95/4.96, fig. 4.32). Both passes are cumulative minima of ``v^2 +- 2 A s``
  (sliding minima for a finite window), so 200 000 segments plan without a Python loop;
* trapezoidal profiles per segment (eqs. 4.51-4.54 and the eight block-pair cases of
  §4.3.2, which are what the look-ahead boundary speeds reduce to);
* S-curve, at every curvature discontinuity (line-arc, arc-line, arc-arc, helix joints):
  the speed at which the step of the axis acceleration over one period stays within half
  the jerk limit (kernel.path.curvature, own derivation); paths built for an S-curve machine
  have their lines cut ``T_f v`` from such joints, so only that stretch is slowed;
* S-curve: the trapezoidal path profile smoothed by a moving average of ``T_f = 2A/J``
  along the path (the linear filter of eq. 4.4 applied to the path parameter, so the path
  itself is not changed): jerk ``= (a(t) - a(t - T_f))/T_f <= 2A/T_f = J`` even where the
  acceleration reverses from +A to -A within ``T_f`` (short blocks, speed dips at corners);
  a plain acceleration phase runs at jerk J/2. Acceleration and speed are never above the
  trapezoid's. Caps are eroded over the distance travelled in ``T_f`` and the profile
  pauses ``T_f`` at every stop so the smoothed speed is exactly zero there.

Exact stop (G61) makes every junction a stop; G61.1 and G64 blend with the corner rule.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic, Location
from kernel.machine import Controller, Machine, filter_time
from kernel.path.blend import blend_corners
from kernel.path.curvature import curvature_joint_caps, erode_joint_caps
from kernel.path.segments import ARC, HOLD, RAPID, Path

_TINY = 1e-12


# ----------------------------------------------------------------------------- book formulas
def angle_corner_speed(theta: np.ndarray | float, accel: float, period: float) -> np.ndarray:
    """Eq. 4.88: ``F_c = A T / (1 - cos theta)`` (theta = change of direction; inf if 0)."""
    den = 1.0 - np.cos(np.asarray(theta, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(den > _TINY, accel * period / np.maximum(den, _TINY), np.inf)


def axis_corner_speed(u1: np.ndarray, u2: np.ndarray, dv_max: np.ndarray) -> np.ndarray:
    """Eqs. 4.89-4.92 at one feed ``F`` on both sides: the largest ``F`` whose per-axis speed
    step ``F |u2_i - u1_i|`` stays within ``dVm_i`` (inf where no axis changes speed).
    Rows of ``u1`` / ``u2`` (unit tangents, d position / ds) are corners; the planner's
    ``axis`` corner rule."""
    return ratio_min(np.asarray(dv_max, float), np.asarray(u2, float) - np.asarray(u1, float))


def axis_corner_speeds(
    f1: float, f2: float, u1: np.ndarray, u2: np.ndarray, dv_max: np.ndarray
) -> tuple[float, float]:
    """Eqs. 4.89-4.92: end speed of N1 and start speed of N2 from per-axis speed steps.

    ``Q = min_i dVm_i / |dV_i|`` over axes whose speed changes; ``F_E1 = Q F1``,
    ``F_S2 = Q F2`` when ``Q < 1`` (the book's "greater than 1" is an erratum). The ratio is
    the one :func:`axis_corner_speed` takes (``dV = u2 - u1`` there: ``F1 = F2 = 1``).
    """
    dv = f2 * np.asarray(u2, float) - f1 * np.asarray(u1, float)
    q = min(float(ratio_min(np.asarray(dv_max, float), dv)), 1.0)
    return q * f1, q * f2


def arc_feed_limit(
    axis_accel: tuple[float, float], reference_radius: float, radius: float
) -> float:
    """Eqs. 4.85/4.86: ``F_o = sqrt(A_x R_o + A_y R_o)``, ``F_1 = F_o sqrt(R_c / R_o)``.

    The book's XY-plane rule for its worked examples; the planner caps arcs per axis and in
    any plane with :func:`centripetal_speed` (eq. 4.97) instead."""
    fo = math.sqrt(axis_accel[0] * reference_radius + axis_accel[1] * reference_radius)
    return fo * math.sqrt(radius / reference_radius)


def centripetal_speed(
    alpha: np.ndarray | float, radius: np.ndarray | float, weight: np.ndarray | float = 1.0
) -> np.ndarray:
    """Eq. 4.97 ``V = sqrt(alpha R)``; ``weight`` is the share of the arc's curvature an axis
    carries (1 in the book's plane; the planner's per-axis cap ``sqrt(alpha R / w_i)``)."""
    return np.sqrt(alpha * radius / weight)


def chord_error_speed(
    radius: np.ndarray | float, chord: float, period: np.ndarray | float
) -> np.ndarray:
    """Eq. 4.98, read ``R - E``: ``V = 2 R acos((R - E)/(R + E)) / T``, the speed at which
    one period's chord of an improved-Tustin arc stays within ``E``."""
    return 2.0 * radius * np.arccos(np.clip((radius - chord) / (radius + chord), -1, 1)) / period


def arc_speed_caps(alpha: float, radius: float, chord: float, period: float) -> tuple[float, float]:
    """Eq. 4.97 ``V = sqrt(alpha R)`` and eq. 4.98 ``V = 2 R acos((R-E)/(R+E)) / T``."""
    return float(centripetal_speed(alpha, radius)), float(chord_error_speed(radius, chord, period))


def short_block_peak(
    length: np.ndarray | float,
    accel: np.ndarray | float,
    decel: np.ndarray | float,
    v_start: np.ndarray | float = 0.0,
    v_end: np.ndarray | float = 0.0,
) -> np.ndarray:
    """Peak speed of a block too short to cruise (eq. 4.54 generalised, cases (f)-(h)):
    ``F^2 = (2 A D L + D vs^2 + A ve^2) / (A + D)``; :func:`trapezoids` uses it per block."""
    return np.sqrt(
        (2 * accel * decel * length + decel * v_start**2 + accel * v_end**2) / (accel + decel)
    )


# ----------------------------------------------------------------------------- range minima
def range_min(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """``min(values[lo:hi+1])`` for every query (inf for empty ranges), by a sparse table."""
    values = np.asarray(values, dtype=float)
    lo = np.maximum(np.asarray(lo, dtype=np.int64), 0)
    hi = np.minimum(np.asarray(hi, dtype=np.int64), values.size - 1)
    out = np.full(lo.shape, np.inf)
    ok = hi >= lo
    if not ok.any() or values.size == 0:
        return out
    span = (hi - lo + 1)[ok]
    level = np.floor(np.log2(span)).astype(np.int64)
    tables = [values]
    for j in range(1, int(level.max()) + 1):
        prev, h = tables[-1], 1 << (j - 1)
        tables.append(np.minimum(prev[:-h], prev[h:]))
    qlo, qhi = lo[ok], hi[ok]
    res = np.empty(qlo.shape)
    for j in np.unique(level):
        m = level == j
        t = tables[j]
        res[m] = np.minimum(t[qlo[m]], t[qhi[m] - (1 << int(j)) + 1])
    out[ok] = res
    return out


# ----------------------------------------------------------------------------- look-ahead
def lookahead(
    length: np.ndarray,
    junction_cap: np.ndarray,
    accel: np.ndarray,
    decel: np.ndarray | None = None,
    window: int | None = None,
    compiled: bool = False,
) -> np.ndarray:
    """Junction speeds (n+1) for n segments, starting and ending at rest.

    Backward (fig. 4.33, eqs. 4.93/4.94): the end speed of segment ``i`` is the largest from
    which every later junction cap in the window ``i .. i+N-1`` can be met decelerating at
    ``decel``, the window's last junction taken as a stop. Forward (fig. 4.32, eqs.
    4.95/4.96): a junction speed is lowered to what ``accel`` reaches from the previous one.
    With ``w = v^2`` and ``G_k = sum_{m<k} 2 D_m L_m`` the backward pass is
    ``w_i = min_k (c_k + G_k) - G_i``: a (sliding) minimum, likewise the forward pass.
    ``window`` ``None`` means unlimited; ``1`` is no look-ahead (stop after every block).
    ``compiled``: the window's minima by a compiled loop (kernel.plan.plan_kernels, the same
    numbers; for callers that load numba anyway).
    """
    length = np.asarray(length, dtype=float)
    decel = accel if decel is None else decel
    g = np.concatenate([[0.0], np.cumsum(2.0 * decel * length)])
    h = np.concatenate([[0.0], np.cumsum(2.0 * accel * length)])
    return _speeds(junction_cap, g, h, window, compiled)


def resumed_lookahead(
    length: np.ndarray,
    junction_cap: np.ndarray,
    accel: np.ndarray,
    window: int | None,
    g0: float,
    m0: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`lookahead` (``decel = accel``) of one window of a program, which may start
    anywhere in it (not only at a stop) and whose last junction is taken as a stop (the
    same sums as the whole program's, in the same order): ``g0`` is ``G`` at its first
    junction and ``m0`` the forward pass's running minimum of ``w - G`` there (``-g0`` at
    a stop). Returns the junction speeds and, at every junction, ``G`` and that running
    minimum: a later window resumed from junction ``k`` with ``G[k]`` and ``M[k]`` gets the
    speeds the whole program's look-ahead gives from ``k`` on, as long as this window's
    rows up to ``window`` junctions past ``k`` are the program's."""
    g = np.cumsum(np.concatenate([[g0], 2.0 * np.asarray(accel) * np.asarray(length, float)]))
    d = _end_speeds(junction_cap, g, window) - g
    d[0] = m0
    m = np.minimum.accumulate(d)
    return np.sqrt(np.clip(m + g, 0.0, None)), g, m


def _end_speeds(
    junction_cap: np.ndarray, g: np.ndarray, window: int | None, compiled: bool = False
) -> np.ndarray:
    """The backward pass of :func:`lookahead` over the running sums ``g``: the squared
    speed each junction may have (0 at the first and the last)."""
    n = g.size - 1
    c2 = np.square(np.asarray(junction_cap, dtype=float))
    c2[0] = c2[-1] = 0.0
    x = c2 + g
    if window is None or window >= n + 1:
        back = np.minimum.accumulate(x[::-1])[::-1]
        end2 = back[1:] - g[1:]
    else:
        i = np.arange(n)
        far = np.minimum(i + window, n)
        if compiled and not np.isnan(x).any():
            from kernel.plan.plan_kernels import window_min

            inner = window_min(x, window - 1)
        else:
            inner = range_min(x, i + 1, np.minimum(i + window - 1, n))
        end2 = np.minimum(inner, g[far]) - g[1:]
    return np.concatenate([[0.0], end2])


def _speeds(
    junction_cap: np.ndarray,
    g: np.ndarray,
    h: np.ndarray,
    window: int | None,
    compiled: bool = False,
) -> np.ndarray:
    """The backward and forward passes of :func:`lookahead` over the running sums ``g``
    (deceleration) and ``h`` (acceleration)."""
    y = _end_speeds(junction_cap, g, window, compiled)
    w = np.minimum.accumulate(y - h) + h
    return np.sqrt(np.clip(w, 0.0, None))


# ----------------------------------------------------------------------------- profiles
@dataclass(frozen=True, slots=True)
class Profiles:
    """Trapezoidal speed profile of every segment (s-units, s)."""

    v_start: np.ndarray
    v_end: np.ndarray
    v_peak: np.ndarray
    accel: np.ndarray
    decel: np.ndarray
    t_acc: np.ndarray
    t_cruise: np.ndarray
    t_dec: np.ndarray

    @property
    def duration(self) -> np.ndarray:
        return self.t_acc + self.t_cruise + self.t_dec


def trapezoids(
    length: np.ndarray,
    v_start: np.ndarray,
    v_end: np.ndarray,
    v_cap: np.ndarray,
    accel: np.ndarray,
    decel: np.ndarray | None = None,
) -> Profiles:
    """Closed-form accelerate / cruise / decelerate phases (eqs. 4.50-4.56, 4.57-4.82).

    A block is normal when ``L >= (F^2 - vs^2)/(2A) + (F^2 - ve^2)/(2D)`` (eq. 4.50,
    inequality corrected), otherwise short with the peak of :func:`short_block_peak`.
    """
    length = np.asarray(length, float)
    decel = accel if decel is None else decel
    a = np.where(accel > 0, accel, 1.0)
    d = np.where(decel > 0, decel, 1.0)
    vs, ve = np.asarray(v_start, float), np.asarray(v_end, float)
    vp = np.minimum(np.asarray(v_cap, float), short_block_peak(length, a, d, vs, ve))
    vp = np.maximum(vp, np.maximum(vs, ve))
    t_acc = (vp - vs) / a
    t_dec = (vp - ve) / d
    s_c = length - (vp**2 - vs**2) / (2 * a) - (vp**2 - ve**2) / (2 * d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_cru = np.where(vp > 0, np.clip(s_c, 0.0, None) / np.where(vp > 0, vp, 1.0), 0.0)
    return Profiles(vs, ve, vp, a, d, t_acc, t_cru, t_dec)


# ----------------------------------------------------------------------------- caps
def _machine_vectors(machine: Machine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return (
        np.array(machine.limit_vector("velocity")),
        np.array(machine.limit_vector("acceleration")),
        np.array(machine.limit_vector("jerk")),
    )


def ratio_min(limit: np.ndarray, comp: np.ndarray) -> np.ndarray:
    """min over axes of limit_i / |comp_i| (inf where no axis component): the path rate at
    which the first axis reaches its limit (Grbl's ``limit_value_by_axis_maximum``)."""
    c = np.abs(comp)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(c > _TINY, limit / np.where(c > _TINY, c, 1.0), np.inf)
    if r.ndim != 2 or not 0 < r.shape[1] <= 8:
        return r.min(axis=-1)
    # a few axes: the minimum column by column (a reduction over a short inner axis is an
    # order of magnitude slower; the minimum is the same in any order)
    out = r[:, 0].copy()
    for col in range(1, r.shape[1]):
        np.minimum(out, r[:, col], out=out)
    return out


def commanded_feed(path: Path, ctl: Controller) -> np.ndarray:
    """Every segment's programmed feed, rapids capped at the controller's rapid rate and
    feeds at its maximum feed (each when set)."""
    seg = path.segments
    feed = seg["feed"].copy()
    rapid = seg["category"] == RAPID
    if ctl.rapid_rate > 0:
        feed[rapid] = np.minimum(feed[rapid], ctl.rapid_rate)
    if ctl.max_feed > 0:
        feed[~rapid] = np.minimum(feed[~rapid], ctl.max_feed)
    return feed


def segment_limits(path: Path, machine: Machine) -> tuple[np.ndarray, np.ndarray]:
    """Speed cap and path acceleration of every segment (s-units/s, s-units/s^2)."""
    seg = path.segments
    ctl = machine.controller
    vmax, amax, jmax = _machine_vectors(machine)
    kind = seg["kind"]
    feed = commanded_feed(path, ctl)
    u = seg["u_start"]
    cap = np.minimum(feed, ratio_min(vmax, u))
    acc = ratio_min(amax, u)
    arc = np.flatnonzero(kind == ARC)
    if arc.size:
        # per-axis shares for an arc in any plane: in-plane weight w_i = sqrt(1 - n_i^2)
        # (the most of the tangent or the normal an axis can carry), along-normal n_i
        sa = seg[arc]
        nrm = np.abs(sa["normal"])
        w = np.sqrt(np.clip(1.0 - nrm**2, 0.0, 1.0))
        r = np.minimum(sa["radius"], sa["radius_end"])[:, None]
        planar = 0.5 * (sa["radius"] + sa["radius_end"]) * np.abs(sa["sweep"])
        frac = np.clip(planar / sa["length"], _TINY, 1.0)[:, None]  # in-plane speed share
        ax_comp = (np.abs(sa["axial"]) / sa["length"])[:, None]
        share = w * frac + nrm * ax_comp  # |axis velocity| <= v * share
        ratio = ctl.arc_acceleration_ratio
        bend = w > 1e-9
        with np.errstate(divide="ignore", invalid="ignore"):
            v_arc = np.where(share > _TINY, vmax[:3] / share, np.inf).min(axis=1)
            v_cent = centripetal_speed(ratio * amax[:3], r, w) / frac
            v_cent = np.where(bend, v_cent, np.inf).min(axis=1)
            budget = np.where(bend, (1 - ratio) * amax[:3], amax[:3])  # eq. 4.97 share
            a_tan = np.where(share > _TINY, budget / share, np.inf).min(axis=1)
        r1 = r[:, 0]
        f1 = frac[:, 0]
        period = ctl.interpolation_period * f1  # one period's in-plane travel
        if ctl.circle_method == "improved_tustin":  # eq. 4.98 (R - E reading)
            v_chord = chord_error_speed(r1, ctl.chord_tolerance, period)
        else:  # exact points: sagitta R (1 - cos(dtheta/2)) <= E
            step = 2 * np.arccos(np.clip(1 - ctl.chord_tolerance / r1, -1, 1))
            v_chord = r1 * step / period
        rot = ratio_min(vmax[3:], sa["u_start"][:, 3:])
        cap[arc] = np.minimum.reduce([feed[arc], v_arc, v_cent, v_chord, rot])
        acc[arc] = np.minimum(a_tan, ratio_min(amax[3:], sa["u_start"][:, 3:]))
        if ctl.accdec == "scurve":
            # axis jerk on arcs: j p1 + 3 v a p2 + v^3 p3, |p2| = w/R, |p3| = w/R^2: a
            # quarter of each in-plane jerk limit to v^3/R^2, a quarter to 3 v a/R, half
            # to the smoothed path jerk
            tf = filter_time(machine)
            with np.errstate(divide="ignore", invalid="ignore"):
                v_j = np.where(bend, np.cbrt(jmax[:3] * r * r / (4.0 * w)) / frac, np.inf)
                cap[arc] = np.minimum(cap[arc], v_j.min(axis=1))
                v_now = np.maximum(cap[arc], _TINY)[:, None]
                a_j1 = np.where(bend, jmax[:3] * r / (12.0 * v_now * w * frac), np.inf)
                a_j2 = np.where(share > _TINY, jmax[:3] * tf / (2.0 * share), np.inf)
            acc[arc] = np.minimum.reduce([acc[arc], a_j1.min(axis=1), a_j2.min(axis=1)])
    hold = kind == HOLD
    cap[hold] = 0.0
    acc[hold] = np.inf
    bad = (~hold) & ~(cap > 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise Diagnostic(
            "PLAN-LIMIT",
            "a move has no feasible speed (zero limit on a moving axis)",
            Location(path.file, int(seg["line"][i])),
        )
    return cap, acc


def junction_caps(path: Path, machine: Machine, cap: np.ndarray, acc: np.ndarray) -> np.ndarray:
    """Speed allowed at each of the n+1 junctions (0 at the ends, at barriers and G61)."""
    seg = path.segments
    ctl = machine.controller
    n = len(seg)
    out = np.zeros(n + 1)
    if n < 2:
        return out
    u1, u2 = seg["u_end"][:-1], seg["u_start"][1:]
    _, amax, _ = _machine_vectors(machine)
    if ctl.corner_rule == "axis":  # eqs. 4.89-4.92 with dVm = step x A x T
        dvm = ctl.corner_velocity_step * amax * ctl.interpolation_period
        corner = axis_corner_speed(u1, u2, dvm)
    else:  # eq. 4.88 on the XYZ direction change
        a3, b3 = u1[:, :3], u2[:, :3]
        na = np.linalg.norm(a3, axis=1)
        nb = np.linalg.norm(b3, axis=1)
        cos = np.einsum("ij,ij->i", a3, b3) / np.maximum(na * nb, _TINY)
        cos = np.where((na > _TINY) & (nb > _TINY), cos, np.sum(u1 * u2, axis=1))
        a = np.minimum(acc[:-1], acc[1:])
        corner = angle_corner_speed(np.arccos(np.clip(cos, -1, 1)), a, ctl.interpolation_period)
    inner = np.minimum.reduce([cap[:-1], cap[1:], corner])
    stop = seg["exact_stop"][:-1] | (seg["kind"][1:] == HOLD) | (seg["kind"][:-1] == HOLD)
    out[1:-1] = np.where(stop, 0.0, inner)
    return out


# ----------------------------------------------------------------------------- the plan
@dataclass(frozen=True, slots=True)
class Plan:
    """A planned path: junction speeds, per-segment trapezoids, start times.

    ``pause`` is the extra stand-still after a segment (S-curve smoothing, ``T_f`` at every
    stop); ``t_start[i]`` is when segment ``i`` starts; ``s_start`` its path position.
    ``filter_time`` is ``T_f`` (0 for trapezoidal acc/dec). ``overlap[i]`` (a controller
    model's parabolic blends, else ``None``): how long segment ``i``'s motion runs on past
    its slot (``duration[i]``) while segment ``i + 1`` already moves; the two motions add
    (kernel.interp.interpolate samples both).
    """

    path: Path
    machine: Machine
    v_junction: np.ndarray
    cap: np.ndarray
    profiles: Profiles
    pause: np.ndarray
    duration: np.ndarray
    t_start: np.ndarray
    s_start: np.ndarray
    filter_time: float
    overlap: np.ndarray | None = None

    @property
    def total_time(self) -> float:
        return float(self.t_start[-1] + self.duration[-1]) if len(self.duration) else 0.0


def _erode(
    s: np.ndarray, cap: np.ndarray, jcap: np.ndarray, dist: np.ndarray, moving: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Lower caps to their minimum within ``dist`` along the path (S-curve smoothing).

    ``dist`` is per segment; a junction uses the larger of its two segments' distances.
    """
    dj = np.concatenate([[dist[0]], np.maximum(dist[:-1], dist[1:]), [dist[-1]]])
    seg_cap = np.where(moving, cap, np.inf)
    j_in = np.where(jcap > 0, jcap, np.inf)
    a, b = s[:-1] - dist, s[1:] + dist
    lo = np.searchsorted(s[1:], a, "right")
    hi = np.searchsorted(s[:-1], b, "left") - 1
    klo = np.searchsorted(s, a, "left")
    khi = np.searchsorted(s, b, "right") - 1
    new_cap = np.minimum(range_min(seg_cap, lo, hi), range_min(j_in, klo, khi))
    new_cap = np.where(moving, np.minimum(cap, new_cap), cap)
    ja, jb = s - dj, s + dj
    lo = np.searchsorted(s[1:], ja, "right")
    hi = np.searchsorted(s[:-1], jb, "left") - 1
    klo = np.searchsorted(s, ja, "left")
    khi = np.searchsorted(s, jb, "right") - 1
    new_j = np.minimum(range_min(seg_cap, lo, hi), range_min(j_in, klo, khi))
    new_j = np.where(jcap > 0, np.minimum(jcap, new_j), 0.0)
    return new_cap, new_j


def smoothing_reach(seg: np.ndarray, cap: np.ndarray, tf: float) -> float:
    """The distance covered in ``T_f`` at the fastest finite cap of a moving row (``d0``):
    the reach of the S-curve smoothing, the one figure of it that spans the whole program
    (kernel.stream_scurve finds it in a first pass over the program)."""
    finite = cap[(seg["kind"] != HOLD) & np.isfinite(cap)]
    return tf * (float(finite.max()) if finite.size else 0.0)


def smoothed_limits(
    seg: np.ndarray,
    machine: Machine,
    s: np.ndarray,
    cap: np.ndarray,
    acc: np.ndarray,
    jcap: np.ndarray,
    d0: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """S-curve: the caps, junction caps and accelerations of the rows ``seg`` (path
    positions ``s``, n + 1) eroded over the distance the smoothing spans (``d0``:
    :func:`smoothing_reach`); the junction caps not yet lowered to their two rows' caps.
    Each row's result reads only the rows within ``d0`` of the rows within ``d0`` of it."""
    n = len(seg)
    moving = seg["kind"] != HOLD
    tf = filter_time(machine)
    # distance covered in T_f: first with the fastest cap anywhere, then with the
    # fastest cap within that reach (what the smoothing window can really span)
    fin = np.where(moving & np.isfinite(cap), cap, 0.0)
    lo = np.searchsorted(s[1:], s[:-1] - d0, "right")
    hi = np.searchsorted(s[:-1], s[1:] + d0, "left") - 1
    dist = tf * -range_min(-fin, lo, np.maximum(hi, lo))
    cap, jcap = _erode(s, cap, jcap, dist, moving)
    # acceleration steps at curvature joints (kernel.path.curvature), eroded over the
    # distance travelled in T_f at their own (low) speed
    _, _, jmax = _machine_vectors(machine)
    v_curv = curvature_joint_caps(seg, jmax, machine.controller.interpolation_period)
    cap, jcap = erode_joint_caps(s, cap, jcap, v_curv, tf)
    acc_e, _ = _erode(s, np.where(moving, acc, np.inf), np.zeros(n + 1), dist, moving)
    return cap, jcap, np.where(moving, acc_e, acc)


def plan(path: Path, machine: Machine) -> Plan:
    """Plan ``path`` on ``machine`` (controller settings from the profile)."""
    path = blend_corners(path)  # no-op for paths from build_path (already blended)
    ctl = machine.controller
    seg = path.segments
    n = len(seg)
    length = seg["length"]
    cap, acc = segment_limits(path, machine)
    jcap = junction_caps(path, machine, cap, acc)
    s = np.concatenate([[0.0], np.cumsum(length)])
    tf = filter_time(machine) if ctl.accdec == "scurve" else 0.0
    moving = seg["kind"] != HOLD
    if tf > 0 and n:
        d0 = smoothing_reach(seg, cap, tf)
        cap, jcap, acc = smoothed_limits(seg, machine, s, cap, acc, jcap, d0)
        jcap[1:-1] = np.minimum.reduce([jcap[1:-1], cap[:-1], cap[1:]])
    window = None if ctl.lookahead >= n else ctl.lookahead
    v = lookahead(length, jcap, np.where(moving, acc, 0.0), None, window)
    prof = trapezoids(length, v[:-1], v[1:], cap, np.where(moving, acc, 0.0))
    duration = np.where(moving, prof.duration, seg["duration"])
    pause = np.zeros(n)
    if tf > 0 and n:
        stop_after = v[1:] <= 0.0
        pause = np.where(stop_after & moving, tf, 0.0)
        duration = duration + pause
    t_start = np.concatenate([[0.0], np.cumsum(duration)[:-1]]) if n else np.zeros(0)
    return Plan(path, machine, v, cap, prof, pause, duration, t_start, s[:-1], tf)


__all__ = [
    "Plan",
    "Profiles",
    "angle_corner_speed",
    "arc_feed_limit",
    "arc_speed_caps",
    "axis_corner_speed",
    "axis_corner_speeds",
    "resumed_lookahead",
    "centripetal_speed",
    "chord_error_speed",
    "filter_time",
    "junction_caps",
    "lookahead",
    "plan",
    "range_min",
    "segment_limits",
    "short_block_peak",
    "smoothed_limits",
    "smoothing_reach",
    "trapezoids",
]
