"""Properties of planned and sampled motion for random programs and random machines.

For every program (lines, rapids, arcs and helices, tangent or not): no sample exceeds an
axis velocity or acceleration limit (nor jerk with S-curve acc/dec, including the change of
acceleration over the period that crosses a tangent line-arc or arc-arc joint, where the
curvature jumps: kernel.path.curvature) beyond rounding; the path speed never exceeds the
programmed feed; samples lie on the programmed path (no blending: tolerance 0); the speed is
zero at every barrier; the last sample is the program's end point exactly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import AxisLimits, Controller, Machine, with_controller
from kernel.path.build import build_path
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, HOLD, LINE
from kernel.plan.planner import plan
from kernel.plan.strategy import plan_program

RTOL, ATOL = 1e-6, 1e-7

coord = st.floats(-40, 40, allow_nan=False).map(lambda v: round(v, 3))


@st.composite
def programs(draw, rapids: bool = True, chain: bool = False):
    """Random programs starting at the origin, all in mm, XY arcs: lines, rapids, arcs and
    helices (free, or tangent to the move before: tangent line-arc, arc-arc and arc-line
    joints), dwells and feed changes. ``chain``: a line along X, then only tangent planar
    lines and arcs (every joint tangent)."""
    cmds: list[canon.Command] = [canon.SetFeedRate(draw(st.floats(300, 6000)))]
    x = y = z = 0.0
    tangent = None  # XY unit direction at the end of the last move, if it is planar
    kinds = ["feed", "feed", "tangent_feed", "arc", "tangent_arc", "tangent_arc", "dwell"]
    kinds += ["feedrate", "rapid"] if rapids else ["feedrate"]
    if chain:
        x, tangent = draw(st.floats(1, 60)), (1.0, 0.0)
        cmds.append(canon.StraightFeed(x, y, z))
        kinds = ["tangent_feed", "tangent_arc", "tangent_arc"]
    for _ in range(draw(st.integers(1, 7))):
        kind = draw(st.sampled_from(kinds))
        if kind == "tangent_feed" and tangent is not None:
            step = draw(st.floats(0.5, 40))
            x, y = x + step * tangent[0], y + step * tangent[1]
            cmds.append(canon.StraightFeed(x, y, z))
        elif kind in ("feed", "rapid", "tangent_feed"):
            nx, ny, nz = draw(coord), draw(coord), draw(coord)
            h = math.hypot(nx - x, ny - y)
            tangent = ((nx - x) / h, (ny - y) / h) if h > 1e-6 and nz == z else None
            x, y, z = nx, ny, nz
            cls = canon.StraightTraverse if kind == "rapid" else canon.StraightFeed
            cmds.append(cls(x, y, z))
        elif kind in ("arc", "tangent_arc"):
            r = draw(st.floats(0.5, 30))
            sweep = draw(st.floats(0.2, 2 * math.pi - 0.2))
            rot = draw(st.sampled_from([1, -1]))
            if kind == "tangent_arc" and tangent is not None:  # centre on the left (CCW)
                cx, cy = x - rot * r * tangent[1], y + rot * r * tangent[0]
                a0 = math.atan2(y - cy, x - cx)
            else:
                a0 = draw(st.floats(0, 2 * math.pi))
                cx, cy = x - r * math.cos(a0), y - r * math.sin(a0)
            a1 = a0 + rot * sweep
            x, y = cx + r * math.cos(a1), cy + r * math.sin(a1)
            helix = not chain and draw(st.booleans())
            z = draw(coord) if helix else z
            cmds.append(canon.ArcFeed(x, y, cx, cy, rot, z))
            tangent = None if helix else (-rot * math.sin(a1), rot * math.cos(a1))
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


def _on_path(path, samples, where=None, slack=None) -> float:
    """Largest distance of a sample from the geometry of its own segment (of the samples
    ``where`` selects, less ``slack`` per sample: the excess over it)."""
    seg = path.segments
    k = samples.segment
    moving = k >= 0 if where is None else (k >= 0) & where
    idx = k[moving]
    pos = samples.position[moving]
    if slack is not None and idx.size:
        return max(_distances(seg, idx, pos) - slack[moving])
    return max(_distances(seg, idx, pos), default=0.0)


def _distances(seg, idx, pos) -> np.ndarray:
    """Distance of each position from the geometry of its segment ``idx``."""
    out = np.zeros(len(idx))
    line = seg["kind"][idx] == LINE
    if line.any():
        s0, u = seg["start"][idx[line], :3], seg["u_start"][idx[line], :3]
        t = np.clip(np.sum((pos[line] - s0) * u, axis=1), 0, seg["length"][idx[line]])
        out[line] = np.linalg.norm(pos[line] - (s0 + t[:, None] * u), axis=1)
    arc = seg["kind"][idx] == ARC
    if arc.any():
        rows = idx[arc]
        rel = pos[arc] - seg["centre"][rows]
        n = seg["normal"][rows]
        planar = rel - np.sum(rel * n, axis=1)[:, None] * n
        r = np.linalg.norm(planar, axis=1)
        out[arc] = np.abs(r - seg["radius"][rows])
    return out


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(), machines())
def test_sampled_motion_respects_every_limit_and_the_program(cmds, machine):
    _assert_limits_and_program(cmds, machine)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(rapids=False, chain=True), machines())
def test_trapezoid_tangent_line_arc_chains_respect_every_limit_and_the_program(cmds, machine):
    from kernel.machine import with_controller

    _assert_limits_and_program(cmds, with_controller(machine, accdec="trapezoid"))


def _assert_limits_and_program(cmds, machine):
    path = build_path(cmds, machine)
    if not len(path):
        return
    p = plan(path, machine)
    s = sample(p)
    path = p.path  # the planned path (the same rows as built)
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


def _joint_crossings(path, s):
    """Sample pairs ``(k, k + 1)`` that cross exactly one junction between two motions, and
    the per-axis step of d2p/ds2 (curvature vector) and of the tangent at that junction."""
    seg = path.segments
    a, b = s.segment[:-1], s.segment[1:]
    k = np.flatnonzero((b == a + 1) & (a >= 0))
    a, b = a[k], b[k]

    def geometry(idx, at):
        _, d1, curved, d2c, _ = evaluate(seg, idx, at, "exact", 1.0, [0, 1, 2])
        d2 = np.zeros((idx.size, 3))
        d2[curved] = d2c
        return d1, d2

    u_a, k_a = geometry(a, seg["length"][a].copy())
    u_b, k_b = geometry(b, np.zeros(b.size))
    return k, np.abs(k_b - k_a), np.linalg.norm(u_b - u_a, axis=1)


def _assert_s_curve_jerk(path, machine):
    p = plan(path, machine)
    s, path = sample(p), p.path
    jmax = np.array([machine.axis(n).jerk for n in s.axes])
    for j, name in enumerate(s.axes):
        ax = machine.axis(name)
        assert np.abs(s.jerk[:, j]).max() <= ax.jerk * (1 + RTOL) + ATOL
        assert np.abs(s.velocity[:, j]).max() <= ax.velocity * (1 + RTOL) + ATOL
        assert np.abs(s.acceleration[:, j]).max() <= ax.acceleration * (1 + RTOL) + ATOL
    k, dcurv, dtan = _joint_crossings(path, s)
    if not k.size:
        return
    # the acceleration step at a curvature joint, at the speed the joint is crossed with
    # (at least the lower of the two samples' speeds), is at most J T / 2 per axis
    v = np.minimum(np.linalg.norm(s.velocity[k], axis=1), np.linalg.norm(s.velocity[k + 1], axis=1))
    step = dcurv * (v * v)[:, None]
    assert np.all(step <= 0.5 * jmax * s.period * (1 + RTOL) + ATOL)
    # across a tangent joint the axis acceleration is one motion: its change over the
    # sampling period (smooth part + curvature step) stays within the jerk limit
    tan = dtan < 1e-9
    fd = np.abs(s.acceleration[k[tan] + 1] - s.acceleration[k[tan]]) / s.period
    assert np.all(fd <= jmax * (1 + RTOL) + ATOL)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(rapids=False), machines())
def test_s_curve_programs_with_arcs_respect_the_jerk_limit(cmds, machine):
    """Lines, arcs and helices, tangent or not: the sampled axis jerk within the limit, and
    at every line-arc / arc-arc joint the curvature step within half the jerk budget of a
    period (kernel.path.curvature)."""
    from kernel.machine import with_controller

    machine = with_controller(machine, accdec="scurve")
    path = build_path(cmds, machine)
    if len(path):
        _assert_s_curve_jerk(path, machine)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(rapids=False, chain=True), machines())
def test_s_curve_tangent_line_arc_chains_respect_the_jerk_limit(cmds, machine):
    """Every joint tangent: the change of axis acceleration over each period that crosses a
    joint (where the curvature jumps) stays within the jerk limit."""
    from kernel.machine import with_controller

    machine = with_controller(machine, accdec="scurve")
    _assert_s_curve_jerk(build_path(cmds, machine), machine)


@pytest.mark.slow
@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs(rapids=False), machines())
def test_s_curve_programs_with_arcs_respect_the_jerk_limit_many(cmds, machine):
    from kernel.machine import with_controller

    machine = with_controller(machine, accdec="scurve")
    path = build_path(cmds, machine)
    if len(path):
        _assert_s_curve_jerk(path, machine)


def test_tangent_line_arc_joint_speed_is_the_jerk_cap():
    """Line -> tangent arc of R 30 mm at F 6000 mm/min, J 2e4 mm/s^3, T 1 ms: the centripetal
    step v^2/R over one period is held to J T / 2, so v = sqrt(J T R / 2) = 17.32 mm/s (it
    would be 100 mm/s without the cap: a 16.7 J jerk spike)."""
    from kernel.machine import with_controller

    m = Machine(
        "t",
        tuple(AxisLimits(n, velocity=300, acceleration=5000, jerk=2e4) for n in "xyz"),
        Controller(accdec="scurve"),
    )
    cmds = [
        canon.SetFeedRate(6000),
        canon.StraightFeed(100, 0, 0),
        canon.ArcFeed(100, 60, 100, 30, 1, 0),
    ]
    path = build_path(cmds, m)  # built for the S-curve machine: the line is cut
    p = plan(path, m)
    assert p.path is path  # the planner keeps the built rows (samples index them)
    v = math.sqrt(2e4 * 1e-3 * 30 / 2)
    joint = int(np.flatnonzero(p.path.segments["kind"] == ARC)[0])
    assert joint == 2
    assert p.v_junction[joint] == pytest.approx(v)
    trap = with_controller(m, accdec="trapezoid")
    assert plan(build_path(cmds, trap), trap).v_junction[1] == pytest.approx(100.0)
    # only the last T_f v of the line is slowed (the line is cut there, T_f = 2A/J): the
    # line runs at the feed and reaches the joint at v, in far less time than 100 mm at v
    s = sample(p)
    on_line = np.flatnonzero(s.segment < joint)
    speed = np.linalg.norm(s.velocity[on_line], axis=1)
    assert p.path.segments["length"][joint - 1] == pytest.approx(2 * 5000 / 2e4 * v)
    assert speed.max() == pytest.approx(100.0)
    assert speed[-1] <= v * (1 + RTOL)
    assert on_line.size * s.period < 0.4 * 100 / v  # 1.8 s against 5.8 s


def test_cut_lines_keep_the_geometry_feeds_and_stops():
    """S-curve cuts (kernel.path.curvature.split_lines_at_joints): the pieces of a line are
    collinear, contiguous and add up to it; only its last piece keeps a G61 stop; a joint
    that is a stop anyway is not cut for."""
    from kernel.path.curvature import split_lines_at_joints

    cmds = [
        canon.SetFeedRate(3000),
        canon.StraightFeed(50, 0, 0),
        canon.ArcFeed(60, 10, 50, 10, 1, 0),
        canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP),
        canon.StraightFeed(60, 70, 5),
        canon.StraightFeed(60, 80, 5),
        canon.ArcFeed(70, 90, 70, 80, -1, 5),  # after a G61 line: that joint is a stop
    ]
    path = build_path(cmds, Machine("t", tuple(AxisLimits(n) for n in "xyz"), Controller()))
    v = np.array([4.0, 2.0, np.inf, 3.0])  # caps at the joints of the arcs
    cut_path, v_cut = split_lines_at_joints(path, v, 0.5)
    cut = cut_path.segments
    assert list(v_cut) == [np.inf, 4.0, 2.0, np.inf, np.inf, np.inf]  # G61 joint: a stop
    seg = path.segments
    assert list(cut["kind"]) == [LINE, LINE, ARC, LINE, LINE, LINE, ARC]
    assert cut["length"][[1, 3]] == pytest.approx([2.0, 1.0])  # T_f v before / after
    assert cut["length"][[0, 1]].sum() == pytest.approx(seg["length"][0])
    assert cut["length"][[3, 4]].sum() == pytest.approx(seg["length"][2])
    assert np.array_equal(cut["end"][[1, 2, 4, 5, 6]], seg["end"])
    assert np.array_equal(cut["start"][1:], cut["end"][:-1])
    assert list(cut["exact_stop"]) == [False, False, False, False, True, True, True]
    assert list(cut["source"]) == [1, 1, 2, 4, 4, 5, 6]
    u = (cut["end"][:, :3] - cut["start"][:, :3])[[0, 1]]
    assert np.allclose(np.cross(u[0], u[1]), 0)


def test_curvature_cap_uses_the_axes_the_curvature_step_falls_on():
    """Line along +X into a tangent quarter arc in the XZ plane (R 5, centre above): the
    curvature step 1/R is on Z only, so the joint speed is sqrt(J_z T R / 2) with Z's jerk
    (X's much lower jerk limit does not enter); the arc -> end joint is a stop."""
    axes = (
        AxisLimits("x", velocity=300, acceleration=5000, jerk=1e4),
        AxisLimits("y", velocity=300, acceleration=5000, jerk=1e4),
        AxisLimits("z", velocity=300, acceleration=5000, jerk=8e4),
    )
    m = Machine("t", axes, Controller(accdec="scurve"))
    r = 5.0
    cmds = [
        canon.SetFeedRate(6000),
        canon.SelectPlane(canon.Plane.XZ),
        canon.StraightFeed(10, 0, 0),
        canon.ArcFeed(r, 10 + r, r, 10, -1, 0),  # (Z, X) order; CW about +Y: +X then up
    ]
    path = build_path(cmds, m)
    assert np.allclose(path.segments["u_start"][1][:3], [1, 0, 0])
    p = plan(path, m)
    joint = int(np.flatnonzero(p.path.segments["kind"] == ARC)[0])
    assert p.v_junction[joint] == pytest.approx(math.sqrt(8e4 * 1e-3 * r / 2))


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
@example(  # two blends eat a whole line: it must go, not stay -1e-16 long (NaN profile)
    points=[(0.0, 0.0, 2.0), (0.0, 0.0, 0.0), (0.0, 1.0, 1.0), (0.0, 0.0, 2.0)],
    machine=Machine(
        "short",
        tuple(AxisLimits(n, velocity=20.0, acceleration=200.0, jerk=2e4) for n in "xyz"),
        Controller(lookahead=1, accdec="trapezoid", corner_rule="axis"),
    ),
    tol=1.0,
    feed=300.0,
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
    from kernel.path.blend import blend_corners

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


@pytest.mark.parametrize("model", ["linuxcnc", "grbl"])
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cmds=programs(), machine=machines())
def test_controller_models_respect_every_limit_and_their_path(model, cmds, machine):
    """The controller models (kernel.plan.models) under the same properties: no axis over
    its speed or acceleration limit, the path speed never above the feed, every sample on
    the path the model plans (its blend arcs, Grbl's chords), the end point exact, stopped at
    every barrier and at the end. The linuxcnc model keeps a helix's axes within their
    limits when told to (``axis_limits = "strict"``): by default it passes them where
    LinuxCNC does (test_linuxcnc_model_passes_the_limit_on_a_steep_helix_as_linuxcnc_does)."""
    m = with_controller(machine, model=model)
    if model == "linuxcnc":
        m = with_controller(m, axis_limits="strict")
    _, p = plan_program(cmds, m)
    if not len(p.path):
        return
    s = sample(p)
    path = p.path
    for j, name in enumerate(s.axes):
        ax = m.axis(name)
        assert np.abs(s.velocity[:, j]).max() <= ax.velocity * (1 + RTOL) + ATOL
        assert np.abs(s.acceleration[:, j]).max() <= ax.acceleration * (1 + RTOL) + ATOL
    # LinuxCNC's parabolic blends (Plan.overlap): two moves at once, their motions add, off
    # the first move's path by at most what the second has gone, the speeds not bounded by
    # one feed
    blend = np.zeros(len(s), dtype=bool)
    off = np.zeros(len(s))
    if p.overlap is not None:
        for k in np.flatnonzero(p.overlap > 0):
            t_on = p.t_start[k + 1]
            inside = (s.t >= t_on - 1e-12) & (s.t < t_on + p.overlap[k])
            blend |= inside
            off[inside] = 0.5 * p.profiles.accel[k + 1] * p.overlap[k] ** 2
    moving = (s.segment >= 0) & ~blend
    speed = np.linalg.norm(s.velocity[moving], axis=1)
    feed = path.segments["feed"][s.segment[moving]]
    assert np.all(speed <= feed * (1 + RTOL) + ATOL)
    assert _on_path(path, s, ~blend) <= 1e-7
    if blend.any():
        assert _on_path(path, s, blend, off) <= 1e-7
    assert np.allclose(s.position[-1], path.end_position[:3], rtol=0, atol=1e-9)
    assert np.all(s.velocity[s.segment < 0] == 0.0)
    assert np.all(s.velocity[-1] == 0.0)
    assert np.all(p.v_junction[np.r_[False, path.segments["kind"] == HOLD]] == 0.0)
    assert p.v_junction[0] == 0.0 and p.v_junction[-1] == 0.0
