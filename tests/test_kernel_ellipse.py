"""ELLIPSE_FEED planned as chords (kernel.path.ellipse): against the analytic ellipse, its
perimeter (numeric integral and Ramanujan's approximation), NIST's helix rule 2 and the
closed-form cycle time of a constant-feed move from rest to rest."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from cli.plan import command
from kernel.diagnostics import Diagnostic
from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import AxisLimits, Controller, Machine, with_controller
from kernel.path.build import build_path
from kernel.path.segments import LINE
from kernel.plan.planner import plan

TOL = 0.001
MILL = Machine(
    "t",
    tuple(AxisLimits(n, velocity=200.0, acceleration=1000.0, jerk=50000.0) for n in "xyz"),
    Controller(chord_tolerance=TOL),
)


def _perimeter(a: float, b: float, sweep: float = 2 * math.pi) -> float:
    """Arc length of ``(a cos t, b sin t)`` over ``t`` in [0, sweep] (numeric integral)."""
    return quad(lambda t: math.hypot(a * math.sin(t), b * math.cos(t)), 0.0, sweep, limit=200)[0]


def ramanujan(a: float, b: float) -> float:
    """Ramanujan's second approximation of the perimeter."""
    h = ((a - b) / (a + b)) ** 2
    return math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))


def _distance_to_ellipse(p: np.ndarray, centre, a: float, b: float, phi: float) -> np.ndarray:
    """Exact distance of points (n x 2) from the ellipse: Newton on the foot parameter."""
    c, s = math.cos(phi), math.sin(phi)
    dx, dy = p[:, 0] - centre[0], p[:, 1] - centre[1]
    x, y = c * dx + s * dy, -s * dx + c * dy
    t = np.arctan2(y / b, x / a)
    for _ in range(30):
        g = (b * b - a * a) * np.sin(t) * np.cos(t) + a * x * np.sin(t) - b * y * np.cos(t)
        dg = (b * b - a * a) * np.cos(2 * t) + a * x * np.cos(t) + b * y * np.sin(t)
        t = t - g / dg
    return np.hypot(a * np.cos(t) - x, b * np.sin(t) - y)


def _ellipse_program(a, b, phi_deg, centre, rotation=1, z_end=0.0, feed=600.0):
    """Start on the ellipse at eccentric anomaly 0, a full turn (or more) back to it."""
    phi = math.radians(phi_deg)
    x0 = centre[0] + a * math.cos(phi)
    y0 = centre[1] + a * math.sin(phi)
    return [
        canon.SetFeedRate(feed),
        canon.StraightFeed(x0, y0, 0.0),
        canon.EllipseFeed(2 * a, 2 * b, phi_deg, x0, y0, *centre, rotation, z_end),
    ], (x0, y0)


def test_full_ellipse_samples_stay_within_the_chord_tolerance_and_end_exactly():
    a, b, phi, centre = 20.0, 8.0, 30.0, (5.0, -3.0)
    cmds, (x0, y0) = _ellipse_program(a, b, phi, centre)
    path = build_path(cmds, MILL)
    seg = path.segments
    ell = seg["source"] == 2
    assert np.all(seg["kind"][ell] == LINE) and ell.sum() > 100
    assert np.all(seg["source"][1:] == 2)  # every chord maps back to the ELLIPSE_FEED
    s = sample(plan(path, MILL))
    on = s.segment >= 1
    dist = _distance_to_ellipse(s.position[on, :2], centre, a, b, math.radians(phi))
    assert dist.max() <= TOL * (1 + 1e-9)
    assert dist.max() > 0.5 * TOL  # the chords do use the tolerance
    assert np.array_equal(s.position[-1], [x0, y0, 0.0])
    assert np.array_equal(seg["end"][-1][:3], [x0, y0, 0.0])


@pytest.mark.parametrize(("a", "b"), [(20.0, 8.0), (5.0, 5.0), (3.0, 30.0)])
def test_chord_path_length_matches_the_perimeter(a, b):
    cmds, _ = _ellipse_program(a, b, 15.0, (0.0, 0.0))
    seg = build_path(cmds, MILL).segments
    chords = seg["length"][seg["source"] == 2]
    exact = _perimeter(a, b)
    assert ramanujan(a, b) == pytest.approx(exact, rel=2e-5)  # 1.2e-5 off at b/a = 0.1
    # a chord c of sagitta E <= TOL is shorter than its arc by about 8 E^2 / (3 c)
    shortfall = exact - float(chords.sum())
    assert 0.0 < shortfall <= 1.05 * 8 / 3 * TOL**2 * float(np.sum(1 / chords))
    assert shortfall <= TOL / (3 * min(a, b)) * exact  # = E / 3R relative on a circle


