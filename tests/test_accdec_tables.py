"""ADCAI filters against the book's tables (ch. 4.2, 6.2) and research/seed-book-motion.md."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kernel.axes import accdec
from kernel.diagnostics import Diagnostic
from kernel.interp.samples import Samples
from kernel.machine import DEFAULT_MACHINE, Machine
from tests.test_kernel_interp_tables import B2 as TABLE_3_9_B2

T = 0.008  # the book's interpolation period


def _zeros_trimmed(y: np.ndarray) -> list[float]:
    return np.round(y, 9).tolist()


def test_linear_filter_reproduces_table_4_1():
    """n = 5, T = 8 ms (tau = 40 ms, eq. 4.11), 10 pulses for k = 1..8."""
    x = np.r_[np.full(8, 10.0), np.zeros(5)]
    y = accdec.run(accdec.linear_filter(0.040, T), x)
    assert y.tolist() == [2, 4, 6, 8, 10, 10, 10, 10, 8, 6, 4, 2, 0]
    assert np.cumsum(x).tolist()[-1] == y.sum() == 80


def test_linear_filter_table_4_2_short_block_sums_to_40_not_the_printed_48():
    y = accdec.filter_blocks(accdec.linear_filter(0.040, T), [np.full(4, 10.0)], exact_stop=True)
    assert y.tolist() == [2, 4, 6, 8, 8, 6, 4, 2, 0]
    assert y.max() == 8  # a short block never reaches the commanded 10
    assert y.sum() == 40


def test_weighted_circuit_with_unit_weights_is_the_linear_filter_table_4_3():
    x = np.full(8, 10.0)
    assert accdec.filter_pulses(accdec.weighted_fir([1] * 5), x).tolist() == [
        2,
        4,
        6,
        8,
        10,
        10,
        10,
        10,
        8,
        6,
        4,
        2,
    ]


def test_s_shape_circuit_reproduces_table_4_4():
    """K = (0.5, 1, 2, 1, 0.5), divider 5 (eqs. 4.12-4.14)."""
    y = accdec.filter_pulses(accdec.weighted_fir([0.5, 1, 2, 1, 0.5]), np.full(8, 10.0))
    assert _zeros_trimmed(y) == [1, 3, 7, 9, 10, 10, 10, 10, 9, 7, 3, 1]
    assert y.sum() == pytest.approx(80)


def test_s_shape_filter_is_two_moving_averages_eq_4_6_corrected():
    """H_S = H_L H_L with m = tau/(2T) = 5 taps each (TC-05)."""
    y = accdec.filter_pulses(accdec.s_shape_filter(0.080, T), np.full(8, 10.0))
    expected = [0.4, 1.2, 2.4, 4.0, 6.0, 7.6, 8.8, 9.6, 9.6, 8.8, 7.6, 6.0, 4.0, 2.4, 1.2, 0.4]
    assert y == pytest.approx(expected)


def test_exponential_dda_circuit_eq_4_30():
    """n = 2 (tau = 4T, eq. 4.31), input 8 for k = 1..10 (TC-06)."""
    filt = accdec.dda_exponential_filter(2, tolerance=1e-9, amplitude=8.0)
    y = accdec.filter_pulses(filt, np.full(10, 8.0))
    assert y[:4] == pytest.approx([2, 3.5, 4.625, 5.46875])
    assert y[10] == pytest.approx(5.66211, abs=1e-5)
    assert y[11] == pytest.approx(4.2466, abs=1e-4)
    assert y.sum() == pytest.approx(80)  # the residual of the tail is emitted at the end
    assert y[-1] < 1e-6 * 8 * 10


def test_exponential_filter_step_response_is_first_order_eq_4_5():
    tau, period = 0.05, 0.001
    alpha = math.exp(-period / tau)
    y = accdec.run(accdec.exponential_filter(tau, period), np.ones(200))
    k = np.arange(1, 201)
    assert y == pytest.approx(1 - alpha**k, rel=1e-12)


def test_block_overlap_continuous_and_exact_stop_tc_08():
    filt = accdec.linear_filter(0.040, T)
    blocks = [np.full(8, 10.0), np.full(8, 5.0)]
    cont = accdec.filter_blocks(filt, blocks, exact_stop=False)
    assert cont.tolist() == [2, 4, 6, 8, 10, 10, 10, 10, 9, 8, 7, 6, 5, 5, 5, 5, 4, 3, 2, 1]
    es = accdec.filter_blocks(filt, blocks, exact_stop=True)
    assert es.tolist() == [
        2,
        4,
        6,
        8,
        10,
        10,
        10,
        10,
        8,
        6,
        4,
        2,
        0,
        1,
        2,
        3,
        4,
        5,
        5,
        5,
        5,
        4,
        3,
        2,
        1,
        0,
    ]
    assert es.sum() == cont.sum() == 120


def test_residual_pulses_method_2_spreads_and_method_1_appends_tc_40():
    assert accdec.distribute_pulses(745, 10).tolist() == [75] * 5 + [74] * 5
    assert accdec.distribute_pulses(745, 10, method=1).tolist() == [74] * 10 + [5]
    assert accdec.distribute_pulses(-745, 10).sum() == -745


def test_quantised_pulses_never_drift_more_than_half_a_pulse():
    d = np.full(1000, 0.0013)
    p = accdec.quantise_pulses(d, 0.001)
    assert abs(p.sum() * 0.001 - d.sum()) <= 0.0005
    assert np.abs(np.cumsum(p) * 0.001 - np.cumsum(d)).max() <= 0.0005 + 1e-12


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(-50, 50, allow_nan=False), min_size=1, max_size=60),
    st.sampled_from(["linear", "s_shape", "exponential"]),
    st.integers(1, 12),
)
def test_filters_keep_every_pulse_tc_07(pulses, kind, taps):
    x = np.array(pulses)
    cfg = accdec.AccDecConfig(accdec.AccDecKind(kind), tau=taps * T, exp_tail_tolerance=1e-9)
    amp = float(np.abs(x).max()) or 1.0
    y = accdec.filter_pulses(accdec.make_filter(cfg, T, amp), x)
    assert y.sum() == pytest.approx(x.sum(), abs=1e-6 * max(1.0, np.abs(x).sum()))


def test_chunked_filtering_equals_one_call():
    rng = np.random.default_rng(1)
    x = rng.normal(size=(500, 3))
    for filt in (
        accdec.linear_filter(0.05, 0.001),
        accdec.s_shape_filter(0.05, 0.001),
        accdec.exponential_filter(0.05, 0.001),
    ):
        whole = accdec.run(filt, x)
        state = accdec.FilterState()
        parts = [accdec.run(filt, x[i : i + 77], state) for i in range(0, 500, 77)]
        assert np.concatenate(parts) == pytest.approx(whole, abs=1e-12)


def _machine(table: dict | None) -> Machine:
    extra = {} if table is None else {"accdec": table}
    return Machine("m", DEFAULT_MACHINE.axes, DEFAULT_MACHINE.controller, extra)


def test_profile_chooses_filter_type_and_placement():
    assert not accdec.config_from_machine(_machine(None)).filters_after
    cfg = accdec.config_from_machine(_machine({"type": "s_shape", "tau": 0.08}))
    assert cfg.kind is accdec.AccDecKind.S_SHAPE and cfg.tau == 0.08 and cfg.filters_after
    before = accdec.config_from_machine(_machine({"type": "linear", "placement": "before"}))
    assert not before.filters_after
    both = accdec.config_from_machine(_machine({"type": "linear", "placement": "both"}))
    assert both.filters_after


@pytest.mark.parametrize(
    ("table", "code"),
    [
        ({"type": "cubic"}, "MACH-RANGE"),
        ({"tau": -1.0}, "MACH-RANGE"),
        ({"tau": "fast"}, "MACH-TYPE"),
        ({"taux": 0.1}, "MACH-KEY"),
    ],
)
def test_bad_accdec_table_is_a_diagnostic(table, code):
    with pytest.raises(Diagnostic) as err:
        accdec.config_from_machine(_machine(table))
    assert err.value.code == code


def _samples(pos: np.ndarray, period: float, seg: np.ndarray | None = None) -> Samples:
    n = pos.shape[0]
    z = np.zeros_like(pos)
    seg = np.zeros(n, dtype=np.int64) if seg is None else seg
    return Samples(period, np.arange(n) * period, pos, z, z, z, seg, seg.astype(np.int32) + 1)


def test_fine_interpolation_linear_method_eq_3_72():
    """p = 8 pulses per 4 ms rough period becomes 2 per 1 ms fine period."""
    pos = np.cumsum(np.r_[0.0, np.full(5, 8.0)])[:, None]
    fine = accdec.fine_interpolate(_samples(pos, 0.004), 4)
    assert fine.period == pytest.approx(0.001)
    assert np.diff(fine.position[:, 0]).tolist() == [2.0] * 20
    assert fine.position[-1, 0] == 40.0


def test_apply_to_samples_keeps_the_end_point_and_stops_between_blocks():
    pos = np.r_[np.linspace(0, 10, 101), np.full(50, 10.0)][:, None]
    seg = np.r_[np.zeros(101, dtype=np.int64), np.ones(50, dtype=np.int64)]
    s = _samples(pos, 0.001, seg)
    out = accdec.apply(
        s,
        accdec.AccDecConfig(accdec.AccDecKind.LINEAR, 0.02, accdec.AccDecPlacement.AFTER),
        exact_stop=True,
    )
    assert out.position[-1, 0] == pytest.approx(10.0)
    assert len(out) == len(s) + 2 * (20 - 1 + 1)
    assert np.all(np.diff(out.position[:, 0]) >= -1e-12)


def test_exact_stop_only_after_flagged_path_rows():
    """G61 on the first block only: it is filtered alone and emptied, the next two overlap."""
    steps = np.r_[np.full(8, 10.0), np.full(8, 5.0), np.full(8, 10.0)]
    pos = np.cumsum(np.r_[0.0, steps])[:, None]
    seg = np.r_[0, np.repeat(np.arange(3), 8)].astype(np.int64)
    s = _samples(pos, T, seg)
    cfg = accdec.AccDecConfig(accdec.AccDecKind.LINEAR, 0.040, accdec.AccDecPlacement.AFTER)
    out = accdec.apply(s, cfg, np.array([True, False, False]))
    v = np.diff(out.position[:, 0]).round(9).tolist()
    first = [2, 4, 6, 8, 10, 10, 10, 10, 8, 6, 4, 2, 0]  # ends with the empty period
    assert v[: len(first)] == first
    rest = accdec.filter_pulses(accdec.linear_filter(0.040, T), steps[8:]).tolist()
    assert v[len(first) :] == [*rest, 0.0]  # the last block also ends emptied
    assert out.position[-1, 0] == pos[-1, 0]
    assert len(accdec.apply(s, cfg, np.array([False, False, False]))) == len(s) + 4


def test_moving_average_fine_interpolation_table_3_9():
    """Rough pulses 8, 16, 24, 24, 16, 8 per 4 ms, N = 4: b'' of table 3.9."""
    pos = np.cumsum(np.r_[0.0, 0.0, 8, 16, 24, 24, 16, 8, 0.0])[:, None]
    fine = accdec.fine_interpolate(_samples(pos, 0.004), 4, "moving_average")
    inc = np.diff(fine.position[:, 0])
    expected = TABLE_3_9_B2  # the book's b'' column, shared with the kernel's test
    # the output starts N/2 fine periods early: skip those two leading zeros
    assert inc[2 : 2 + 32] == pytest.approx(expected)
    assert fine.position[-1, 0] == pos[-1, 0]
