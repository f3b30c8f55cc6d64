"""``cnc plan`` window by window for the book model's S-curve acc/dec (kernel.stream_scurve,
issue 19) against the whole-program pipeline (kernel.simulation.plan_and_measure and
kernel.report.breakdown): the same report, cycle time and time per tool, with windows of a
few commands (so the smoothing's reach, its samples' lag and the look-ahead all cross
windows), on the golden programs, random programs and a hypothesis property; and
``cnc plan --compare``, each model planned window by window, against the whole-program
plans it was made from before. The cycle-time parts and path lengths are sums numpy forms
pairwise over the whole table: they agree to 1e-12, everything else bit for bit.

The ``slow`` tests run every golden program and many random ones, and ``cnc plan`` with an
S-curve profile on CAM programs of 10**5 and 10**6 lines, comparing peak resident set
sizes."""

from __future__ import annotations

import json
import math
import sys
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import kernel.ir.canon as canon
from cli.plan import command, compare
from cli.programs import program_commands
from kernel.diagnostics import Diagnostic
from kernel.machine import DEFAULT_MACHINE, Machine, filter_time, with_controller
from kernel.report.breakdown import Stretches
from kernel.report.compare import differing_stretches, line_times
from kernel.simulation import simulate
from kernel.stream import streams
from kernel.stream_scurve import measure_scurve, scurve_windows, smoothed, smoothing_reach_of
from tests.test_plan_stream import (
    GOLDEN,
    TIGHT,
    _peak_rss,
    assert_same,
    blended_zigzag,
    golden,
    random_program,
    whole,
)

ROOT = Path(__file__).parent.parent
SCURVE = with_controller(DEFAULT_MACHINE, accdec="scurve")
#: S-curve on a slow machine: limit hits; a long look-ahead (the stopping-distance rule)
#: and a short one
MACHINES = {
    "scurve": SCURVE,
    "tight": with_controller(TIGHT, accdec="scurve"),
    "long": with_controller(SCURVE, lookahead=10**6),
    "short": with_controller(SCURVE, lookahead=3),
}


def streamed(cmds: list[canon.Command], machine: Machine, batch: int) -> tuple[dict, list, float]:
    """The report, shares per tool and cycle time planned in windows of ``batch`` commands
    (the first pass over the program too)."""
    st_ = Stretches()
    d0 = smoothing_reach_of(iter(cmds), machine, "p", batch)
    got = measure_scurve(st_.watch(iter(cmds)), machine, d0, "p", st_.tools, st_.operations, batch)
    assert got.tools is not None
    return asdict(got.report), [asdict(s) for s in got.tools.shares()], got.total_time


def check(cmds: list[canon.Command], machine: Machine, batches: tuple[int, ...]) -> dict[str, Any]:
    ref, shares, total = whole(cmds, machine)
    for batch in batches:
        got, got_shares, got_total = streamed(cmds, machine, batch)
        assert_same(ref, got)
        assert got_shares == shares and got_total == total, batch
    return ref


# ----------------------------------------------------------------------------- default run
def test_scurve_is_planned_here() -> None:
    assert smoothed(SCURVE) and not streams(SCURVE)
    assert not smoothed(DEFAULT_MACHINE)
    assert not smoothed(with_controller(SCURVE, model="grbl"))


def test_window_cuts_inside_blends_and_smoothing() -> None:
    """A run of G64 P corners then a stop, windows of one and of seven commands: the
    smoothing's reach (``T_f`` at the programmed feed) spans several windows."""
    cmds = blended_zigzag(16)
    # the fastest cap is the programmed feed, 2000 mm/min
    d0 = smoothing_reach_of(iter(cmds), SCURVE)
    assert d0 == pytest.approx(filter_time(SCURVE) * 2000.0 / 60.0, rel=1e-12)
    ref = check(cmds, SCURVE, (1, 7))
    assert ref["segments"] > 25


def test_random_program_plans_as_a_whole() -> None:
    check(random_program(0, 40), SCURVE, (4,))


def test_golden_blending_program_plans_as_a_whole() -> None:
    name = "114_g64_p_q_blending.canon"
    if not (GOLDEN / name).exists():
        pytest.skip(f"{name} not in the corpus")
    check(golden(name), SCURVE, (5,))


