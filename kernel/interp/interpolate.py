"""Sampling a planned path at the interpolation period (book ch. 3.3.2, 6.3.3).

The plan gives each segment a trapezoidal path-speed profile; here the path position
``S(t)``, speed, acceleration and jerk are evaluated in closed form at ``t_k = k T`` for all
samples at once (vectorised per chunk of samples, no per-sample Python loop), then mapped
onto the geometry (kernel.path.geometry) to give per-axis position, velocity, acceleration and
jerk by the chain rule. The last sample is the program's end point exactly (book ch. 3.1
requirement 3: no accumulated error).

S-curve (kernel.plan.planner): with ``T_f > 0`` the path motion is the moving average of the
trapezoidal one over ``T_f``; in closed form, with ``I(t) = int_0^t S``:

    S~(t) = (I(t) - I(t-T_f)) / T_f,  v~ = (S(t) - S(t-T_f)) / T_f,
    a~ = (v(t) - v(t-T_f)) / T_f,     j~ = (a(t) - a(t-T_f)) / T_f

Sampled-data circle methods (``controller.circle_method``) replace arcs by the method's
chords (kernel.interp.circle), traversed at the planned speed.

Speed (issue 3: a 200,000-segment program at 1 ms, bench/bench_plan.py): per chunk of
samples the path state is computed in reused scratch rows and the line geometry written
straight into the output arrays; samples on arcs are gathered over several chunks and go
through :func:`kernel.path.geometry.evaluate` in batches; the output arrays are allocated by
:func:`kernel.interp.bulk.bulk_array`. The results are bit-for-bit those of the straight
formulation (tests/test_kernel_sampling_equivalence.py).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

import kernel.limits as limits
from kernel.diagnostics import Diagnostic, Location
from kernel.interp.arc_kernel import (
    axis_samples,
    first_over,
    trapezoid_pieces,
    trapezoid_states,
)
from kernel.interp.bulk import bulk_array
from kernel.interp.samples import Samples
from kernel.machine import AXIS_NAMES, Controller, Machine
from kernel.path.geometry import arc_cache, evaluate
from kernel.path.segments import ARC, HOLD, LINE
from kernel.plan.planner import Plan

CHUNK = 32_768
#: arc samples from which the compiled arc kernel (kernel.interp.arc_kernel) pays: loading it
#: costs a process about 0.3 s of CPU, numpy takes about 1 s per million arc samples
COMPILED_ARC_SAMPLES = 200_000


@dataclass(frozen=True, slots=True)
class Pieces:
    """The path motion as polynomial pieces: 4 per segment (accelerate, cruise, decelerate,
    rest; piece ``k`` belongs to segment ``k >> 2``), as contiguous columns: start time
    ``t0`` (sorted), local path position ``s0``, speed ``v0`` and acceleration ``a``; per
    segment the length ``smax`` (0 for holds). With ``integral``: the global position
    ``big_s0`` and ``i0 = int_0^t0 S dt`` (else ``None``), and ``i_end`` after the last."""

    t0: np.ndarray
    s0: np.ndarray
    v0: np.ndarray
    a: np.ndarray
    smax: np.ndarray
    big_s0: np.ndarray | None = None
    i0: np.ndarray | None = None
    i_end: float = 0.0  # the integral at the last piece's end (with ``integral``)


def pieces(
    plan: Plan, integral: bool = True, i_start: float = 0.0, compiled: bool = False
) -> Pieces:
    """Split every segment's trapezoid into its constant-acceleration pieces (the integral
    columns, needed by S-curve smoothing, only when ``integral``; ``i_start``: the integral
    at the first piece's start, for a plan that is one window of a longer one).
    ``compiled``: without the integral, in one compiled pass (kernel.interp.arc_kernel,
    the same numbers)."""
    p = plan.profiles
    seg = plan.path.segments
    n = len(seg)
    if compiled and not integral:
        cols = bulk_array((4, n, 4))
        smax = np.empty(n)
        trapezoid_pieces(
            seg["kind"], seg["length"], plan.t_start, p.t_acc, p.t_cruise, p.t_dec,
            p.v_start, p.v_peak, p.accel, p.decel, cols, smax,
        )  # fmt: skip
        return Pieces(*(c.ravel() for c in cols), smax)
    moving = seg["kind"] != HOLD
    ta, tc, td = (np.where(moving, x, 0.0) for x in (p.t_acc, p.t_cruise, p.t_dec))
    vs, vp = np.where(moving, p.v_start, 0.0), np.where(moving, p.v_peak, 0.0)
    acc, dec = np.where(moving, p.accel, 0.0), np.where(moving, p.decel, 0.0)
    smax = np.where(moving, seg["length"], 0.0)
    cols = bulk_array((4, n, 4))  # t0, s0, v0, a; one row per segment, one column per piece
    t0, s0, v0, a0 = cols
    t0[:, 0] = plan.t_start  # t_start + 0
    t0[:, 1] = ta
    t0[:, 2] = ta + tc
    t0[:, 3] = t0[:, 2] + td  # the running sum of the phase durations
    rest = plan.duration - (ta + tc + td)
    dur = None
    if integral:
        dur = np.stack([ta, tc, td, rest], axis=1)
    t0[:, 1:] += plan.t_start[:, None]
    s0[:, 0] = 0.0
    s0[:, 1] = vs * ta + 0.5 * acc * ta**2
    s0[:, 2] = s0[:, 1] + vp * tc
    s0[:, 3] = smax
    v0[:, 0], v0[:, 1], v0[:, 2], v0[:, 3] = vs, vp, vp, 0.0
    a0[:, 0], a0[:, 1], a0[:, 2], a0[:, 3] = acc, 0.0, -dec, 0.0
    big_s0 = i0 = None
    i_end = 0.0
    if dur is not None:
        # integral of S over each piece: S0 tau + v tau^2/2 + a tau^3/6 with S0 global
        big_s0 = plan.s_start[:, None] + s0
        whole = big_s0 * dur + v0 * dur**2 / 2 + a0 * dur**3 / 6
        running = np.cumsum(np.concatenate([[i_start], whole.ravel()]))
        i0, i_end = running[:-1], float(running[-1])
        big_s0 = big_s0.ravel()
    return Pieces(t0.ravel(), s0.ravel(), v0.ravel(), a0.ravel(), smax, big_s0, i0, i_end)


def _piece_of(t0: np.ndarray, t: np.ndarray, grid: tuple[int, float] | None = None) -> np.ndarray:
    """``searchsorted(t0, t, "right") - 1`` clipped to valid pieces, for sorted ``t``, in
    O(len(t) + pieces in range) by counting samples per piece. ``grid = (lo, period)``
    says ``t[i]`` is ``float(lo + i) * period`` (the samples of a chunk): the counts then
    come from ``ceil(t0 / period)``, corrected by one either way against ``t`` itself."""
    n = len(t0)
    if not len(t):
        return np.zeros(0, dtype=np.int64)
    i_lo = max(int(np.searchsorted(t0, t[0], "right")) - 1, 0)
    i_hi = int(np.searchsorted(t0, t[-1], "right"))
    inner = t0[i_lo + 1 : i_hi]  # pieces starting inside (t[0], t[-1]]
    if grid is None:
        starts = np.searchsorted(t, inner, "left")
    else:  # the number of samples before each start: t[c - 1] < t0 <= t[c]
        lo, period = grid
        c = np.ceil(inner / period)
        c -= lo
        np.clip(c, 1, len(t) - 1, out=c)
        starts = c.astype(np.intp)
        starts -= t.take(starts - 1) >= inner
        starts += t.take(starts) < inner
    bounds = np.concatenate([[0], starts, [len(t)]])
    return np.repeat(np.arange(i_lo, max(min(i_hi, n), i_lo + 1)), np.diff(bounds))


def path_state(pc: Pieces, t: np.ndarray, integral: bool = False) -> tuple[np.ndarray, ...]:
    """``(segment, local s, global S, v, a, I)`` at sorted times ``t`` (at rest at S = 0
    before 0). ``I`` (the time integral of S) only when ``integral``, else ``None``; needs
    ``pc`` built with the integral columns."""
    assert pc.big_s0 is not None and pc.i0 is not None
    k = _piece_of(pc.t0, t)
    gk = k >> 2
    s0, v0, a0, big_s0 = (x.take(k) for x in (pc.s0, pc.v0, pc.a, pc.big_s0))
    tau = t - pc.t0.take(k)
    np.maximum(tau, 0.0, out=tau)
    s = v0 * tau
    s += 0.5 * a0 * tau * tau
    s += s0
    np.minimum(s, pc.smax.take(gk), out=s)
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
    return gk, s, big_s, v, a0, out_i


def _trapezoid_state(
    pc: Pieces, tt: np.ndarray, scratch: np.ndarray, grid: tuple[int, float] | None
) -> tuple[np.ndarray, ...]:
    """``(segment, local s, v, a)`` at sorted times ``tt >= 0``: :func:`path_state` without
    the global position and the integral, with the same floating-point operations, in rows
    of ``scratch`` (at least 3 x len(tt), reused from chunk to chunk); ``grid`` as for
    :func:`_piece_of`."""
    n = len(tt)
    k = _piece_of(pc.t0, tt, grid)
    s, v, a = scratch[0, :n], scratch[1, :n], scratch[2, :n]
    tau = tt - pc.t0.take(k)
    np.maximum(tau, 0.0, out=tau)
    np.take(pc.a, k, out=a, mode="clip")  # k is in range: "clip" only skips the check
    np.take(pc.v0, k, out=v, mode="clip")
    np.multiply(v, tau, out=s)
    q = a * 0.5
    q *= tau
    q *= tau
    s += q  # v0 tau + 0.5 a tau tau
    s += np.take(pc.s0, k, out=q, mode="clip")
    k >>= 2  # the segment
    np.minimum(s, np.take(pc.smax, k, out=q, mode="clip"), out=s)
    np.multiply(a, tau, out=q)
    v += q  # v0 + a tau
    return k, s, v, a


def _line_rows(seg: np.ndarray, cols: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Start points and unit tangents of the line rows (axes ``cols``), C-contiguous; zero
    tangent on other rows, so ``start + s u`` is a hold's point (arcs are patched)."""
    lines = seg["kind"] == LINE
    start = np.ascontiguousarray(seg["start"][:, cols])
    u = np.ascontiguousarray(np.where(lines[:, None], seg["u_start"][:, cols], 0.0))
    return start, u


