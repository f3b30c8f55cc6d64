"""Siemens 840D subprograms with parameters (issue 14): PROC with parameters, calls with
arguments, EXTERN; and refusals that name the construct met. Expected results follow the
840D sl programming manuals (fundamentals and job planning, "Subprograms with parameter
transfer"): docs/readers/siemens840d.md."""

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
        ("SETAL(61000)\n", "SIEM-UNSUPPORTED", "SETAL", 1),
        ("PROC MAIN(STRING[8] NAME)\n", "SIEM-UNSUPPORTED", "STRING", 11),
        ("PROC MAIN(REAL AA) SAVE\n", "SIEM-UNSUPPORTED", "SAVE", 20),
        ("PROC MAIN(REAL AA, REAL AA)\n", "SIEM-PROC", "AA twice", 25),
    ],
)
def test_refusals_name_the_construct_met(text: str, code: str, words: str, column: int) -> None:
    err = _error("F100\n" + text)
    assert (err.code, err.location.column) == (code, column)
    assert words in err.message
    assert "parameters are not supported" not in err.message
