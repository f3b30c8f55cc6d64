"""Look-ahead planning against the book's worked examples (ch. 4.3-4.4) and closed forms.

Numbers: research/seed-book-motion.md §2-§3 and test cases TC-11..TC-30 (A = 1000 mm/s^2,
D = 500 mm/s^2 in the block-pair cases, so A/D mix-ups fail).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import AxisLimits, Controller, Machine
from kernel.path.build import build_path, lines_table
from kernel.plan.planner import (
    angle_corner_speed,
    arc_feed_limit,
    arc_speed_caps,
    axis_corner_speed,
    axis_corner_speeds,
    centripetal_speed,
    chord_error_speed,
    junction_caps,
    lookahead,
    plan,
    range_min,
    segment_limits,
    short_block_peak,
    trapezoids,
)

A, D = 1000.0, 500.0


def pair(l1: float, l2: float, f1: float, f2: float):
    """Two collinear blocks from rest to rest: junction speeds and profiles."""
    length = np.array([l1, l2])
    cap = np.array([f1, f2])
    acc, dec = np.full(2, A), np.full(2, D)
    v = lookahead(length, np.array([0.0, min(f1, f2), 0.0]), acc, dec)
    return v, trapezoids(length, v[:-1], v[1:], cap, acc, dec)


def test_single_normal_block_phases_tc11():
    p = trapezoids(
        np.array([20.0]), np.zeros(1), np.zeros(1), np.array([100.0]), np.array([A]), np.array([D])
    )
    assert (p.t_acc[0], p.t_cruise[0], p.t_dec[0]) == pytest.approx((0.1, 0.05, 0.2))


def test_single_short_block_peak_tc12():
    p = trapezoids(
        np.array([5.0]), np.zeros(1), np.zeros(1), np.array([100.0]), np.array([A]), np.array([D])
    )
    assert p.v_peak[0] == pytest.approx(57.735, abs=1e-3)
    assert short_block_peak(5.0, A, D) == pytest.approx(57.735, abs=1e-3)
    assert (p.t_acc[0], p.t_dec[0], p.t_cruise[0]) == pytest.approx(
        (0.057735, 0.11547, 0.0), abs=1e-6
    )


def test_case_a_normal_normal_same_feed_tc14():
    v, p = pair(20, 20, 100, 100)
    assert v[1] == pytest.approx(100)
    assert (p.t_acc[0], p.t_cruise[0], p.t_dec[0]) == pytest.approx((0.1, 0.15, 0.0))
    assert (p.t_acc[1], p.t_cruise[1], p.t_dec[1]) == pytest.approx((0.0, 0.1, 0.2))


def test_case_b_high_then_low_feed_tc15():
    v, p = pair(20, 20, 100, 50)
    assert v[1] == pytest.approx(50)
    assert (p.t_acc[0], p.t_dec[0], p.t_cruise[0]) == pytest.approx((0.1, 0.1, 0.075))
    assert (p.t_dec[1], p.t_cruise[1]) == pytest.approx((0.1, 0.35))


def test_case_c_low_then_high_feed_consistent_variant_tc16():
    v, p = pair(20, 20, 50, 100)
    assert v[1] == pytest.approx(50)
    assert (p.t_acc[0], p.t_cruise[0]) == pytest.approx((0.05, 0.375))
    assert (p.t_acc[1], p.t_cruise[1], p.t_dec[1]) == pytest.approx((0.05, 0.0625, 0.2))


def test_case_d_short_then_normal_tc17():
    v, p = pair(2, 20, 100, 100)
    assert v[1] == pytest.approx(63.2456, abs=1e-4)  # eq. 4.68
    assert p.t_acc[0] == pytest.approx(0.063246, abs=1e-6)
    assert (p.t_acc[1], p.t_dec[1], p.t_cruise[1]) == pytest.approx((0.036754, 0.2, 0.07), abs=1e-6)


def test_case_e_normal_then_short_tc18():
    v, p = pair(20, 2, 100, 100)
    assert v[1] == pytest.approx(44.7214, abs=1e-4)  # eq. 4.72
    assert (p.t_acc[0], p.t_dec[0], p.t_cruise[0]) == pytest.approx((0.1, 0.110557, 0.07), abs=1e-6)
    assert p.t_dec[1] == pytest.approx(0.089443, abs=1e-6)


def test_case_f_short_short_second_limits_tc19():
    v, p = pair(2, 2, 100, 100)
    assert v[1] == pytest.approx(44.7214, abs=1e-4)
    assert p.v_peak[0] == pytest.approx(51.6398, abs=1e-4)  # eq. 4.79
    assert (p.t_acc[0], p.t_dec[0], p.t_dec[1]) == pytest.approx(
        (0.05164, 0.013837, 0.089443), abs=1e-5
    )


def test_case_f_short_short_first_limits_tc20():
    v, p = pair(1, 4, 100, 100)
    assert v[1] == pytest.approx(44.7214, abs=1e-4)
    assert p.v_peak[1] == pytest.approx(57.7350, abs=1e-4)  # eq. 4.80
    assert p.t_acc[0] == pytest.approx(0.044721, abs=1e-6)
    assert (p.t_acc[1], p.t_dec[1]) == pytest.approx((0.013014, 0.11547), abs=1e-6)


def test_angle_corner_rule_eq_4_88_tc23():
    got = angle_corner_speed(np.radians([30, 45, 90, 135]), 1000.0, 0.001)
    assert got == pytest.approx([7.4641, 3.4142, 1.0, 0.5858], abs=1e-4)
    assert np.isinf(angle_corner_speed(0.0, 1000.0, 0.001))


def test_axis_corner_rule_eqs_4_89_to_4_92_tc24():
    dvm = np.full(3, 20.0)
    ex, ey = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    assert axis_corner_speeds(100, 100, ex, ey, dvm) == pytest.approx((20.0, 20.0))
    diag = np.array([10.0, 10.0, 0]) / math.hypot(10, 10)
    assert axis_corner_speeds(100, 100, ex, diag, dvm) == pytest.approx((28.284, 28.284), abs=1e-3)
    assert axis_corner_speeds(100, 100, ex, ex, dvm) == (100, 100)


def test_arc_feed_limits_eq_4_86_4_97_4_98_tc21_tc30():
    assert arc_feed_limit((1000, 1000), 10, 10) == pytest.approx(141.421, abs=1e-3)
    assert arc_feed_limit((1000, 1000), 10, 40) == pytest.approx(282.843, abs=1e-3)
    assert arc_feed_limit((1000, 1000), 10, 2.5) == pytest.approx(70.711, abs=1e-3)
    perf, err = arc_speed_caps(1000, 10, 0.001, 0.008)
    assert perf == pytest.approx(100.0)
    assert err == pytest.approx(49.998, abs=1e-3)


def test_axis_corner_speed_is_the_pair_rule_at_one_feed_vectorised():
    """The planner's corner rule (rows of tangents at once) is eqs. 4.89-4.92 at F1 = F2."""
    dvm = np.full(3, 20.0)
    ex, ey = [1.0, 0, 0], [0, 1.0, 0]
    diag = [math.sqrt(0.5), math.sqrt(0.5), 0]
    got = axis_corner_speed(np.array([ex, ex, ex]), np.array([ey, diag, ex]), dvm)
    assert got[:2] == pytest.approx([20.0, 28.284], abs=1e-3)
    assert np.isinf(got[2])
    for u2, corner in zip((ey, diag), got[:2], strict=True):
        for f in (10.0, 100.0):
            assert axis_corner_speeds(f, f, np.array(ex), np.array(u2), dvm) == pytest.approx(
                (min(f, corner), min(f, corner))
            )


