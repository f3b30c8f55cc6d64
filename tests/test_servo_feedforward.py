"""Feedforward (book §5.4.3, §5.5.2): speed, torque, FIR and ZPETC."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from kernel.axes.feedforward import apply_fir, apply_zpetc, fir_coefficients, zpetc
from kernel.axes.servo import AxisServo, simulate_axis
from kernel.axes.servo_params import BOOK_PLANT, ServoParams

T = 0.001
V_BOOK = 10_000.0 / 60.0  # 10 m/min, book §5.5.3


def ramp(v: float, n: int = 3000, rest: int = 50) -> np.ndarray:
    return np.maximum(0, np.arange(n) - rest) * v * T


def test_ideal_speed_feedforward_drives_the_following_error_to_zero():
    p = ServoParams(kp=30.0, feedforward="speed", balance=False)
    e = simulate_axis(p, ramp(100.0)).following_error
    assert abs(e[-1]) < 1e-6
    assert abs(simulate_axis(ServoParams(kp=30.0), ramp(100.0)).following_error[-1]) > 3.3


def test_balanced_speed_feedforward_leaves_feed_times_speed_loop_time_constant_eq_5_39():
    """T_en = 4 ms: the digital P speed loop at sub-period h has T_en = 1/K_pn - h/2
    [derived], so K_pn = 1/(T_en + h/2). Book: e = V_t T_en = 0.6667 mm at 10 m/min."""
    h = T / 4
    p = ServoParams(kp=30.0, feedforward="speed", speed_gain=1.0 / (0.004 + h / 2), substeps=4)
    servo = AxisServo(p)
    assert servo.balance_time == pytest.approx(0.004, rel=1e-6)
    res = servo.step(ramp(V_BOOK))
    assert res.following_error[-1] == pytest.approx(0.6667, rel=0.01)
    # balanced: the position controller has nothing left to correct
    fb = res.velocity_command - np.diff(ramp(V_BOOK), append=ramp(V_BOOK)[-1]) / T
    assert abs(fb[-2]) < 1e-6 * V_BOOK


@pytest.mark.parametrize("substeps", [1, 4, 16])
def test_equivalent_time_constant_of_the_digital_speed_loop(substeps):
    p = ServoParams(feedforward="speed", speed_gain=250.0, substeps=substeps)
    h = T / substeps
    assert AxisServo(p).balance_time == pytest.approx(1 / 250.0 - h / 2, rel=1e-6)


def test_torque_feedforward_follows_closer_than_speed_feedforward():
    """Book §5.4.3.5 / §5.5.3: commanding the current loop gives the smallest error."""
    common = {"kp": 30.0, "speed_gain": 250.0, "current_time_constant": 0.0004}
    e_speed = simulate_axis(ServoParams(feedforward="speed", **common), ramp(V_BOOK))
    e_torque = simulate_axis(ServoParams(feedforward="torque", **common), ramp(V_BOOK))
    assert abs(e_torque.following_error[-1]) < 0.5 * abs(e_speed.following_error[-1])


@pytest.mark.parametrize("tei", [0.0, 0.0004, 0.002])
def test_balanced_torque_feedforward_leaves_feed_times_current_lag_plus_half_period_eq_5_40(tei):
    """e = V_t (T_ei + T/2). The digital drive's sub-steps shorten the current-loop part by
    about half a sub-period [derived]; at 16 sub-steps that is 31 us."""
    p = ServoParams(kp=30.0, feedforward="torque", current_time_constant=tei, substeps=16)
    res = simulate_axis(p, ramp(V_BOOK, n=4000))
    expected = V_BOOK * (tei + T / 2)
    assert res.following_error[-1] == pytest.approx(expected, rel=0.04)
    h = T / 16
    assert res.following_error[-1] == pytest.approx(
        V_BOOK * (tei + T / 2 - (h / 2 if tei else 0.0)), rel=0.005
    )


def test_fir_feedforward_coefficients_eq_5_29_tc_36():
    a0, a1, a2 = fir_coefficients(0.01, 0.0, T)
    assert a0 + a1 + a2 == pytest.approx(1.0)
    a0, a1, a2 = fir_coefficients(0.01, 2e-5, T)
    assert (a0, a1, a2) == pytest.approx((20.0, -10.0 - 40.0, 1 + 10.0 + 20.0))
    assert a0 + a1 + a2 == pytest.approx(1.0)


def test_fir_on_a_ramp_adds_v2_times_speed_and_the_noncausal_form_is_two_samples_ahead():
    r = np.arange(200) * 100.0 * T  # 100 mm/s
    causal = apply_fir(r, 0.01, 0.0, T, causal=True)
    assert causal[10:] == pytest.approx(r[10:] + 1.0)  # 1 mm of lead
    noncausal = apply_fir(r, 0.01, 0.0, T, causal=False)
    assert noncausal[:-2] == pytest.approx(causal[2:])  # eq. 5.30 = z^2 eq. 5.29


def test_zpetc_overall_response_is_zero_phase_tc_37():
    """B^u = 1 + 2 z^-1 gives G_zpetc = (5 + 4 cos w)/9: impulse response [2, 5, 2]/9."""
    a = np.poly([0.5, 0.3])
    b = np.convolve([1.0, 2.0], [1.0, -0.5])
    num = np.r_[0.0, b * a.sum() / b.sum()]
    z = zpetc(num, a)
    assert z.b_unstable == pytest.approx([1.0, 2.0]) and z.delay == 1
    imp = np.zeros(64)
    imp[32] = 1.0
    out = lfilter(num, a, apply_zpetc(z, imp))
    assert out[31:34] == pytest.approx([2 / 9, 5 / 9, 2 / 9], abs=1e-12)
    assert np.abs(np.delete(out, [31, 32, 33])).max() < 1e-12


def test_zpetc_on_the_book_plant_tracks_a_ramp_without_error():
    """The book's closed loop has a zero at -2.316 (non-minimum phase, research §4.2)."""
    book = {
        "plant": "transfer",
        "numerator": BOOK_PLANT["numerator"],
        "denominator": BOOK_PLANT["denominator"],
        "kp": 2.0,
    }
    r = np.arange(1, 400) * 0.02
    plain = simulate_axis(ServoParams(**book), r).following_error
    zp = simulate_axis(ServoParams(prefilter="zpetc", **book), r).following_error
    assert plain[300] == pytest.approx(0.1278, abs=1e-4)
    assert abs(zp[300]) < 1e-9


def test_fir_prefilter_with_v2_one_over_kp_cancels_the_p_loop_lag():
    p = ServoParams(kp=30.0, prefilter="fir_causal", fir_v2=1 / 30.0)
    e = simulate_axis(p, ramp(100.0)).following_error
    assert abs(e[-100]) < 1e-6
