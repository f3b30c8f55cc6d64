"""kernel.ir.equivalence.equivalent, the array fast path of convert's verification: True
only where first_difference finds nothing, whatever mix of command objects and Moves
arrays each side comes as."""

from __future__ import annotations

import numpy as np
import pytest

from gcode.readers import read_text
from kernel.ir import canon
from kernel.ir.equivalence import Moves, equivalent, expanded, first_difference
from tests.convert_support import ir_of, programs


def _stream(shift: float = 0.0, feed: float = 100.0, speed: float = 1000.0) -> list:
    return [
        canon.UseLengthUnits(canon.Units.MM),
        canon.SetSpindleSpeed(speed),
        canon.StartSpindleClockwise(),
        canon.SetFeedRate(feed),
        canon.StraightTraverse(0.0, 0.0, 5.0),
        canon.StraightFeed(10.0 + shift, 0.0, 0.0),
        canon.ArcFeed(20.0, 0.0, 15.0, 0.0, -1, 0.0),
        canon.ChangeTool(2),
        canon.StraightFeed(20.0, 5.0, 0.0),
        canon.ProgramEnd(),
    ]


def _as_moves(stream: list) -> list:
    """The stream's plain moves and feed changes as Moves arrays, as a fast lane gives them."""
    out: list = []
    run: list = []
    feed = 0.0  # the rate in force, across runs

    def close() -> None:
        nonlocal feed
        if run:
            kind = np.array(
                [{canon.StraightTraverse: 0, canon.StraightFeed: 1}.get(type(c), 2) for c in run],
                dtype=np.int8,
            )
            rates, pos, rows = [], (0.0,) * 6, []
            for c in run:
                if isinstance(c, canon.SetFeedRate):
                    feed = c.rate
                else:
                    pos = (c.x, c.y, c.z, c.a, c.b, c.c)
                rows.append(pos)
                rates.append(feed)
            out.append(
                Moves(
                    kind, np.array(rows), np.array(rates), np.zeros(len(run), dtype=np.int64), "f"
                )
            )
            run.clear()

    for c in stream:
        if isinstance(c, canon.StraightTraverse | canon.StraightFeed | canon.SetFeedRate):
            run.append(c)
        else:
            close()
            out.append(c)
    close()
    return out


def test_the_same_stream_is_equivalent_as_objects_and_as_arrays() -> None:
    assert equivalent(_stream(), _stream())
    assert equivalent(_as_moves(_stream()), _stream())
    assert equivalent(_stream(), _as_moves(_stream()))
    assert [c.to_text() for c in expanded(_as_moves(_stream()))] == [c.to_text() for c in _stream()]


@pytest.mark.parametrize(
    "changed",
    [
        _stream(shift=0.001),
        _stream(feed=101.0),
        _stream(speed=1200.0),
        _stream()[:-2] + _stream()[-1:],
        [
            c if not isinstance(c, canon.ArcFeed) else canon.ArcFeed(20.0, 0.0, 15.0, 1.0, -1, 0.0)
            for c in _stream()
        ],
        [c if not isinstance(c, canon.ChangeTool) else canon.ChangeTool(3) for c in _stream()],
    ],
    ids=["position", "feed", "spindle", "a-motion-less", "arc-centre", "tool"],
)
def test_a_difference_is_left_to_first_difference(changed: list) -> None:
    assert not equivalent(_stream(), changed)
    assert not equivalent(_as_moves(_stream()), _as_moves(changed))
    assert first_difference(_stream(), changed, 0.001) is not None


def test_written_rounding_is_allowed_as_the_rule_allows_it() -> None:
    rounded = _stream(shift=0.0004)
    half = {canon.Units.MM: 0.0005, None: 0.0005}
    assert equivalent(_stream(), rounded, half)
    assert first_difference(_stream(), rounded, 0.001, half) is None
    assert not equivalent(_stream(), rounded)


def test_it_never_passes_what_the_rule_rejects_on_the_golden_programs() -> None:
    checked = passed = 0
    for program in programs()[::5]:
        ir = ir_of(program)
        if ir is None:
            continue
        moved = [
            canon.StraightFeed(c.x + 0.01, c.y, c.z, c.a, c.b, c.c, source=c.source)
            if isinstance(c, canon.StraightFeed)
            else c
            for c in ir
        ]
        if equivalent(_as_moves(list(ir)), list(ir)):  # the same program: passed, mostly
            passed += 1
            assert first_difference(ir, ir, 0.001) is None
        if moved != list(ir):
            assert not equivalent(list(ir), moved)
            checked += 1
    assert checked > 10 and passed > 30


