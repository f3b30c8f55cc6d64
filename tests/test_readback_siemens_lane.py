"""The Siemens 840D reader's fast lane (gcode/siemens/lane.py) reads as its general path.

``cnc convert`` reads its 840D output back through the lane (``gcode.readers.read_chunks(...,
arcs=True)``). Here the lane is forced on for every file (it normally starts at
``LANE_MIN_BYTES``) and what it gives must be, command for command and source line for
source line, what the general 840D reader gives (the same commands, or the same error at
the same place):

* every hand-derived 840D program of tests/dialects/siemens840d (frames, R parameters,
  jumps, loops, subprograms, cycles: the lane must stand aside for all of them);
* random programs of plain and nearly plain blocks (hypothesis): blanks inside a word,
  words glued together, lower case, N numbers, F0, bad centres, the other planes, units
  and distance modes, comments, frames, modal calls;
* every golden and corpus program converted to 840D and read back both ways is in
  tests/test_readback_lanes.py (``LANE_TARGETS``), with the CAM-shaped program.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import gcode.siemens.reader as siemens_reader
import tests.lane_support as lane_support
from gcode.ngc.interpreter import InterpreterOptions
from gcode.siemens.lane import SiemensLane
from gcode.siemens.program import Program
from tests.lane_support import Listing, spy_lane, through_lanes

HERE = Path(__file__).resolve().parent
SUITE = sorted((HERE / "dialects" / "siemens840d").glob("*.mpf"))


@pytest.fixture
def lane_always(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    """The lane forced on for every file; counts the lanes opened and the lines their runs
    took, so a test can tell the compiled lane really ran."""
    monkeypatch.setattr(siemens_reader, "LANE_MIN_BYTES", 0)
    return spy_lane(monkeypatch, SiemensLane, "for_program")


def general(path: Path, opts: InterpreterOptions) -> Listing:
    return lane_support.general(path, "siemens840d", opts)


def through_lane(path: Path, opts: InterpreterOptions) -> Listing:
    return through_lanes(path, "siemens840d", opts)


@pytest.mark.parametrize("program", SUITE, ids=lambda p: p.stem)
def test_the_lane_reads_the_hand_derived_programs_as_the_general_path(
    program: Path, lane_always: dict[str, int]
) -> None:
    opts = InterpreterOptions(search_path=(str(program.parent),))
    assert through_lane(program, opts) == general(program, opts)
    assert lane_always["opened"] == 1


def test_the_lane_takes_the_plain_blocks_of_a_converted_program(
    tmp_path: Path, lane_always: dict[str, int]
) -> None:
    """The blocks the 840D writer emits for lines and arcs (G0 with F, modal X Y, G2/G3 with
    I J, G91), in every plane: the lane takes nearly all of them."""
    lines = ["G710", "G90 G17", "S8000 M3", "G0 X0 Y0 Z1 F600", "G1 Z-0.5"]
    x = 0.0
    for i in range(60):
        x += 1.0
        lines.append(f"X{x:g} Y{0.03 * i:g}")
        if i % 5 == 4:
            lines.append(f"G{2 + i % 2} X{x + 4:g} Y{0.03 * i:g} I2 J0")
            lines.append(f"G1 X{x + 5:g}")
            x += 5
    lines += ["G18", f"G3 X{x:g} Z-2.5 K-1 I0", "G19 G91", "G1 Y1 Z-1", "G3 Y2 Z0 J1 K0"]
    lines += ["G90 G17", "G0 X0 Y0", "M5", "M30"]
    path = tmp_path / "out.mpf"
    path.write_text("\n".join(lines) + "\n")
    opts = InterpreterOptions()
    assert through_lane(path, opts) == general(path, opts)
    assert lane_always["lines"] >= 80  # every block of the zig-zag and its arcs


#: blocks a random program is made of: the writer's plain blocks, and their near misses
#: that the 840D reads otherwise or refuses (the lane must leave those to the general path)
_NUMBERS = st.sampled_from(["1", "-2.5", "+3.", ".5", "-.25", "0", "12.125", "7"])
_AXIS = st.sampled_from(["X", "Y", "Z"])


@st.composite
def _block(draw: st.DrawFn) -> str:
    kind = draw(st.integers(0, 9))
    if kind <= 3:  # plain words, maybe with a motion code and a feed
        words = [f"{a}{draw(_NUMBERS)}" for a in draw(st.lists(_AXIS, max_size=3, unique=True))]
        if draw(st.booleans()):
            words.insert(0, f"G{draw(st.sampled_from(['0', '1', '01', '1.0']))}")
        if draw(st.booleans()):
            words.append(f"F{draw(st.sampled_from(['100', '0', '250.5']))}")
        return " ".join(words)
    if kind == 4:  # an arc by centre (often not on a circle: a radius error)
        end = f"X{draw(_NUMBERS)} Y{draw(_NUMBERS)}"
        centre = draw(st.sampled_from(["I1 J0", "I.5", "J-1", "I1 J0 K1", "", "CR=2"]))
        return f"G{draw(st.sampled_from(['2', '3']))} {end} {centre}".strip()
    if kind == 5:  # what the lane's kernel reads but the 840D's plain path does not
        return draw(
            st.sampled_from(
                ["G1 X 1.5", "G1 X1 .5", "G1 X- 5", "G1X1Y2", "X1Y2", "g1 x1 y2", "N10 G1 X1"]
            )
        )
    if kind == 6:  # modes
        return draw(
            st.sampled_from(["G90", "G91", "G17", "G18", "G19", "G70", "G700", "G710", "G94"])
        )
    if kind == 7:  # blocks the lane never takes
        return draw(
            st.sampled_from(
                ["; a comment", "", "G1 X1 ; moved", "TRANS X1", "ROT Z30", "R1=2", "X=R1", "M3"]
            )
        )
    if kind == 8:  # feeds and bare motion codes
        return draw(st.sampled_from(["F200", "F0", "G1", "G2", "G0 F50", "G1 F-1"]))
    return draw(st.sampled_from(["G1 X1 X2", "G1 G0 X1", "G2 X1 I1 J0 CR=1", "G33 Z1 K1"]))


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_block(), min_size=1, max_size=25))
def test_the_lane_reads_random_programs_as_the_general_path(
    tmp_path_factory: pytest.TempPathFactory, blocks: list[str]
) -> None:
    path = tmp_path_factory.mktemp("lane") / "random.mpf"
    path.write_text("G710 G90 G17\nF300\n" + "\n".join(blocks) + "\nM30\n")
    opts = InterpreterOptions()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(siemens_reader, "LANE_MIN_BYTES", 0)
        assert through_lane(path, opts) == general(path, opts)


def test_a_split_or_glued_word_keeps_the_lane_off_that_block(tmp_path: Path) -> None:
    """``X 1.5`` is not an 840D word (the general path refuses it) and ``G1X1`` is read by
    the 840D's full parser: the lane's kernel would take both, so its buffer ends first."""
    path = tmp_path / "split.mpf"
    path.write_text("G1 X1 F100\nX2\nG1 X 1.5\n")
    program = Program.load(str(path))
    lane = SiemensLane.for_program(program, True)
    assert lane is not None
    assert lane._limit(0) == len("G1 X1 F100\nX2\n")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(siemens_reader, "LANE_MIN_BYTES", 0)
        fast, error = through_lane(path, InterpreterOptions())
    assert error is not None and "SIEM-WORD" in error and ":3:" in error
    assert ("STRAIGHT_FEED(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)", 2) in fast
