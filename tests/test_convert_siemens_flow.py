"""Siemens 840D flow control and subprograms with parameters (issue 14): CASE, REPEAT and
REPEATB, PROC with parameters, calls with arguments, EXTERN, settable frames G505-G599,
axes the machine lacks (W); and refusals that name the construct met.

Expected results follow the 840D sl programming manuals (job planning, "Program jumps"
(CASE), "Program section repetition" (REPEAT, REPEATB); fundamentals and job planning,
"Subprograms with parameter transfer"; fundamentals, "Settable zero offset"):
docs/readers/siemens840d.md."""

from __future__ import annotations

from pathlib import Path

import pytest

from gcode.ngc.interpreter import InterpreterOptions
from gcode.siemens.reader import interpret, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon


def _xyz(text: str, tmp: Path | None = None) -> list[tuple[float, float, float]]:
    """The end points of the program's feed moves."""
    if tmp is None:
        cmds = interpret_text(text, "t.mpf")
    else:
        (tmp / "main.mpf").write_text(text)
        cmds = interpret(tmp / "main.mpf", InterpreterOptions(search_path=(str(tmp),)))
    return [(c.x, c.y, c.z) for c in cmds if isinstance(c, canon.StraightFeed)]


def _error(text: str, tmp: Path | None = None) -> Diagnostic:
    with pytest.raises(Diagnostic) as info:
        _xyz(text, tmp)
    return info.value


HEAD = "G0 X0 Y0 Z0\nF100\n"


@pytest.mark.parametrize(("value", "x"), [(1, 1.0), (2, 2.0), (5, 3.0), (-1, 4.0)])
def test_case_jumps_to_the_matching_constant_else_default(value: int, x: float) -> None:
    text = (
        f"{HEAD}R1={value}\n"
        "CASE R1 OF 1 GOTOF AA -1 GOTOF DD 2 GOTOF BB DEFAULT GOTOF CC\n"
        "AA: G1 X1\nGOTOF EE\nBB: G1 X2\nGOTOF EE\nCC: G1 X3\nGOTOF EE\nDD: G1 X4\nEE: M30\n"
    )
    assert _xyz(text) == [(x, 0.0, 0.0)]


def test_case_without_a_match_nor_default_goes_on() -> None:
    text = f"{HEAD}CASE 7 OF 1 GOTOF AA 2 GOTOF AA\nG1 X5\nAA: G1 Y5\nM30\n"
    assert _xyz(text) == [(5.0, 0.0, 0.0), (5.0, 5.0, 0.0)]


def test_case_jumps_backward_and_its_endless_loop_is_stopped() -> None:
    text = f"{HEAD}AA: R1=R1+1\nCASE R1 OF 3 GOTOF BB DEFAULT GOTOB AA\nBB: G1 X=R1\nM30\n"
    assert _xyz(text) == [(3.0, 0.0, 0.0)]
    err = _error(f"{HEAD}AA: R1=1\nCASE R1 OF 1 GOTOB AA\nM30\n")
    assert (err.code, err.location.line) == ("LOOP-NO-PROGRESS", 4)
    assert "GOTOB AA" in err.message


def test_repeat_runs_the_section_up_to_the_repeat_p_more_times() -> None:
    text = f"{HEAD}AA: G91 G1 X1\nG90\nREPEAT AA P=3\nG1 Y1\nM30\n"
    assert _xyz(text) == [(float(i), 0.0, 0.0) for i in range(1, 5)] + [(4.0, 1.0, 0.0)]


def test_repeat_between_two_labels_and_to_endlabel() -> None:
    text = (
        f"{HEAD}GOTOF GO\nAA: G1 X1\nBB: G1 X2\nG1 X3\nGO: REPEAT AA BB P2\nG1 Y1\n"
        "CC: G1 Z1\nENDLABEL: G1 Z2\nG1 Z3\nREPEAT CC ENDLABEL\nM30\n"
    )
    assert [p[0] for p in _xyz(text)[:4]] == [1.0, 2.0, 1.0, 2.0]
    assert [p[2] for p in _xyz(text)[5:]] == [1.0, 2.0, 3.0, 1.0, 2.0]


def test_repeatb_repeats_one_line_searching_backward_then_forward() -> None:
    assert _xyz(f"{HEAD}AA: G91 G1 X1\nREPEATB AA P=2\nG90 G1 Y1\nM30\n") == [
        (1.0, 0.0, 0.0),
        (2.0, 0.0, 0.0),
        (3.0, 0.0, 0.0),
        (3.0, 1.0, 0.0),
    ]
    # forward: the line after the REPEATB runs once (P1), then the program goes on after
    # the REPEATB, where it runs again in its turn
    assert _xyz(f"{HEAD}REPEATB AA P1\nAA: G91 G1 X1\nM30\n") == [(1.0, 0.0, 0.0), (2.0, 0.0, 0.0)]


def test_repeat_inside_a_repeat_until_loop_is_no_structure() -> None:
    text = f"{HEAD}REPEAT\nR1=R1+1\nAB: G1 X=R1\nREPEATB AB P1\nUNTIL R1>=2\nM30\n"
    assert [p[0] for p in _xyz(text)] == [1.0, 1.0, 2.0, 2.0]