def _xz_arcs(centre: float = 2.5, turns: int = 1, normal: float = 1.0) -> tuple[list, list]:
    """Two arcs in the XZ plane (in-plane end Z then X, normal axis Y), as command objects
    and with the second one's run as Moves arrays, as a reader's fast lane gives it."""
    head = [
        canon.UseLengthUnits(canon.Units.MM),
        canon.SelectPlane(canon.Plane.XZ),
        canon.SetFeedRate(100.0),
        canon.ArcFeed(5.0, 10.0, 2.5, 10.0, 1, 0.0),
    ]
    arc = canon.ArcFeed(0.0, 10.0, centre, 10.0, turns, normal)
    run = Moves(
        np.array([3], dtype=np.int8),
        np.array([[10.0, normal, 0.0, 0.0, 0.0, 0.0]]),
        np.array([100.0]),
        np.zeros(1, dtype=np.int64),
        "f",
        np.array([[0.0, 10.0, centre, 10.0, float(turns), normal]]),
    )
    return [*head, arc, canon.ProgramEnd()], [*head, run, canon.ProgramEnd()]


@pytest.mark.parametrize(
    "changed",
    [_xz_arcs(centre=2.6), _xz_arcs(turns=-1), _xz_arcs(normal=1.5)],
    ids=["centre", "turns", "normal-end"],
)
def test_arcs_out_of_the_xy_plane_compare_as_the_rule_does(changed: tuple[list, list]) -> None:
    """An arc of a run is compared at its position (its end in x y z), an arc command at its
    end placed by the plane: the same arcs agree either way round, a changed one never."""
    objects, arrays = _xz_arcs()
    assert equivalent(objects, arrays) and equivalent(arrays, objects)
    assert equivalent(arrays, arrays) and first_difference(objects, expanded(arrays), 0.001) is None
    for other in changed:
        assert first_difference(objects, list(expanded(other)), 0.001) is not None
        assert not equivalent(objects, other) and not equivalent(arrays, other)
        assert not equivalent(other, arrays)


def _two_units(inch_shift: float = 0.0, mm_shift: float = 0.0) -> list:
    """Moves in inches, then in millimetres (the fast path's tolerances per row)."""
    return [
        canon.UseLengthUnits(canon.Units.INCHES),
        canon.SetFeedRate(10.0),
        *[canon.StraightFeed(i + (inch_shift if i == 3 else 0.0), 1.0, 0.0) for i in range(6)],
        canon.UseLengthUnits(canon.Units.MM),
        canon.SetFeedRate(250.0),
        *[canon.StraightFeed(10.0 * i + (mm_shift if i == 4 else 0.0), 0.0, 0.0) for i in range(6)],
        canon.ProgramEnd(),
    ]


@pytest.mark.parametrize(
    ("inch_shift", "mm_shift", "same"),
    [
        (0.0, 0.0, True),
        (0.00008, 0.0, True),
        (0.0, 0.0004, True),
        (0.00012, 0.0, False),
        (0.0, 0.0008, False),
    ],
)
def test_each_motion_has_the_tolerance_of_its_own_units(
    inch_shift: float, mm_shift: float, same: bool
) -> None:
    """1e-4 inch in the inch part (2.54 um), the output's rounding (0.5 um) in the mm part:
    0.8 um off in millimetres differs though it is far within the inch part's tolerance."""
    half = {canon.Units.MM: 0.0005, canon.Units.INCHES: 0.00005, None: 0.0005}
    src, out = _two_units(), _two_units(inch_shift, mm_shift)
    assert (first_difference(src, out, 0.001, half) is None) is same
    assert equivalent(_as_moves(src), _as_moves(out), half) is same
    assert equivalent(src, _as_moves(out), half) is same


# A closed arc of several turns (its end on its start) written as one full circle a turn:
# each circle's end is on the start, so a piece must be found a turn further on, and the
# source ends only in its last half turn (a three-turn circle failed verification before)
@pytest.mark.parametrize(("circles", "same"), [(3, True), (2, False), (4, False)])
def test_a_closed_arc_of_three_turns_is_three_full_circles_not_two_or_four(
    circles: int, same: bool
) -> None:
    head = "G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10 F500\n"
    source = list(read_text(head + "G2 X10 Y0 I-10 J0 P3\nM2\n", "rs274ngc", "s.ngc"))
    output = list(read_text(head + "G2 X10 Y0 I-10 J0\n" * circles + "M2\n", "rs274ngc", "o.ngc"))
    assert (first_difference(source, output, 0.001, None) is None) is same
