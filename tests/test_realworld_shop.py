"""Real Fanuc, Haas and Siemens programs from public repositories read as their controls
read them (issue 14): every program of tests/realworld/shop/manifest.toml either runs to
its golden IR or is refused with the code and line the manifest names, within a time bound
(no hang); each golden is checked a second way where the manifest says so.

The goldens were made by our readers (tests/realworld/shop/regen.py) and checked: by
``rs274`` reading our IR written as RS274/NGC (``<file>.rs274.canon``, committed, so the
default run compares without rs274; the ``reference`` test makes it again), by CEAD's
nc-gcode-interpreter (pip ``nc_gcode_interpreter``; skipped where it is not installed) for
Siemens programs, and by hand for the programs whose manifest note says what was checked.
"""

from __future__ import annotations

import csv
import shutil
import signal
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import rs274
from tests.shop_suite import CHECKS, HERE, TOOL_TABLE, Entry, entries, ngc_text, our_ir

ENTRIES = entries()
#: a program the control runs in a blink must not take the reader longer (no hang)
TIME_LIMIT = 60
#: positions printed with 3 decimals (the peer) and 4 (the golden) agree within this
PRINTED = 5e-4 + 5e-5 + 1e-9


def _param(entry: Entry) -> object:
    marks = [pytest.mark.slow] if entry.slow else []
    return pytest.param(entry, id=entry.name, marks=marks)


RUNS = [_param(e) for e in ENTRIES if e.expect == "runs"]
REFUSED = [_param(e) for e in ENTRIES if e.expect == "refused"]


@contextmanager
def _bounded(seconds: int) -> Iterator[None]:
    """Fail instead of hanging: an alarm ``seconds`` from now."""

    def _timeout(signum: int, frame: object) -> None:
        raise AssertionError(f"the reader took more than {seconds} s")

    previous = signal.signal(signal.SIGALRM, _timeout)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def test_the_manifest_lists_every_program_once_with_a_complete_expectation() -> None:
    names = [e.name for e in ENTRIES]
    assert len(names) == len(set(names))
    on_disk = {
        p.relative_to(HERE).as_posix()
        for p in HERE.rglob("*")
        if p.suffix.lower() in (".nc", ".mpf", ".spf")
    }
    assert on_disk == set(names)
    for e in ENTRIES:
        assert e.dialect == e.name.split("/")[0], e.name
        assert e.expect in ("runs", "refused"), e.name
        if e.expect == "refused":
            assert e.code and e.line and len(e.reason) > 20, e.name
        else:
            assert e.golden.exists(), e.name
            assert e.checks and set(e.checks) <= CHECKS, e.name
            if e.rs274:
                assert e.second.exists(), e.name


@pytest.mark.parametrize("entry", RUNS)
def test_program_runs_to_its_golden_ir(entry: Entry) -> None:
    with _bounded(TIME_LIMIT):
        ours = list(canon.write_text(our_ir(entry)))
    expected = entry.golden.read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []
    assert ours == expected  # the golden is this reader's exact text


@pytest.mark.parametrize("entry", REFUSED)
def test_program_is_refused_where_the_control_stops(entry: Entry) -> None:
    with _bounded(TIME_LIMIT), pytest.raises(Diagnostic) as info:
        our_ir(entry)
    err = info.value
    assert (err.code, err.location.line) == (entry.code, entry.line), err.message
    assert err.location.file is not None and Path(err.location.file).name == entry.path.name
    assert err.location.column is not None and err.location.column >= 1


@pytest.mark.parametrize("entry", [_param(e) for e in ENTRIES if e.rs274])
def test_golden_equals_rs274_reading_our_ir_written_as_rs274ngc(entry: Entry) -> None:
    expected = entry.golden.read_text().splitlines()
    second = entry.second.read_text().splitlines()
    assert canon_equiv.compare(expected, second) == []


@pytest.mark.reference
@pytest.mark.skipif(shutil.which("rs274") is None, reason="needs LinuxCNC's rs274")
@pytest.mark.parametrize("entry", [_param(e) for e in ENTRIES if e.rs274])
def test_rs274_reading_is_what_rs274_prints_today(entry: Entry, tmp_path: Path) -> None:
    golden = entry.golden.read_text().splitlines()
    ir = list(canon.read_commands(golden, entry.name, keep_linuxcnc=True))
    lines = rs274(ngc_text(ir), TOOL_TABLE, tmp_path)
    assert canon_equiv.compare(lines, entry.second.read_text().splitlines()) == []


def _dedupe(points: list[tuple[float, ...]]) -> list[tuple[float, ...]]:
    out: list[tuple[float, ...]] = []
    for p in points:
        if not out or max(abs(a - b) for a, b in zip(p, out[-1], strict=True)) > 1e-6:
            out.append(p)
    return out


def _peer_points(table: Path) -> list[tuple[float, ...]]:
    """The positions X Y Z A CEAD's interpreter printed for the program (its repository's
    expected output, one row per block; an empty cell keeps the value before)."""
    rows = list(csv.DictReader(table.read_text().splitlines()))
    position = [0.0] * 4
    points = [tuple(position)]
    for row in rows:
        for k, axis in enumerate("XYZA"):
            cell = row.get(axis) or ""
            if cell.strip():
                position[k] = float(cell)
        points.append(tuple(position))
    return _dedupe(points)


def _our_points(lines: list[str], name: str) -> list[tuple[float, ...]]:
    """Our motions' end points X Y Z A plus the offsets in force (the peer prints positions
    with TRANS added; the IR keeps the frame's translation as an offset)."""
    g5x = [0.0] * 4
    g92 = [0.0] * 4
    points = [(0.0, 0.0, 0.0, 0.0)]
    for c in canon.read_commands(lines, name, keep_linuxcnc=True):
        if isinstance(c, canon.SetG5xOffset):
            g5x = [c.x, c.y, c.z, c.a]
        elif isinstance(c, canon.SetG92Offset):
            g92 = [c.x, c.y, c.z, c.a]
        elif isinstance(c, canon.StraightFeed | canon.StraightTraverse):
            p = (c.x, c.y, c.z, c.a)
            points.append(tuple(v + g5x[k] + g92[k] for k, v in enumerate(p)))
        elif isinstance(c, canon.ArcFeed):  # the suite's peer programs are in G17
            p = (c.first_end, c.second_end, c.axis_end_point, c.a)
            points.append(tuple(v + g5x[k] + g92[k] for k, v in enumerate(p)))
    return _dedupe(points)


@pytest.mark.parametrize("entry", [_param(e) for e in ENTRIES if "peer" in e.checks])
def test_golden_positions_are_the_peer_interpreters(entry: Entry) -> None:
    theirs = _peer_points(entry.path.parent / (entry.path.name + ".peer.csv"))
    ours = _our_points(entry.golden.read_text().splitlines(), entry.name)
    assert len(ours) == len(theirs), (ours, theirs)
    for a, b in zip(ours, theirs, strict=True):  # the peer prints 3 decimals, the golden 4
        assert max(abs(x - y) for x, y in zip(a, b, strict=True)) < PRINTED, (a, b)
