"""``cnc plan`` window by window (kernel.stream, issue 19) against the whole-program pipeline
(kernel.simulation.plan_and_measure and kernel.report.breakdown): the same report, cycle
time and time per tool, with windows cut everywhere (a few commands per window): inside
runs of G64 P corner blends, at stops, with a look-ahead longer than the window (the
stopping-distance rule) and shorter, for the book and Grbl models, on the golden programs
and on random programs; for the linuxcnc model, whose windows end at stops or inside long
runs (tests/test_lcnc_windows.py), also on LinuxCNC's golden programs (tests/data/lcnc_tp).
The cycle-time parts and path lengths are sums numpy forms pairwise over the whole table:
they agree to 1e-12, everything else bit for bit.

The ``slow`` tests run ``cnc plan`` on CAM programs of 10**5 and 10**6 lines (the book
model; the linuxcnc model with stops and in one G64 run) and compare their peak resident
set sizes."""

from __future__ import annotations

import json
import math
import random
import sys
from dataclasses import asdict
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

import kernel.ir.canon as canon
from cli.plan import command
from gcode.readers import read
from kernel.diagnostics import Diagnostic
from kernel.machine import DEFAULT_MACHINE, Machine, parse_machine, with_controller
from kernel.path.segments import HOLD
from kernel.report.breakdown import Stretches, breakdown
from kernel.simulation import plan_and_measure
from kernel.stream import measure_streamed, plan_windows, streams

ROOT = Path(__file__).parent.parent
GOLDEN = ROOT / "tests" / "golden" / "ngc"

#: a slow machine with a small travel: limit hits, many runs crossing windows
TIGHT = parse_machine(
    'name = "tight"\n'
    + "".join(
        f"[axes.{a}]\nmin = {lo}\nmax = {hi}\nvelocity = {v}\nacceleration = 100\njerk = 1000\n"
        for a, lo, hi, v in (("x", -1, 30, 20), ("y", -1, 30, 20), ("z", -5, 30, 10))
    )
)
GRBL = with_controller(DEFAULT_MACHINE, model="grbl")
LCNC = with_controller(DEFAULT_MACHINE, model="linuxcnc")
LCNC_TP = ROOT / "tests" / "data" / "lcnc_tp"  # LinuxCNC's profile and golden programs
LONG = with_controller(DEFAULT_MACHINE, lookahead=10**6)  # the stopping-distance rule
SHORT = with_controller(DEFAULT_MACHINE, lookahead=3)
MACHINES = {
    "book": DEFAULT_MACHINE,
    "grbl": GRBL,
    "long": LONG,
    "short": SHORT,
    "tight": TIGHT,
    "linuxcnc": LCNC,
}
_SUMMED = ("cutting", "rapid", "dwell", "tool_change", "other")


def whole(cmds: list[canon.Command], machine: Machine) -> tuple[dict[str, Any], list, float]:
    """The report, the shares per tool and the cycle time of the whole-program pipeline."""
    st = Stretches()
    pl, report = plan_and_measure(st.watch(iter(cmds)), machine, "p")
    return asdict(report), [asdict(s) for s in breakdown(pl, st.tools)], pl.total_time


def streamed(
    cmds: list[canon.Command], machine: Machine, batch: int
) -> tuple[dict[str, Any], list, float]:
    st = Stretches()
    got = measure_streamed(st.watch(iter(cmds)), machine, "p", st.tools, st.operations, batch)
    assert got.tools is not None
    return asdict(got.report), [asdict(s) for s in got.tools.shares()], got.total_time


def assert_same(a: dict[str, Any], b: dict[str, Any]) -> None:
    """Reports equal: bit for bit but for the pairwise sums (1e-12 relative)."""
    a, b = dict(a), dict(b)
    for key in ("feed_length", "rapid_length"):
        assert b.pop(key) == pytest.approx(a.pop(key), rel=1e-12, abs=1e-12), key
    ca, cb = dict(a.pop("cycle")), dict(b.pop("cycle"))
    for key in _SUMMED:
        assert cb.pop(key) == pytest.approx(ca.pop(key), rel=1e-12, abs=1e-12), key
    assert ca == cb
    assert a == b


def check(cmds: list[canon.Command], machine: Machine, batches: tuple[int, ...]) -> dict:
    ref, shares, total = whole(cmds, machine)
    for batch in batches:
        got, got_shares, got_total = streamed(cmds, machine, batch)
        assert_same(ref, got)
        assert got_shares == shares and got_total == total, batch
    return ref


