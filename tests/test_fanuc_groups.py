"""Fanuc G code groups (issue 14): one table for mill and lathe, G80 in group 09.

Expected behaviour from the Fanuc 0i-MF/30i-B operator's manuals' G code list and its
notes: codes of one group in a block, the last counts; a canned cycle (group 09) leaves
group 01 as it was, so after G80 an axis word moves in the group 01 mode (G00 at power-on).
Where the program is also RS274/NGC, the equivalent program (the group 01 code written
out after G80, as LinuxCNC's G80 is in group 1) is run through LinuxCNC's ``rs274``.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.fanuc import executor, groups
from gcode.fanuc import lathe as fanuc_lathe
from gcode.fanuc.reader import interpret_text
from kernel.ir import canon
from tests.convert_support import rs274

SIM_TBL = Path(__file__).resolve().parent / "golden" / "ngc" / "sim.tbl"

#: a shop program's safe-start line, then G43 with no motion code of its own
SAFE_START = """O1000
G21 G90 G17 G40 G80
G43 H1 Z50.
G1 X5. F200.
G99 G81 X10. Y10. Z-5. R2. F100.
X20.
G80 Z30.
X30.
G0 G81 X40. Z-5. R2.
G80 G0 Z40.
M30
"""
#: the same program as RS274/NGC reads it: group 01 written out where Fanuc keeps it
SAFE_START_NGC = """G21 G90 G17 G40 G80
G0 G43 H1 Z50.
G1 X5. F200.
G99 G81 X10. Y10. Z-5. R2. F100.
X20.
G80
G1 Z30.
X30.
G81 X40. Z-5. R2.
G80 G0 Z40.
M30
"""


def _moves(text: str, **kw: bool) -> list[canon.Command]:
    return [c for c in interpret_text(text, **kw) if c.NAME in canon_equiv.MOTION_NAMES]


def test_the_table_holds_every_code_the_readers_accept() -> None:
    accepted = executor._PASS | executor._OWN
    assert set(groups.MILL) == accepted
    assert set(groups.HAAS_MILL) == executor._HAAS
    lathe_codes = fanuc_lathe._PASS | fanuc_lathe._OWN | set(fanuc_lathe._SINGLE)
    assert set(groups.LATHE) == lathe_codes | set(fanuc_lathe._MULTI) | {800}
    assert groups.MILL[800] == groups.CYCLE and groups.MILL[0] == groups.MOTION
    assert groups.LATHE[800] == groups.LATHE_CYCLE


def test_g80_leaves_group_01_so_g43_after_the_safe_start_line_moves_at_rapid() -> None:
    moves = _moves(SAFE_START)
    assert moves[0] == canon.StraightTraverse(0.0, 0.0, 50.0, 0.0, 0.0, 0.0)
    # G80 Z30. after a cycle started in G01: the move is a G01 feed
    after = [m for m in moves if m.NAME == "STRAIGHT_FEED" and m.z == 30.0]
    assert len(after) == 2  # Z30. and X30.
    # G80 G0 Z40.: the cycle ends and the block moves at rapid
    assert moves[-1] == canon.StraightTraverse(40.0, 10.0, 40.0, 0.0, 0.0, 0.0)


@pytest.mark.reference
@pytest.mark.skipif(shutil.which("rs274") is None, reason="needs LinuxCNC's rs274")
def test_safe_start_program_moves_as_rs274_moves_its_ngc_equivalent(tmp_path: Path) -> None:
    ours = list(canon.write_text(interpret_text(SAFE_START)))
    theirs = rs274(SAFE_START_NGC, SIM_TBL, tmp_path)
    assert canon_equiv.compare(ours, theirs) == []


def test_the_lathe_reads_g80_in_its_safe_start_line() -> None:
    text = "O1000\nG18 G20 G40 G80 G99\nT0101\nS500 M3\nG0 X1. Z0.1\nG80\nG1 Z-1. F0.01\nM30\n"
    moves = _moves(text, lathe=True)
    assert moves == [
        canon.StraightTraverse(0.5, 0.0, 0.1, 0.0, 0.0, 0.0),
        canon.StraightFeed(0.5, 0.0, -1.0, 0.0, 0.0, 0.0),
    ]


@pytest.mark.parametrize(
    ("block", "expected_inch"), [("G21 G20", True), ("G20 G21", False), ("G21 G20 G21", False)]
)
def test_of_two_codes_of_one_group_the_last_counts(block: str, expected_inch: bool) -> None:
    units = [
        c for c in interpret_text(f"O1\n{block}\nG0 X1.\nM30\n") if c.NAME == "USE_LENGTH_UNITS"
    ]
    assert (units[-1].units is canon.Units.INCHES) is expected_inch


def test_a_group_01_code_after_the_cycle_code_cancels_it_in_the_block() -> None:
    text = "O1\nG0 Z10.\nG81 G0 X5. Y5.\nX6.\nM30\n"
    assert _moves(text)[1:] == [
        canon.StraightTraverse(5.0, 5.0, 10.0, 0.0, 0.0, 0.0),
        canon.StraightTraverse(6.0, 5.0, 10.0, 0.0, 0.0, 0.0),
    ]