class _ArcBatch:
    """Samples on arcs, gathered over chunks and evaluated together (fewer, larger calls
    of :func:`kernel.path.geometry.evaluate`), then written over the line values."""

    def __init__(
        self,
        seg: np.ndarray,
        kind: np.ndarray,
        ctl: Controller,
        cols: list[int],
        out: tuple,
        fields: dict[str, np.ndarray],
    ) -> None:
        self.seg, self.ctl, self.cols, self.out = seg, ctl, cols, out
        self.cache = {  # kernel.path.geometry.line_cache; only "kind" is read for arc queries
            "kind": kind,
            "length": np.zeros(0),
            "start": np.zeros((0, len(cols))),
            "u": np.zeros((0, len(cols))),
            **fields,  # kernel.path.geometry.arc_cache (its "length" is the rows' own)
        }
        self.parts: list[tuple[np.ndarray, ...]] = []
        self.size = 0

    def add(self, rows: np.ndarray, *values: np.ndarray | None) -> None:
        self.parts.append((rows, *values))
        self.size += rows.size
        if self.size >= CHUNK:
            self.flush()

    def flush(self) -> None:
        if not self.parts:
            return
        rows, gk, local, v, a, j = (
            None if p[0] is None else np.concatenate(p) for p in zip(*self.parts, strict=True)
        )
        self.parts, self.size = [], 0
        pos, vel, acc, jerk = self.out
        ctl = self.ctl
        p, d1, curved, d2, d3 = evaluate(
            self.seg, gk, local, ctl.circle_method, ctl.chord_tolerance, self.cols, self.cache
        )
        va, aa = v[:, None], a[:, None]
        pos[rows] = p
        vel[rows] = d1 * va
        acc_a = d1 * aa
        jerk_a = d1 * j[:, None] if j is not None else np.zeros_like(d1)
        if curved.size == len(gk):  # every sample on an exactly sampled arc
            acc_a += d2 * va * va
            jerk_a += 3 * d2 * va * aa + d3 * va**3
        elif curved.size:
            vc, ac = va[curved], aa[curved]
            acc_a[curved] += d2 * vc * vc
            jerk_a[curved] += 3 * d2 * vc * ac + d3 * vc**3
        acc[rows] = acc_a
        if j is not None or curved.size:
            jerk[rows] = jerk_a


