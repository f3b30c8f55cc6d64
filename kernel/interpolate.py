"""Sampling a planned path at the interpolation period (book ch. 3.3.2, 6.3.3).

The plan gives each segment a trapezoidal path-speed profile; here the path position
``S(t)``, speed, acceleration and jerk are evaluated in closed form at ``t_k = k T`` for all
samples at once (vectorised per chunk of samples, no per-sample Python loop), then mapped
onto the geometry (kernel.geometry) to give per-axis position, velocity, acceleration and
jerk by the chain rule. The last sample is the program's end point exactly (book ch. 3.1
requirement 3: no accumulated error).

S-curve (kernel.planner): with ``T_f > 0`` the path motion is the moving average of the
trapezoidal one over ``T_f``; in closed form, with ``I(t) = int_0^t S``:

    S~(t) = (I(t) - I(t-T_f)) / T_f,  v~ = (S(t) - S(t-T_f)) / T_f,
    a~ = (v(t) - v(t-T_f)) / T_f,     j~ = (a(t) - a(t-T_f)) / T_f

Sampled-data circle methods (``controller.circle_method``) replace arcs by the method's
chords (kernel.circle), traversed at the planned speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kernel.geometry import evaluate, line_cache
from kernel.machine import AXIS_NAMES
from kernel.path import HOLD
from kernel.planner import Plan
from kernel.samples import Samples

CHUNK = 32_768


@dataclass(frozen=True, slots=True)
class Pieces:
    """The path motion as polynomial pieces: 4 per segment (accelerate, cruise, decelerate,
    rest), as contiguous columns: start time ``t0`` (sorted), local path position ``s0``,
    speed ``v0``, acceleration ``a``, the segment's length ``smax``, global position ``S0``,
    ``I0 = int_0^t0 S dt`` and the segment index ``seg``."""

    t0: np.ndarray
    s0: np.ndarray
    v0: np.ndarray
    a: np.ndarray
    smax: np.ndarray
    big_s0: np.ndarray
    i0: np.ndarray
    seg: np.ndarray


def pieces(plan: Plan) -> Pieces:
    """Split every segment's trapezoid into its constant-acceleration pieces."""
    p = plan.profiles
    seg = plan.path.segments
    n = len(seg)
    moving = seg["kind"] != HOLD
    length = seg["length"]
    zero = np.zeros(n)
    ta, tc, td = (np.where(moving, x, 0.0) for x in (p.t_acc, p.t_cruise, p.t_dec))
    rest = plan.duration - (ta + tc + td)
    vs, vp = np.where(moving, p.v_start, 0.0), np.where(moving, p.v_peak, 0.0)
    acc, dec = np.where(moving, p.accel, 0.0), np.where(moving, p.decel, 0.0)
    sa = vs * ta + 0.5 * acc * ta**2
    sc = sa + vp * tc
    sd = np.where(moving, length, 0.0)
    dur = np.stack([ta, tc, td, rest], axis=1)
    s0 = np.stack([zero, sa, sc, sd], axis=1)
    v0 = np.stack([vs, vp, vp, zero], axis=1)
    a0 = np.stack([acc, zero, -dec, zero], axis=1)
    t0 = plan.t_start[:, None] + np.concatenate(
        [np.zeros((n, 1)), np.cumsum(dur, axis=1)[:, :3]], axis=1
    )
    # integral of S over each piece: S0 tau + v tau^2/2 + a tau^3/6 with S0 global
    big_s0 = plan.s_start[:, None] + s0
    whole = big_s0 * dur + v0 * dur**2 / 2 + a0 * dur**3 / 6
    i0 = np.concatenate([[0.0], np.cumsum(whole.ravel())[:-1]])
    smax = np.repeat(np.where(moving, length, 0.0), 4)
    return Pieces(
        t0.ravel(),
        s0.ravel(),
        v0.ravel(),
        a0.ravel(),
        smax,
        big_s0.ravel(),
        i0,
        np.repeat(np.arange(n), 4),
    )