def golden(name: str) -> list[canon.Command]:
    with open(GOLDEN / name) as fh:
        return list(canon.read_commands(fh, name, keep_linuxcnc=True))


def random_program(seed: int, n: int = 160) -> list[canon.Command]:
    """Lines, arcs, rapids, feed changes, G64 P / G61 / G61.1, dwells and tool changes."""
    rng = random.Random(seed)
    x = y = z = 0.0
    out: list[canon.Command] = [canon.SetFeedRate(600.0)]
    for _ in range(n):
        r = rng.random()
        if r < 0.55:
            if rng.random() < 0.05:  # a zero-length move
                out.append(canon.StraightFeed(x, y, z))
                continue
            x += rng.uniform(-3, 3)
            y += rng.uniform(-3, 3)
            z += rng.uniform(-0.3, 0.3) * (rng.random() < 0.3)
            out.append(canon.StraightFeed(x, y, z))
        elif r < 0.65:
            rad = rng.uniform(0.5, 4)
            a0 = rng.uniform(0, 2 * math.pi)
            cx, cy = x - rad * math.cos(a0), y - rad * math.sin(a0)
            a1 = a0 + rng.uniform(-3, 3)
            x, y = cx + rad * math.cos(a1), cy + rad * math.sin(a1)
            out.append(canon.ArcFeed(x, y, cx, cy, 1 if a1 > a0 else -1, z))
        elif r < 0.70:
            x += rng.uniform(-10, 10)
            y += rng.uniform(-10, 10)
            out.append(canon.StraightTraverse(x, y, z + 1.0))
            out.append(canon.StraightFeed(x, y, z))
        elif r < 0.78:
            out.append(canon.SetFeedRate(rng.choice((120.0, 600.0, 1500.0, 3000.0))))
        elif r < 0.90:
            mode = rng.choice(list(canon.MotionMode))
            tol = rng.choice((0.0, 0.01, 0.2)) if mode is canon.MotionMode.CONTINUOUS else 0.0
            out.append(canon.SetMotionControlMode(mode, tol))
        elif r < 0.95:
            out.append(canon.Dwell(rng.choice((0.0, 0.01))))
        else:
            out.append(canon.ChangeTool(rng.randint(1, 3)))
    return out


def blended_zigzag(n: int) -> list[canon.Command]:
    """A run of ``n`` G64 P corners, every one blended (no cut before the program's end)."""
    out: list[canon.Command] = [
        canon.SetFeedRate(2000.0),
        canon.SetMotionControlMode(canon.MotionMode.CONTINUOUS, 0.05),
    ]
    out += [canon.StraightFeed(2.0 * i, 1.5 * (i % 2), 0.0) for i in range(1, n)]
    out.append(canon.Dwell(0.0))
    out += [canon.StraightFeed(2.0 * n + i, 3.0 * (i % 2), 0.0) for i in range(1, n)]
    return out


# ----------------------------------------------------------------------------- default run
@pytest.mark.parametrize("model", ["book", "grbl", "long", "short", "linuxcnc"])
def test_window_cuts_inside_blends_and_at_stops(model: str) -> None:
    ref = check(blended_zigzag(40), MACHINES[model], (1, 5, 16))
    assert ref["segments"] > 60


@pytest.mark.parametrize("seed", range(3))
def test_random_programs_plan_as_a_whole(seed: int) -> None:
    cmds = random_program(seed, 50)
    check(cmds, MACHINES[("book", "grbl", "linuxcnc")[seed]], (1, 9))


@pytest.mark.parametrize(
    "name", ["072_g20_arcs_planes.canon", "114_g64_p_q_blending.canon", "097_tool_change_m6.canon"]
)
def test_golden_programs_plan_as_a_whole(name: str) -> None:
    if not (GOLDEN / name).exists():
        pytest.skip(f"{name} not in the corpus")
    for m in (DEFAULT_MACHINE, GRBL, LCNC):
        check(golden(name), m, (7,))


def test_the_first_error_is_the_whole_programs() -> None:
    """PLAN-FEED in the first window, PLAN-AXIS in a later one: PLAN-AXIS, as the whole
    program's table checks axes before feeds; a travel error after a planner error."""
    ok = [canon.SetFeedRate(600.0)] + [canon.StraightFeed(i, 0.0, 0.0) for i in range(1, 30)]
    no_feed = [canon.SetFeedRate(0.0), canon.StraightFeed(0.0, 5.0, 0.0)]
    axis = [canon.SetFeedRate(600.0), canon.StraightFeed(0.0, 5.0, 0.0, 10.0)]
    cases = [ok + no_feed + ok + axis, ok + axis + no_feed, ok + no_feed + ok]
    for cmds in cases:
        with pytest.raises(Diagnostic) as ref:
            whole(cmds, DEFAULT_MACHINE)
        for batch in (2, 9):
            with pytest.raises(Diagnostic) as got:
                streamed(cmds, DEFAULT_MACHINE, batch)
            assert (got.value.code, got.value.location) == (ref.value.code, ref.value.location)


