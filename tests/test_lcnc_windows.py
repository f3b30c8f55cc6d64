"""The linuxcnc model planned window by window inside a run of joins (kernel.stream, issue 19)
against planning the whole program at once (kernel.plan.models.linuxcnc, itself checked
against LinuxCNC in tests/test_controller_models.py and tests/test_lcnc*.py): windows of a
few rows (1, 7, 50, 64) cut inside G64 runs, between blend arcs, parabolic blends and
naive-CAM merges, each planned with rows before and after it. Every row of the table, its
junction speeds, duration, start time, cap and parabolic overlap are the whole program's
bit for bit, and so is the report (but the pairwise sums, tests/test_plan_stream.py).

LinuxCNC's golden programs (tests/data/lcnc_tp) on their machine profile, and random
G64 / G64 P Q / G61 programs of lines and arcs (hypothesis) with short segments at high
feeds, where the look-ahead reads its whole ``OPT_DEPTH``."""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import kernel.ir.canon as canon
from gcode.readers import read
from kernel.machine import Machine, parse_machine
from kernel.plan.planner import Plan
from kernel.simulation import plan_and_measure
from kernel.stream import plan_windows
from tests.test_plan_stream import assert_same, streamed, whole

LCNC_TP = Path(__file__).parent / "data" / "lcnc_tp"
MACHINE = parse_machine((LCNC_TP / "machine.toml").read_text())
#: golden programs with long runs of joins: blend arcs, parabolic blends, arcs, merges
RUNS = ["lcnc_sam-circle_lines.G64P.ngc", "own_sine_0p2_f3000.native.ngc", "corpus_axis.G64P.ngc"]


def program(name: str) -> list[canon.Command]:
    return list(read(LCNC_TP / "ngc" / name, "rs274ngc"))


def joined(windows: list[Plan]) -> dict[str, np.ndarray]:
    """The windows' rows and numbers, one after the other; each window's first junction
    speed is the last one's end speed."""
    assert all(
        a.v_junction[-1] == b.v_junction[0] for a, b in zip(windows[:-1], windows[1:], strict=True)
    )
    assert windows
    out = {
        "v": np.concatenate([w.v_junction[:-1] for w in windows] + [windows[-1].v_junction[-1:]])
    }
    for key in ("duration", "t_start", "s_start", "cap", "pause", "overlap"):
        out[key] = np.concatenate([getattr(w, key) for w in windows])
    out["rows"] = np.concatenate([w.path.segments for w in windows])
    return out


def assert_windows_plan_as_whole(
    cmds: list[canon.Command], machine: Machine, sizes: tuple[int, ...]
) -> int:
    """Windows of each size give the whole program's plan, row for row; the most windows."""
    ref, _ = plan_and_measure(iter(cmds), machine, "p")
    most = 0
    for size in sizes:
        windows = list(plan_windows(iter(cmds), machine, "p", batch=size))
        most = max(most, len(windows))
        got = joined(windows)
        assert got["rows"].tobytes() == ref.path.segments.tobytes(), size
        assert np.array_equal(got["v"], ref.v_junction), size
        for key in ("duration", "t_start", "s_start", "cap", "pause", "overlap"):
            assert np.array_equal(got[key], getattr(ref, key)), (size, key)
    return most


@pytest.mark.parametrize(("name", "size"), [(RUNS[0], 7), (RUNS[1], 50), (RUNS[2], 64)])
def test_golden_runs_plan_as_a_whole_in_small_windows(name: str, size: int) -> None:
    """Cuts at every ``size``-th join of a long G64 run (several windows per program)."""
    assert assert_windows_plan_as_whole(program(name), MACHINE, (size,)) > 3


def test_golden_run_report_in_small_windows() -> None:
    """The report (cycle time, peaks, limits) and time per tool of a windowed run with
    parabolic blends, sampled window by window."""
    cmds = program(RUNS[2])
    ref, shares, total = whole(cmds, MACHINE)
    got, got_shares, got_total = streamed(cmds, MACHINE, 13)
    assert_same(ref, got)
    assert (got_shares, got_total) == (shares, total)


def test_cam_program_in_small_windows(tmp_path: Path) -> None:
    """bench/cam_program.py's CAM program (one G64 run, parabolic blends): the plan and
    the report, sampled window by window across the blends' overlaps."""
    sys.path.insert(0, str(Path(__file__).parent.parent / "bench"))
    from cam_program import write_program

    cmds = list(read(write_program(tmp_path / "cam.ngc", 400), "rs274ngc"))
    assert assert_windows_plan_as_whole(cmds, MACHINE, (32,)) > 10
    ref, shares, total = whole(cmds, MACHINE)
    got, got_shares, got_total = streamed(cmds, MACHINE, 32)
    assert_same(ref, got)
    assert (got_shares, got_total) == (shares, total)


