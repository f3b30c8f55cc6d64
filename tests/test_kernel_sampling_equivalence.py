"""The optimised sampler (kernel.interp.interpolate.sample) gives the same numbers as before.

Reference: the sampler as it was before the speed work (issue 3 speed clause), kept
below as :func:`reference_sample`, verbatim but for one marked clip (per chunk: the path
state from the pieces, then every sample through :func:`kernel.path.geometry.evaluate`).
The new one computes the same floating-point operations in reused buffers, writes lines
straight into the outputs and evaluates arcs in batches over chunks; its results must be
identical bit for bit (``segment`` is now int32: compared by value) for golden programs, a
CAM-style zig-zag with helical turn-arounds, S-curve smoothing, the sampled-data circle
methods, rotary axes, holds, and random programs (hypothesis), with chunk sizes that cut
arcs and pieces anywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path as FsPath

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from kernel.diagnostics import Diagnostic
from kernel.interp import interpolate
from kernel.interp.bulk import MAPPED_BYTES, bulk_array
from kernel.interp.interpolate import _piece_of, sample, sample_windows
from kernel.interp.samples import Samples
from kernel.ir import canon
from kernel.machine import AXIS_NAMES, DEFAULT_MACHINE, AxisLimits, Machine, with_controller
from kernel.path.build import build_path
from kernel.path.geometry import evaluate, line_cache
from kernel.path.segments import HOLD
from kernel.plan.planner import Plan, plan
from kernel.plan.strategy import plan_program

GOLDEN = FsPath(__file__).resolve().parent / "golden" / "ngc"
FIELDS = ("t", "position", "velocity", "acceleration", "jerk", "segment", "source_line")
SIX_AXES = Machine(
    "6ax",
    (
        *DEFAULT_MACHINE.axes,
        *(AxisLimits(n, velocity=3600.0, acceleration=36000.0, jerk=1e6) for n in "abc"),
    ),
    DEFAULT_MACHINE.controller,
)
SCURVE = with_controller(DEFAULT_MACHINE, accdec="scurve")


# ----------------------------------------------------------------------------- reference
@dataclass(frozen=True, slots=True)
class _Pieces:
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


def _pieces(plan: Plan) -> _Pieces:
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
    return _Pieces(
        t0.ravel(),
        s0.ravel(),
        v0.ravel(),
        a0.ravel(),
        smax,
        big_s0.ravel(),
        i0,
        np.repeat(np.arange(n), 4),
    )


def _reference_piece_of(t0: np.ndarray, t: np.ndarray) -> np.ndarray:
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


def _path_state(pc: _Pieces, t: np.ndarray, integral: bool = False) -> tuple[np.ndarray, ...]:
    """``(segment, local s, global S, v, a, I)`` at sorted times ``t`` (at rest at S = 0
    before 0). ``I`` (the time integral of S) only when ``integral``, else ``None``."""
    k = _reference_piece_of(pc.t0, t)
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


def reference_sample(plan: Plan, period: float | None = None, chunk: int = 32_768) -> Samples:
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
    pc = _pieces(plan)
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
        k, local, big_s, v, a, integral = _path_state(pc, tt, tf > 0)
        j = None
        gk = k
        if tf > 0:
            _, _, s2, v2, a2, i2 = _path_state(pc, tt - tf, True)
            big_s, v, a, j = (integral - i2) / tf, (big_s - s2) / tf, (v - v2) / tf, (a - a2) / tf
            g = np.searchsorted(s_end_moving, big_s - 1e-12, "left")
            gk = moving_idx[np.clip(g, 0, moving_idx.size - 1)] if moving_idx.size else k
            gk = np.where(kind[k] == HOLD, np.where(v == 0, k, gk), gk)
            local = big_s - plan.s_start[gk]
            # The one deliberate change since: the S-curve position is kept on its segment.
            # The old sampler ran past a segment's end by the rounding of the moving
            # average (up to 1e-12 mm, the search tolerance above).
            np.clip(local, 0.0, seg["length"][gk], out=local)
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


# ----------------------------------------------------------------------------- helpers
def assert_same(new: Samples, ref: Samples) -> None:
    """Every array equal bit for bit (0.0 and -0.0 apart), the segment index by value."""
    assert new.period == ref.period and new.axes == ref.axes
    for f in FIELDS:
        a, b = getattr(new, f), getattr(ref, f)
        assert a.shape == b.shape, f
        if a.dtype.kind == "f":
            assert a.dtype == b.dtype, f
            assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), f
        else:
            assert np.array_equal(a, b), f
    assert new.segment.dtype == np.int32 and new.source_line.dtype == np.int32


def zigzag(passes: int, per_pass: int = 40, step: float = 0.5) -> list[canon.Command]:
    """A CAM-style surfacing program: short G1 lines over a wavy surface, helical G2/G3
    half-circle turn-arounds between passes, a dwell, traverses in and out (the bench's
    program, bench/bench_plan.py, in small)."""
    cmds: list[canon.Command] = [
        canon.UseLengthUnits(canon.Units.MM),
        canon.SetFeedRate(3000.0),
        canon.StraightTraverse(0.0, 0.0, 20.0),
    ]
    line = 1
    x = np.arange(per_pass + 1) * step
    for p in range(passes):
        y = p * 0.4
        xs = x if p % 2 == 0 else x[::-1]
        z = 2.0 * np.sin(xs / 7.0) * np.cos(y / 11.0)
        if p == 0:
            cmds.append(canon.StraightFeed(float(xs[0]), y, float(z[0])))
        for xi, zi in zip(xs[1:], z[1:], strict=True):
            line += 1
            src = canon.Source(None, line, 1)
            cmds.append(canon.StraightFeed(float(xi), y, float(zi), source=src))
        z2 = 2.0 * math.sin(xs[-1] / 7.0) * math.cos((y + 0.4) / 11.0)
        rot = 1 if p % 2 == 0 else -1
        line += 1
        src = canon.Source(None, line, 1)
        cmds.append(
            canon.ArcFeed(float(xs[-1]), y + 0.4, float(xs[-1]), y + 0.2, rot, z2, source=src)
        )
        if p == passes // 2:
            cmds.append(canon.Dwell(0.05))
    cmds.append(canon.StraightTraverse(0.0, 0.0, 20.0))
    cmds.append(canon.ProgramEnd())
    return cmds


def planned(cmds: list[canon.Command], machine: Machine) -> Plan:
    return plan(build_path(cmds, machine), machine)


def golden_plans(limit: float) -> list[Plan]:
    """Plans of the golden programs that plan on the default machine and last at most
    ``limit`` seconds."""
    out = []
    for f in sorted(GOLDEN.glob("*.canon")):
        with open(f) as fh:
            cmds = list(canon.read_commands(fh, str(f), keep_linuxcnc=True))
        try:
            pl = planned(cmds, DEFAULT_MACHINE)
        except Diagnostic:
            continue
        if pl.total_time <= limit:
            out.append(pl)
    return out


# ----------------------------------------------------------------------------- tests
def test_golden_programs_sample_bit_for_bit_as_before():
    """The golden feature programs (arcs in every plane, helices, dwells, tool changes,
    G61/G64, units, offsets) on the default machine."""
    plans = golden_plans(60.0)
    assert len(plans) >= 100
    for pl in plans:
        assert_same(sample(pl), reference_sample(pl))


@pytest.mark.parametrize("chunk", [32_768, 1000, 97])
@pytest.mark.parametrize(
    "machine",
    [
        DEFAULT_MACHINE,
        SCURVE,
        with_controller(DEFAULT_MACHINE, circle_method="tustin"),
        with_controller(DEFAULT_MACHINE, circle_method="improved_tustin"),
        with_controller(SCURVE, circle_method="euler", blend_tolerance=0.05),
    ],
    ids=["trapezoid", "scurve", "tustin", "improved_tustin", "scurve_euler_blended"],
)
def test_cam_zigzag_samples_as_before_for_any_chunk_size(machine, chunk):
    """Chunks cutting arcs, pieces and the dwell anywhere (the arcs are batched across
    chunks), for trapezoidal and S-curve profiles and sampled-data circle methods."""
    pl = planned(zigzag(12), machine)
    ref = reference_sample(pl)
    assert len(ref) > 3 * 97
    assert_same(sample(pl, chunk=chunk), ref)


@pytest.mark.parametrize("chunk", [32_768, 97])
def test_compiled_arc_kernel_samples_as_before(monkeypatch, chunk):
    """The compiled arc kernel (kernel.interp.arc_kernel), used from
    ``COMPILED_ARC_SAMPLES`` arc samples on, here forced on for small programs: the golden
    programs and the CAM zig-zag, bit for bit as the numpy formulation."""
    monkeypatch.setattr(interpolate, "COMPILED_ARC_SAMPLES", 0)
    plans = [planned(zigzag(12), DEFAULT_MACHINE), *golden_plans(20.0)[::3]]
    for pl in plans:
        assert_same(sample(pl, chunk=chunk), reference_sample(pl, chunk=chunk))


@pytest.mark.parametrize("chunk", [1000, 97])
def test_compiled_sampling_of_a_linuxcnc_plan_in_windows(monkeypatch, chunk):
    """A LinuxCNC-model plan (blend arcs, overlapping parabolic blends) sampled by the
    compiled kernels, whole and in windows, bit for bit as by numpy."""
    machine = with_controller(DEFAULT_MACHINE, model="linuxcnc")
    _, pl = plan_program(zigzag(12), machine)
    assert np.any(pl.path.segments["kind"] == 1) and pl.overlap is not None
    monkeypatch.setattr(interpolate, "COMPILED_ARC_SAMPLES", math.inf)
    ref = sample(pl, chunk=chunk)
    monkeypatch.setattr(interpolate, "COMPILED_ARC_SAMPLES", 0)
    assert interpolate._Sampler(pl, 0.001, chunk).compiled
    ours, theirs = interpolate.pieces(pl, False, 0.0, True), interpolate.pieces(pl, False)
    for f in ("t0", "s0", "v0", "a", "smax"):
        x, y = getattr(ours, f), getattr(theirs, f)
        assert np.array_equal(x.view(np.uint64), y.view(np.uint64)), f
    assert_same(sample(pl, chunk=chunk), ref)
    parts = list(sample_windows(pl, window=2 * chunk, chunk=chunk))
    assert len(parts) > 1
    for f in FIELDS:
        whole = np.concatenate([getattr(w, f) for w in parts])
        assert np.array_equal(whole, getattr(ref, f)), f


def test_golden_programs_with_scurve_and_circle_methods_sample_as_before():
    plans = golden_plans(15.0)[::4]
    assert len(plans) >= 20
    for m in (SCURVE, with_controller(DEFAULT_MACHINE, circle_method="taylor")):
        for pl in plans:
            pl = plan(pl.path, m)
            assert_same(sample(pl, chunk=512), reference_sample(pl, chunk=512))


def test_other_periods_and_empty_plans_sample_as_before():
    pl = planned(zigzag(3), DEFAULT_MACHINE)
    for period in (0.004, 0.0005, 0.0037):
        assert_same(sample(pl, period), reference_sample(pl, period))
    empty = planned([canon.SetFeedRate(100.0)], DEFAULT_MACHINE)
    assert_same(sample(empty), reference_sample(empty))


_moves = st.one_of(
    st.tuples(st.just("line"), st.floats(-20, 20), st.floats(-20, 20), st.floats(-5, 5)),
    st.tuples(st.just("rotary"), st.floats(-20, 20), st.floats(-5, 5), st.floats(-90, 90)),
    st.tuples(
        st.just("arc"),
        st.sampled_from(list(canon.Plane)),
        st.floats(0.2, 8.0),
        st.floats(0.1, 6.2),
        st.sampled_from([-2, -1, 1, 2]),
        st.floats(-3, 3),
    ),
    st.tuples(st.just("dwell"), st.floats(0.0, 0.02)),
    st.tuples(st.just("traverse"), st.floats(-20, 20), st.floats(-20, 20), st.floats(0, 10)),
    st.tuples(st.just("feed"), st.floats(60.0, 6000.0)),
    st.tuples(st.just("mode"), st.booleans()),
)


def _random_program(moves: list[tuple]) -> list[canon.Command]:
    """Commands from drawn moves; arcs start where the tool is (centre at a drawn radius
    and angle from it, end a drawn sweep further on)."""
    cmds: list[canon.Command] = [canon.SetFeedRate(1200.0)]
    pos = [0.0] * 6
    plane = canon.Plane.XY
    axes = {canon.Plane.XY: (0, 1, 2), canon.Plane.YZ: (1, 2, 0), canon.Plane.XZ: (2, 0, 1)}
    for mv in moves:
        kind = mv[0]
        if kind in ("line", "traverse"):
            pos[:3] = mv[1:4]
            cls = canon.StraightFeed if kind == "line" else canon.StraightTraverse
            cmds.append(cls(*pos))
        elif kind == "rotary":
            pos[0], pos[2], pos[3] = mv[1], mv[2], mv[3]
            cmds.append(canon.StraightFeed(*pos))
        elif kind == "arc":
            _, pl, r, ang, turns, dz = mv
            if pl != plane:
                plane = pl
                cmds.append(canon.SelectPlane(pl))
            f, s, ax = axes[plane]
            cf, cs = pos[f] - r, pos[s]
            a1 = ang if turns > 0 else -ang
            ef, es = cf + r * math.cos(a1), cs + r * math.sin(a1)
            pos[f], pos[s], pos[ax] = ef, es, pos[ax] + dz
            cmds.append(canon.ArcFeed(ef, es, cf, cs, turns, pos[ax], *pos[3:]))
        elif kind == "dwell":
            cmds.append(canon.Dwell(mv[1]))
        elif kind == "feed":
            cmds.append(canon.SetFeedRate(mv[1]))
        else:
            mode = canon.MotionMode.EXACT_STOP if mv[1] else canon.MotionMode.CONTINUOUS
            cmds.append(canon.SetMotionControlMode(mode, 0.0))
    cmds.append(canon.ProgramEnd())
    return cmds


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(_moves, min_size=1, max_size=25),
    st.sampled_from([SIX_AXES, with_controller(SIX_AXES, accdec="scurve")]),
    st.integers(7, 5000),
)
@example(  # S-curve end of a traverse: the moving average overshoots by 2e-13 mm
    moves=[
        ("dwell", 0.016481538752497655),
        ("dwell", 0.011153404580562529),
        ("mode", True),
        ("traverse", 0.0, -13.618415768024626, 7.463339314326162),
        ("line", 0.0, 18.0, 2.75),
    ],
    machine=with_controller(SIX_AXES, accdec="scurve"),
    chunk=7,
)
def test_random_programs_sample_as_before(moves, machine, chunk):
    """Random mixes of lines, rotary moves, arcs and helices in every plane (multi-turn
    too), dwells, traverses, feed and G61/G64 changes, on a 6-axis machine."""
    pl = planned(_random_program(moves), machine)
    assume(pl.total_time < 600.0)  # tiny moves can make the plan crawl (hours of samples)
    assert_same(sample(pl, chunk=chunk), reference_sample(pl, chunk=chunk))


# ----------------------------------------------------------------------------- bulk arrays
@pytest.mark.parametrize("sparse", [False, True])
@pytest.mark.parametrize("shape", [(10,), (MAPPED_BYTES // 24 + 1, 3), (0, 3)])
def test_bulk_arrays_are_writable_zeros_of_the_asked_shape(shape, sparse):
    """Small, large (own mapping) and empty arrays: writable C-contiguous zeros."""
    a = bulk_array(shape, np.float64, sparse=sparse)
    assert a.shape == shape and a.dtype == np.float64 and a.flags.writeable
    assert a.flags.c_contiguous and not a.any()
    a[...] = 2.5
    assert (a == 2.5).all()
    b = bulk_array(shape[0], np.int32, sparse=sparse)
    assert b.dtype == np.int32 and b.shape == shape[:1] and not b.any()


def test_a_bulk_array_larger_than_memory_is_a_memory_error():
    with pytest.raises(MemoryError):
        bulk_array((1 << 46,), np.float64)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.integers(0, 3000), min_size=1, max_size=60),
    st.lists(st.floats(0.0, 3.0), max_size=20),
    st.sampled_from([0.001, 0.0005, 0.004, 1e-3 / 3, 0.1]),
    st.integers(0, 2000),
    st.integers(1, 700),
)
def test_piece_lookup_on_the_sample_grid_is_searchsorted(on_grid, off_grid, period, lo, n):
    """Piece starts on grid points (k * period, the hardest case), between them, before
    and after the chunk: the counts from ``ceil(t0 / period)`` equal searchsorted's."""
    t0 = np.sort(np.concatenate([np.array(on_grid) * period, np.array(off_grid) * 1000 * period]))
    t = np.arange(lo, lo + n, dtype=float) * period
    want = _piece_of(t0, t)
    assert np.array_equal(_piece_of(t0, t, (lo, period)), want)
    i = np.clip(np.searchsorted(t0, t, "right") - 1, 0, None)
    assert np.array_equal(want, i)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_move_longer_than_an_axis_travel_is_plan_travel(compiled):
    """``PLAN-TRAVEL`` names every linear axis a move spans more than its travel (the
    default machine: X 800 mm, Y 500 mm, Z 500 mm), at the first such move, found by numpy
    or by the compiled loop."""
    cmds = [
        canon.SetFeedRate(1000.0),
        canon.StraightFeed(-100.0, 0.0, 0.0),
        canon.StraightFeed(100.0, 0.0, -99.0),
        canon.StraightFeed(200.0, 0.0, 0.0),
    ]
    pl = planned(cmds, DEFAULT_MACHINE)
    interpolate.check_travel(pl, compiled)  # within the travel
    seg = pl.path.segments
    seg["end"][1, :3] = (100.0, 600.0, -600.0)
    seg["end"][2, :3] = (1000.0, 0.0, 0.0)  # a later one (X) is not reported
    with pytest.raises(Diagnostic) as err:
        interpolate.check_travel(pl, compiled)
    assert err.value.code == "PLAN-TRAVEL"
    assert "along Y, Z" in str(err.value) and "X moves" not in str(err.value)
    assert "Y moves 600.000 mm, its travel is 500.000 mm" in str(err.value)
    assert "Z moves 600.000 mm, its travel is 500.000 mm" in str(err.value)