def test_planner_junction_caps_use_the_axis_corner_rule():
    """Two lines at a right angle on the axis rule: the junction cap is dVm = A T."""
    m = _mill(200, 1000.0, corner_rule="axis")
    path = lines_table(np.zeros(3), np.array([[10.0, 0, 0], [10.0, 10.0, 0]]), 6000.0)
    cap, acc = segment_limits(path, m)
    jcap = junction_caps(path, m, cap, acc)
    assert jcap[1] == pytest.approx(1000.0 * 0.001)
    assert jcap[1] == axis_corner_speed(np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), 1.0)


@pytest.mark.parametrize("method", ["improved_tustin", "exact"])
@pytest.mark.parametrize("chord", [1e-4, 1e-2])
def test_arc_cap_is_eq_4_97_or_4_98_in_the_plane(method, chord):
    """A full XY circle of radius R with feed and axis speed out of the way: the planner's cap
    is the smaller of the centripetal (eq. 4.97 per axis, alpha = ratio x A) and the chord
    error speed (eq. 4.98 for improved Tustin, the sagitta bound for exact points)."""
    m = _mill(200, 1000.0, circle_method=method, chord_tolerance=chord, interpolation_period=0.01)
    cmds = [
        canon.SetFeedRate(60000.0),
        canon.StraightFeed(10.0, 0, 0),
        canon.ArcFeed(10.0, 0, 0, 0, 1, 0),
    ]
    path = build_path(cmds, m)
    cap, _ = segment_limits(path, m)
    r, e, t = 10.0, chord, 0.01
    v_perf = float(centripetal_speed(0.5 * 1000.0, r))
    assert v_perf == pytest.approx(math.sqrt(0.5 * 1000.0 * r))
    if method == "improved_tustin":
        v_chord = float(chord_error_speed(r, e, t))
        assert v_chord == pytest.approx(2 * r * math.acos((r - e) / (r + e)) / t)
    else:
        v_chord = 2 * r * math.acos(1 - e / r) / t
    assert (v_chord < v_perf) == (chord < 1e-3)  # each bound binds in one of the cases
    assert cap[-1] == pytest.approx(min(v_perf, v_chord), rel=1e-12)


