"""Properties of planned and sampled motion for random programs and random machines.

For every program: no sample exceeds an axis velocity or acceleration limit (nor jerk with
S-curve acc/dec) beyond rounding; the path speed never exceeds the programmed feed; samples
lie on the programmed path (no blending: tolerance 0); the speed is zero at every barrier;
the last sample is the program's end point exactly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kernel import canon
from kernel.geometry import evaluate
from kernel.interpolate import sample
from kernel.machine import AxisLimits, Controller, Machine
from kernel.path import ARC, HOLD, LINE, build_path
from kernel.planner import plan

RTOL, ATOL = 1e-6, 1e-7

coord = st.floats(-40, 40, allow_nan=False).map(lambda v: round(v, 3))


@st.composite
def programs(draw):
    """Random line / arc / dwell programs starting at the origin, all in mm, XY arcs."""
    cmds: list[canon.Command] = [canon.SetFeedRate(draw(st.floats(300, 6000)))]
    x = y = z = 0.0
    for _ in range(draw(st.integers(1, 7))):
        kind = draw(st.sampled_from(["feed", "feed", "rapid", "arc", "dwell", "feedrate"]))
        if kind in ("feed", "rapid"):
            x, y, z = draw(coord), draw(coord), draw(coord)
            cls = canon.StraightFeed if kind == "feed" else canon.StraightTraverse
            cmds.append(cls(x, y, z))
        elif kind == "arc":
            r = draw(st.floats(0.5, 30))
            a0 = draw(st.floats(0, 2 * math.pi))
            sweep = draw(st.floats(0.2, 2 * math.pi - 0.2))
            rot = draw(st.sampled_from([1, -1]))
            cx, cy = x - r * math.cos(a0), y - r * math.sin(a0)
            a1 = a0 + rot * sweep
            x, y = cx + r * math.cos(a1), cy + r * math.sin(a1)
            z = draw(coord) if draw(st.booleans()) else z
            cmds.append(canon.ArcFeed(x, y, cx, cy, rot, z))
        elif kind == "dwell":
            cmds.append(canon.Dwell(draw(st.floats(0, 0.05))))
        else:
            cmds.append(canon.SetFeedRate(draw(st.floats(300, 6000))))
    return cmds


@st.composite
def machines(draw):
    axes = tuple(
        AxisLimits(
            n,
            velocity=draw(st.floats(20, 300)),
            acceleration=draw(st.floats(200, 5000)),
            jerk=draw(st.floats(2e4, 2e5)),
        )
        for n in "xyz"
    )
    ctl = Controller(
        lookahead=draw(st.sampled_from([1, 2, 5, 200])),
        accdec=draw(st.sampled_from(["trapezoid", "scurve"])),
        corner_rule=draw(st.sampled_from(["axis", "angle"])),
        chord_tolerance=draw(st.sampled_from([0.001, 0.01])),
    )
    return Machine("random", axes, ctl)


def _programmed_feeds(cmds: list[canon.Command], path) -> np.ndarray:
    return path.segments["feed"]


def _on_path(path, samples) -> float:
    """Largest distance of a sample from the geometry of its own segment."""
    seg = path.segments
    k = samples.segment
    moving = k >= 0
    idx = k[moving]
    pos = samples.position[moving]
    worst = 0.0
    line = seg["kind"][idx] == LINE
    if line.any():
        s0, u = seg["start"][idx[line], :3], seg["u_start"][idx[line], :3]
        t = np.clip(np.sum((pos[line] - s0) * u, axis=1), 0, seg["length"][idx[line]])
        worst = max(worst, float(np.linalg.norm(pos[line] - (s0 + t[:, None] * u), axis=1).max()))
    arc = seg["kind"][idx] == ARC
    if arc.any():
        rows = idx[arc]
        rel = pos[arc] - seg["centre"][rows]
        n = seg["normal"][rows]
        planar = rel - np.sum(rel * n, axis=1)[:, None] * n
        r = np.linalg.norm(planar, axis=1)
        worst = max(worst, float(np.abs(r - seg["radius"][rows]).max()))
    return worst


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(), machines())
def test_sampled_motion_respects_every_limit_and_the_program(cmds, machine):
    path = build_path(cmds, machine)
    if not len(path):
        return
    p = plan(path, machine)
    s = sample(p)
    for j, name in enumerate(s.axes):
        ax = machine.axis(name)
        assert np.abs(s.velocity[:, j]).max() <= ax.velocity * (1 + RTOL) + ATOL
        assert np.abs(s.acceleration[:, j]).max() <= ax.acceleration * (1 + RTOL) + ATOL
    # feed never above the programmed one (path speed of the segment being run)
    moving = s.segment >= 0
    speed = np.linalg.norm(s.velocity[moving], axis=1)
    feed = path.segments["feed"][s.segment[moving]]
    assert np.all(speed <= feed * (1 + RTOL) + ATOL)
    # on the programmed path (exact path: no blending), and exactly at the end
    assert _on_path(path, s) <= 1e-7
    assert np.array_equal(s.position[-1], path.end_position[:3])
    # zero speed at every barrier: while a hold runs, and at the end
    assert np.all(s.velocity[s.segment < 0] == 0.0)
    assert np.all(s.velocity[-1] == 0.0)
    assert np.all(p.v_junction[np.r_[False, path.segments["kind"] == HOLD]] == 0.0)
    assert p.v_junction[0] == 0.0 and p.v_junction[-1] == 0.0


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(coord, coord, coord), min_size=1, max_size=8),
    machines(),
    st.floats(300, 6000),
)
def test_s_curve_line_programs_respect_the_jerk_limit(points, machine, feed):
    from kernel.machine import with_controller

    machine = with_controller(machine, accdec="scurve")
    cmds = [canon.SetFeedRate(feed)] + [canon.StraightFeed(*p) for p in points]
    path = build_path(cmds, machine)
    if not len(path):
        return
    s = sample(plan(path, machine))
    for j, name in enumerate(s.axes):
        ax = machine.axis(name)
        assert np.abs(s.jerk[:, j]).max() <= ax.jerk * (1 + RTOL) + ATOL
        assert np.abs(s.velocity[:, j]).max() <= ax.velocity * (1 + RTOL) + ATOL
        assert np.abs(s.acceleration[:, j]).max() <= ax.acceleration * (1 + RTOL) + ATOL


@settings(max_examples=30, deadline=None)
@given(programs(), machines())
def test_sample_derivatives_agree_with_position_differences(cmds, machine):
    """The reported velocity is the derivative of the reported positions (within a
    period's worth of acceleration), i.e. the arrays are one consistent motion."""
    path = build_path(cmds, machine)
    if not len(path):
        return
    s = sample(plan(path, machine))
    if len(s) < 3:
        return
    same = (s.segment[1:] == s.segment[:-1]) & (s.segment[1:] >= 0)
    fd = np.diff(s.position, axis=0) / s.period
    mid = 0.5 * (s.velocity[1:] + s.velocity[:-1])
    amax = max(a.acceleration for a in machine.axes)
    jmax = max(a.jerk for a in machine.axes)
    assert np.all(np.abs(fd - mid)[same] <= amax * s.period + jmax * s.period**2 + 1e-6)


def test_evaluate_agrees_with_the_segment_end_points():
    m = Machine("t", tuple(AxisLimits(n) for n in "xyz"), Controller())
    path = build_path(
        [canon.SetFeedRate(100), canon.StraightFeed(3, 4, 0), canon.ArcFeed(7, 4, 5, 4, 1, 2)], m
    )
    seg = path.segments
    idx = np.arange(len(seg))
    p0 = evaluate(seg, idx, np.zeros(len(seg)))[0]
    p1 = evaluate(seg, idx, seg["length"].copy())[0]
    assert p0 == pytest.approx(seg["start"])
    assert np.array_equal(p1, seg["end"])


def _distance_to_polyline(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    a, b = poly[:-1][None], poly[1:][None]
    d = b - a
    ll = np.maximum(np.sum(d * d, axis=-1), 1e-300)
    t = np.clip(np.sum((points[:, None] - a) * d, axis=-1) / ll, 0, 1)
    return np.linalg.norm(points[:, None] - (a + t[..., None] * d), axis=-1).min(axis=1)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.tuples(coord, coord, coord), min_size=2, max_size=8),
    machines(),
    st.floats(0.001, 2.0),
    st.floats(300, 6000),
)
def test_g64_p_blending_stays_within_the_tolerance_and_the_limits(points, machine, tol, feed):
    head = [canon.SetFeedRate(feed)]
    moves = [canon.StraightFeed(*p) for p in points]
    g64 = [canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, tol)]
    exact = build_path(head + moves, machine)
    blended_path = build_path(head + g64 + moves, machine)
    if len(exact) < 2:
        return
    p_blend = plan(blended_path, machine)
    s = sample(p_blend)
    poly = np.vstack([exact.segments["start"][:1, :3], exact.segments["end"][:, :3]])
    assert _distance_to_polyline(s.position, poly).max() <= tol * (1 + 1e-9) + 1e-9
    assert np.array_equal(s.position[-1], exact.end_position[:3])
    for j, name in enumerate(s.axes):
        ax = machine.axis(name)
        assert np.abs(s.velocity[:, j]).max() <= ax.velocity * (1 + RTOL) + ATOL
        assert np.abs(s.acceleration[:, j]).max() <= ax.acceleration * (1 + RTOL) + ATOL


