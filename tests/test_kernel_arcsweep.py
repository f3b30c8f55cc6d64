"""The ARC_FEED rotation -> swept angle rule (kernel.ir.arcsweep), against the closed form
(NISTIR 5970 §3.6.1: |rotation| = N sweeps an angle in ((N-1) 2π, N 2π]) and against an
oracle that builds the arc from a known sweep; and the STEP-NC gouge check's samples,
which once gave a two-turn circle a single turn."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweep, arc_sweeps, first_turn, total_sweep
from stepnc.gouge import _samples

PI = math.pi


def _angle(x: float, y: float) -> float:
    return math.atan2(y, x)


@pytest.mark.parametrize(
    ("start", "end", "rotation", "expected"),
    [
        ((1.0, 0.0), (1.0, 0.0), 1, 2 * PI),  # an end on its start: one full circle
        ((1.0, 0.0), (1.0, 0.0), -1, -2 * PI),
        ((1.0, 0.0), (1.0, 0.0), 2, 4 * PI),  # a two-turn full circle sweeps 4π
        ((1.0, 0.0), (1.0, 0.0), -2, -4 * PI),
        ((1.0, 0.0), (1.0, 0.0), 3, 6 * PI),
        ((1.0, 0.0), (-1.0, 0.0), 2, 3 * PI),  # 1.5 turns: a half circle plus one turn
        ((1.0, 0.0), (-1.0, 0.0), -2, -3 * PI),
        ((1.0, 0.0), (0.0, 1.0), 1, PI / 2),  # a quarter counter-clockwise
        ((1.0, 0.0), (0.0, 1.0), -1, -3 * PI / 2),  # the same ends clockwise: the long way
        ((1.0, 0.0), (0.0, 1.0), 3, PI / 2 + 4 * PI),
        ((-1.0, 0.0), (-1.0, -0.0), 1, 2 * PI),  # on the atan2 branch cut: still a circle
        ((-1.0, -0.0), (-1.0, 0.0), -1, -2 * PI),
        ((1.0, 0.0), (0.0, 1.0), 0, 0.0),  # rotation 0: no in-plane motion
    ],
)
def test_sweep_of_signed_turns_is_the_closed_form(start, end, rotation, expected) -> None:
    got = arc_sweep(_angle(*start), _angle(*end), rotation)
    assert got == pytest.approx(expected, abs=1e-12)
    assert math.copysign(1.0, got) == math.copysign(1.0, expected)


def test_a_first_turn_and_each_further_turn_adding_two_pi() -> None:
    assert first_turn(0.0, 0.0, True) == 2 * PI
    assert first_turn(0.0, 1e-12, True) == 2 * PI  # within the tolerance: full circle
    assert first_turn(0.0, 2e-12, True) == 2e-12
    assert first_turn(0.0, PI / 2, False) == pytest.approx(3 * PI / 2)
    assert total_sweep(PI, 1) == PI
    assert total_sweep(PI, 3) == pytest.approx(5 * PI)


def _oracle_case(theta0: float, fraction: float, turns: int, ccw: bool) -> tuple:
    """Start and end angles (via atan2 of the two radius vectors) of an arc built from the
    known sweep ``(turns - 1 + fraction) 2π``, and that sweep, signed."""
    sweep = (turns - 1 + fraction) * 2 * PI * (1 if ccw else -1)
    t0 = _angle(math.cos(theta0), math.sin(theta0))
    t1 = _angle(math.cos(theta0 + sweep), math.sin(theta0 + sweep))
    return t0, t1, (turns if ccw else -turns), sweep


@settings(max_examples=400, deadline=None)
@given(
    theta0=st.floats(-4 * PI, 4 * PI, allow_nan=False),
    fraction=st.floats(1e-6, 1.0),
    turns=st.integers(1, 6),
    ccw=st.booleans(),
)
@example(theta0=PI, fraction=1.0, turns=2, ccw=True)
@example(theta0=-PI, fraction=1.0, turns=1, ccw=False)
@example(theta0=0.0, fraction=0.5, turns=2, ccw=False)
def test_sweep_matches_an_arc_built_from_its_known_sweep(theta0, fraction, turns, ccw) -> None:
    t0, t1, rotation, sweep = _oracle_case(theta0, fraction, turns, ccw)
    assert arc_sweep(t0, t1, rotation) == pytest.approx(sweep, abs=1e-9)


angles = st.one_of(
    st.floats(-PI, PI, allow_nan=False),
    st.sampled_from([0.0, -0.0, PI, -PI, 1e-12, -1e-12, 2e-12, PI - 1e-13, -PI + 1e-13]),
)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(angles, angles, st.integers(-5, 5)), min_size=1, max_size=30))
def test_numpy_form_is_the_scalar_form_bit_for_bit(arcs) -> None:
    t0, t1, rot = (np.array(col, dtype=np.float64) for col in zip(*arcs, strict=True))
    got = arc_sweeps(t0, t1, rot)
    want = [arc_sweep(a, b, r) for a, b, r in arcs]
    assert got.tolist() == want


@pytest.mark.parametrize(("rotation", "expected"), [(2, 4 * PI), (-2, -4 * PI), (1, 2 * PI)])
def test_gouge_samples_go_round_a_full_circle_once_per_turn(rotation, expected) -> None:
    """The gouge check samples a two-turn circle twice round (it sampled one turn)."""
    start = np.array([10.0, 0.0, 0.0])
    cmd = canon.ArcFeed(10.0, 0.0, 0.0, 0.0, rotation, -4.0, 0.0, 0.0, 0.0)
    pts = _samples(start, cmd, 0.5)
    travelled = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
    assert travelled[-1] - travelled[0] == pytest.approx(expected, abs=1e-9)
    assert pts[-1] == pytest.approx([10.0, 0.0, -4.0])
