"""Measurements (kernel.report.measure) against independent oracles.

Cycle times of single lines from rest to rest are the trapezoid worked by hand (``L/F + F/A``
when the block cruises, ``2 sqrt(L/A)`` when it is too short to); path lengths of lines,
circles and helices are their formulas; the chord error of a sampled circle is the sagitta of
one sample step; limit hits are counted again by a plain walk over the samples; peaks are
``max |x|`` of the sampled columns; hypothesis checks the bookkeeping on random polylines.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kernel.interp.interpolate import sample
from kernel.interp.samples import Samples
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, AxisLimits, Machine, with_controller
from kernel.path.build import build_path
from kernel.path.segments import ARC
from kernel.plan.planner import plan
from kernel.report.measure import ATOL, RTOL, Report, measure

#: the default mill's X axis: velocity 250 mm/s, acceleration 2000 mm/s^2
VX, AX = 250.0, 2000.0


def _measured(cmds: list[canon.Command], machine: Machine = DEFAULT_MACHINE):
    pl = plan(build_path(cmds, machine), machine)
    s = sample(pl)
    return pl, s, measure(pl, s)


# ----------------------------------------------------------------------------- cycle time
def _by_hand(length: float, v: float, a: float) -> float:
    """Rest-to-rest time of one block: trapezoid, or triangle when too short to cruise."""
    if length >= v * v / a:
        return length / v + v / a
    return 2.0 * math.sqrt(length / a)


@pytest.mark.parametrize(
    "move, length, feed, expect_v",
    [
        ("feed", 100.0, 6000.0, 100.0),  # cruises at 100 mm/s
        ("feed", 1.0, 6000.0, 100.0),  # too short: a triangle
        ("rapid", 100.0, 0.0, VX),  # traverse at the axis velocity
    ],
)
def test_cycle_time_of_a_single_line_is_the_trapezoid_by_hand(move, length, feed, expect_v):
    cmd = canon.StraightFeed if move == "feed" else canon.StraightTraverse
    _, _, rep = _measured([canon.SetFeedRate(feed), cmd(length, 0.0, 0.0)])
    want = _by_hand(length, expect_v, AX)
    assert rep.cycle.total == pytest.approx(want, rel=1e-12)
    part = rep.cycle.cutting if move == "feed" else rep.cycle.rapid
    assert part == pytest.approx(want, rel=1e-12)
    assert rep.cycle.dwell == rep.cycle.tool_change == rep.cycle.other == 0.0
    assert (rep.feed_length, rep.rapid_length) == (
        (length, 0.0) if move == "feed" else (0.0, length)
    )
    assert rep.segments == 1
    assert rep.samples == math.ceil(want / 0.001 - 1e-9) + 1


# ----------------------------------------------------------------------------- path lengths
R, DROP = 5.0, 3.0


def _program() -> list[canon.Command]:
    """A traverse, a polyline, a full circle, a dwell, a two-turn helix, a spindle orientation,
    a tool change, a traverse back and a probe move down."""
    pts = [(0.0, 0.0, -1.0), *((i * 1.5, 3.0 * math.sin(i / 3.0), -1.0) for i in range(1, 40))]
    x, y, _ = pts[-1]
    return [
        canon.SetFeedRate(2400.0),
        canon.StraightTraverse(0.0, 0.0, 5.0),
        *(canon.StraightFeed(*p) for p in pts),
        canon.ArcFeed(x, y, x - R, y, 1, -1.0),
        canon.Dwell(0.1),
        canon.ArcFeed(x, y, x - R, y, -2, -1.0 - DROP),
        canon.OrientSpindle(0.0, canon.Direction.CLOCKWISE),
        canon.ChangeTool(2),
        canon.StraightTraverse(0.0, 0.0, 5.0),
        canon.StraightProbe(0.0, 0.0, 1.0),
        canon.ProgramEnd(),
    ]


def _polyline_length() -> float:
    pts = [(0.0, 0.0, -1.0), *((i * 1.5, 3.0 * math.sin(i / 3.0), -1.0) for i in range(1, 40))]
    return sum(math.dist(a, b) for a, b in zip(pts, pts[1:], strict=False))


@pytest.mark.parametrize("accdec", ["trapezoid", "scurve"])
def test_path_lengths_of_lines_circles_and_helices_are_their_formulas(accdec):
    machine = with_controller(DEFAULT_MACHINE, accdec=accdec)
    _, _, rep = _measured(_program(), machine)
    circle = 2 * math.pi * R
    helix = math.hypot(2 * 2 * math.pi * R, DROP)
    probe = 4.0
    assert rep.feed_length == pytest.approx(6.0 + _polyline_length() + circle + helix + probe)
    x, y, _ = (39 * 1.5, 3.0 * math.sin(13.0), 0.0)
    back = math.dist((x, y, -1.0 - DROP), (0.0, 0.0, 5.0))
    assert rep.rapid_length == pytest.approx(5.0 + back)
    ctl = machine.controller
    assert rep.cycle.dwell == pytest.approx(0.1, abs=1e-12)
    assert rep.cycle.tool_change == pytest.approx(ctl.tool_change_time, abs=1e-12)
    assert rep.cycle.other == pytest.approx(ctl.spindle_orient_time, abs=1e-12)
    c = rep.cycle
    assert c.total == pytest.approx(c.cutting + c.rapid + c.dwell + c.tool_change + c.other)


# ----------------------------------------------------------------------------- peaks, hits
def _peaks(arr: np.ndarray, axes: tuple[str, ...]) -> dict[str, float]:
    m = np.abs(arr).max(axis=0) if len(arr) else np.zeros(len(axes))
    return {a: float(v) for a, v in zip(axes, m, strict=True)}


def test_peaks_of_a_cruising_line_are_its_feed_and_the_axis_acceleration():
    _, s, rep = _measured([canon.SetFeedRate(6000.0), canon.StraightFeed(100.0, 0.0, 0.0)])
    assert rep.peak_velocity == {"x": pytest.approx(100.0, rel=1e-12), "y": 0.0, "z": 0.0}
    assert rep.peak_acceleration == {"x": pytest.approx(AX, rel=1e-12), "y": 0.0, "z": 0.0}
    assert rep.peak_velocity == _peaks(s.velocity, s.axes)
    assert rep.peak_jerk == _peaks(s.jerk, s.axes)


def _runs_over(values: list[float], threshold: float) -> list[tuple[int, int]]:
    """Runs (first index, length) of ``values`` strictly above ``threshold``, by a loop."""
    runs, start = [], None
    for i, v in enumerate(values):
        if v > threshold and start is None:
            start = i
        elif v <= threshold and start is not None:
            runs.append((start, i - start))
            start = None
    if start is not None:
        runs.append((start, len(values) - start))
    return runs


def _walk_hits(machine: Machine, s: Samples) -> dict[tuple[str, str], list[tuple[int, int]]]:
    """(axis, kind) -> runs (first sample, length) over the limit, by a plain walk."""
    kinds = ["velocity", "acceleration"]
    if machine.controller.accdec == "scurve":
        kinds.append("jerk")
    out: dict[tuple[str, str], list[tuple[int, int]]] = {}
    for j, name in enumerate(s.axes):
        ax = machine.axis(name)
        for kind in kinds:
            col = [abs(v) for v in getattr(s, kind)[:, j].tolist()]
            out[(name, kind)] = _runs_over(col, getattr(ax, kind) * (1 + RTOL) + ATOL)
        pos = s.position[:, j].tolist()
        out[(name, "travel")] = _runs_over(pos, ax.max + ATOL) + _runs_over(
            [-v for v in pos], -(ax.min - ATOL)
        )
    return out


def _check_hits(rep: Report, machine: Machine, s: Samples) -> None:
    """Every reported hit is a run the walk finds, the total is the walk's count, at most 50
    are listed, the earliest first."""
    walk = _walk_hits(machine, s)
    assert rep.hits_total == sum(len(r) for r in walk.values())
    assert len(rep.hits) == min(50, rep.hits_total)
    assert [h.time for h in rep.hits] == sorted(h.time for h in rep.hits)
    for h in rep.hits:
        first = round(h.time / s.period)
        assert (first, h.samples) in walk[(h.axis, h.kind)]
        assert h.line == int(s.source_line[first])
        ax = machine.axis(h.axis)
        if h.kind == "travel":
            col = s.position[first : first + h.samples, s.axes.index(h.axis)]
            assert h.value == (col.max() if h.limit == ax.max else col.min())
        else:
            col = getattr(s, h.kind)[first : first + h.samples, s.axes.index(h.axis)]
            assert h.value == np.abs(col).max() > h.limit == getattr(ax, h.kind)


def _judged(pl, axes: tuple[AxisLimits, ...]):
    """``pl`` judged against other axis limits (the samples stay those of ``pl``)."""
    return dataclasses.replace(pl, machine=Machine("tight", axes, pl.machine.controller))


def test_limit_hits_of_a_line_judged_against_lower_limits_are_where_the_profile_says():
    """100 mm at 100 mm/s on X (A = 2000): over 50 mm/s from t = 0.025 s for 1 s; over an
    acceleration of 1000 while accelerating and decelerating; past X = 60 from t = 0.625 s."""
    pl, s, _ = _measured([canon.SetFeedRate(6000.0), canon.StraightFeed(100.0, 0.0, 0.0)])
    x = dataclasses.replace(DEFAULT_MACHINE.axes[0], velocity=50.0, acceleration=1000.0, max=60.0)
    judged = _judged(pl, (x, *DEFAULT_MACHINE.axes[1:]))
    rep = measure(judged, s)
    _check_hits(rep, judged.machine, s)
    by_kind = {k: [h for h in rep.hits if h.kind == k] for k in ("velocity", "acceleration")}
    travel = [h for h in rep.hits if h.kind == "travel"]
    assert rep.hits_total == 4 and len(by_kind["velocity"]) == 1 and len(travel) == 1
    (v,) = by_kind["velocity"]
    assert v.time == pytest.approx(50.0 / AX, abs=0.0011)
    assert v.samples == pytest.approx(1000, abs=2)
    assert v.value == pytest.approx(100.0)
    assert [h.value for h in by_kind["acceleration"]] == [pytest.approx(AX)] * 2
    assert travel[0].time == pytest.approx(0.05 + 57.5 / 100.0, abs=0.0011)
    assert travel[0].value == pytest.approx(100.0)


@pytest.mark.parametrize("accdec", ["trapezoid", "scurve"])
def test_jerk_is_judged_only_for_a_jerk_limited_profile(accdec):
    machine = with_controller(DEFAULT_MACHINE, accdec=accdec)
    pl, s, _ = _measured([canon.SetFeedRate(6000.0), canon.StraightFeed(100.0, 0.0, 0.0)], machine)
    axes = tuple(dataclasses.replace(a, jerk=1.0) for a in machine.axes)
    rep = measure(_judged(pl, axes), s)
    jerk = [h for h in rep.hits if h.kind == "jerk"]
    assert bool(jerk) == (accdec == "scurve")
    _check_hits(rep, _judged(pl, axes).machine, s)


def _tight(machine: Machine, factor: float, travel: float) -> tuple[AxisLimits, ...]:
    """``machine``'s axes with every limit scaled by ``factor``, travel ``[-travel, travel]``."""
    return tuple(
        dataclasses.replace(
            a,
            velocity=a.velocity * factor,
            acceleration=a.acceleration * factor,
            jerk=a.jerk * factor,
            min=-travel,
            max=travel,
        )
        for a in machine.axes
    )