def test_g64_p_blend_arc_is_tangent_and_bounded_by_p():
    from kernel.blend import blend_corners

    m = Machine("t", tuple(AxisLimits(n, acceleration=1000.0) for n in "xyz"), Controller())
    cmds = [
        canon.SetFeedRate(1200),
        canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, 0.05),
        canon.StraightFeed(10, 0, 0),
        canon.StraightFeed(10, 10, 0),
    ]
    path = build_path(cmds, m)
    assert len(blend_corners(path)) == len(path)  # blending is idempotent
    arc = path.segments[path.segments["kind"] == ARC][0]
    # 90 degree corner: e = r (sqrt 2 - 1) = P
    assert arc["radius"] == pytest.approx(0.05 / (math.sqrt(2) - 1))
    assert np.allclose(arc["u_start"][:3], [1, 0, 0]) and np.allclose(arc["u_end"][:3], [0, 1, 0])
    mid = evaluate(path.segments, np.array([1]), np.array([arc["length"] / 2]))[0][0]
    assert np.linalg.norm(mid[:3] - [10, 0, 0]) == pytest.approx(0.05)
    p = plan(build_path(cmds, m), m)
    assert p.v_junction[1] > 0 and p.v_junction[2] > 0  # the corner is run through the arc
    assert p.v_junction[1] == pytest.approx(math.sqrt(0.5 * 1000 * arc["radius"]))