def _mill(lookahead_n: int, acc: float, **ctl: object) -> Machine:
    axes = tuple(AxisLimits(n, velocity=1e3, acceleration=acc, jerk=1e7) for n in "xyz")
    return Machine("test", axes, Controller(lookahead=lookahead_n, **ctl))


def half_circle_plan(n_buffer: int):
    """Book §4.4.2: 15 blocks of pi*10/15 mm (corner angles ignored: collinear), F 400
    mm/min, A 9600 mm/min^2."""
    seg_len = math.pi * 10 / 15
    pts = np.zeros((15, 3))
    pts[:, 0] = seg_len * np.arange(1, 16)
    path = lines_table(np.zeros(3), pts, feed=400 / 60)
    return plan(path, _mill(n_buffer, 9600 / 3600))


def per_min(v):
    return np.asarray(v) * 60


def test_lookahead_none_peaks_141_78_and_stops_every_block_tc25():
    p = half_circle_plan(1)
    assert per_min(p.profiles.v_peak) == pytest.approx(np.full(15, 141.78), abs=0.5)
    assert np.all(p.v_junction == 0)
    assert p.total_time / 60 == pytest.approx(0.443, abs=0.002)


def test_lookahead_two_blocks_200_and_245_tc26():
    p = half_circle_plan(2)
    v = per_min(p.v_junction)
    assert v[1] == pytest.approx(200, abs=0.6)  # book 200, exact 200.51
    assert per_min(p.profiles.v_peak[5]) == pytest.approx(245.17, abs=0.5)
    assert np.all(v[1:-1] == pytest.approx(v[1]))
    assert p.total_time / 60 == pytest.approx(0.164, abs=0.002)


def test_lookahead_three_blocks_window_speeds_0_200_283_tc27():
    p = half_circle_plan(3)
    v = per_min(p.v_junction)
    assert v[1] == pytest.approx(200, abs=0.6)
    assert v[2] == pytest.approx(283.2, abs=0.5)  # eq. 4.96 / book's 283
    assert per_min(p.profiles.v_peak[7]) == pytest.approx(317.04, abs=0.5)
    assert p.total_time / 60 == pytest.approx(0.136, abs=0.002)