def compiled_sampling(plan: Plan, period: float, kind: np.ndarray | None = None) -> bool:
    """Whether ``plan`` is sampled by the compiled kernels (kernel.interp.arc_kernel, which
    read the table itself): exact arcs on an XYZ machine, no S-curve, enough arc samples
    (``kind``: the table's kinds, if at hand)."""
    ctl = plan.machine.controller
    if ctl.circle_method != "exact" or plan.filter_time > 0:
        return False
    if _columns(plan.machine) != [0, 1, 2]:
        return False
    kind = plan.path.segments["kind"] if kind is None else kind
    return float(plan.duration[kind == ARC].sum()) >= COMPILED_ARC_SAMPLES * period


class _Sampler:
    """The chunk loop of :func:`sample`: the read-only tables the chunks share, and
    :meth:`run`, which fills the rows of the given chunks (every chunk is computed alone)."""

    def __init__(self, plan: Plan, period: float, chunk: int, i_start: float = 0.0) -> None:
        self.plan, self.period, self.chunk = plan, period, chunk
        seg = plan.path.segments
        machine = plan.machine
        self.ctl = machine.controller
        self.cols = _columns(machine)
        self.total = plan.total_time
        self.tf = tf = plan.filter_time
        self.kind = kind = np.ascontiguousarray(seg["kind"])
        self.compiled = compiled_sampling(plan, period, kind)
        self.pc = pieces(plan, tf > 0, i_start, self.compiled)
        self.blends = _Blends.of(plan, self.pc) if tf <= 0 else None
        self.lines_of = np.ascontiguousarray(seg["line"], dtype=np.int32)
        self.seg_index = np.where(kind == HOLD, -1, np.arange(len(seg), dtype=np.int32))
        self.has_arcs = bool(np.any(kind == ARC))
        self.fields: dict[str, np.ndarray] = {}
        if self.compiled:
            self.fields = {f + "3": np.ascontiguousarray(seg[f]) ** 3 for f in ("sweep", "length")}
        else:
            self.start, self.u = _line_rows(seg, self.cols)
            if self.has_arcs:
                self.fields = arc_cache(seg)
        if tf > 0:
            self.moving_idx = np.flatnonzero(kind != HOLD)
            self.s_end_moving = (plan.s_start + seg["length"])[self.moving_idx]
            self.length = np.ascontiguousarray(seg["length"])

    def run(
        self, los: range, out: tuple[np.ndarray, ...], offset: int = 0, count: int | None = None
    ) -> None:
        """Fill the chunks starting at ``los`` of ``out`` (:func:`_outputs`), with scratch
        buffers of this call's own. ``out`` holds the rows from ``offset`` on (a window of
        :func:`sample_windows`) of the ``count`` samples in all."""
        t, pos, vel, acc, jerk, seg_out, line_out = out
        count = len(t) + offset if count is None else count
        if self.compiled:
            self._run_compiled(los, out, offset, count)
        else:
            self._run_numpy(los, out, offset, count)
        if self.blends is not None:
            self.blends.add(self, out, offset, count)

    def _run_compiled(
        self, los: range, out: tuple[np.ndarray, ...], offset: int, count: int
    ) -> None:
        """:meth:`run` by the compiled kernels: per chunk the path state, the cube of the
        speed by numpy, then the axes."""
        t, pos, vel, acc, jerk, seg_out, line_out = out
        chunk, period, total, pc = self.chunk, self.period, self.total, self.pc
        seg = self.plan.path.segments
        sweep3, length3 = self.fields["sweep3"], self.fields["length3"]
        width = min(chunk, count)
        gk = np.empty(width, dtype=np.int64)
        state = np.empty((4, width))
        for lo in los:
            hi = min(count, lo + chunk)
            a_, b_ = lo - offset, hi - offset  # rows of this call's arrays
            n = hi - lo
            local, v, a, v3 = state[0, :n], state[1, :n], state[2, :n], state[3, :n]
            first = min(float(lo) * period, total)
            k = max(int(np.searchsorted(pc.t0, first, "right")) - 1, 0)
            trapezoid_states(
                lo, period, total, k, pc.t0, pc.s0, pc.v0, pc.a, pc.smax, t[a_:b_],
                gk[:n], local, v, a,
            )  # fmt: skip
            np.power(v, 3, out=v3)
            axis_samples(
                a_, gk[:n], local, v, v3, a, seg, sweep3, length3, self.seg_index,
                self.lines_of, pos, vel, acc, jerk, seg_out, line_out,
            )  # fmt: skip

    def _run_numpy(self, los: range, out: tuple[np.ndarray, ...], offset: int, count: int) -> None:
        """:meth:`run` by numpy: per chunk the path state, the lines' axes, and the arcs'
        samples gathered for :class:`_ArcBatch`."""
        t, pos, vel, acc, jerk, seg_out, line_out = out
        chunk, period, total = self.chunk, self.period, self.total
        kind, u, start, tf = self.kind, self.u, self.start, self.tf
        seg = self.plan.path.segments
        arcs = None
        if self.has_arcs:
            arcs = _ArcBatch(seg, kind, self.ctl, self.cols, (pos, vel, acc, jerk), self.fields)
        width = min(chunk, count)
        scratch = np.empty((3, width))
        rows = np.empty((2, width, len(self.cols)))
        for lo in los:
            hi = min(count, lo + chunk)
            a_, b_ = lo - offset, hi - offset  # rows of this call's arrays
            tt = np.multiply(np.arange(lo, hi, dtype=float), period, out=t[a_:b_])
            grid = (lo, period)
            if tt[-1] > total:
                tt, grid = np.minimum(tt, total), None
            j = None
            if tf > 0:
                gk, local, v, a, j = self._smoothed_state(tt)
            else:
                gk, local, v, a = _trapezoid_state(self.pc, tt, scratch, grid)
            n = hi - lo
            uk = np.take(u, gk, axis=0, out=rows[0, :n], mode="clip")
            p = np.multiply(uk, local[:, None], out=pos[a_:b_])
            p += np.take(start, gk, axis=0, out=rows[1, :n], mode="clip")
            np.multiply(uk, v[:, None], out=vel[a_:b_])
            np.multiply(uk, a[:, None], out=acc[a_:b_])
            if j is not None:
                np.multiply(uk, j[:, None], out=jerk[a_:b_])
            if arcs is not None:
                on_arc = np.flatnonzero(kind.take(gk) == ARC)
                if on_arc.size:
                    sel = (gk[on_arc], local[on_arc], v[on_arc], a[on_arc])
                    arcs.add(a_ + on_arc, *sel, None if j is None else j[on_arc])
            np.take(self.seg_index, gk, out=seg_out[a_:b_], mode="clip")
            np.take(self.lines_of, gk, out=line_out[a_:b_], mode="clip")
        if arcs is not None:
            arcs.flush()

    def _smoothed_state(self, tt: np.ndarray) -> tuple[np.ndarray, ...]:
        """``(segment, local s, v, a, j)`` of the S-curve (moving-average) motion."""
        pc, tf, kind = self.pc, self.tf, self.kind
        k, _, big_s, v, a, integral = path_state(pc, tt, True)
        _, _, s2, v2, a2, i2 = path_state(pc, tt - tf, True)
        big_s, v, a, j = (integral - i2) / tf, (big_s - s2) / tf, (v - v2) / tf, (a - a2) / tf
        moving_idx = self.moving_idx
        g = np.searchsorted(self.s_end_moving, big_s - 1e-12, "left")
        gk = moving_idx[np.clip(g, 0, moving_idx.size - 1)] if moving_idx.size else k
        gk = np.where(kind[k] == HOLD, np.where(v == 0, k, gk), gk)
        local = big_s - self.plan.s_start[gk]
        np.clip(local, 0.0, self.length[gk], out=local)
        return gk, local, v, a, j


