"""Siemens 840D input (issue 7): hand-derived programs and their expected IR.

Each ``tests/dialects/siemens840d/NNN_name.mpf`` has ``NNN_name.canon`` beside it: the IR
derived by hand from the 840D semantics (840D sl programming manual) with the derivation
in its ``#`` lines; subprograms (``*.SPF``) and the tool table ``tools.tbl`` lie beside
them. The reader's output must be equivalent (tests/canon_equiv.py).
"""

from __future__ import annotations

from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read_text
from gcode.siemens.reader import interpret, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table

HERE = Path(__file__).resolve().parent / "dialects" / "siemens840d"
PROGRAMS = sorted(HERE.glob("*.mpf"))


def _options() -> InterpreterOptions:
    table = HERE / "tools.tbl"
    return InterpreterOptions(
        tool_table=read_tool_table(table.read_text().splitlines(), str(table)),
        search_path=(str(HERE),),
    )


def test_every_program_has_its_expected_ir_with_a_derivation() -> None:
    assert len(PROGRAMS) >= 15
    for program in PROGRAMS:
        expected = program.with_suffix(".canon").read_text().splitlines()
        assert expected[0].startswith("# "), program.name
        assert list(canon.read_commands(expected, str(program)))


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_siemens_reader_gives_the_hand_derived_ir(program: Path) -> None:
    ours = list(canon.write_text(interpret(program, _options())))
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []


def test_commands_carry_their_source_line_and_column() -> None:
    text = "G710 G90\nN20 G1 X5 F100\n  G0 Z3\nM30\n"
    cmds = list(interpret_text(text, "p.mpf"))
    feed = next(c for c in cmds if isinstance(c, canon.StraightFeed))
    rapid = next(c for c in cmds if isinstance(c, canon.StraightTraverse))
    assert (feed.source.file, feed.source.line, feed.source.column) == ("p.mpf", 2, 5)
    assert (rapid.source.line, rapid.source.column) == (3, 3)


def test_the_registry_finds_the_reader_by_alias() -> None:
    cmds = list(read_text("G1 X1 F10\nM30\n", "840d", "p.mpf"))
    assert [c.NAME for c in cmds if c.NAME in ("STRAIGHT_FEED", "PROGRAM_END")] == [
        "STRAIGHT_FEED",
        "PROGRAM_END",
    ]


def test_reader_streams_without_reading_the_whole_program_first() -> None:
    """The first motion arrives before a bad block further down is reached."""
    gen = interpret_text("G1 X1 F10\n" + "G1 X2\n" * 1000 + "G1 X=\n", "p.mpf")
    first = next(c for c in gen if isinstance(c, canon.StraightFeed))
    assert first.x == 1.0


def test_work_offsets_come_from_the_parameters_and_g500_clears_them() -> None:
    """G55 reads the machine's table (RS274/NGC numbering 5241..); the point stays put."""
    opts = InterpreterOptions(parameters={5241: 100.0, 5242: 50.0})
    cmds = list(interpret_text("G0 X10 Y10\nG55\nG1 X20 F10\nG500\nG1 Y0\nM30\n", "p.mpf", opts))
    offsets = [c for c in cmds if c.NAME in ("SET_G5X_OFFSET", "SET_ORIGIN_OFFSETS")]
    assert (offsets[-2].index, offsets[-2].x, offsets[-2].y) == (2, 100.0, 50.0)
    assert (offsets[-1].x, offsets[-1].y) == (0.0, 0.0)
    feeds = [(c.x, c.y) for c in cmds if isinstance(c, canon.StraightFeed)]
    # after G55 the tool, still at (10, 10) of G54, is at (-90, -40); G500: at (120, 10)
    assert feeds == [(20.0, -40.0), (120.0, 0.0)]


def test_linuxcnc_compat_off_gives_origin_offsets_only() -> None:
    opts = InterpreterOptions(linuxcnc_compat=False)
    cmds = list(interpret_text("TRANS X5\nG1 X1 F10\nM30\n", "p.mpf", opts))
    names = {c.NAME for c in cmds}
    assert "SET_G92_OFFSET" not in names and "ON_RESET" not in names
    origins = [c for c in cmds if isinstance(c, canon.SetOriginOffsets)]
    assert origins[-1].x == 5.0


def test_a_program_start_character_on_the_first_line_is_not_a_block() -> None:
    """``%`` before the first block (840D character set: the program start character of a
    program written on a PC) reads as nothing, a ``;`` comment after it as a comment; a
    ``%`` anywhere else is still refused."""

    def feeds(text: str) -> list[float]:
        cmds = interpret_text(text, "p.mpf")
        return [c.x for c in cmds if isinstance(c, canon.StraightFeed)]

    assert feeds("%\nG1 X1 F10\nM30\n") == [1.0]
    assert feeds("%; PART 7\nG1 X2 F10\nM30\n") == [2.0]
    for bad in ("%X1\nM30\n", "G1 X1 F10\n%\nM30\n"):
        with pytest.raises(Diagnostic) as info:
            list(interpret_text(bad, "p.mpf"))
        assert info.value.code == "SIEM-CHARACTER"


def test_a_standard_cycle_without_a_program_file_is_refused_as_a_cycle() -> None:
    """LONGHOLE is one of the 840D's own cycles: without a LONGHOLE.SPF on the search path
    the refusal names it as a cycle that is not expanded, not as a missing subprogram.
    (HOLES2, the example here before, is now expanded: tests/test_siemens_cycles.py.)"""
    text = "G1 X0 Y0 F100\nLONGHOLE(10, 0, 2, -5, , 2, 20, 50, 50, 30, 0, 180)\nM30\n"
    with pytest.raises(Diagnostic) as info:
        list(interpret_text(text, "p.mpf"))
    assert info.value.code == "SIEM-CYCLE-UNSUPPORTED" and "LONGHOLE" in info.value.message
    assert info.value.location.line == 2