def test_lookahead_six_blocks_reaches_feed_without_fluctuation_tc28():
    p = half_circle_plan(6)
    v = per_min(p.v_junction)
    assert np.all(v[4:-4] == pytest.approx(400.0))
    assert per_min(p.profiles.v_peak.max()) == pytest.approx(400.0)
    assert p.total_time / 60 == pytest.approx(0.120, abs=0.002)
    p4 = half_circle_plan(4)
    assert per_min(p4.profiles.v_peak.max()) == pytest.approx(375.12, abs=0.5)


def test_finite_window_equals_unlimited_when_window_covers_program():
    rng = np.random.default_rng(1)
    length = rng.uniform(0.1, 3, 40)
    caps = rng.uniform(1, 50, 41)
    acc = rng.uniform(100, 1000, 40)
    assert lookahead(length, caps, acc, None, 50) == pytest.approx(lookahead(length, caps, acc))


def test_lookahead_never_needs_more_than_the_available_acceleration():
    rng = np.random.default_rng(2)
    length = rng.uniform(0.01, 2, 300)
    caps = rng.uniform(0, 80, 301)
    acc = rng.uniform(50, 2000, 300)
    for window in (1, 2, 7, None):
        v = lookahead(length, caps, acc, None, window)
        dv2 = np.diff(v**2)
        assert np.all(np.abs(dv2) <= 2 * acc * length * (1 + 1e-9) + 1e-9)
        assert np.all(v <= np.r_[0, caps[1:-1], 0] + 1e-9)


def test_range_min_matches_brute_force():
    rng = np.random.default_rng(3)
    vals = rng.normal(size=200)
    lo = rng.integers(0, 200, 500)
    hi = lo + rng.integers(-3, 40, 500)
    hi = np.minimum(hi, 199)
    want = [vals[a : b + 1].min() if b >= a else np.inf for a, b in zip(lo, hi, strict=True)]
    assert range_min(vals, lo, hi) == pytest.approx(np.array(want))


def test_single_long_line_takes_the_trapezoid_time():
    m = _mill(200, 2000.0)
    path = lines_table(np.zeros(3), np.array([[100.0, 0, 0]]), feed=50.0)
    p = plan(path, m)
    assert p.total_time == pytest.approx(100 / 50 + 50 / 2000, rel=1e-12)


def test_single_long_line_takes_the_s_curve_time():
    axes = tuple(AxisLimits(n, velocity=1e3, acceleration=2000.0, jerk=50000.0) for n in "xyz")
    m = Machine("s", axes, Controller(accdec="scurve"))
    path = lines_table(np.zeros(3), np.array([[400.0, 0, 0]]), feed=200.0)
    p = plan(path, m)
    # trapezoid smoothed over T_f = 2 A/J (a double-S profile with jerk J/2 on its
    # ramps; V/A >= T_f so the full acceleration is reached): T = L/V + V/A + T_f
    assert p.total_time == pytest.approx(2.0 + 0.1 + 0.08, rel=1e-12)
    s = sample(p)
    assert np.abs(s.jerk[:, 0]).max() == pytest.approx(25000, rel=1e-9)
    assert np.abs(s.acceleration[:, 0]).max() == pytest.approx(2000, rel=1e-9)


def test_s_curve_short_block_reversing_acceleration_stays_within_jerk():
    axes = tuple(AxisLimits(n, velocity=1e3, acceleration=2000.0, jerk=50000.0) for n in "xyz")
    m = Machine("s", axes, Controller(accdec="scurve"))
    # triangle profile: +A for 60 ms, then -A for 60 ms, longer than T_f/2 = 40 ms
    path = lines_table(np.zeros(3), np.array([[7.2, 0, 0]]), feed=200.0)
    s = sample(plan(path, m))
    assert np.abs(s.jerk[:, 0]).max() <= 50000 * (1 + 1e-9)
    assert np.abs(s.jerk[:, 0]).max() > 40000  # the reversal uses the whole budget