class _Blends:
    """Overlapping moves (:attr:`Plan.overlap`, a controller model's parabolic blends): in
    the overlap of segment ``p`` and ``q = p + 1`` both move, and the axis position,
    velocity and acceleration are the sum of the two motions. The samples are ``p``'s
    (its segment and line); ``q``'s motion since its start is added here. ``q``'s pieces
    are cut at ``p``'s end, so that the sampler's own pass follows ``p`` until it ends and
    ``q`` after (its pieces stay sorted in time)."""

    def __init__(self, q: np.ndarray, t_on: np.ndarray, t_cut: np.ndarray, rows: tuple) -> None:
        self.q, self.t_on, self.t_cut = q, t_on, t_cut
        self.t0, self.s0, self.v0, self.a = rows  # q's own pieces, (blends, 4)

    @classmethod
    def of(cls, plan: Plan, pc: Pieces) -> _Blends | None:
        """The overlaps of ``plan``; cuts the pieces ``pc`` of the later moves in place."""
        ov = plan.overlap
        if ov is None or not np.any(ov > 0):
            return None
        p = np.flatnonzero(ov > 0)
        q = p + 1
        t_cut = plan.t_start[p] + plan.profiles.duration[p]  # p's own end
        rows = q[:, None] * 4 + np.arange(4)[None, :]
        own = tuple(x[rows] for x in (pc.t0, pc.s0, pc.v0, pc.a))
        t0, s0, v0, a = own
        d = np.clip(t_cut[:, None] - t0, 0.0, None)
        pc.s0[rows] = s0 + v0 * d + 0.5 * a * d * d
        pc.v0[rows] = v0 + a * d
        pc.t0[rows] = np.maximum(t0, t_cut[:, None])
        return cls(q, plan.t_start[q], t_cut, own)

    def add(self, sampler: _Sampler, out: tuple[np.ndarray, ...], offset: int, count: int) -> None:
        """Add the later move's motion to the rows ``out`` holds (from ``offset`` on)."""
        t, pos, vel, acc, jerk = out[:5]
        if not len(t):
            return
        lo = np.searchsorted(self.t_cut, float(t[0]), "right")
        hi = np.searchsorted(self.t_on, float(t[-1]), "right")
        if hi <= lo:
            return
        b = np.arange(lo, hi)
        first = np.searchsorted(t, self.t_on[b], "left")
        last = np.searchsorted(t, self.t_cut[b], "left")
        n = np.maximum(last - first, 0)
        if not n.sum():
            return
        which = np.repeat(b, n)
        rows = np.repeat(first - np.cumsum(n) + n, n) + np.arange(int(n.sum()))
        tt = t[rows]
        t0 = self.t0[which]
        k = np.maximum((tt[:, None] >= t0[:, 1:]).sum(axis=1), 0)
        pick = (np.arange(which.size), k)
        tau = np.maximum(tt - t0[pick], 0.0)
        a = self.a[which][pick]
        v = self.v0[which][pick] + a * tau
        s = self.s0[which][pick] + self.v0[which][pick] * tau + 0.5 * a * tau * tau
        # the later moves' rows only (evaluate's caches are per row: not of the whole table)
        moves, q = np.unique(self.q[which], return_inverse=True)
        seg = sampler.plan.path.segments[moves]
        s = np.clip(s, 0.0, seg["length"][q])
        ctl, cols = sampler.ctl, sampler.cols
        p, d1, curved, d2, d3 = evaluate(seg, q, s, ctl.circle_method, ctl.chord_tolerance, cols)
        pos[rows] += p - seg["start"][q][:, cols]
        vel[rows] += d1 * v[:, None]
        acc[rows] += d1 * a[:, None]
        if curved.size:
            vc, ac = v[curved, None], a[curved, None]
            acc[rows[curved]] += d2 * vc * vc
            jerk[rows[curved]] += 3 * d2 * vc * ac + d3 * vc**3


