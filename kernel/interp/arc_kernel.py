"""Compiled sampling of trapezoidal motion on lines and exact arcs (numba): the path state
and the axes' position, velocity, acceleration and jerk of every sample in two passes per
chunk, for :class:`kernel.interp.interpolate._Sampler`.

It computes what :func:`kernel.interp.interpolate._trapezoid_state`, the line formulas of
``_Sampler.run`` and, on arcs and helices, :func:`kernel.path.geometry.evaluate`
(``_arc``) with the chain rule of ``_ArcBatch`` compute with numpy, sample by sample, with
the same floating-point operations in the same order (numba adds no fused multiply-adds
without ``fastmath``), so the results are the same bit for bit
(tests/test_kernel_sampling_equivalence.py). The cubes (the samples' speed, the arcs'
sweep and length) come from numpy's ``**`` between the passes (its power is not the C
library's). Speed (issue 16): on LinuxCNC-model plans most samples lie on blend arcs, and
the numpy formulation makes a dozen (n, 3) temporaries per chunk and gathers the arc rows.
The segment table is read in place (numba reads its packed records). Compiled once and
cached next to this file (``cache=True``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from kernel.path.segments import ARC, HOLD, LINE


@njit(cache=True)
def trapezoid_states(
    lo: int,
    period: float,
    total: float,
    k: int,
    t0: np.ndarray,
    s0: np.ndarray,
    v0: np.ndarray,
    acc: np.ndarray,
    smax: np.ndarray,
    t_out: np.ndarray,
    gk: np.ndarray,
    local: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
) -> None:
    """The samples ``lo .. lo + len(t_out) - 1`` at ``t = float(i) * period`` (written to
    ``t_out``; at most ``total`` for the state): segment ``gk``, local path position, speed
    and acceleration of the trapezoidal pieces (``t0`` sorted, ``s0``, ``v0``, ``acc``;
    ``smax`` per segment). ``k``: the piece of the first sample (the last with
    ``t0 <= t``); the later ones are found by walking on."""
    npieces = t0.size
    for i in range(t_out.size):
        t = float(lo + i) * period
        t_out[i] = t
        if t > total:
            t = total
        while k + 1 < npieces and t0[k + 1] <= t:
            k += 1
        tau = t - t0[k]
        if tau < 0.0:
            tau = 0.0
        ak = acc[k]
        vk = v0[k]
        s = vk * tau
        q = ak * 0.5
        q *= tau
        q *= tau
        s += q
        s += s0[k]
        g = k >> 2
        if s > smax[g]:
            s = smax[g]
        gk[i] = g
        local[i] = s
        v[i] = vk + ak * tau
        a[i] = ak


@njit(cache=True)
def axis_samples(
    lo: int,
    gk: np.ndarray,
    local: np.ndarray,
    v: np.ndarray,
    v3: np.ndarray,
    a: np.ndarray,
    seg: np.ndarray,
    sweep3: np.ndarray,
    length3: np.ndarray,
    seg_index: np.ndarray,
    lines_of: np.ndarray,
    pos: np.ndarray,
    vel: np.ndarray,
    acc: np.ndarray,
    jerk: np.ndarray,
    seg_out: np.ndarray,
    line_out: np.ndarray,
) -> None:
    """Write rows ``lo ..`` of ``pos``, ``vel``, ``acc`` (XYZ), ``seg_out``, ``line_out``
    and, on arcs, ``jerk``, for the samples at local path position ``local`` of segments
    ``gk`` of ``seg`` with path speed ``v`` (``v3``: its cube) and acceleration ``a``
    (trapezoidal motion: the path jerk is zero). A line moves along its start tangent, a
    hold stays at its start; ``sweep3`` and ``length3`` are every row's cubes."""
    for i in range(gk.size):
        k = gk[i]
        r = lo + i
        row = seg[k]
        vi = v[i]
        ai = a[i]
        if row.kind == ARC:
            sweep = row.sweep
            r0 = row.radius
            dr = row.radius_end - row.radius
            length = row.length
            lam = min(max(local[i] / length, 0.0), 1.0)
            psi = sweep * lam
            c = math.cos(psi)
            s = math.sin(psi)
            rho = r0 + dr * lam
            ax = row.axial
            axlam = ax * lam
            rho_sweep = rho * sweep
            sweep2 = sweep * sweep
            length2 = length * length
            two_dr_sweep = 2.0 * dr * sweep
            rho_sweep2 = rho * sweep2
            m3_dr_sweep2 = -3.0 * dr * sweep2
            rho_sweep3 = rho * sweep3[k]
            for col in range(3):
                e1 = row.e1[col]
                e2 = row.e2[col]
                n = row.normal[col]
                w = c * e1 + s * e2
                wp = -s * e1 + c * e2
                p = row.end[col] if lam >= 1.0 else row.centre[col] + rho * w + axlam * n
                d1 = (dr * w + rho_sweep * wp + ax * n) / length
                d2 = (two_dr_sweep * wp - rho_sweep2 * w) / length2
                d3 = (m3_dr_sweep2 * w - rho_sweep3 * wp) / length3[k]
                pos[r, col] = p
                vel[r, col] = d1 * vi
                acc[r, col] = d1 * ai + d2 * vi * vi
                jerk[r, col] = 0.0 + (3.0 * d2 * vi * ai + d3 * v3[i])
        else:
            line = row.kind == LINE
            s_i = local[i]
            for col in range(3):
                u = row.u_start[col] if line else 0.0
                pos[r, col] = u * s_i + row.start[col]
                vel[r, col] = u * vi
                acc[r, col] = u * ai
        seg_out[r] = seg_index[k]
        line_out[r] = lines_of[k]