@pytest.mark.parametrize("accdec", ["trapezoid", "scurve"])
@pytest.mark.parametrize("factor, travel", [(1.0, math.inf), (0.3, 20.0), (0.05, 1.0)])
def test_hits_and_peaks_of_a_mixed_program_match_a_plain_walk(accdec, factor, travel):
    """On its own machine the program hits nothing; against tighter limits every hit is a run
    of samples over a limit (many of them: the list is capped at 50)."""
    machine = with_controller(DEFAULT_MACHINE, accdec=accdec)
    pl, s, _ = _measured(_program(), machine)
    judged = _judged(pl, _tight(machine, factor, travel))
    rep = measure(judged, s)
    _check_hits(rep, judged.machine, s)
    assert (rep.hits_total > 0) == (factor < 1)
    for name in ("velocity", "acceleration", "jerk"):
        assert getattr(rep, f"peak_{name}") == _peaks(getattr(s, name), s.axes)
    assert rep.chord_error > 0  # the arcs were measured


# ----------------------------------------------------------------------------- chord error
def test_chord_error_of_a_sampled_circle_is_the_sagitta_of_one_step():
    """Exact points on a circle of radius R, ``d = v T`` apart at the cruise speed ``v``: the
    chord's midpoint lies ``R (1 - cos(d / 2R))`` inside."""
    cmds = [
        canon.SetFeedRate(3000.0),
        canon.StraightFeed(10.0, 0.0, 0.0),
        canon.ArcFeed(10.0, 0.0, 0.0, 0.0, 1, 0.0),
    ]
    pl, s, rep = _measured(cmds)
    arc = int(np.flatnonzero(pl.path.segments["kind"] == ARC)[0])
    v = float(pl.profiles.v_peak[arc])
    assert v == pytest.approx(50.0)  # the programmed feed
    r = 10.0
    assert rep.chord_error == pytest.approx(r * (1 - math.cos(v * s.period / (2 * r))), rel=1e-3)