def _columns(machine: Machine) -> list[int]:
    """Columns of the machine's axes among the six of the segment table."""
    return [AXIS_NAMES.index(a) for a in machine.axis_names]


def check_moves(plan: Plan, period: float, compiled: bool = False) -> None:
    """Before sampling: ``PLAN-TRAVEL`` for a move longer along a linear axis than that
    axis' whole travel (it cannot stay inside it), and ``LIMIT-COUNT`` for a move that would
    take more than ``kernel.limits``' ``samples_per_move`` samples (an arc of 1e9 turns).
    ``compiled``: as :func:`check_travel`."""
    if not len(plan.path.segments):
        return
    check_travel(plan, compiled)
    steps, i = move_steps(plan, period)
    check_steps(plan, steps, i)


def check_travel(plan: Plan, compiled: bool = False) -> None:
    """``PLAN-TRAVEL`` at the first move longer along a linear axis than its travel.
    ``compiled``: that move found by a compiled loop (kernel.interp.arc_kernel, for plans
    :func:`compiled_sampling` takes: numba is loaded there anyway)."""
    seg = plan.path.segments
    if not len(seg):
        return
    machine = plan.machine
    span = np.asarray(machine.limit_vector("max")) - np.asarray(machine.limit_vector("min"))
    linear = np.isfinite(span) & np.array([n not in "abc" for n in AXIS_NAMES])
    if not linear.any():
        return
    # only the columns from the first linear axis with a travel to the last (views)
    cols = np.flatnonzero(linear)
    lo, hi = int(cols[0]), int(cols[-1]) + 1
    limit = np.where(linear, span * (1 + 1e-9) + 1e-6, np.inf)[lo:hi]
    if compiled:
        i = int(first_over(seg["start"], seg["end"], lo, limit))
    else:
        over = np.abs(seg["end"][:, lo:hi] - seg["start"][:, lo:hi]) > limit
        rows = over[:, 0].copy()  # any over the columns, column by column (a few)
        for col in range(1, hi - lo):
            rows |= over[:, col]
        i = int(np.argmax(rows)) if rows.any() else -1
    if i < 0:
        return
    extent = np.abs(seg["end"][i, lo:hi] - seg["start"][i, lo:hi])
    axes = [lo + int(k) for k in np.flatnonzero(extent > limit)]
    names = ", ".join(AXIS_NAMES[k].upper() for k in axes)
    values = "; ".join(
        f"{AXIS_NAMES[k].upper()} moves {float(extent[k - lo]):.3f} mm, its travel is "
        f"{float(span[k]):.3f} mm"
        for k in axes
    )
    raise Diagnostic(
        "PLAN-TRAVEL",
        f"move longer along {names} than the machine's travel: {values}",
        Location(plan.path.file, int(seg["line"][i])),
    )


