"""The compiled kernel of :mod:`kernel.ir.chords`: a source's motions against an output that
replaced its arcs by straight chords, by :func:`kernel.ir.equivalence.first_difference`'s
rule (its ``_cover`` and ``_Curve.locate`` for arcs), over whole motion tables at once.

Compiled ahead of time by numba.pycc through :mod:`kernel.aot` (``python -m
kernel.ir.chord_kernels DIR NAME``), numba's JIT as the fallback; the AOT entry point
takes exactly the argument types of :data:`SIGNATURES`.
"""

from __future__ import annotations

import math
import sys

from numba import njit
from numba import types as nt

from kernel.aot import build_module
from kernel.array_types import F64, F64_2D, I8, I64, I64_2D

_TWO_PI = 2.0 * math.pi
_FULL_TURN_TOL = 1e-12  # kernel.ir.arcsweep.FULL_TURN_TOL
_EXACT = 1e-4 + 1e-9  # kernel.ir.equivalence.EXACT
#: a comparison this close to its bound is left to the Python rule (last-bit differences
#: of hypot and of the order of operations must not decide a verdict)
_MARGIN = 1e-9


@njit(cache=True)
def _near(value, bound):  # pragma: no cover - compiled
    return abs(value - bound) <= _MARGIN * (1.0 + abs(bound))


@njit(cache=True)
def _within(diff, bound):  # pragma: no cover - compiled
    """1: ``diff <= bound`` for sure, 0: not, -1: too close to tell."""
    if _near(diff, bound):
        return -1
    return 1 if diff <= bound else 0


@njit(cache=True)
def _same_state(sstate, ostate, sfeed, ofeed, key, mm, exact):  # pragma: no cover - compiled
    """Both motions see the same state (speed, spindle, tool, coolant, units: ``key``) and
    feed rates within the rule's bound (equivalence._seen_difference); False also where
    it is too close to tell."""
    if key[sstate] != key[ostate]:
        return False
    a = sfeed * mm[sstate]
    b = ofeed * mm[ostate]
    return _within(abs(a - b), max(exact[sstate], 1e-4 * abs(a))) == 1


@njit(cache=True)
def _sweep(t0, t1, rotation):  # pragma: no cover - compiled
    """kernel.ir.arcsweep.arc_sweep."""
    if rotation == 0:
        return 0.0
    turned = (t1 - t0) if rotation > 0 else (t0 - t1)
    part = turned % _TWO_PI
    if part <= _FULL_TURN_TOL:
        part = _TWO_PI
    whole = part + _TWO_PI * (abs(rotation) - 1)
    return whole if rotation > 0 else -whole


@njit(cache=True)
def _locate(
    px, py, pn, ci, cj, theta0, sweep, r0, r1, s_n, e_n, progress, tol
):  # pragma: no cover - compiled
    """equivalence._Curve._locate_arc: (status, progress) of the point (in-plane ``px``,
    ``py``, normal ``pn``) along the arc past ``progress``; status 1 on the arc, 0 off it,
    -1 too close to tell."""
    total = abs(sweep)
    if total == 0.0:
        return 0, 0.0
    sign = 1.0 if sweep > 0 else -1.0
    radius = math.hypot(px - ci, py - cj)
    base = (sign * (math.atan2(py - cj, px - ci) - theta0)) % _TWO_PI
    slack = tol / max(min(r0, r1), tol) + 1e-9
    low = progress * total - slack
    high = total + slack
    for turn in range(-1, int(total / _TWO_PI) + 2):
        angle = base + turn * _TWO_PI
        if _near(angle, low) or _near(angle, high):
            return -1, 0.0
        if angle < low or angle > high:
            continue
        frac = min(max(angle / total, 0.0), 1.0)
        expect_r = r0 + (r1 - r0) * frac
        expect_n = s_n + (e_n - s_n) * frac
        inside = _within(math.hypot(radius - expect_r, pn - expect_n), tol)
        if inside == -1:
            return -1, 0.0
        if inside == 1:
            return 1, frac
    return 0, 0.0