def test_windows_stay_small() -> None:
    """A long program of short moves is planned in windows of a bounded size: the rows of
    the smoothing's reach and the look-ahead, not the program."""
    cmds = random_program(3, 250)
    d0 = smoothing_reach_of(iter(cmds), SCURVE, "p", 9)
    windows = list(scurve_windows(iter(cmds), SCURVE, d0, "p", 9))
    assert len(windows) > 12
    assert max(len(w.path.segments) for w, _ in windows) < 80
    assert max(len(later) for _, later in windows) < 150


def test_the_first_error_is_the_whole_programs() -> None:
    """PLAN-FEED in an early window, PLAN-AXIS in a later one: PLAN-AXIS, as the whole
    program's table checks axes before feeds."""
    ok = [canon.SetFeedRate(600.0)] + [canon.StraightFeed(i, 0.0, 0.0) for i in range(1, 30)]
    no_feed = [canon.SetFeedRate(0.0), canon.StraightFeed(0.0, 5.0, 0.0)]
    axis = [canon.SetFeedRate(600.0), canon.StraightFeed(0.0, 5.0, 0.0, 10.0)]
    far = [canon.SetFeedRate(600.0), canon.StraightFeed(5000.0, 5.0, 0.0)]
    for cmds in (ok + no_feed + ok + axis, ok + far + ok + no_feed, ok + far + ok):
        with pytest.raises(Diagnostic) as ref:
            whole(cmds, SCURVE)
        for batch in (3,):
            with pytest.raises(Diagnostic) as got:
                streamed(cmds, SCURVE, batch)
            assert (got.value.code, got.value.location) == (ref.value.code, ref.value.location)


def _whole_compare(path: str, machine: Machine, models: list[str]) -> tuple[dict, list]:
    """``--compare`` as it was computed before (each model simulated whole): reports and
    stretches."""
    reports, times = {}, {}
    for name in models:
        result = simulate(program_commands(path), with_controller(machine, model=name), path)
        reports[name] = asdict(result.measure())
        times[name] = line_times(result.plan)
    return reports, [asdict(s) for s in differing_stretches(times, window=5, count=5)]


@pytest.mark.parametrize(
    "machine",
    [pytest.param(DEFAULT_MACHINE, marks=pytest.mark.slow), SCURVE],
    ids=["trapezoid", "scurve"],
)
def test_compare_streamed_equals_whole(tmp_path: Path, machine: Machine) -> None:
    """``--compare linuxcnc,grbl,book``, each model planned window by window: the reports
    and the stretches of the whole-program plans."""
    sys.path.insert(0, str(ROOT / "bench"))
    from cam_program import write_program

    prog = str(write_program(tmp_path / "cam.ngc", 100, stop_every=30))
    models = ["linuxcnc", "grbl", "book"]
    ref_reports, ref_stretches = _whole_compare(prog, machine, models)
    reports, stretches = compare(prog, machine, models)
    assert [asdict(s) for s in stretches] == ref_stretches
    assert len(ref_stretches) == 5
    for name in models:
        assert_same(ref_reports[name], asdict(reports[name]))
    out = CliRunner().invoke(command, [prog, "--compare", "linuxcnc,grbl,book"])
    assert out.exit_code == 0, out.output
    assert "where they differ most" in out.output


def test_cli_plan_streams_scurve(tmp_path: Path) -> None:
    """``cnc plan`` with an S-curve profile: the whole-program cycle time and times."""
    sys.path.insert(0, str(ROOT / "bench"))
    from cam_program import write_program

    prog = write_program(tmp_path / "cam.ngc", 80)
    profile = tmp_path / "scurve.toml"
    profile.write_text(_profile_text())
    out = CliRunner().invoke(command, [str(prog), "--machine", str(profile), "--format", "json"])
    assert out.exit_code == 0, out.output
    doc = json.loads(out.output)
    _ref, _shares, total = whole(list(program_commands(str(prog))), SCURVE)
    assert doc["times"]["cycle"] == doc["cycle"]["total"] == total


def _profile_text() -> str:
    """The default machine as a profile with S-curve acc/dec (bench/bench_memory.py's)."""
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_memory import scurve_profile

    return scurve_profile()


