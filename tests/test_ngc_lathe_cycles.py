"""LinuxCNC's lathe cycles G70-G72.2 beyond the rs274 goldens (tests/golden/ngc 199-224).

The goldens pin what rs274 2.9.0 prints. Here: the programs on which rs274 2.9.0 loops for
ever, checked against LinuxCNC 2.9.10's own expected output (tests/data/lathe_cycles), and
closed forms of the profile geometry (offsets, intersections, the turn and mirrors undone).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.ngc.lathe_profile import Arc, Line, Profile, _Turned, join
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table
from tests.canon_equiv import compare

DATA = Path(__file__).parent / "data" / "lathe_cycles"


def test_endless_loop_2_ends_as_linuxcnc_2_9_10_expects() -> None:
    ours = list(canon.write_text(interpret(DATA / "g71-endless-loop_2.ngc", InterpreterOptions())))
    expected = (DATA / "g71-endless-loop_2.expected").read_text().splitlines()
    numbered = [f"{i:5d} {line.strip()}" for i, line in enumerate(expected, 1)]
    assert compare(ours, numbered) == []


def test_a_layer_that_repeats_for_ever_is_refused_at_its_cycle() -> None:
    with pytest.raises(Diagnostic) as info:
        for _ in interpret(DATA / "g71-endless-loop.ngc", InterpreterOptions()):
            pass
    assert info.value.code == "NGC-G7X-NO-PROGRESS"
    assert info.value.location.line == 18  # the G71.2 block; G71.1 before it runs through


class _Record:
    def __init__(self) -> None:
        self.moves: list[tuple[str, complex]] = []

    def feed(self, end: complex) -> None:
        self.moves.append(("feed", end))

    def rapid(self, end: complex) -> None:
        self.moves.append(("rapid", end))

    def arc(self, ccw: bool, centre: complex, end: complex) -> None:
        self.moves.append(("arc", end))


def test_a_line_offsets_to_its_left() -> None:
    seg = Line(0j, -10 + 0j)  # along -Z: its left is +X
    seg.offset(1.0)
    assert seg.start == pytest.approx(1j) and seg.end == pytest.approx(-10 + 1j)


def test_two_lines_meet_where_they_cross() -> None:
    a = Line(10j, -10 + 10j)
    b = Line(-5 + 20j, -5 + 0j)
    join(a, b)
    assert a.end == pytest.approx(-5 + 10j) and b.start == pytest.approx(-5 + 10j)


def test_arc_crossings_are_on_the_arc_only() -> None:
    quarter = Arc(True, 5 + 0j, 0j, 5j)  # counter-clockwise from +Z to +X, radius 5
    assert quarter.crossings(3.0) == pytest.approx([4.0])
    assert quarter.crossings(6.0) == []


@pytest.mark.parametrize("state", range(8))
def test_turned_moves_undo_the_turn_and_mirrors(state: int) -> None:
    p = complex(-3.25, 7.5)
    seg = Line(p, p)
    if state & 4:
        seg.turn()
    if state & 2:
        seg.mirror_x()
    if state & 1:
        seg.mirror_z()
    out = _Record()
    _Turned(out, state).feed(seg.start)
    assert out.moves[0][1] == pytest.approx(p)


def test_finishing_a_step_follows_the_profile_at_the_allowance() -> None:
    # profile X6 Z0 -> Z-10 -> X20 from start X25 Z2; one pass at distance 0.5
    lead = Line(complex(2, 25), complex(0, 6))
    profile = Profile(
        [lead, Line(complex(0, 6), complex(-10, 6)), Line(complex(-10, 6), -10 + 20j)]
    )
    out = _Record()
    profile.finishing(out, 25.0, 2.0, 0.5, 0.5, 1.0)
    points = [m[1] for m in out.moves]
    assert out.moves[0] == ("rapid", pytest.approx(complex(2, 25)))
    # the offset profile: X6.5 from Z0 to Z-9.5, then X up to 20 at Z-9.5
    assert points[1] == pytest.approx(complex(0, 6.5))
    assert points[2] == pytest.approx(complex(-9.5, 6.5))
    assert points[3] == pytest.approx(complex(-9.5, 20))
    assert all(math.isfinite(p.real) and math.isfinite(p.imag) for p in points)


def test_linuxcnc_lathe_demo_runs_its_g71_1_as_rs274_and_stops_at_t10() -> None:
    golden = Path(__file__).parent / "golden" / "ngc" / "sim.tbl"
    tools = read_tool_table(golden.read_text().splitlines(), str(golden))
    program = DATA / "lathe_g70_71_demo.ngc"
    ours: list[canon.Command] = []
    with pytest.raises(Diagnostic) as info:
        for cmd in interpret(program, InterpreterOptions(tool_table=tools)):
            ours.append(cmd)
    assert info.value.location.line == 29  # G40 T10M6G43: tool 10 is not in the table
    reference = program.with_suffix(".canon").read_text().splitlines()
    assert compare(list(canon.write_text(ours)), reference) == []