def test_full_circle_takes_two_pi_r_over_f_plus_acc_dec():
    m = _mill(200, 2000.0, arc_acceleration_ratio=0.5)
    cmds = [
        canon.SetFeedRate(1200.0),  # 20 mm/s
        canon.ArcFeed(0, 0, 20, 0, 1, 0),  # full CCW circle of R 20 about (20, 0)
    ]
    p = plan(build_path(cmds, m), m)
    assert len(p.duration) == 1
    a_tan = (1 - 0.5) * 2000.0  # the share left for tangential acceleration (eq. 4.97)
    assert p.total_time == pytest.approx(2 * math.pi * 20 / 20 + 20 / a_tan, rel=1e-9)
    s = sample(p)
    assert np.array_equal(s.position[-1], [0.0, 0.0, 0.0])
    r = np.hypot(s.position[:, 0] - 20, s.position[:, 1])
    assert r == pytest.approx(np.full(len(s), 20.0), abs=1e-9)


def test_g61_exact_stop_stops_at_every_corner_g64_does_not():
    m = _mill(50, 1000.0)
    base = [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10, 0, 0),
        canon.StraightFeed(20, 1, 0),
        canon.StraightFeed(30, 1, 0),
    ]
    cont = plan(build_path(base, m), m)
    es = plan(build_path([canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP), *base], m), m)
    assert np.all(es.v_junction == 0)
    assert np.all(cont.v_junction[2:-1] > 0)
    assert es.total_time > cont.total_time


def test_line_arc_line_of_fig_4_25_runs_through_the_joints_with_capped_arc_feed():
    m = _mill(50, 1000.0, corner_velocity_step=1.0)
    cmds = [
        canon.SetFeedRate(10000.0),
        canon.StraightFeed(100, 0, 0),
        canon.ArcFeed(150, -50, 100, -50, -1, 0),  # G02 X50 Y-50 R50 (incremental)
        canon.StraightFeed(150, -150, 0),
        canon.ChangeTool(6),
    ]
    p = plan(build_path(cmds, m), m)
    v = p.v_junction
    assert v[1] > 0 and v[2] > 0  # tangent joints: no stop
    assert v[3] == 0  # M06 is a barrier
    assert p.cap[1] == pytest.approx(math.sqrt(0.5 * 1000.0 * 50.0))  # eq. 4.97
    assert v[1] == pytest.approx(p.cap[1])


def test_eq_4_55_discrete_ramp_increments_tc13():
    from kernel.plan.blocks import block_iterations

    b = block_iterations(20.0, 0.0, 100.0, 0.0, 1000.0, 1000.0, 0.01)
    assert b.n_acc == 10 and b.accel == pytest.approx(1000.0)
    assert b.displacement[:10] == pytest.approx(np.arange(0.05, 1.0, 0.1))
    assert b.displacement[:10].sum() == pytest.approx(5.0)  # F^2/(2A)


def test_line_normal_block_whole_periods_and_adjusted_acceleration_tc44():
    from kernel.plan.blocks import block_iterations

    b = block_iterations(25.0, 0.0, 100.0, 0.0, 1000.0, 1000.0, 0.008)
    assert b.n_acc == 13 and b.accel == pytest.approx(961.54, abs=0.01)
    assert b.displacement.sum() == pytest.approx(25.0, abs=1e-12)  # residual spread
    assert b.n_const == 18 and b.residual == pytest.approx(25.0 - 10.4 - 18 * 0.8)


@pytest.mark.parametrize(
    ("length", "vs", "ve"), [(3.0, 0.0, 0.0), (1.0, 20.0, 5.0), (7.0, 40.0, 40.0), (0.2, 0.0, 10.0)]
)
def test_line_small_block_stays_within_acceleration_and_covers_the_block(length, vs, ve):
    from kernel.plan.blocks import block_iterations

    b = block_iterations(length, vs, 100.0, ve, 1000.0, 1000.0, 0.008)
    assert b.displacement.sum() == pytest.approx(length, abs=1e-12)
    v = np.concatenate([[vs], b.speed])
    assert np.abs(np.diff(v)).max() <= 1000.0 * 0.008 * (1 + 1e-9)
    assert b.v_max <= 100.0
