"""Compiled join decisions of the LinuxCNC model (numba), for large programs.

:func:`kernel.plan.models.linuxcnc._joins` decides every join with numpy, some two hundred
whole-array operations; on a 200,000-segment program that is a third of the model's plan
time (issue 16, bench/bench_plan.py). These loops compute the same thing join by join, with
the same floating-point operations in the same order (numba adds no fused multiply-adds
without ``fastmath``; ``error_model="numpy"``: a division by zero gives inf or NaN as in
numpy), so the result is the same bit for bit (tests/test_controller_models.py). The
inverse cosines and tangents are left to numpy between the loops: numpy's are not the C
library's to the last bit, its sines and cosines are. Compiled once and cached next to this
file (``cache=True``); loading costs a process about 0.45 s CPU the first time it runs any
compiled kernel (kernel.interp.arc_kernel shares it), so the model uses these from
:data:`COMPILED_JOINS` joins on.

The constants of LinuxCNC's planner that the decisions use live here, so that the model and
its loops share one definition.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit

from kernel.path.segments import ARC, HOLD, LINE

# terminal conditions (LinuxCNC's TC_TERM_COND_*): how a segment ends
STOP = 0  # G61.1 exact stop
EXACT = 1  # G61 exact path
PARABOLIC = 2  # G64
TANGENT = 3
ARC_JOIN = 4  # a blend arc between two lines
VIRTUAL = 5  # a blend arc next to a circle: modelled on the line beside it

KINK_RATIO = 0.1  # [TRAJ] ARC_BLEND_KINK_RATIO default (initraj.cc)
ACC_RATIO_TAN = 0.5  # blendmath.h BLEND_ACC_RATIO_TANGENTIAL
ACC_RATIO_NORMAL = math.sqrt(1.0 - ACC_RATIO_TAN**2)
SHARP = (math.pi * 2.0 / 180.0) ** 2  # tp.c SHARP_CORNER_DEG = 2, small-angle squared
TINY = 1e-12
#: joins from which the compiled loops pay for their loading
COMPILED_JOINS = 100_000

_COS_FLAT = math.cos(math.pi / 2 - 1e-3)  # tpComputeBlendVelocity: no tolerance cap beyond
_BIG = sys.float_info.max  # numpy.nan_to_num's inf


@njit(cache=True, inline="always")
def _mn(a: float, b: float) -> float:
    """numpy.minimum of two floats (a NaN wins)."""
    return a if (a < b or a != a) else b


@njit(cache=True, inline="always")
def _mx(a: float, b: float) -> float:
    """numpy.maximum of two floats (a NaN wins)."""
    return a if (a > b or a != a) else b


@njit(cache=True, inline="always")
def _finite(a: float) -> float:
    """numpy.nan_to_num of a float."""
    if a != a:
        return 0.0
    if a == math.inf:
        return _BIG
    if a == -math.inf:
        return -_BIG
    return a


@njit(cache=True, error_model="numpy")
def tangent_joins(
    kind: np.ndarray,
    u_end: np.ndarray,
    u_start: np.ndarray,
    length: np.ndarray,
    lim_maxvel: np.ndarray,
    lim_reqvel: np.ndarray,
    lim_maxacc: np.ndarray,
    term: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    period: float,
    out_kind: np.ndarray,
    kink_vel: np.ndarray,
    kink_red: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    dot: np.ndarray,
    blend: np.ndarray,
    vt: np.ndarray,
    maxvel: np.ndarray,
) -> None:
    """tp.c ``tpSetupTangent`` at every join (``_joins`` up to the blend arcs): the joins'
    kind, kink speed and acceleration loss, the unit directions either side and their dot
    product, which joins are blended, and each segment's speeds when its join is decided."""
    n = kind.size
    for i in range(n):
        mv = _mn(lim_maxvel[i], length[i] / period)
        maxvel[i] = mv
        vt[i] = _mn(lim_reqvel[i], mv)
    for j in range(n - 1):
        a, b = j, j + 1
        valid = kind[a] != HOLD and kind[b] != HOLD
        rot_a = _mx(_mx(abs(u_end[a, 3]), abs(u_end[a, 4])), abs(u_end[a, 5])) > 0 or (
            _mx(_mx(abs(u_start[a, 3]), abs(u_start[a, 4])), abs(u_start[a, 5])) > 0
        )
        rot_b = _mx(_mx(abs(u_end[b, 3]), abs(u_end[b, 4])), abs(u_end[b, 5])) > 0 or (
            _mx(_mx(abs(u_start[b, 3]), abs(u_start[b, 4])), abs(u_start[b, 5])) > 0
        )
        rot_j = rot_a or rot_b
        mode = term[a]
        x0, x1, x2 = u_end[a, 0], u_end[a, 1], u_end[a, 2]
        norm = _mx(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), TINY)
        p0, p1, p2 = x0 / norm, x1 / norm, x2 / norm
        y0, y1, y2 = u_start[b, 0], u_start[b, 1], u_start[b, 2]
        norm = _mx(math.sqrt(y0 * y0 + y1 * y1 + y2 * y2), TINY)
        q0, q1, q2 = y0 / norm, y1 / norm, y2 / norm
        u1[j, 0], u1[j, 1], u1[j, 2] = p0, p1, p2
        u2[j, 0], u2[j, 1], u2[j, 2] = q0, q1, q2
        v_max = _mn(vt[a], vt[b])
        circ = kind[a] == ARC or kind[b] == ARC
        s0, s1, s2 = p0 + q0, p1 + q1, p2 + q2
        anti = s0 * s0 + s1 * s1 + s2 * s2 < SHARP
        a_inst = v_max / period + lim_maxacc[b]
        scale = 0.0
        d = (q0 - p0, q1 - p1, q2 - p2)
        for k in range(3):
            share = abs(a_inst * d[k]) / amax[k] if amax[k] > 0 else 0.0
            scale = share if k == 0 else _mx(scale, share)
        if circ:
            scale = scale / ACC_RATIO_TAN
        tangent = scale < KINK_RATIO
        considered = valid and not rot_j and mode != STOP and not anti
        jk = STOP
        kv = -1.0
        kr = 0.0
        if considered and tangent:
            jk = TANGENT
            kv = v_max
            kr = scale
        if considered and not tangent:
            kv = v_max * KINK_RATIO / _mx(scale, TINY)
            kr = KINK_RATIO
        if valid and rot_j and mode == PARABOLIC:
            jk = PARABOLIC
        out_kind[j] = jk
        kink_vel[j] = kv
        kink_red[j] = kr
        blend[j] = considered and not tangent and mode == PARABOLIC
        dot[j] = _mn(_mx(p0 * q0 + p1 * q1 + p2 * q2, -1.0), 1.0)


