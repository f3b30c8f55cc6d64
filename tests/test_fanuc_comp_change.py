"""G41/G42 given again while compensation is on (issue 14), Fanuc and Haas readers.

Expected behaviour from the Fanuc 0i-MF operator's manual ("Tool radius compensation":
change of the compensation value in offset mode): the same G41/G42 and D again changes
nothing; a new D takes effect at the end of the block that gives it (the vector at its
start keeps the old value, the vector at its end is computed for the new one). LinuxCNC
refuses G41 while on, so the no-change case is compared with ``rs274`` running the
program without the repeated code; the new-D case is derived by hand below.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.fanuc.reader import interpret_text as fanuc
from gcode.haas.reader import interpret_text as haas
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import rs274

SIM_TBL = Path(__file__).resolve().parent / "golden" / "ngc" / "sim.tbl"

HEAD = "O1000\nG21 G90 G17 G40 G80\nG10 L12 P1 R2.\nG10 L12 P2 R3.\nG0 X0 Y0 Z5.\n"


def _path(commands: list[canon.Command]) -> list[tuple[float, ...]]:
    out = []
    for c in commands:
        if c.NAME in ("STRAIGHT_FEED", "STRAIGHT_TRAVERSE"):
            out.append((c.x, c.y))
        elif c.NAME == "ARC_FEED":
            out.append((c.first_end, c.second_end, c.first_axis, c.second_axis))
    return out


@pytest.mark.parametrize("read", [fanuc, haas], ids=["fanuc", "haas"])
def test_the_same_g41_and_d_again_changes_nothing(read) -> None:  # noqa: ANN001
    again = HEAD + "G1 G41 D1 X10. Y0 F100.\nG41 D1 Y10.\nG41 X20.\nG40 X30. Y30.\nM30\n"
    once = HEAD + "G1 G41 D1 X10. Y0 F100.\nY10.\nX20.\nG40 X30. Y30.\nM30\n"
    assert _path(list(read(again))) == _path(list(read(once)))


@pytest.mark.reference
@pytest.mark.skipif(shutil.which("rs274") is None, reason="needs LinuxCNC's rs274")
def test_the_same_g41_again_moves_as_rs274_without_it(tmp_path: Path) -> None:
    # sim.tbl: T1 diameter 0.125 in, so offset 1 holds the radius 0.0625 in
    body = "G1 G41 D1 X1. Y0 F10.\n{again}Y1.\nX2.\nG40 X3. Y3.\nM30\n"
    ours = fanuc(
        "O1\nG20 G90 G17 G40 G80\nG10 L12 P1 R0.0625\nT1 M6\nG0 X0 Y0 Z0.5\n"
        + body.format(again="G41 D1\n")
    )
    theirs = rs274(
        "G20 G90 G17 G40 G80\nT1 M6\nG0 X0 Y0 Z0.5\n" + body.format(again=""), SIM_TBL, tmp_path
    )
    assert canon_equiv.compare(list(canon.write_text(ours)), theirs) == []


def test_a_new_d_applies_from_the_end_of_its_block() -> None:
    program = HEAD + "G1 G41 D1 X10. Y0 F100.\nY10.\nG41 D2 X20.\nY20.\nG40 X30. Y30.\nM30\n"
    assert _path(list(fanuc(program))) == [
        (0.0, 0.0),
        # start-up, D1 = 2: the +X line's offset y = 2 meets the +Y line's x = 8
        (8.0, 2.0),
        (8.0, 10.0),
        # convex corner at (10, 10), old radius 2: arc from (8, 10) to (10, 12)
        (10.0, 12.0, 10.0, 10.0),
        # the D2 block: from the old vector (10, 12) to its end vector for radius 3, where
        # its offset y = 13 meets the next (+Y) line's offset x = 17
        (17.0, 13.0),
        (17.0, 20.0),  # the Y20. line on the new offset path, G40 ends it square
        (30.0, 30.0),
    ]


def test_a_change_of_side_is_refused_at_its_line() -> None:
    program = HEAD + "G1 G41 D1 X10. Y0 F100.\nY10.\nG42 D1 X20.\nM30\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc(program))
    assert info.value.code == "FANUC-COMP-CHANGE"
    assert info.value.location is not None and info.value.location.line == 8


def test_a_new_d_on_an_arc_is_refused_at_its_line() -> None:
    program = HEAD + "G1 G41 D1 X10. Y0 F100.\nY10.\nG41 D2 G3 X0. Y10. R5.\nM30\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc(program))
    assert info.value.code == "FANUC-COMP-CHANGE"
    assert info.value.location is not None and info.value.location.line == 8