@njit(cache=True)
def first_over(start: np.ndarray, end: np.ndarray, lo: int, limit: np.ndarray) -> int:
    """The first row whose ``|end - start|`` in a column ``lo + c`` is over ``limit[c]``
    (-1: none), for :func:`kernel.interp.interpolate.check_travel`; ``start``, ``end``
    are the table's packed fields, read in place."""
    for i in range(start.shape[0]):
        for c in range(limit.size):
            if abs(end[i, lo + c] - start[i, lo + c]) > limit[c]:
                return i
    return -1


@njit(cache=True)
def trapezoid_pieces(
    kind: np.ndarray,
    length: np.ndarray,
    t_start: np.ndarray,
    t_acc: np.ndarray,
    t_cruise: np.ndarray,
    t_dec: np.ndarray,
    v_start: np.ndarray,
    v_peak: np.ndarray,
    accel: np.ndarray,
    decel: np.ndarray,
    cols: np.ndarray,
    smax: np.ndarray,
) -> None:
    """:func:`kernel.interp.interpolate.pieces` without the integral: each segment's four
    pieces into ``cols`` (4, n, 4: ``t0, s0, v0, a``), its length (0 for a hold) into
    ``smax``, with the same operations in the same order."""
    for i in range(kind.size):
        moving = kind[i] != HOLD
        ta = t_acc[i] if moving else 0.0
        tc = t_cruise[i] if moving else 0.0
        td = t_dec[i] if moving else 0.0
        vs = v_start[i] if moving else 0.0
        vp = v_peak[i] if moving else 0.0
        acc = accel[i] if moving else 0.0
        dec = decel[i] if moving else 0.0
        sm = length[i] if moving else 0.0
        ts = t_start[i]
        tac = ta + tc
        cols[0, i, 0] = ts
        cols[0, i, 1] = ta + ts
        cols[0, i, 2] = tac + ts
        cols[0, i, 3] = (tac + td) + ts
        s1 = vs * ta + 0.5 * acc * (ta * ta)
        cols[1, i, 0] = 0.0
        cols[1, i, 1] = s1
        cols[1, i, 2] = s1 + vp * tc
        cols[1, i, 3] = sm
        cols[2, i, 0] = vs
        cols[2, i, 1] = vp
        cols[2, i, 2] = vp
        cols[2, i, 3] = 0.0
        cols[3, i, 0] = acc
        cols[3, i, 1] = 0.0
        cols[3, i, 2] = -dec
        cols[3, i, 3] = 0.0
        smax[i] = sm