def move_steps(plan: Plan, period: float) -> tuple[float, int]:
    """The most samples one move of ``plan`` takes and its row (the first such; a plan
    with rows only)."""
    steps = (plan.duration + plan.pause) / period
    i = int(np.argmax(steps))
    return float(steps[i]), i


def check_steps(plan: Plan, steps: float, i: int) -> None:
    """``LIMIT-COUNT`` when row ``i``'s ``steps`` samples (:func:`move_steps`) are over
    ``kernel.limits``' ``samples_per_move``."""
    limit = limits.current().samples_per_move
    if not steps <= limit:
        raise limits.count_error(
            "interpolation samples of one move",
            steps,
            limit,
            "samples_per_move",
            Location(plan.path.file, int(plan.path.segments["line"][i])),
        )


def _outputs(count: int, nax: int) -> tuple[np.ndarray, ...]:
    """``t``, position, velocity, acceleration, jerk, segment and line arrays."""
    return (
        bulk_array(count),
        bulk_array((count, nax)),
        bulk_array((count, nax)),
        bulk_array((count, nax)),
        bulk_array((count, nax), sparse=True),  # written on arcs and S-curves only
        bulk_array(count, np.int32),
        bulk_array(count, np.int32),
    )


def _whole_outputs(plan: Plan, period: float, count: int, nax: int) -> tuple[np.ndarray, ...]:
    """:func:`_outputs` for all ``count`` samples of ``plan``, or ``LIMIT-MEMORY`` at its
    longest move when they do not fit in memory (a program of hours sampled at 1 ms: about
    ``16 + 32 * nax`` bytes a sample)."""
    try:
        return _outputs(count, nax)
    except MemoryError:
        steps, i = move_steps(plan, period)
        need = count * (16 + 32 * nax) / 2**20
        raise Diagnostic(
            "LIMIT-MEMORY",
            f"the program's {count:,} samples ({plan.total_time:.6g} s at {period:g} s) need "
            f"about {need:,.0f} MB, more than there is; its longest move, here, takes "
            f"{steps * period:.6g} s (a larger interpolation_period or a shorter program "
            "needs fewer)",
            Location(plan.path.file, int(plan.path.segments["line"][i])),
        ) from None