@pytest.mark.parametrize("model", ["short", "long"])
def test_windows_stay_small_in_a_run_of_blends(model: str) -> None:
    """A run of blended corners with no stop is planned as it comes: by the look-ahead of
    three rows, or with an unbounded look-ahead by the stopping distance."""
    cmds = blended_zigzag(120)[:121]
    windows = list(plan_windows(iter(cmds), MACHINES[model], "p", batch=10))
    assert len(windows) > 10
    assert max(len(w.path.segments) for w in windows) <= 60


def test_models_that_plan_whole() -> None:
    assert streams(DEFAULT_MACHINE) and streams(GRBL) and streams(LCNC)
    assert not streams(with_controller(DEFAULT_MACHINE, accdec="scurve"))


def lcnc_program(name: str) -> list[canon.Command]:
    return list(read(LCNC_TP / "ngc" / name, "rs274ngc"))


@pytest.mark.parametrize(
    "name",
    ["lcnc_rick_combine.native.ngc", "lcnc_parabolic_varying.G64P.ngc", "corpus_axis.G64P.ngc"],
)
def test_linuxcnc_golden_programs_plan_as_a_whole(name: str) -> None:
    """LinuxCNC's golden programs (spindle and coolant waits, dwells: cut there) on its
    profile: the whole-program plan's report, cycle time and time per tool."""
    check(lcnc_program(name), parse_machine((LCNC_TP / "machine.toml").read_text()), (1, 7))


def test_linuxcnc_windows_end_at_stops() -> None:
    """The linuxcnc model's windows end at hold rows (a dwell) where the runs of blends
    between them are short; a long run with no stop is cut into windows of about a batch
    (tests/test_lcnc_windows.py), planned as the whole program."""
    run = blended_zigzag(40)
    stops = [c for k in range(6) for c in (*run, canon.Dwell(0.01 * k))]
    windows = list(plan_windows(iter(stops), LCNC, "p", batch=10))
    assert len(windows) >= 6
    assert all(w.path.segments["kind"][-1] == HOLD for w in windows[:-1])
    assert max(len(w.path.segments) for w in windows) < 200
    check(stops, LCNC, (10, 64))
    no_stop = [c for k in range(4) for c in run if not isinstance(c, canon.Dwell)]
    windows = list(plan_windows(iter(no_stop), LCNC, "p", batch=10))
    assert len(windows) > 10 and max(len(w.path.segments) for w in windows[:-1]) < 60
    assert len(windows[-1].path.segments) < 200  # the rows planned after the last cut
    check(no_stop, LCNC, (10, 64))


def test_linuxcnc_windows_end_at_traverses_and_exact_stops() -> None:
    """Blended runs joined by traverses, and by G61.1 exact stops, with no hold row:
    windows end at those joins, and plan as the whole program."""
    run = blended_zigzag(30)
    run = [c for c in run if not isinstance(c, canon.Dwell)]
    exact = canon.SetMotionControlMode(canon.MotionMode.EXACT_STOP)
    cmds: list[canon.Command] = []
    for k in range(5):
        cmds += run
        cmds.append(canon.StraightTraverse(0.0, 0.0, 1.0 + k))
        cmds.append(canon.StraightFeed(0.0, 0.0, 0.0))
    cmds += [exact] + [canon.StraightFeed(float(i), 2.0 * (i % 2), 0.0) for i in range(20)]
    for batch in (10, 64):
        windows = list(plan_windows(iter(cmds), LCNC, "p", batch=batch))
        assert len(windows) >= 5 and not any(
            (w.path.segments["kind"] == HOLD).any() for w in windows
        )
    check(cmds, LCNC, (1, 10, 64))


