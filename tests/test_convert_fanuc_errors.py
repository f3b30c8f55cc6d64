"""Bad Fanuc/Haas input gives a located Diagnostic, never a traceback (readers.md §3)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gcode.fanuc import reader as fanuc_reader
from gcode.fanuc.flow import read_text
from gcode.fanuc.options import FANUC, HAAS, Flavour
from gcode.haas import reader as haas_reader
from gcode.ngc.interpreter import InterpreterOptions
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HEAD = "%\nO0001\nG21 G90 G17\nG00 X0 Y0\n"  # the bad block is line 5

CASES = [
    ("G07.1 C20.", "FANUC-UNKNOWN-G"),
    ("M123456789", "FANUC-UNKNOWN-M"),  # M123: a machine function (issue 14)
    ("G01 X1.2.3 F100.", "FANUC-SYNTAX"),
    ("G01 X F100.", "FANUC-SYNTAX"),
    ("G01 X1. (open comment", "FANUC-COMMENT"),
    ("G01 X1. X2. F100.", "FANUC-DUPLICATE-WORD"),
    ("M98 P4242", "FANUC-NO-PROGRAM"),
    ("GOTO77", "FANUC-GOTO"),
    ("END1", "FANUC-LOOP"),
    ("WHILE [1 LT 0] DO1", "FANUC-LOOP"),
    ("WHILE [1 GT 0] DO4", "FANUC-LOOP"),
    ("#1=1/0", "FANUC-DIVIDE-BY-ZERO"),
    ("#1=SQRT[-1]", "FANUC-FUNCTION"),
    ("#1=ACOS[2]", "FANUC-FUNCTION"),
    ("#0=1", "FANUC-VARIABLE"),
    ("#40=1", "FANUC-VARIABLE"),
    ("#1=#7777", "FANUC-SYSTEM-VARIABLE"),
    ("#3000=5 (TOOL BROKEN)", "FANUC-ALARM"),
    ("G02 X10. Y0 R2. F100.", "FANUC-ARC-R-TOO-SMALL"),
    ("G01 X10.", "FANUC-ZERO-FEED"),
    ("G51 X0 Y0", "FANUC-G51"),
    ("G44 H1 Z10.", "FANUC-G44"),
    ("G68 X0 Y0 I0 J0 K1 R30.", "FANUC-G68-3D"),
    ("G05.1 Q5", "FANUC-G05-1"),
    ("G10 L50 P1 R2.", "FANUC-G10-L"),
    ("G10 L2 P9 X1.", "FANUC-G10-P"),
    ("G06.2 P3 K0 X5. Y5. F100.", "FANUC-NURBS-START"),
    ("G06.2 P9 K0 X0 Y0 F100.", "FANUC-NURBS-ORDER"),
    ("G87 X0 Y0 Z-5. R2. Q1. F100.", "FANUC-CYCLE-R-BELOW"),
    ("G04", "FANUC-DWELL"),
    ("M98", "FANUC-CALL"),
    ("G65 A1.", "FANUC-CALL"),
    ("G01 U5. F100.", "FANUC-WORD"),
    ("G01 X1. E2. F100.", "FANUC-WORD"),
    ("G81 X0 Y0 Z-1. R1. K0.5 F100.", "FANUC-CYCLE-L"),
]


@pytest.mark.parametrize(("block", "code"), CASES, ids=[c[1] + ":" + c[0] for c in CASES])
def test_bad_block_is_refused_at_its_line(block: str, code: str) -> None:
    text = HEAD + block + "\nM30\n%\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret_text(text, "bad.nc"))
    assert info.value.code == code
    assert info.value.location.file == "bad.nc"
    assert info.value.location.line == 5


def test_transformed_incremental_cycle_is_refused() -> None:
    text = HEAD + "G68 X0 Y0 R30.\nG91 G81 X5. Y0 Z-5. R-1. F100.\nM30\n%\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret_text(text, "t.nc"))
    assert (info.value.code, info.value.location.line) == ("FANUC-TRANSFORM-CYCLE", 6)


def test_unfinished_nurbs_is_refused_at_the_block_that_interrupts_it() -> None:
    text = HEAD + "G06.2 P3 K0 X0 Y0 F100.\nK0 X1. Y1.\nG01 X3.\nM30\n%\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret_text(text, "n.nc"))
    assert (info.value.code, info.value.location.line) == ("FANUC-NURBS-INCOMPLETE", 7)


def test_endless_recursion_stops_at_the_call_depth_limit() -> None:
    text = HEAD + "M98 P10\nM30\nO10\nM98 P10\nM99\n%\n"
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret_text(text, "r.nc"))
    assert info.value.code == "FANUC-CALL-DEPTH"
    assert info.value.location.line == 8


def test_endless_loop_stops_at_the_jump_limit() -> None:
    text = HEAD + "N10 G01 X1. F100.\nGOTO10\nM30\n%\n"
    flavour = replace(FANUC, max_loops=50)
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, "l.nc", InterpreterOptions(), flavour))
    assert (info.value.code, info.value.location.line) == ("FANUC-LOOP-LIMIT", 6)


def test_haas_refuses_engraving_and_fanuc_does_not_know_m97() -> None:
    with pytest.raises(Diagnostic) as info:
        list(haas_reader.interpret_text(HEAD + "G47 P0 X0 Y0 I0 J.1 R.1 Z-.01 F10.\n", "e.nc"))
    assert (info.value.code, info.value.location.line) == ("HAAS-ENGRAVING", 5)
    # a Fanuc hands the M97 it does not define to the machine (issue 14)
    cmds = list(fanuc_reader.interpret_text(HEAD + "M97 P100\nM30\n", "e.nc"))
    (event,) = [c for c in cmds if isinstance(c, canon.MachineFunction)]
    assert (event.code, event.p, event.source.line) == (97, 100.0, 5)


ALPHABET = "GXYZIJKRFPQLMNO#[]=+-*/.0123456789 ()%;\n" + "ABCDEHSTUVW"
TOKENS = [
    "G00", "G01", "G02", "G03", "G04", "G06.2", "G16", "G15", "G51", "G50", "G51.1", "G50.1",
    "G68", "G69", "G81", "G83", "G84", "G80", "G90", "G91", "G41", "G40", "G43", "G10 L2 P1",
    "G65 P10", "G66 P10", "G67", "M98 P10", "M99", "M03", "M30", "#1=", "#1", "IF [", "]",
    "GOTO10", "WHILE [#1 LT 3] DO1", "END1", "N10", "X1.", "Y-2", "Z3.5", "R2.", "I1.",
    "J-1.", "K2", "F100.", "P2", "Q1.", "S500", "T1", "H1", "D1", "O10", "\n",
]  # fmt: skip


@settings(max_examples=300, deadline=None)
@given(
    st.one_of(
        st.text(ALPHABET, max_size=120),
        st.lists(st.sampled_from(TOKENS), max_size=40).map(" ".join),
    ),
    st.booleans(),
    st.sampled_from([FANUC, HAAS]),
)
def test_random_text_gives_commands_or_a_diagnostic(
    text: str, lathe: bool, control: Flavour
) -> None:
    flavour = replace(control, max_loops=200, lathe=lathe)
    try:
        for _ in read_text(text, "fuzz.nc", InterpreterOptions(), flavour):
            pass
    except Diagnostic as exc:
        assert exc.code.startswith(("FANUC-", "HAAS-"))
        assert exc.location.file == "fuzz.nc"


def test_a_line_that_is_not_utf8_is_refused_at_its_line(tmp_path: Path) -> None:
    path = tmp_path / "latin.nc"
    path.write_bytes(HEAD.encode() + b"G01 X1. F100. (\xe9bauche)\nM30\n%\n")
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret(path))
    assert (info.value.code, info.value.location.line) == ("FANUC-ENCODING", 5)