def _piece_of(t0: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``searchsorted(t0, t, "right") - 1`` clipped to valid pieces, for sorted ``t``, in
    O(len(t) + pieces in range) by counting samples per piece."""
    n = len(t0)
    if not len(t):
        return np.zeros(0, dtype=np.int64)
    i_lo = max(int(np.searchsorted(t0, t[0], "right")) - 1, 0)
    i_hi = int(np.searchsorted(t0, t[-1], "right"))
    starts = np.searchsorted(t, t0[i_lo + 1 : i_hi], "left")
    bounds = np.concatenate([[0], starts, [len(t)]])
    return np.repeat(np.arange(i_lo, max(min(i_hi, n), i_lo + 1)), np.diff(bounds))


def path_state(pc: Pieces, t: np.ndarray, integral: bool = False) -> tuple[np.ndarray, ...]:
    """``(segment, local s, global S, v, a, I)`` at sorted times ``t`` (at rest at S = 0
    before 0). ``I`` (the time integral of S) only when ``integral``, else ``None``."""
    k = _piece_of(pc.t0, t)
    s0, v0, a0, smax, big_s0 = (x.take(k) for x in (pc.s0, pc.v0, pc.a, pc.smax, pc.big_s0))
    tau = t - pc.t0.take(k)
    np.maximum(tau, 0.0, out=tau)
    s = v0 * tau
    s += 0.5 * a0 * tau * tau
    s += s0
    np.minimum(s, smax, out=s)
    big_s = big_s0 + (s - s0)
    v = v0 + a0 * tau
    out_i = None
    if integral:
        out_i = pc.i0.take(k) + big_s0 * tau + v0 * tau**2 / 2 + a0 * tau**3 / 6
    neg = t < 0
    if neg.any():
        s[neg] = big_s[neg] = v[neg] = a0[neg] = 0.0
        if out_i is not None:
            out_i[neg] = 0.0
    return pc.seg[k], s, big_s, v, a0, out_i


def sample(plan: Plan, period: float | None = None, chunk: int = CHUNK) -> Samples:
    """Sample ``plan`` every ``period`` (default: the controller's interpolation period)."""
    machine = plan.machine
    ctl = machine.controller
    period = ctl.interpolation_period if period is None else period
    seg = plan.path.segments
    cols = [AXIS_NAMES.index(a) for a in machine.axis_names]
    total = plan.total_time
    count = int(math.ceil(total / period - 1e-9)) + 1 if len(seg) else 1
    t = np.arange(count) * period
    nax = len(cols)
    pos = np.empty((count, nax))
    vel = np.empty((count, nax))
    acc = np.empty((count, nax))
    jerk = np.zeros((count, nax))  # untouched pages stay shared zeros (trapezoid, lines)
    seg_out = np.empty(count, dtype=np.int64)
    line_out = np.empty(count, dtype=np.int32)
    if not len(seg):
        pos[:] = np.asarray(machine.limit_vector("home"))[cols]
        vel[:] = acc[:] = jerk[:] = 0.0
        seg_out[:] = -1
        line_out[:] = 0
        return Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)
    pc = pieces(plan)
    cache = line_cache(seg, cols)
    kind = cache["kind"]
    lines_of = np.ascontiguousarray(seg["line"])
    seg_index = np.where(kind == HOLD, -1, np.arange(len(seg)))
    moving_idx = np.flatnonzero(kind != HOLD)
    s_end_moving = (plan.s_start + seg["length"])[moving_idx]
    tf = plan.filter_time
    for lo in range(0, count, chunk):
        hi = min(count, lo + chunk)
        tt = np.minimum(t[lo:hi], total)
        k, local, big_s, v, a, integral = path_state(pc, tt, tf > 0)
        j = None
        gk = k
        if tf > 0:
            _, _, s2, v2, a2, i2 = path_state(pc, tt - tf, True)
            big_s, v, a, j = (integral - i2) / tf, (big_s - s2) / tf, (v - v2) / tf, (a - a2) / tf
            g = np.searchsorted(s_end_moving, big_s - 1e-12, "left")
            gk = moving_idx[np.clip(g, 0, moving_idx.size - 1)] if moving_idx.size else k
            gk = np.where(kind[k] == HOLD, np.where(v == 0, k, gk), gk)
            local = big_s - plan.s_start[gk]
        p, d1, curved, d2, d3 = evaluate(
            seg, gk, local, ctl.circle_method, ctl.chord_tolerance, cols, cache
        )
        pos[lo:hi] = p
        np.multiply(d1, v[:, None], out=vel[lo:hi])
        np.multiply(d1, a[:, None], out=acc[lo:hi])
        if j is not None:
            np.multiply(d1, j[:, None], out=jerk[lo:hi])
        if curved.size:
            vc, ac = v[curved][:, None], a[curved][:, None]
            acc[lo + curved] += d2 * vc * vc
            jerk[lo + curved] += 3 * d2 * vc * ac + d3 * vc**3
        seg_out[lo:hi] = seg_index[gk]
        np.take(lines_of, gk, out=line_out[lo:hi])
    pos[-1] = seg["end"][-1][cols]
    vel[-1] = acc[-1] = jerk[-1] = 0.0
    return Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)