# ----------------------------------------------------------------------------- property
_FEEDS = [60.0, 600.0, 3000.0, 12000.0]
_MOVE = st.one_of(
    st.tuples(st.just("line"), st.floats(-4, 4), st.floats(-4, 4), st.booleans()),
    st.tuples(st.just("arc"), st.floats(0.3, 4), st.floats(-3, 3), st.booleans()),
    st.tuples(st.just("rapid"), st.floats(-20, 20), st.floats(-20, 20), st.booleans()),
    st.tuples(
        st.just("feed"),
        st.sampled_from([60.0, 600.0, 3000.0, 12000.0]),
        st.just(0.0),
        st.booleans(),
    ),
    st.tuples(st.just("mode"), st.sampled_from([0.0, 0.01, 0.3]), st.just(0.0), st.booleans()),
    st.tuples(st.just("dwell"), st.sampled_from([0.0, 0.02]), st.just(0.0), st.booleans()),
)


def _program(moves: list[tuple[str, float, float, bool]]) -> list[canon.Command]:
    """Lines, arcs, rapids, feed changes, G64 P / G61, dwells from hypothesis' draws."""
    x = y = 0.0
    out: list[canon.Command] = [canon.SetFeedRate(1200.0)]
    for kind, a, b, flag in moves:
        if kind == "line":
            x, y = x + a, y + b
            out.append(canon.StraightFeed(x, y, 0.5 if flag else 0.0))
        elif kind == "arc":
            cx, cy = x - a, y
            turn = b
            nx, ny = cx + a * math.cos(turn), cy + a * math.sin(turn)
            out.append(canon.ArcFeed(nx, ny, cx, cy, 1 if flag else -1, 0.0))
            x, y = nx, ny
        elif kind == "rapid":
            x, y = x + a, y + b
            out.append(canon.StraightTraverse(x, y, 1.0 if flag else 0.0))
        elif kind == "feed":
            out.append(canon.SetFeedRate(a))
        elif kind == "mode":
            mode = canon.MotionMode.EXACT_PATH if flag else canon.MotionMode.CONTINUOUS
            out.append(canon.SetMotionControlMode(mode, 0.0 if flag else a))
        else:
            out.append(canon.Dwell(a))
    return out


@settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_MOVE, min_size=1, max_size=20), st.integers(1, 12))
def test_property_streamed_equals_whole(moves: list, batch: int) -> None:
    cmds = _program(moves)
    try:
        whole(cmds, SCURVE)
    except Diagnostic:
        return
    check(cmds, SCURVE, (batch,))


# ----------------------------------------------------------------------------- slow
@pytest.mark.slow
@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(_MOVE, min_size=1, max_size=120), st.integers(1, 40), st.sampled_from(list(MACHINES))
)
def test_many_programs_streamed_equals_whole(moves: list, batch: int, machine: str) -> None:
    cmds = _program(moves)
    try:
        whole(cmds, MACHINES[machine])
    except Diagnostic:
        return
    check(cmds, MACHINES[machine], (batch,))


@pytest.mark.slow
def test_all_golden_programs_plan_as_a_whole() -> None:
    names = sorted(p.name for p in GOLDEN.glob("*.canon"))
    done = 0
    for name in names:
        cmds = golden(name)
        try:
            ref, _, total = whole(cmds, SCURVE)
        except Diagnostic:
            continue
        if total > 120.0:
            continue
        for batch in (1, 13):
            got, _, got_total = streamed(cmds, SCURVE, batch)
            assert_same(ref, got)
            assert got_total == total, (name, batch)
        done += 1
    assert done > 60


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(2, 30))
def test_many_random_programs_plan_as_a_whole(seed: int) -> None:
    cmds = random_program(seed, 300)
    for m in MACHINES.values():
        check(cmds, m, (1, 11, 97))


@pytest.mark.slow
def test_scurve_after_interpolation_plans_as_a_whole() -> None:
    """S-curve acc/dec after interpolation only: the path is built (its lines cut next to
    curvature joints) for S-curve, the planner plans a trapezoid."""
    after = replace(SCURVE, extra={"accdec": {"type": "linear", "placement": "after"}})
    assert smoothed(after)
    for seed in range(3):
        check(random_program(seed, 200), after, (1, 13))


@pytest.mark.slow
def test_scurve_plan_peak_memory_is_flat_in_program_length(tmp_path: Path) -> None:
    """Peak RSS of ``cnc plan`` with an S-curve profile at 10**6 lines within 1.3 times
    that at 10**5 (kernel.stream_scurve)."""
    profile = tmp_path / "scurve.toml"
    profile.write_text(_profile_text())
    extra = ("--machine", str(profile))
    small = _peak_rss(10**5, tmp_path, extra)
    large = _peak_rss(10**6, tmp_path, extra)
    assert large <= 1.3 * small, (small, large)