@njit(cache=True)
def _cover(
    skind,
    svals,
    sfeed,
    sstate,
    sarcs,
    okind,
    ovals,
    ofeed,
    ostate,
    key,
    mm,
    exact,
    cover,
    axes,
    carry,
    where,
    done,
):  # pragma: no cover - compiled
    """Walk the source's motions (``skind`` 0 rapid, 1 feed, 3 arc; ``svals`` their ends,
    an arc's in-plane end and normal end in place of x y z, then A B C; ``sarcs`` each
    arc's centre and turns) along one segment of the output (``okind`` 0 rapid, 1 feed,
    2 a feed change, skipped; ``ovals`` x y z a b c; all seeing state ``ostate``): a
    straight motion against one of the same kind, an arc against the straight feeds that
    cover it (equivalence._cover). Per state id: ``key`` what must be equal, ``mm``
    millimetres per unit, ``exact`` and ``cover`` the bounds in mm of a length and of a
    chord point's distance from its arc, ``axes`` the plane's first, second and normal axes.

    The walk goes on from the last segment's end: ``carry`` holds the next source motion,
    the next arc, 1 inside an arc and the output motions so far; ``where`` the progress
    along that arc and the last source end (x y z, mm); both are updated, and ``done[s]``
    gets the output motions consumed after source motion ``s``. Returns 1 when the segment
    passes (all of it consumed), 0 on a difference or where it is too close to tell."""
    n_src = skind.shape[0]
    n_out = okind.shape[0]
    s = carry[0]
    q = carry[1]
    inside = carry[2]
    moves = carry[3]
    progress = where[0]
    sx = where[1]
    sy = where[2]
    sz = where[3]
    o = 0
    ok = 1
    while o < n_out:
        if okind[o] == 2:
            o += 1
            continue
        if s >= n_src:
            ok = 0  # the output has more
            break
        st = sstate[s]
        k = mm[st]
        if skind[s] != 3:
            ex = svals[s, 0] * k
            ey = svals[s, 1] * k
            ez = svals[s, 2] * k
            if okind[o] != skind[s] or not _same_state(
                st, ostate, sfeed[s], ofeed[o], key, mm, exact
            ):
                ok = 0
                break
            ko = mm[ostate]
            bound = exact[st]
            if (
                _within(abs(ex - ovals[o, 0] * ko), bound) != 1
                or _within(abs(ey - ovals[o, 1] * ko), bound) != 1
                or _within(abs(ez - ovals[o, 2] * ko), bound) != 1
            ):
                ok = 0
                break
            same = True
            for a in range(3, 6):
                if _within(abs(svals[s, a] - ovals[o, a]), _EXACT) != 1:
                    same = False
            if not same:
                ok = 0
                break
            o += 1
            moves += 1
        else:
            i = axes[st, 0]
            j = axes[st, 1]
            m = axes[st, 2]
            end = [0.0, 0.0, 0.0]
            end[i] = svals[s, 0] * k
            end[j] = svals[s, 1] * k
            end[m] = svals[s, 2] * k
            ex, ey, ez = end[0], end[1], end[2]
            start = [sx, sy, sz]
            ci = sarcs[q, 0] * k
            cj = sarcs[q, 1] * k
            theta0 = math.atan2(start[j] - cj, start[i] - ci)
            theta1 = math.atan2(end[j] - cj, end[i] - ci)
            sweep = _sweep(theta0, theta1, int(sarcs[q, 2]))
            r0 = math.hypot(start[i] - ci, start[j] - cj)
            r1 = math.hypot(end[i] - ci, end[j] - cj)
            tol = cover[st]
            closing = _within(math.sqrt((sx - ex) ** 2 + (sy - ey) ** 2 + (sz - ez) ** 2), tol)
            if closing == -1:
                ok = 0
                break
            if not inside:
                inside = 1
                progress = 0.0
            arrived = 0
            while o < n_out:
                if okind[o] == 2:
                    o += 1
                    continue
                if okind[o] != 1 or not _same_state(st, ostate, sfeed[s], ofeed[o], key, mm, exact):
                    ok = 0
                    break
                ko = mm[ostate]
                p = [ovals[o, 0] * ko, ovals[o, 1] * ko, ovals[o, 2] * ko]
                found, at = _locate(
                    p[i], p[j], p[m], ci, cj, theta0, sweep, r0, r1, start[m], end[m], progress, tol
                )
                if found != 1:
                    ok = 0
                    break
                progress = at
                o += 1
                moves += 1
                arrived = _within(
                    math.sqrt((p[0] - ex) ** 2 + (p[1] - ey) ** 2 + (p[2] - ez) ** 2), tol
                )
                if arrived == -1 or (arrived == 1 and closing == 1 and _near(at, 0.5)):
                    ok = 0
                    break
                if arrived == 1 and (at > 0.5 or closing == 0):
                    break
                arrived = 0
            if ok == 0 or arrived != 1:
                break  # a difference, or the segment ends inside the arc
            inside = 0
            q += 1
        done[s] = moves
        s += 1
        sx, sy, sz = ex, ey, ez
    carry[0] = s
    carry[1] = q
    carry[2] = inside
    carry[3] = moves
    where[0] = progress
    where[1] = sx
    where[2] = sy
    where[3] = sz
    return ok


#: exported name -> (JIT function, explicit signature for numba.pycc)
SIGNATURES = {
    "cover": (
        _cover,
        nt.int64(
            I8,
            F64_2D,
            F64,
            I64,
            F64_2D,
            I8,
            F64_2D,
            F64,
            nt.int64,
            I64,
            F64,
            F64,
            F64,
            I64_2D,
            I64,
            F64,
            I64,
        ),
    ),
}

#: the JIT form under the exported name (the fallback when no AOT module can be built)
cover = _cover


if __name__ == "__main__":  # python -m MODULE DIR NAME: the AOT build (kernel.aot)
    build_module(sys.argv[1], sys.argv[2], SIGNATURES)