def test_the_empty_program_and_a_single_tiny_line_measure_by_hand():
    _, s, rep = _measured([canon.SetFeedRate(100.0)])
    zero = {"x": 0.0, "y": 0.0, "z": 0.0}
    assert (rep.cycle.total, rep.feed_length, rep.segments, rep.samples) == (0.0, 0.0, 0, 1)
    assert rep.peak_velocity == rep.peak_acceleration == rep.peak_jerk == zero
    assert (rep.chord_error, rep.hits, rep.hits_total) == (0.0, [], 0)
    _, s, rep = _measured([canon.SetFeedRate(100.0), canon.StraightFeed(1e-3, 0.0, 0.0)])
    assert rep.cycle.total == pytest.approx(2 * math.sqrt(1e-3 / AX), rel=1e-12)
    assert rep.feed_length == pytest.approx(1e-3) and rep.segments == 1
    assert rep.samples == len(s) == 3  # 0, 1 and 1.41 ms


# ----------------------------------------------------------------------------- properties
_coord = st.floats(-50.0, 50.0, allow_nan=False).map(lambda v: round(v, 3))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    points=st.lists(st.tuples(_coord, _coord, _coord), min_size=1, max_size=8),
    feeds=st.lists(st.floats(60.0, 12000.0), min_size=1, max_size=8),
    rapid=st.lists(st.booleans(), min_size=8, max_size=8),
)
def test_random_polylines_measure_their_lengths_times_and_peaks(points, feeds, rapid):
    cmds: list[canon.Command] = []
    feed_len = rapid_len = 0.0
    here, moves = (0.0, 0.0, 0.0), 0
    for i, p in enumerate(points):
        cmds.append(canon.SetFeedRate(feeds[i % len(feeds)]))
        cmds.append((canon.StraightTraverse if rapid[i] else canon.StraightFeed)(*p))
        d = math.dist(here, p)
        if d > 1e-9:
            moves += 1
            if rapid[i]:
                rapid_len += d
            else:
                feed_len += d
        here = p
    pl, s, rep = _measured(cmds)
    assert rep.feed_length == pytest.approx(feed_len, abs=1e-9)
    assert rep.rapid_length == pytest.approx(rapid_len, abs=1e-9)
    assert rep.segments == moves
    c = rep.cycle
    assert c.total == pytest.approx(c.cutting + c.rapid, abs=1e-12)
    # no block is faster than its feed or the axes allow, so no faster than by hand
    fastest_rapid = math.hypot(250.0, 250.0, 200.0)  # every axis at its velocity limit
    assert c.total >= (feed_len / 200.0 + rapid_len / fastest_rapid) * (1 - 1e-12)
    assert rep.peak_velocity == _peaks(s.velocity, s.axes)
    assert rep.peak_acceleration == _peaks(s.acceleration, s.axes)
    assert rep.hits_total == 0