def test_multi_turn_ellipse_runs_the_perimeter_twice():
    cmds, _ = _ellipse_program(12.0, 6.0, 0.0, (0.0, 0.0), rotation=-2)
    seg = build_path(cmds, MILL).segments
    length = float(seg["length"][seg["source"] == 2].sum())
    assert length == pytest.approx(2 * _perimeter(12.0, 6.0), rel=TOL / (3 * 6.0))


def test_cycle_time_is_the_perimeter_at_the_feed_plus_acc_dec():
    """From rest to rest along +Y at both ends (one axis: path acceleration A), the chord
    corners never binding at F 10 mm/s: T = L/F + F/A (eqs. 4.51-4.53)."""
    a, b, feed = 20.0, 10.0, 10.0
    cmds = [
        canon.SetFeedRate(feed * 60),
        canon.StraightFeed(a, 0, 0),
        canon.Dwell(0.5),  # a barrier: the ellipse starts from rest
        canon.EllipseFeed(2 * a, 2 * b, 0.0, a, 0.0, 0.0, 0.0, 1, 0.0),
    ]
    path = build_path(cmds, MILL)
    p = plan(path, MILL)
    ell = path.segments["source"] == 3
    t_ell = float(p.duration[ell].sum())
    length = float(path.segments["length"][ell].sum())
    assert length == pytest.approx(_perimeter(a, b), rel=TOL / (3 * b))
    # path acceleration of the first and last chord: A / max |u_i| (one axis nearly)
    u = path.segments["u_start"][ell][[0, -1], :3]
    a_start, a_end = 1000.0 / np.abs(u).max(axis=1)
    assert t_ell == pytest.approx(length / feed + feed / (2 * a_start) + feed / (2 * a_end))
    assert t_ell == pytest.approx(_perimeter(a, b) / feed + feed / 1000.0, rel=TOL / (3 * b))
    s = sample(p)
    assert s.t[-1] == pytest.approx(p.total_time, abs=s.period)
    speed = np.linalg.norm(s.velocity[np.isin(s.segment, np.flatnonzero(ell))], axis=1)
    assert speed.max() <= feed * (1 + 1e-9)


def test_s_curve_cycle_time_adds_the_smoothing_time():
    """With S-curve acc/dec the moving average of T_f = 2A/J delays the end by T_f: the
    trapezoid's time plus T_f (kernel.plan.planner)."""
    a, b, feed = 20.0, 10.0, 10.0
    # the machine starts at home (0, 0): a full ellipse through it, centre (0, b)
    cmds = [
        canon.SetFeedRate(feed * 60),
        canon.EllipseFeed(2 * a, 2 * b, 0.0, 0.0, 0.0, 0.0, b, 1, 0.0),
    ]
    m = with_controller(MILL, accdec="scurve")
    trap_time = plan(build_path(cmds, MILL), MILL).total_time
    s_time = plan(build_path(cmds, m), m).total_time
    tf = 2 * 1000.0 / 50000.0
    assert s_time == pytest.approx(trap_time + tf, rel=1e-9)


def test_helix_axis_follows_the_swept_polar_angle():
    """NIST rule 2: the axial travel is proportional to the polar angle swept about the
    centre, so at half the swept angle half the travel is done (not half the length)."""
    a, b, h = 30.0, 6.0, 12.0
    cmds = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(a, 0.0, 0.0),
        canon.EllipseFeed(2 * a, 2 * b, 0.0, -a, 0.0, 0.0, 0.0, 1, h),  # half an ellipse
    ]
    seg = build_path(cmds, MILL).segments
    pts = np.vstack([seg["start"][1:2, :3], seg["end"][1:, :3]])
    polar = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
    assert polar[-1] - polar[0] == pytest.approx(math.pi)
    assert pts[:, 2] == pytest.approx(h * (polar - polar[0]) / math.pi, abs=1e-9)
    assert pts[-1] == pytest.approx([-a, 0.0, h], abs=0)
    # the length fraction at the quarter angle (x = 0, y = b) is not a half: rule 2 only
    quarter = np.argmin(np.abs(pts[:, 0]))
    assert pts[quarter, 2] == pytest.approx(h / 2, abs=h * 1e-3)
    # feed along the 3-D path: the chords' length is the helix length
    planar = _perimeter(a, b, math.pi)
    assert seg["length"][1:].sum() > planar + 1.0