@njit(cache=True, error_model="numpy")
def blend_angles(
    blend: np.ndarray,
    theta0: np.ndarray,
    kind: np.ndarray,
    length: np.ndarray,
    tol: np.ndarray,
    radius: np.ndarray,
    radius_end: np.ndarray,
    sweep: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    centre: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    theta: np.ndarray,
    l1: np.ndarray,
    l2: np.ndarray,
    tolerance: np.ndarray,
    ok: np.ndarray,
) -> None:
    """The blend arc's corner half-angle (``theta0``, from the directions; smaller next to a
    convex circle), the lengths it may take off either move, the tolerance, and whether the
    angle allows an arc, at every blended join."""
    half_pi = math.pi / 2
    for j in range(blend.size):
        if not blend[j]:
            continue
        a, b = j, j + 1
        th = theta0[j]
        ok[j] = (half_pi - th >= 1e-6) and (th >= 1e-6)
        t1 = tol[a] if tol[a] > 0 else length[a] * 0.25
        t2 = tol[b] if tol[b] > 0 else length[b] * 0.25
        tolerance[j] = _mn(_mn(_mn(t1, t2), length[a] * 0.25), length[b] * 0.25)
        la = length[a] * 0.5
        lb = length[b] * 0.5
        theta_tan = th
        if kind[b] == ARC:
            r2 = radius[b]
            dot2 = (
                (start[b, 0] - centre[b, 0]) * u1[j, 0]
                + (start[b, 1] - centre[b, 1]) * u1[j, 1]
                + (start[b, 2] - centre[b, 2]) * u1[j, 2]
            )
            convex2 = dot2 >= 0
            phi2 = _mn(abs(sweep[b]) / 3.0, theta_tan if convex2 else math.pi / 2)
            lb = math.sin(phi2 / 4.0) * r2 if convex2 else phi2 * r2
            if convex2:
                th = _mn(th, theta_tan - phi2 / 4.0)
        if kind[a] == ARC:
            r1 = radius_end[a]
            dot1 = (
                (end[a, 0] - centre[a, 0]) * u2[j, 0]
                + (end[a, 1] - centre[a, 1]) * u2[j, 1]
                + (end[a, 2] - centre[a, 2]) * u2[j, 2]
            )
            convex1 = dot1 < 0
            phi1 = _mn(abs(sweep[a]) * 2.0 / 3.0, theta_tan if convex1 else math.pi / 2)
            la = math.sin(phi1 / 4.0) * r1 if convex1 else phi1 * r1
            if convex1:
                th = _mn(th, theta_tan - phi1 / 4.0)
        theta[j] = _mx(th, 1e-6)
        l1[j] = la
        l2[j] = lb