def test_linuxcnc_first_error_is_the_whole_programs() -> None:
    """A later window's table error before an earlier window's travel error, as the
    whole program's table is made before it is planned and checked."""
    ok = [canon.SetFeedRate(600.0)] + [canon.StraightFeed(i, 0.0, 0.0) for i in range(1, 30)]
    ok.append(canon.Dwell(0.1))
    no_feed = [canon.SetFeedRate(0.0), canon.StraightFeed(0.0, 5.0, 0.0), canon.Dwell(0.0)]
    far = [canon.SetFeedRate(600.0), canon.StraightFeed(5000.0, 5.0, 0.0), canon.Dwell(0.0)]
    for cmds in (ok + far + ok + no_feed, ok + far + ok, ok + no_feed + ok):
        with pytest.raises(Diagnostic) as ref:
            whole(cmds, LCNC)
        for batch in (2, 9):
            with pytest.raises(Diagnostic) as got:
                streamed(cmds, LCNC, batch)
            assert (got.value.code, got.value.location) == (ref.value.code, ref.value.location)


# ----------------------------------------------------------------------------- slow
@pytest.mark.slow
def test_all_golden_programs_plan_as_a_whole() -> None:
    names = sorted(p.name for p in GOLDEN.glob("*.canon"))
    done = 0
    for name in names:
        cmds = golden(name)
        for m in (DEFAULT_MACHINE, GRBL, LONG, LCNC):
            try:
                ref, _, total = whole(cmds, m)
            except Diagnostic:
                continue
            if total > 120.0:
                continue
            for batch in (1, 13):
                got, _, got_total = streamed(cmds, m, batch)
                assert_same(ref, got)
                assert got_total == total
            done += 1
    assert done > 200


@pytest.mark.slow
def test_all_linuxcnc_golden_programs_plan_as_a_whole() -> None:
    machine = parse_machine((LCNC_TP / "machine.toml").read_text())
    names = sorted(p.name for p in (LCNC_TP / "ngc").glob("*.ngc"))
    for name in names:
        check(lcnc_program(name), machine, (1, 7))
    assert len(names) > 100


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(2, 40))
def test_many_random_programs_plan_as_a_whole(seed: int) -> None:
    cmds = random_program(seed, 400)
    for m in MACHINES.values():
        check(cmds, m, (1, 11, 97))


def _peak_rss(lines: int, tmp: Path, extra: tuple[str, ...] = (), stop_every: int = 0) -> float:
    """``cnc plan``'s peak RSS (MB) on a CAM program of ``lines`` lines (``extra``: more
    arguments; ``stop_every``: a stop every so many lines)."""
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_memory import peak
    from cam_program import write_program

    prog = write_program(tmp / f"cam_{lines}.ngc", lines, stop_every=stop_every)
    rss, _cpu, _wall, rc = peak([sys.executable, "-m", "cli.main", "plan", str(prog), *extra])
    assert rc == 0
    prog.unlink()
    return rss


@pytest.mark.slow
def test_plan_peak_memory_is_flat_in_program_length(tmp_path: Path) -> None:
    """Peak RSS at 10**6 lines within 1.3 times that at 10**5 (kernel.stream)."""
    small = _peak_rss(10**5, tmp_path)
    large = _peak_rss(10**6, tmp_path)
    assert large <= 1.3 * small, (small, large)


@pytest.mark.slow
def test_linuxcnc_plan_peak_memory_is_flat_with_stops(tmp_path: Path) -> None:
    """The linuxcnc model (planned from stop to stop) on CAM programs with a stop every
    1,000 lines: peak RSS at 10**6 lines within 1.3 times that at 10**5."""
    extra = ("--machine", str(LCNC_TP / "machine.toml"))
    small = _peak_rss(10**5, tmp_path, extra, 1000)
    large = _peak_rss(10**6, tmp_path, extra, 1000)
    assert large <= 1.3 * small, (small, large)


@pytest.mark.slow
def test_linuxcnc_plan_peak_memory_is_flat_in_a_g64_run(tmp_path: Path) -> None:
    """The linuxcnc model on CAM programs in one G64 run with no stop (cut at joins):
    peak RSS at 10**6 lines within 1.3 times that at 10**5."""
    extra = ("--machine", str(LCNC_TP / "machine.toml"))
    small = _peak_rss(10**5, tmp_path, extra)
    large = _peak_rss(10**6, tmp_path, extra)
    assert large <= 1.3 * small, (small, large)


def test_cli_plan_streams_the_bench_program(tmp_path: Path) -> None:
    """``cnc plan`` on a CAM program: the cycle time and the time per tool."""
    sys.path.insert(0, str(ROOT / "bench"))
    from cam_program import write_program

    prog = write_program(tmp_path / "cam.ngc", 120)
    out = CliRunner().invoke(command, [str(prog), "--format", "json"])
    assert out.exit_code == 0, out.output
    doc = json.loads(out.output)
    assert doc["times"]["cycle"] == doc["cycle"]["total"] > 0
    assert [t["label"] for t in doc["times"]["tools"]] == ["T1"]