def test_xz_plane_ellipse_puts_z_first_and_moves_y_along_the_axis():
    """XZ plane: first axis Z, second X, helix axis Y, counter-clockwise from +Z to +X."""
    a, b = 10.0, 4.0
    cmds = [
        canon.SelectPlane(canon.Plane.XZ),
        canon.SetFeedRate(600.0),
        canon.StraightFeed(0.0, 0.0, a),
        canon.EllipseFeed(2 * a, 2 * b, 0.0, 0.0, b, 0.0, 0.0, 1, 3.0),  # to z 0, x b
    ]
    seg = build_path(cmds, MILL).segments
    ell = seg[seg["source"] == 3]
    assert ell["end"][-1][:3] == pytest.approx([b, 3.0, 0.0], abs=0)
    x, z = ell["end"][:, 0], ell["end"][:, 2]
    assert np.all(x >= -1e-12) and np.all(z >= -1e-12)  # the quarter in +X, +Z
    assert np.abs((z / a) ** 2 + (x / b) ** 2 - 1).max() < 1e-3


def test_inch_units_and_origin_offsets_apply_to_the_ellipse():
    cmds = [
        canon.UseLengthUnits(canon.Units.INCHES),
        canon.SetOriginOffsets(1.0, 0.0, 0.0),
        canon.SetFeedRate(60.0),
        canon.StraightFeed(1.0, 0.0, 0.0),
        canon.EllipseFeed(2.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1, 0.0),
    ]
    seg = build_path(cmds, MILL).segments
    ell = seg["source"] == 4
    assert seg["end"][-1][:3] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    assert seg["feed"][ell] == pytest.approx(25.4)
    assert seg["length"][ell].sum() == pytest.approx(_perimeter(25.4, 12.7) / 2, rel=TOL / 30)


def test_equal_axes_give_the_circle_of_arc_feed_whatever_the_angle():
    r = 10.0
    for angle in (0.0, 77.0):
        cmds = [canon.SetFeedRate(600), canon.StraightFeed(r, 0, 0)]
        cmds.append(canon.EllipseFeed(2 * r, 2 * r, angle, r, 0, 0, 0, 1, 0))
        seg = build_path(cmds, MILL).segments
        ends = seg["end"][1:, :2]
        assert np.hypot(ends[:, 0], ends[:, 1]) == pytest.approx(r, abs=1e-12)
        length = float(seg["length"][1:].sum())
        assert length == pytest.approx(2 * math.pi * r, rel=TOL / (3 * r))
        # sagitta rule of the circle: steps 2 acos(1 - E/R)
        assert len(ends) == math.ceil(2 * math.pi / (2 * math.acos(1 - TOL / r)))


@pytest.mark.parametrize(
    ("ellipse", "message"),
    [
        (canon.EllipseFeed(20, 10, 0, 0, 5, 0, 0, 1, 0), "current point"),  # start off it
        (canon.EllipseFeed(20, 10, 0, 0, 6, 10, 0, 1, 0), "end point"),
        (canon.EllipseFeed(0, 10, 0, 10, 0, 10, 0, 1, 0), "zero or negative axis"),
        (canon.EllipseFeed(20, 10, 0, 20, 0, 10, 0, 0, 0), "rotation 0"),
    ],
)
def test_bad_ellipses_are_plan_ellipse_diagnostics(ellipse, message):
    cmds = [canon.SetFeedRate(600.0), canon.StraightFeed(20.0, 0.0, 0.0), ellipse]
    with pytest.raises(Diagnostic) as e:
        build_path(cmds, MILL)
    assert e.value.code == "PLAN-ELLIPSE" and message in e.value.message