@njit(cache=True, inline="always")
def _inscribed(b0: float, b1: float, b2: float, bounds: np.ndarray) -> float:
    """blendmath.c ``calculateInscribedDiameter`` for one binormal (as the model's)."""
    out = math.inf
    bb = (b0, b1, b2)
    for i in range(3):
        bi = bb[i]
        p0 = abs((1.0 if i == 0 else 0.0) - b0 * bi)
        p1 = abs((1.0 if i == 1 else 0.0) - b1 * bi)
        p2 = abs((1.0 if i == 2 else 0.0) - b2 * bi)
        if i == 0:
            p0 = _mx(p0, TINY)
        elif i == 1:
            p1 = _mx(p1, TINY)
        else:
            p2 = _mx(p2, TINY)
        scale = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        if bounds[i] > 0:
            out = _mn(out, bounds[i] / scale)
    return out


@njit(cache=True, error_model="numpy")
def blend_arcs(
    blend: np.ndarray,
    ok: np.ndarray,
    theta: np.ndarray,
    tan_theta: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    kind: np.ndarray,
    maxvel: np.ndarray,
    vt: np.ndarray,
    l1: np.ndarray,
    l2: np.ndarray,
    tolerance: np.ndarray,
    normal: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    binormal: np.ndarray,
    a_max: np.ndarray,
    v_req: np.ndarray,
    v_plan: np.ndarray,
    r_plan: np.ndarray,
    s_arc: np.ndarray,
) -> None:
    """The blend arc at every blended join (blendmath.c ``blendParamKinematics``,
    ``blendComputeParameters``): its plane, acceleration, requested and planned speed,
    radius and length; ``ok`` cleared where there is none."""
    for j in range(blend.size):
        if not blend[j]:
            continue
        a, b = j, j + 1
        th = theta[j]
        phi = math.pi - 2.0 * th
        p0, p1, p2 = u1[j, 0], u1[j, 1], u1[j, 2]
        q0, q1, q2 = u2[j, 0], u2[j, 1], u2[j, 2]
        c0 = p1 * q2 - p2 * q1
        c1 = p2 * q0 - p0 * q2
        c2 = p0 * q1 - p1 * q0
        norm = _mx(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), TINY)
        b0, b1, b2 = c0 / norm, c1 / norm, c2 / norm
        binormal[j, 0], binormal[j, 1], binormal[j, 2] = b0, b1, b2
        am = _inscribed(b0, b1, b2, amax)
        a_n = am * ACC_RATIO_NORMAL
        vr = _mx(vt[a], vt[b])
        v_planar = _inscribed(b0, b1, b2, vmax)
        phi_eff = _mn(phi, math.pi * 0.49)
        vm1 = _mn(maxvel[a], maxvel[b] / math.cos(phi_eff))
        vm2 = _mn(maxvel[b], maxvel[a] / math.cos(phi_eff))
        area = vm1 * vm2 / 2.0 * math.sin(phi)
        w0, w1, w2 = q0 * vm2 - p0 * vm1, q1 * vm2 - p1 * vm1, q2 * vm2 - p2 * vm1
        base = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        circ = kind[a] == ARC or kind[b] == ARC
        v_alt = 0.0 if (circ or base <= TINY) else 2.0 * area / _mx(base, TINY)
        v_goal = _mn(vr, _mx(v_alt, v_planar))
        h_tol = tolerance[j] / (1.0 - math.sin(th))
        d_tol = math.cos(th) * h_tol
        d_geom = _mn(_mn(l1[j], l2[j]), d_tol)
        r_geom = tan_theta[j] * d_geom
        vp = _mn(math.sqrt(a_n * r_geom), v_goal)
        a_par = 0.5 * am
        v_tri = math.sqrt(2.0 * a_par * d_geom)
        t_b = _mn(v_tri, vp) / a_par
        r_blend = _mn(t_b * vp / phi, r_geom)
        rp = _mx(vp * vp / a_n, r_blend)
        sa = rp * phi
        good = ok[j] and math.isfinite(rp) and rp >= TINY and sa >= 1e-6
        for side in (a, b):
            if kind[side] == ARC:
                n0, n1, n2 = normal[side, 0], normal[side, 1], normal[side, 2]
                e0, e1, e2 = b0 - n0, b1 - n1, b2 - n2
                same = e0 * e0 + e1 * e1 + e2 * e2 < 1e-12
                f0, f1, f2 = b0 + n0, b1 + n1, b2 + n2
                opposite = f0 * f0 + f1 * f1 + f2 * f2 < 1e-12
                good = good and (same or opposite)
        ok[j] = good
        a_max[j] = am
        v_req[j] = vr
        v_plan[j] = vp
        r_plan[j] = rp
        s_arc[j] = sa