@pytest.fixture
def subprograms(tmp_path: Path) -> Path:
    (tmp_path / "MOVE.SPF").write_text(
        "PROC MOVE(REAL DX, INT NY) DISPLOF\nG91 G1 X=DX Y=NY\nG90\nRET\n"
    )
    (tmp_path / "L140.SPF").write_text("PROC L140(REAL DEPTH)\nG1 Z=-DEPTH\nM17\n")
    (tmp_path / "SWAP.SPF").write_text(
        "PROC SWAP(VAR REAL AA, VAR REAL BB, REAL CC)\nDEF REAL TT=AA\nAA=BB\nBB=TT\nCC=99\nRET\n"
    )
    return tmp_path


def test_calls_with_arguments_by_value_and_by_reference(subprograms: Path) -> None:
    text = (
        "EXTERN MOVE(REAL, INT)\nEXTERN SWAP(VAR REAL, VAR REAL, REAL)\n"
        "DEF REAL PP=1\nDEF REAL QQ=2\nDEF REAL CC=5\n"
        f"{HEAD}MOVE(1.5, 2.4)\nL140(2)\nSWAP(PP, QQ, CC)\nG1 X=PP Y=QQ Z=CC\n"
        "R3=4\nSWAP(R3, R[4], 0)\nG1 X=R3 Y=R4\nMOVE(, 1) P2\nM30\n"
    )
    assert _xyz(text, subprograms) == [
        (1.5, 2.0, 0.0),  # INT NY takes 2.4 rounded
        (1.5, 2.0, -2.0),
        (2.0, 1.0, 5.0),  # PP and QQ swapped; CC by value keeps 5
        (0.0, 4.0, 5.0),  # R parameters by reference
        (0.0, 5.0, 5.0),  # an omitted argument is 0; P2 passes the arguments each pass
        (0.0, 6.0, 5.0),
    ]


@pytest.mark.parametrize(
    ("text", "code", "words"),
    [
        ("MOVE(1, 2, 3)\n", "SIEM-CALL", "3 arguments for 2 parameters"),
        ("SWAP(1, R2, 0)\n", "SIEM-CALL", "VAR parameter AA"),
        ("NOSUCH(1, 2)\n", "SIEM-SUBPROGRAM", "NOSUCH"),
    ],
)
def test_bad_calls_are_refused_naming_the_call(
    subprograms: Path, text: str, code: str, words: str
) -> None:
    err = _error(HEAD + text, subprograms)
    assert (err.code, err.location.line) == (code, 3)
    assert words in err.message


@pytest.mark.parametrize(
    ("text", "code", "words", "column"),
    [
        ('PRINT("HELLO")\n', "SIEM-UNSUPPORTED", "PRINT", 1),
        ('WRITE(R1, "LOG", "X")\n', "SIEM-UNSUPPORTED", "WRITE", 1),
        ("SETAL(61000)\n", "SIEM-ALARM", "SETAL", 1),
        ("PROC MAIN(STRING[8] NAME)\n", "SIEM-UNSUPPORTED", "STRING", 11),
        ("PROC MAIN(REAL AA) SAVE\n", "SIEM-UNSUPPORTED", "SAVE", 20),
        ("PROC MAIN(REAL AA, REAL AA)\n", "SIEM-PROC", "AA twice", 25),
        ("CASE R1 GOTOF AA\n", "SIEM-SYNTAX", "OF", 9),
        ("CASE R1 OF 1 AA\n", "SIEM-SYNTAX", "GOTOF", 14),
        ("AA: G1 X1\nREPEAT AA P=0\n", "SIEM-REPEAT", "P=0", 1),
        ("AA: G1 X1\nREPEAT AA BB\nBB: G1 X2\n", "SIEM-REPEAT", "holds the REPEAT", 1),
        ("REPEAT NOWHERE P=2\n", "SIEM-LABEL", "NOWHERE", 1),
    ],
)
def test_refusals_name_the_construct_met(text: str, code: str, words: str, column: int) -> None:
    err = _error("F100\n" + text)
    assert (err.code, err.location.column) == (code, column)
    assert words in err.message
    assert "parameters are not supported" not in err.message


def test_settable_frames_g505_to_g599() -> None:
    """G505-G599 select the settable frames 5-99 (fundamentals, "Settable zero offset"):
    1-9 with their parameters, 10-99 zero, in the IR's system 9."""
    params = {5221: 1.0, 5381: 3.0}  # G54 X1, G509 (frame 9) X3
    text = "G54 G0 X1\nG510\nG1 X2 F10\nG509\nG599 G1 X4\nG505\nG500\nM30\n"
    cmds = list(interpret_text(text, "f.mpf", InterpreterOptions(parameters=params)))
    g5x = [(c.index, c.x) for c in cmds if isinstance(c, canon.SetG5xOffset)]
    assert g5x == [(1, 1.0), (1, 1.0), (9, 0.0), (9, 3.0), (9, 0.0), (5, 0.0)]
    feeds = [c.x for c in cmds if isinstance(c, canon.StraightFeed)]
    assert feeds == [2.0, 4.0]
    nist = list(
        interpret_text(text, "f.mpf", InterpreterOptions(parameters=params, linuxcnc_compat=False))
    )
    totals = [c.x for c in nist if isinstance(c, canon.SetOriginOffsets)]
    assert totals == [1.0, 1.0, 0.0, 3.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize(
    ("text", "letter", "column"),
    [("G0 X1 W5\n", "W", 7), ("G1 W=5 F10\n", "W", 4), ("V2\n", "V", 1)],
)
def test_axes_the_machine_lacks_are_refused_by_name(text: str, letter: str, column: int) -> None:
    err = _error(text)
    assert (err.code, err.location.line, err.location.column) == ("SIEM-AXIS", 1, column)
    assert f"no {letter} axis" in err.message
