"""Position loop P/PI/PID (book §5.4.1) on the book's plant and on the drive model."""

from __future__ import annotations

import numpy as np
import pytest

from kernel.axes.servo import AxisServo, simulate_axis
from kernel.axes.servo_model import closed_loop, drive, pid_coefficients
from kernel.axes.servo_params import BOOK_PLANT, ServoParams

BOOK = {
    "plant": "transfer",
    "numerator": BOOK_PLANT["numerator"],
    "denominator": BOOK_PLANT["denominator"],
}


def _poles(p: ServoParams) -> np.ndarray:
    ev = np.linalg.eigvals(closed_loop(p, drive(p), 0.0).a)
    return ev[np.abs(ev - 1.0) > 1e-7]  # drop the velocity-form controller's summing pole


def test_pid_coefficients_eq_5_8_tc_32():
    assert pid_coefficients(2.0, 0.0001, 0.0, 0.001) == pytest.approx((2.0000001, -2.0, 0.0))
    assert pid_coefficients(2.0, 0.0001, 0.01, 0.001) == pytest.approx((12.0000001, -22.0, 10.0))


def test_book_pseudo_code_reproduced_verbatim():
    """§5.4.1 program: kp 2, ki 0.0001, the overlapping command array as written; the code
    reads the position computed one iteration earlier (feedback_delay = 1)."""
    cmd = np.zeros(301)
    for n in range(1, 201):
        cmd[n] = 10.0 - n * 0.02
        if n + 100 <= 300:
            cmd[n + 100] = 8.0 + n * 0.02
    p = ServoParams(controller="pi", kp=2.0, ki=0.0001, feedback_delay=1, **BOOK)
    y = AxisServo(p).step(cmd).position  # cmd[0] = 0: at rest at 0 like the code
    err = cmd[1:] - y[:-1]  # err(n) = command(n) - pos(n-1)
    assert err[99] == pytest.approx(-0.1278, abs=5e-5)
    assert err[299] == pytest.approx(0.1278, abs=5e-5)


@pytest.mark.parametrize(("kp", "e_ss"), [(1.0, 0.25561), (2.0, 0.12780)])
def test_p_control_ramp_error_on_book_plant_tc_33(kp, e_ss):
    """Ramp 0.02 per sample: e = 0.02/(kp * 0.0782456), the plant's velocity gain."""
    r = np.arange(600) * 0.02
    e = simulate_axis(ServoParams(kp=kp, **BOOK), r).following_error
    assert e[-1] == pytest.approx(e_ss, abs=2e-5)


@pytest.mark.parametrize(("kp", "radius"), [(1.0, 0.8956), (2.0, 0.8065)])
def test_book_plant_closed_loop_poles_tc_33(kp, radius):
    assert np.abs(_poles(ServoParams(kp=kp, **BOOK))).max() == pytest.approx(radius, abs=1e-4)


def test_book_gains_pi_are_stable_and_the_larger_p_gain_halves_the_error():
    """Book §6.2.5 tests 1 and 2 (kp 2.0 and 1.0, ki 0.0001): stable; the error scales as
    1/kp (the book's figures come from an unpublished program, TC-43)."""
    r = np.arange(2000) * 0.02
    errs = {}
    for kp in (1.0, 2.0):
        p = ServoParams(controller="pi", kp=kp, ki=0.0001, **BOOK)
        assert np.abs(_poles(p)).max() < 1.0
        e = simulate_axis(p, r).following_error
        assert np.all(np.isfinite(e))
        errs[kp] = e[-1]
    assert errs[1.0] / errs[2.0] == pytest.approx(2.0, rel=1e-3)


def test_pid_with_derivative_on_book_plant_is_stable_and_tracks_a_ramp():
    p = ServoParams(controller="pid", kp=2.0, ki=0.0001, kd=0.0005, **BOOK)
    assert np.abs(_poles(p)).max() < 1.0
    e = simulate_axis(p, np.arange(1500) * 0.02).following_error
    assert abs(e[-1]) < 0.13


@pytest.mark.parametrize("kp", [10.0, 30.0, 60.0])
@pytest.mark.parametrize("feed", [20.0, 100.0])
def test_p_loop_ramp_following_error_is_feed_over_kp_eq_5_38(kp, feed):
    t = np.arange(4000) * 0.001
    e = simulate_axis(ServoParams(kp=kp), feed * t).following_error
    assert e[-1] == pytest.approx(feed / kp, rel=1e-6)


def test_pi_position_loop_removes_the_ramp_error():
    t = np.arange(20000) * 0.001
    e = simulate_axis(ServoParams(controller="pi", kp=30.0, ki=100.0), 50.0 * t).following_error
    assert abs(e[-1]) < 1e-3 * 50.0 / 30.0


def test_axis_starts_at_rest_at_its_first_command():
    r = np.full(100, 123.4)
    res = simulate_axis(ServoParams(), r)
    assert np.all(res.position == pytest.approx(123.4, abs=1e-9))