@njit(cache=True, error_model="numpy")
def blend_choice(
    blend: np.ndarray,
    ok: np.ndarray,
    v_plan: np.ndarray,
    s_arc: np.ndarray,
    period: float,
    kind: np.ndarray,
    length: np.ndarray,
    lim_maxacc: np.ndarray,
    vt: np.ndarray,
    tol: np.ndarray,
    theta_acc: np.ndarray,
    r_plan: np.ndarray,
    tan_theta: np.ndarray,
    a_max: np.ndarray,
    v_req: np.ndarray,
    out_kind: np.ndarray,
    kink_vel: np.ndarray,
    kink_red: np.ndarray,
    radius: np.ndarray,
    trim: np.ndarray,
    arc_vel: np.ndarray,
    arc_acc: np.ndarray,
    arc_req: np.ndarray,
) -> None:
    """tp.c ``tpChooseBestBlend`` at every blended join: the arc, the kink speed or a
    parabolic blend (its estimate from ``tpComputeBlendVelocity`` on half the segments),
    whichever is fastest, and the join's outputs."""
    for j in range(blend.size):
        if not blend[j]:
            continue
        a, b = j, j + 1
        perf_arc = _mn(v_plan[j], s_arc[j] / period) if ok[j] else 0.0
        acc1 = lim_maxacc[a] * (1.0 - KINK_RATIO) * 0.5
        acc2 = lim_maxacc[b] * (1.0 - KINK_RATIO) * 0.5
        if kind[a] == ARC:
            acc1 = acc1 * ACC_RATIO_TAN
        if kind[b] == ARC:
            acc2 = acc2 * ACC_RATIO_TAN
        len1, len2 = length[a] / 2, length[b] / 2
        cos_half = math.cos(theta_acc[j])
        r1 = _mn(math.sqrt(_mx(acc1 * len1, 0.0)), vt[a])
        r2 = _mn(math.sqrt(_mx(acc2 * len2, 0.0)), vt[b])
        t_reach = _mn(length[a] / r1, length[b] / r2)
        t_blend = _mn(t_reach, _mx(r1 / acc1, r2 / acc2))
        b1 = _mn(r1, t_blend * acc1)
        b2 = _mn(r2, t_blend * acc2)
        capped = tol[a] > 0 and cos_half > _COS_FLAT
        tv = 2.0 * math.sqrt(acc1 * tol[a] / (cos_half if capped else 1.0))
        if capped:
            b1 = _mn(b1, tv)
            b2 = _mn(b2, tv)
        b1, b2 = _finite(b1), _finite(b2)
        perf_par = math.sin(theta_acc[j]) * (b1 + b2) / 2.0 / 2.0
        kv = kink_vel[j]
        # numpy.argmax: the first NaN, else the first largest
        if perf_par != perf_par:
            best = 0
        elif kv != kv:
            best = 1
        elif perf_arc != perf_arc:
            best = 2
        else:
            best = 0
            top = perf_par
            if kv > top:
                best, top = 1, kv
            if perf_arc > top:
                best = 2
        jk = out_kind[j]
        if best == 0:
            jk = PARABOLIC
            kink_vel[j] = -1.0
            kink_red[j] = 0.0
        elif best == 1:
            jk = TANGENT
        else:
            kink_vel[j] = -1.0
            kink_red[j] = 0.0
            jk = ARC_JOIN
            if kind[a] == ARC or kind[b] == ARC:  # next to a circle
                jk = VIRTUAL if (kind[a] == LINE or kind[b] == LINE) else TANGENT
                kink_vel[j] = perf_arc
            radius[j] = r_plan[j]
            trim[j] = r_plan[j] / tan_theta[j]
            arc_vel[j] = perf_arc
            arc_acc[j] = a_max[j]
            arc_req[j] = v_req[j]
        out_kind[j] = jk