def test_cnc_plan_reads_a_canon_file_with_an_ellipse(tmp_path):
    a, b, feed = 20.0, 10.0, 10.0
    prog = tmp_path / "ellipse.canon"
    cmds = [
        canon.SetFeedRate(feed * 60),
        canon.StraightFeed(a, 0.0, 0.0),
        canon.Dwell(1.0),
        canon.EllipseFeed(2 * a, 2 * b, 0.0, a, 0.0, 0.0, 0.0, 1, 0.0),
        canon.ProgramEnd(),
    ]
    prog.write_text("\n".join(c.to_text() for c in cmds) + "\n")
    r = CliRunner().invoke(command, [str(prog), "--format", "json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    # default mill: the line (20 mm from home, at one axis' 2000 mm/s^2), then the ellipse
    # from rest to rest along +Y at 2000 mm/s^2
    expected = (a + _perimeter(a, b)) / feed + 2 * feed / 2000.0
    assert data["cycle"]["cutting"] == pytest.approx(expected, rel=TOL / (3 * b))
    r = CliRunner().invoke(command, [str(prog)])
    assert r.exit_code == 0 and "cutting" in r.output


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.5, 40),
    st.floats(0.5, 40),
    st.floats(-180, 180),
    st.floats(-math.pi, math.pi),
    st.floats(-math.pi, math.pi),
    st.sampled_from([1, -1, 2, -2]),
    st.floats(-10, 10),
    st.sampled_from([0.001, 0.01]),
)
def test_random_elliptical_helices_stay_within_the_tolerance(a, b, angle, t0, t1, rot, h, tol):
    """Any ellipse, arc of it and helix: chord vertices on the ellipse, the curve between
    them within the tolerance of the chords (checked at 50 points per chord), the end point
    exact, and the axial position proportional to the swept polar angle."""
    machine = with_controller(MILL, chord_tolerance=tol)
    phi = math.radians(angle)
    rot_m = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    p0 = rot_m @ [a * math.cos(t0), b * math.sin(t0)]
    p1 = rot_m @ [a * math.cos(t1), b * math.sin(t1)]
    gap = float(np.hypot(*(p1 - p0)))
    assume(gap == 0.0 or gap > 1e-6)  # not a sub-micrometre arc (dropped as too short)
    cmds = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(float(p0[0]), float(p0[1]), 0.0),
        canon.EllipseFeed(2 * a, 2 * b, angle, float(p1[0]), float(p1[1]), 0.0, 0.0, rot, h),
    ]
    seg = build_path(cmds, machine).segments
    ell = seg[seg["source"] == 2]
    assert ell["end"][-1][:3] == pytest.approx([p1[0], p1[1], h], abs=0)
    verts = np.vstack([ell["start"][:1, :3], ell["end"][:, :3]])
    assert _distance_to_ellipse(verts[:, :2], (0, 0), a, b, phi).max() < 1e-9 * max(a, b, 1)
    # the analytic curve between consecutive vertices: eccentric anomaly interpolated
    local = verts[:, :2] @ rot_m  # rows: R^T p
    t = np.unwrap(np.arctan2(local[:, 1] / b, local[:, 0] / a))
    assert np.all(np.sign(rot) * np.diff(t) > 0)
    assert abs(t[-1] - t[0]) <= 2 * math.pi * abs(rot) + 1e-9
    lam = np.linspace(0, 1, 50)[1:-1]
    tt = t[:-1, None] + np.diff(t)[:, None] * lam
    curve = np.stack([a * np.cos(tt), b * np.sin(tt)], axis=-1) @ rot_m.T
    chord_a, chord_b = verts[:-1, None, :2], verts[1:, None, :2]
    d = chord_b - chord_a
    u = np.clip(np.sum((curve - chord_a) * d, -1) / np.sum(d * d, -1), 0, 1)
    assert np.linalg.norm(curve - (chord_a + u[..., None] * d), axis=-1).max() <= tol
    polar = np.unwrap(np.arctan2(verts[:, 1], verts[:, 0]))
    assert verts[:, 2] == pytest.approx(h * (polar - polar[0]) / (polar[-1] - polar[0]), abs=1e-9)


def test_rotary_axes_move_linearly_along_the_chords():
    m = Machine(
        "4ax",
        (*MILL.axes, AxisLimits("a", velocity=3600.0, acceleration=36000.0, jerk=1e6)),
        MILL.controller,
    )
    cmds = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10.0, 0.0, 0.0),
        canon.EllipseFeed(20.0, 8.0, 0.0, 10.0, 0.0, 0.0, 0.0, 1, 0.0, 90.0),
    ]
    seg = build_path(cmds, m).segments[1:]
    s = np.cumsum(seg["length"])
    assert seg["end"][:, 3] == pytest.approx(90.0 * s / s[-1], abs=1e-9)
    assert seg["end"][-1][3] == 90.0
