"""Bad Siemens 840D input gives a located SIEM-* diagnostic, never a traceback."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gcode.ngc.interpreter import InterpreterOptions
from gcode.siemens import flow
from gcode.siemens.reader import interpret, interpret_text
from kernel.diagnostics import Diagnostic


def _error(text: str, options: InterpreterOptions | None = None) -> Diagnostic:
    with pytest.raises(Diagnostic) as info:
        list(interpret_text(text, "bad.mpf", options))
    return info.value


@pytest.mark.parametrize(
    ("text", "code", "line", "column"),
    [
        ("G1 X1 F10\nG112 X2\n", "SIEM-G-CODE", 2, 1),
        ("G1 X1 F10 M1.5\n", "SIEM-M-CODE", 1, 11),  # M98: a machine function (issue 14)
        ("G1 X1 F10 M123456789\n", "SIEM-M-CODE", 1, 11),
        ("G0 G1 X1\n", "SIEM-G-GROUP", 1, 4),
        ("G0 X1 X2\n", "SIEM-WORD", 1, 7),
        ("G0 X1 Q5\n", "SIEM-WORD", 1, 7),
        ("G0 X1 @\n", "SIEM-CHARACTER", 1, 7),
        ("G0 X1EX999\n", "SIEM-NUMBER", 1, 4),
        ("G1 X10\n", "SIEM-FEED", 1, 1),
        ("G0 X0 Y0\nG2 X30 Y0 CR=5 F10\n", "SIEM-ARC-CR", 2, 1),
        ("G0 X0 Y0\nG2 X30 Y0 I5 J0 F10\n", "SIEM-ARC-RADIUS", 2, 1),
        ("G0 X10 Y0\nG3 X0 Y10 F10\n", "SIEM-ARC-CENTRE", 2, 1),
        ("G0 X10 Y0\nG3 X0 Y10 AR=400 F10\n", "SIEM-ARC-AR", 2, 1),
        ("G0 X10 Y0\nG3 X0 Y10 CR=10 TURN=-1 F10\n", "SIEM-ARC-TURN", 2, 17),
        ("ROT X=30\nG0 X10 Y0\nG3 X0 Y10 CR=10 F10\n", "SIEM-FRAME-ARC", 3, 1),
        ("SCALE X2 Y3\nG0 X10 Y0\nG3 X0 Y10 CR=10 F10\n", "SIEM-FRAME-ARC", 3, 1),
        ("TRANS X1 F5\n", "SIEM-FRAME", 1, 10),
        ("SCALE X0\n", "SIEM-FRAME", 1, 1),
        ("GOTOF NOWHERE\n", "SIEM-LABEL", 1, 1),
        ("WHILE R1<1\nG0 X1\n", "SIEM-STRUCTURE", 1, 1),
        ("ENDIF\n", "SIEM-STRUCTURE", 1, 1),
        ("R1=UNDEFINED+1\n", "SIEM-VARIABLE", 1, 4),
        ("R1=1/R2\n", "SIEM-MATH", 1, 5),
        ("R1=SQRT(-1)\n", "SIEM-MATH", 1, 4),
        ("R1000=1\n", "SIEM-R-INDEX", 1, 1),
        ("R1=(1+2\n", "SIEM-SYNTAX", 1, 8),
        ("NOSUCHPROG\n", "SIEM-SUBPROGRAM", 1, 1),
        ("CYCLE800(1,2)\n", "SIEM-CYCLE-UNSUPPORTED", 1, 1),
        ("CYCLE81(10, 0, 2, 5)\n", "SIEM-CYCLE-ARGS", 1, 1),
        ("T1 D2 M6\n", "SIEM-TOOL-EDGE", 1, 4),
        ("G0 X1 W5\n", "SIEM-AXIS", 1, 7),
        ("G4 F1 S2\n", "SIEM-DWELL", 1, 1),
        ("G33 Z-10 K1\n", "SIEM-THREAD", 1, 1),
        ("RET\n", "SIEM-RET", 1, 1),
        ("DEF STRING[8] NAME\n", "SIEM-UNSUPPORTED", 1, 11),
        ("SPOS=400\n", "SIEM-SPOS", 1, 1),
        ("MEAS=1 G0 X5\n", "SIEM-PROBE", 1, 1),
        ("IF R1==0 X5\n", "SIEM-SYNTAX", 1, 10),
        ("G1 X5 F10 GOTOF END\n", "SIEM-BLOCK", 1, 11),
        ("ROT RPL=30\nSUPA X5\n", "SIEM-UNSUPPORTED", 2, 1),
        ("G1 X1 F10 FRC=2\n", "SIEM-UNSUPPORTED", 1, 11),
        ("G1 X1 P3 F10\n", "SIEM-WORD", 1, 7),
        ("G1 F10\nCIP X10 Y0 I1=5 J1=0\n", "SIEM-ARC-CIP", 2, 1),
        ("G1 F10\nCIP X10 Y0 I1=5 J1=5 K1=3\n", "SIEM-ARC-CIP", 2, 1),
        ("G1 X1 I1=5 F10\n", "SIEM-ARC-WORDS", 1, 1),
        ('F="FAST" G1 X5\n', "SIEM-WORD", 1, 3),
        ("G1 X5 F10\nG0 X=$MC_DIAMETER_AX_DEF\n", "SIEM-UNSUPPORTED", 2, 6),
        ("DEF REAL TABLE[5]\nR1=TABLE[5]\n", "SIEM-ARRAY", 2, 4),
        ("DEF STRING[8] NAMES[5]\n", "SIEM-UNSUPPORTED", 1, 11),
        ("R1=" + "(" * 500 + "1" + ")" * 500 + "\n", "SIEM-SYNTAX", 1, 104),
        ("R1=" + "+".join(["1"] * 600) + "\n", "SIEM-SYNTAX", 1, 1005),
    ],
)
def test_bad_input_gives_a_located_error(text: str, code: str, line: int, column: int) -> None:
    err = _error(text)
    assert err.code == code, err.message
    assert (err.location.file, err.location.line, err.location.column) == ("bad.mpf", line, column)


def test_endless_loop_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(flow, "MAX_LOOPS", 1000)
    assert _error("LOOP\nG0 X1\nENDLOOP\n").code == "SIEM-LOOP-LIMIT"
    assert _error("LAB1: G0 X1\nGOTOB LAB1\n").code == "SIEM-LOOP-LIMIT"


def test_recursive_subprogram_is_bounded(tmp_path: Path) -> None:
    (tmp_path / "SELF.SPF").write_text("G0 X1\nSELF\nM17\n")
    opts = InterpreterOptions(search_path=(str(tmp_path),))
    err = _error("SELF\nM30\n", opts)
    assert err.code == "SIEM-CALL-DEPTH"
    assert err.location.file.endswith("SELF.SPF") and err.location.line == 2


def test_an_error_in_a_subprogram_points_into_its_file(tmp_path: Path) -> None:
    (tmp_path / "L7.SPF").write_text("G0 X1\nG1 X2 F10\nG99\nM17\n")
    (tmp_path / "MAIN.MPF").write_text("L7\nM30\n")
    with pytest.raises(Diagnostic) as info:
        list(interpret(tmp_path / "MAIN.MPF"))
    assert info.value.location.file.endswith("L7.SPF")
    assert (info.value.location.line, info.value.location.column) == (3, 1)


def test_missing_file_is_an_io_error(tmp_path: Path) -> None:
    with pytest.raises(Diagnostic) as info:
        list(interpret(tmp_path / "NONE.MPF"))
    assert info.value.code == "IO-OPEN"


_PIECES = st.sampled_from(
    [
        "G0",
        "G1",
        "G2",
        "G3",
        "G4",
        "G17",
        "G18",
        "G19",
        "G33",
        "G54",
        "G91",
        "G90",
        "G93",
        "G94",
        "G95",
        "G96",
        "G500",
        "G700",
        "G710",
        "X",
        "Y",
        "Z",
        "A",
        "I",
        "J",
        "K",
        "F",
        "S",
        "T",
        "D",
        "M3",
        "M6",
        "M17",
        "M30",
        "CR=",
        "AR=",
        "TURN=",
        "=AC(",
        "=IC(",
        ")",
        "(",
        ",",
        "R1",
        "R2=",
        "1",
        "-2.5",
        "0",
        "360",
        ".5",
        "+",
        "-",
        "*",
        "/",
        "==",
        "<",
        ">",
        "IF",
        "ELSE",
        "ENDIF",
        "WHILE",
        "ENDWHILE",
        "FOR",
        "TO",
        "ENDFOR",
        "REPEAT",
        "UNTIL",
        "LOOP",
        "ENDLOOP",
        "GOTOF",
        "GOTOB",
        "LAB:",
        "LAB",
        "DEF",
        "REAL",
        "INT",
        "N10",
        "TRANS",
        "ATRANS",
        "ROT",
        "AROT",
        "RPL=",
        "SCALE",
        "MIRROR",
        'MSG("x")',
        "SIN(",
        "CYCLE81(",
        "MCALL",
        "SPOS=",
        "LIMS=",
        ";",
        "L1",
        "RET",
    ]
)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.lists(_PIECES, max_size=8).map(" ".join), max_size=12))
def test_random_text_gives_commands_or_a_diagnostic(lines: list[str]) -> None:
    saved = flow.MAX_LOOPS
    flow.MAX_LOOPS = 200
    try:
        list(interpret_text("\n".join(lines), "fuzz.mpf"))
    except Diagnostic as exc:
        assert exc.code.startswith(("SIEM-", "IO-")) and exc.location.line >= 0
    finally:
        flow.MAX_LOOPS = saved


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet=st.characters(codec="latin-1"), max_size=200))
def test_arbitrary_characters_give_commands_or_a_diagnostic(text: str) -> None:
    saved = flow.MAX_LOOPS
    flow.MAX_LOOPS = 200
    try:
        list(interpret_text(text, "fuzz.mpf"))
    except Diagnostic as exc:
        assert exc.code.startswith("SIEM-")
    finally:
        flow.MAX_LOOPS = saved


def test_every_code_the_reader_raises_is_documented() -> None:
    root = Path(__file__).resolve().parent.parent
    sources = [*(root / "gcode" / "siemens").glob("*.py")]
    raised = set()
    for src in sources:
        raised |= set(re.findall(r'"(SIEM-[A-Z0-9-]+)"', src.read_text()))
    doc = (root / "docs" / "errors.md").read_text()
    section = doc[doc.index("## Siemens 840D reader") :]
    documented = set(re.findall(r"`(SIEM-[A-Z0-9-]+)`", section))
    assert raised and raised <= documented, raised - documented