def test_a_long_run_is_cut_into_windows() -> None:
    """A G64 run with no stop is no longer one window: windows of about ``batch`` rows."""
    cmds = program("lcnc_sam-circle_lines.G64P.ngc")
    windows = list(plan_windows(iter(cmds), MACHINE, "p", batch=50))
    assert len(windows) > 5  # rows and blend arcs, after a stop up to a batch more
    assert max(len(w.path.segments) for w in windows) < 4 * 50


# ----------------------------------------------------------------------------- random programs
def g64_program(seed: int, n: int) -> list[canon.Command]:
    """About ``n`` moves in G64, G64 P Q and G61: runs of short lines (nearly collinear:
    naive-CAM merging; long enough at a high feed for the look-ahead to read its whole
    ``OPT_DEPTH``) and arcs, between corners of every angle; now and then a stop (a dwell,
    a traverse, G61.1), so that windows cut at joins meet windows cut at stops."""
    rng = random.Random(seed)
    out: list[canon.Command] = [canon.SetFeedRate(rng.choice([2400.0, 3000.0]))]
    x = y = z = heading = 0.0
    while len(out) < n:
        if rng.random() < 0.15:
            p = rng.choice([0.0, 0.0, 0.005, 0.05])
            mode = rng.choice([canon.MotionMode.CONTINUOUS] * 3 + [canon.MotionMode.EXACT_PATH])
            out.append(canon.SetMotionControlMode(mode, p if mode.name == "CONTINUOUS" else 0.0))
            out.append(canon.SetNaivecamTolerance(p))
        if rng.random() < 0.03:  # now and then a stop: a dwell, a traverse, a G61.1 run
            stop = rng.choice(["dwell", "traverse", "exact"])
            if stop == "dwell":
                out.append(canon.Dwell(0.0))
            elif stop == "traverse":
                out.append(canon.StraightTraverse(x, y, z + 1.0))
                out.append(canon.StraightTraverse(x, y, z))
            else:
                out.append(canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP))
        heading += rng.uniform(-2.8, 2.8)  # a corner
        step = rng.choice([0.02, 0.05, 0.05, 0.1, 0.5])
        bend = rng.choice([0.0, 0.0005, 0.01])
        for _ in range(rng.randint(1, 80)):
            if rng.random() < 0.9:
                heading += bend * rng.choice([-1, 1])
                x += step * math.cos(heading)
                y += step * math.sin(heading)
                z += 0.01 if rng.random() < 0.02 else 0.0
                out.append(canon.StraightFeed(x, y, z))
                continue
            rad = rng.choice([0.3, 2.0, 8.0])
            turn = rng.choice([-1, 1])
            cx = x + turn * rad * math.cos(heading + math.pi / 2)
            cy = y + turn * rad * math.sin(heading + math.pi / 2)
            a0 = math.atan2(y - cy, x - cx)
            a1 = a0 + turn * min(4.0 * step / rad, 2.0)
            x, y = cx + rad * math.cos(a1), cy + rad * math.sin(a1)
            heading += a1 - a0
            out.append(canon.ArcFeed(x, y, cx, cy, turn, z))
    return out


_SIZES = st.tuples(st.sampled_from([1, 7, 13]), st.sampled_from([50, 64]))


@settings(max_examples=2, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), sizes=st.tuples(st.sampled_from([7, 13, 64])))
def test_window_sizes_do_not_change_random_runs(seed: int, sizes: tuple[int]) -> None:
    assert_windows_plan_as_whole(g64_program(seed, 160), MACHINE, sizes)


# ----------------------------------------------------------------------------- slow
@pytest.mark.slow
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(60, 600), sizes=_SIZES)
def test_window_sizes_do_not_change_many_random_runs(
    seed: int, n: int, sizes: tuple[int, int]
) -> None:
    assert_windows_plan_as_whole(g64_program(seed, n), MACHINE, sizes)


@pytest.mark.slow
def test_all_golden_programs_plan_as_a_whole_in_small_windows() -> None:
    names = sorted(p.name for p in (LCNC_TP / "ngc").glob("*.ngc"))
    cut = 0
    for name in names:
        cut += assert_windows_plan_as_whole(program(name), MACHINE, (1, 7, 50, 64)) > 1
    assert len(names) > 100 and cut > 15
    for name in names:
        ref, shares, total = whole(program(name), MACHINE)
        for size in (1, 7) if name in RUNS else (7,):
            got, got_shares, got_total = streamed(program(name), MACHINE, size)
            assert_same(ref, got)
            assert (got_shares, got_total) == (shares, total)