def sample(plan: Plan, period: float | None = None, chunk: int = CHUNK) -> Samples:
    """Sample ``plan`` every ``period`` (default: the controller's interpolation period).

    Per chunk of samples: the path state in closed form, then the axes by the chain rule.
    Lines (the bulk) are written straight into the output arrays (``start + s u``, ``u v``,
    ``u a``, ``u j``); the samples on arcs are then overwritten in batches (:class:`_ArcBatch`).
    """
    machine = plan.machine
    period = machine.controller.interpolation_period if period is None else period
    seg = plan.path.segments
    check_moves(plan, period, len(seg) > 0 and compiled_sampling(plan, period))
    count = int(math.ceil(plan.total_time / period - 1e-9)) + 1 if len(seg) else 1
    nax = len(machine.axis_names)
    if not len(seg):
        t, pos, vel, acc, jerk, seg_out, line_out = _outputs(count, nax)
        pos[:] = np.asarray(machine.limit_vector("home"))[_columns(machine)]
        seg_out[:] = -1
        return Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)
    out = _whole_outputs(plan, period, count, nax)
    _Sampler(plan, period, chunk).run(range(0, count, chunk), out)
    t, pos, vel, acc, jerk, seg_out, line_out = out
    pos[-1] = seg["end"][-1][_columns(machine)]
    vel[-1] = acc[-1] = 0.0
    if jerk[-1].any():
        jerk[-1] = 0.0
    return Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)


