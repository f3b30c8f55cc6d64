"""Gain tuning (book §5.4.2): Table 5.1, relay auto-tuning equations, ultimate point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel.axes.servo import simulate_axis
from kernel.axes.servo_model import closed_loop, drive
from kernel.axes.servo_params import BOOK_PLANT, ServoParams
from kernel.axes.tuning import (
    Gains,
    propose,
    relay_amplitude_gain,
    relay_experiment,
    relay_process,
    relay_ultimate,
    ultimate_point,
    ziegler_nichols_step,
    ziegler_nichols_ultimate,
)
from kernel.diagnostics import Diagnostic


def _t(g: Gains) -> tuple[float, float, float]:
    return (g.kp, g.ti, g.td)


BOOK = ServoParams(
    plant="transfer", numerator=BOOK_PLANT["numerator"], denominator=BOOK_PLANT["denominator"]
)


def test_table_5_1_ultimate_sensitivity_tc_34():
    assert ziegler_nichols_ultimate(10, 0.1, "p") == Gains(5.0)
    assert _t(ziegler_nichols_ultimate(10, 0.1, "pi")) == pytest.approx(_t(Gains(4.5, 0.08)))
    assert _t(ziegler_nichols_ultimate(10, 0.1, "pid")) == pytest.approx(
        _t(Gains(6.0, 0.05, 0.0125))
    )


def test_table_5_1_step_response_tc_34():
    assert ziegler_nichols_step(2, 0.5, "p") == Gains(4.0)
    assert _t(ziegler_nichols_step(2, 0.5, "pi")) == pytest.approx(_t(Gains(3.6, 1.65)))
    assert _t(ziegler_nichols_step(2, 0.5, "pid")) == pytest.approx(_t(Gains(4.8, 1.0, 0.25)))


def test_gains_in_parallel_form_eq_5_4():
    assert Gains(6.0, 0.05, 0.0125).parallel() == pytest.approx((6.0, 120.0, 0.075))


def test_relay_chain_round_trip_tc_35():
    assert relay_ultimate(0.01, 0.5) == pytest.approx((78.5398, 0.04), rel=1e-5)
    k_r = 7.091336 - 1.0
    assert relay_amplitude_gain(1.0, 0.209025) == pytest.approx(k_r, rel=1e-5)
    tau, tp = relay_process(143.2032, k_r, kc=10.0, ti=0.05, td=0.0)
    assert (tau, tp) == pytest.approx((0.01, 0.5), rel=1e-5)


@pytest.mark.parametrize("base", [ServoParams(), BOOK], ids=["drive", "book"])
def test_ultimate_point_is_where_the_p_loop_starts_to_oscillate(base):
    ku, tu = ultimate_point(base)

    def radius(kp: float) -> float:
        q = ServoParams(**{**{f: getattr(base, f) for f in base.__slots__}, "kp": kp})
        ev = np.linalg.eigvals(closed_loop(q, drive(q), 0.0).a)
        return float(np.abs(ev[np.abs(ev - 1) > 1e-7]).max())

    assert radius(0.999 * ku) < 1.0 < radius(1.001 * ku)
    assert tu >= 2 * base.period
    # a step under P control at K_u neither grows nor decays much over 10 periods T_u
    q = ServoParams(**{**{f: getattr(base, f) for f in base.__slots__}, "kp": ku})
    e = simulate_axis(q, np.r_[0.0, np.ones(int(12 * tu / base.period))]).following_error
    n = int(tu / base.period)
    early, late = np.abs(e[n : 2 * n]).max(), np.abs(e[-n:]).max()
    assert 0.8 < late / early < 1.25


@pytest.mark.parametrize("kind", ["p", "pid"])
@pytest.mark.parametrize("base", [ServoParams(), BOOK], ids=["drive", "book"])
def test_proposed_p_and_pid_gains_are_stable(base, kind):
    prop = propose(base, kind)
    assert prop.stable
    assert prop.params.controller == kind


def test_ultimate_method_refuses_a_loop_that_never_oscillates():
    """A continuous first-order loop is stable for every gain, but the ZOH delay makes any
    sampled loop oscillate eventually; so does this one, below the search limit."""
    with pytest.raises(Diagnostic) as err:
        ultimate_point(ServoParams(), kp_max=100.0)
    assert err.value.code == "SERVO-TUNE"
    assert math.isfinite(ultimate_point(ServoParams())[0])


def integrator_with_delay(delay: int, tp: float) -> ServoParams:
    """The relay method's process model e^{-tau s}/(T_p s), sampled at 1 ms."""
    return ServoParams(
        plant="transfer", numerator=(0.0,) * delay + (0.001 / tp,), denominator=(1.0, -1.0)
    )


@pytest.mark.parametrize("delay", [10, 20])
def test_relay_experiment_recovers_dead_time_and_time_constant(delay):
    """Describing-function estimates: within 10 % (dead time, including the ZOH's half
    period) and 25 % (T_p), and K_u within 20 % of the model's exact ultimate gain."""
    p = integrator_with_delay(delay, 0.5)
    res = relay_experiment(p, d=1.0, kc=10.0, ti=0.05)
    assert res.tau == pytest.approx((delay + 0.5) * 0.001, rel=0.10)
    assert res.tp == pytest.approx(0.5, rel=0.25)
    ku, tu = ultimate_point(p)
    assert res.ku == pytest.approx(ku, rel=0.20)
    assert res.tu == pytest.approx(tu, rel=0.10)


def test_transfer_plant_keeps_its_input_delay():
    p = integrator_with_delay(10, 0.5)
    y = simulate_axis(
        ServoParams(**{**{f: getattr(p, f) for f in p.__slots__}, "kp": 1.0}),
        np.r_[0.0, np.ones(40)],
    ).position
    assert np.all(y[:11] == 0.0) and y[12] > 0.0
