"""ADCAI machining errors (book §4.2.3, Table 4.5) reproduced by simulation.

A circle R = 10 mm at F = 100 mm/s is sampled in closed form at T = 1 ms, filtered per axis,
and its contour error is measured against the exact arc (kernel.axes.contour), not samples.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel.axes import accdec
from kernel.axes.contour import ContourMeter, circle_error, corner_error
from kernel.interp.samples import Samples
from kernel.path.segments import ARC, LINE, SEGMENT_DTYPE

T = 0.001
R, F, TAU = 10.0, 100.0, 0.05


def _samples(pos: np.ndarray, seg: np.ndarray, period: float = T) -> Samples:
    n = pos.shape[0]
    z = np.zeros_like(pos)
    return Samples(period, np.arange(n) * period, pos, z, z, z, seg, (seg + 1).astype(np.int32))


def circle_path(turns: int) -> np.ndarray:
    seg = np.zeros(1, SEGMENT_DTYPE)
    seg["kind"] = ARC
    seg["start"][0, :3] = seg["end"][0, :3] = (R, 0, 0)
    seg["centre"] = (0, 0, 0)
    seg["normal"], seg["e1"], seg["e2"] = (0, 0, 1), (1, 0, 0), (0, 1, 0)
    seg["radius"] = seg["radius_end"] = R
    seg["sweep"] = 2 * math.pi * turns
    seg["length"] = 2 * math.pi * R * turns
    return seg


def filtered_circle_error(kind: str) -> float:
    turns = 4
    w = F / R
    t = np.arange(int(round(turns * 2 * math.pi / w / T)) + 1) * T
    pos = np.column_stack([R * np.cos(w * t), R * np.sin(w * t), np.zeros_like(t)])
    s = _samples(pos, np.zeros(t.size, dtype=np.int64))
    cfg = accdec.AccDecConfig(accdec.AccDecKind(kind), TAU, accdec.AccDecPlacement.AFTER)
    out = accdec.apply(s, cfg)
    err = ContourMeter(circle_path(turns), lag=200).step(out.position, out.segment)
    steady = slice(int(1.0 / T), t.size - 1)  # after 20 tau, before the end of the command
    return float(err[steady].mean())


@pytest.mark.parametrize(
    ("kind", "exact_mm"),
    [("linear", 0.10384), ("s_shape", 0.05197), ("exponential", 1.05573)],
)
def test_circle_contour_error_by_simulation_matches_exact_form_within_1_percent(kind, exact_mm):
    assert circle_error(kind, F, R, TAU) == pytest.approx(exact_mm, abs=1e-5)
    assert filtered_circle_error(kind) == pytest.approx(exact_mm, rel=0.01)


def test_table_4_5_approximations_and_their_ratios():
    approx = {
        k: circle_error(k, F, R, TAU, exact=False) for k in ("linear", "s_shape", "exponential")
    }
    assert approx["linear"] == pytest.approx(F**2 * TAU**2 / (24 * R))
    assert approx["s_shape"] == pytest.approx(F**2 * TAU**2 / (48 * R))
    assert approx["exponential"] == pytest.approx(F**2 * TAU**2 / (2 * R))
    assert approx["linear"] / approx["s_shape"] == pytest.approx(2.0)


def _corner(angle: float, kind: str) -> float:
    """Two legs at feed F with a direction change ``angle``, filtered, contour error max.

    The prediction is the continuous-time limit; at T = 0.1 ms (500 taps) the discrete
    window differs from it by about T/tau, 0.2 %."""
    leg = 20.0
    period = T / 10
    n = int(round(leg / F / period))
    d1 = np.array([1.0, 0, 0])
    d2 = np.array([math.cos(angle), math.sin(angle), 0])
    s1 = np.arange(n + 1)[:, None] * F * period * d1
    s2 = s1[-1] + np.arange(1, n + 1)[:, None] * F * period * d2
    pos = np.vstack([s1, s2])
    seg_id = np.r_[np.zeros(n + 1, dtype=np.int64), np.ones(n, dtype=np.int64)]
    segs = np.zeros(2, SEGMENT_DTYPE)
    segs["kind"] = LINE
    segs["start"][0, :3], segs["end"][0, :3] = s1[0], s1[-1]
    segs["start"][1, :3], segs["end"][1, :3] = s1[-1], s2[-1]
    cfg = accdec.AccDecConfig(accdec.AccDecKind(kind), TAU, accdec.AccDecPlacement.AFTER)
    out = accdec.apply(_samples(pos, seg_id, period), cfg)
    return float(ContourMeter(segs, lag=2000).step(out.position, out.segment).max())


@pytest.mark.parametrize("kind", ["linear", "s_shape"])
@pytest.mark.parametrize("degrees", [90.0, 45.0])
def test_corner_error_prediction_matches_simulation(kind, degrees):
    angle = math.radians(degrees)
    assert _corner(angle, kind) == pytest.approx(corner_error(kind, F, TAU, angle), rel=0.01)


def test_straight_lines_have_no_adcai_contour_error():
    n = 500
    pos = np.arange(n)[:, None] * np.array([0.06, 0.08, 0.0])
    segs = np.zeros(1, SEGMENT_DTYPE)
    segs["kind"] = LINE
    segs["end"][0, :3] = pos[-1]
    cfg = accdec.AccDecConfig(accdec.AccDecKind.LINEAR, TAU, accdec.AccDecPlacement.AFTER)
    out = accdec.apply(_samples(pos, np.zeros(n, dtype=np.int64)), cfg)
    assert ContourMeter(segs, lag=100).step(out.position, out.segment).max() < 1e-12