#: rows per window of :func:`sample_windows` (a multiple of the chunk): 262,144 samples,
#: about 40 MB of arrays for three axes
WINDOW = 1 << 18


def sample_windows(
    plan: Plan, window: int = WINDOW, period: float | None = None, chunk: int = CHUNK
) -> Iterator[Samples]:
    """The samples of :func:`sample`, ``window`` rows at a time (each a :class:`Samples`
    whose ``t`` goes on from the last): memory bounded by the window, not by the program's
    duration. Every row is computed as :func:`sample` computes it (the same chunks)."""
    machine = plan.machine
    period = machine.controller.interpolation_period if period is None else period
    seg = plan.path.segments
    if not len(seg):
        yield sample(plan, period, chunk)
        return
    check_moves(plan, period)
    count = int(math.ceil(plan.total_time / period - 1e-9)) + 1
    nax = len(machine.axis_names)
    window = max(chunk, window // chunk * chunk)
    sampler = _Sampler(plan, period, chunk)
    for lo in range(0, count, window):
        hi = min(count, lo + window)
        out = _outputs(hi - lo, nax)
        sampler.run(range(lo, hi, chunk), out, offset=lo, count=count)
        t, pos, vel, acc, jerk, seg_out, line_out = out
        if hi == count:
            pos[-1] = seg["end"][-1][_columns(machine)]
            vel[-1] = acc[-1] = 0.0
            if jerk[-1].any():
                jerk[-1] = 0.0
        yield Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)


def sample_span(
    plan: Plan,
    lo: int,
    hi: int,
    last: bool,
    window: int = WINDOW,
    chunk: int = CHUNK,
    i_start: float = 0.0,
) -> Iterator[Samples]:
    """Samples ``lo .. hi - 1`` (``t_k = k T`` from the program's start) of a plan that is
    one window of a longer one (kernel.stream: ``t_start`` from the program's start, and
    every ``t_k`` within the window's time), ``window`` rows at a time, each row computed
    as :func:`sample` computes it. ``last``: the program's last window, whose last sample
    is the end point at rest. The samples' ``segment`` indexes the window's rows.
    ``i_start``: the S-curve's integral of the path position at the plan's first row
    (:func:`pieces`)."""
    machine = plan.machine
    period = machine.controller.interpolation_period
    nax = len(machine.axis_names)
    seg = plan.path.segments
    if hi <= lo:
        return
    sampler = _Sampler(plan, period, chunk, i_start)
    for a in range(lo, hi, window):
        b = min(hi, a + window)
        out = _outputs(b - a, nax)
        sampler.run(range(a, b, chunk), out, offset=a, count=b)
        t, pos, vel, acc, jerk, seg_out, line_out = out
        if last and b == hi:
            pos[-1] = seg["end"][-1][_columns(machine)]
            vel[-1] = acc[-1] = 0.0
            if jerk[-1].any():
                jerk[-1] = 0.0
        yield Samples(period, t, pos, vel, acc, jerk, seg_out, line_out, machine.axis_names)
