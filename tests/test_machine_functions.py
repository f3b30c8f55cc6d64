"""Machine functions (issue 14): M codes a control hands to its PLC become MACHINE_FUNCTION
events in the IR; the machine profile names and times them; check, plan and convert see them."""

from __future__ import annotations

import json

import pytest

from gcode.fanuc import reader as fanuc_reader
from gcode.fanuc_lathe import reader as lathe_reader
from gcode.grbl import reader as grbl_reader
from gcode.haas import reader as haas_reader
from gcode.ngc import interpreter as ngc
from gcode.siemens import reader as siemens_reader
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

FANUC = """%
O0001
G21 G90 G17
G00 X0 Y0
M31
G01 X10. F100. M75
M262 P5 Q2.
G00 Z5. M32
M30
%
"""


def _events(cmds: list[canon.Command]) -> list[tuple[int, float | None, float | None, int, int]]:
    out = []
    for c in cmds:
        if isinstance(c, canon.MachineFunction):
            assert c.source is not None
            out.append((c.code, c.p, c.q, c.source.line, c.source.column))
    return out


# --------------------------------------------------------------------------- the IR
@pytest.mark.parametrize(
    "cmd",
    [canon.MachineFunction(31), canon.MachineFunction(59, 1101.0), canon.MachineFunction(5, q=2.5)],
)
def test_text_and_json_forms_round_trip(cmd: canon.MachineFunction) -> None:
    text = cmd.to_text()
    (back,) = canon.read_commands([f"    1 N..... {text}"])
    assert back == cmd and back.to_text() == text
    (row,) = canon.to_jsonl([cmd])
    assert canon.from_json(json.loads(row)) == cmd


def test_text_form() -> None:
    assert canon.MachineFunction(31).to_text() == "MACHINE_FUNCTION(31)"
    assert canon.MachineFunction(262, 5.0, 2.0).to_text() == (
        "MACHINE_FUNCTION(262, P=5.0000, Q=2.0000)"
    )
    assert canon.MachineFunction(5, q=2.5).to_text() == "MACHINE_FUNCTION(5, Q=2.5000)"


@pytest.mark.parametrize("bad", ["MACHINE_FUNCTION()", "MACHINE_FUNCTION(3, R=1)", "MACHINE_FUNCTION(3.5)"])
def test_bad_text_is_a_located_syntax_error(bad: str) -> None:
    with pytest.raises(Diagnostic) as info:
        list(canon.read_commands(["", bad], "x.canon"))
    assert (info.value.code, info.value.location.line) == ("CANON-SYNTAX", 2)


# --------------------------------------------------------------------------- readers
def test_fanuc_program_with_plc_m_codes_runs() -> None:
    cmds = list(fanuc_reader.interpret_text(FANUC, "mf.nc"))
    assert _events(cmds) == [
        (31, None, None, 5, 1),
        (75, None, None, 6, 16),
        (262, 5.0, 2.0, 7, 1),
        (32, None, None, 8, 9),
    ]
    names = [c.NAME for c in cmds]
    # before the block's motion, in program order
    assert names.index("MACHINE_FUNCTION", names.index("MACHINE_FUNCTION") + 1) < names.index(
        "STRAIGHT_FEED"
    )
    assert isinstance(cmds[-1], canon.ProgramEnd) or "PROGRAM_END" in names


def test_haas_gives_the_same_events() -> None:
    cmds = list(haas_reader.interpret_text(FANUC, "mf.nc"))
    assert [e[0] for e in _events(cmds)] == [31, 75, 262, 32]


def test_p_and_q_stay_with_the_words_that_take_them() -> None:
    text = "%\nO1\nG21 G90\nG00 X0 Y0 Z5.\nG04 P500 M31\nM98 P10 M75\nM30\nO10\nM99\n%\n"
    cmds = list(fanuc_reader.interpret_text(text, "p.nc"))
    assert [(e[0], e[1]) for e in _events(cmds)] == [(31, None), (75, None)]
    assert any(isinstance(c, canon.Dwell) and c.seconds == 0.5 for c in cmds)


def test_fanuc_lathe_gives_events() -> None:
    text = "%\nO1\nG21 G18\nG00 X20. Z2.\nM03 S500 M08 M131\nG01 Z-10. F0.2 M24\nM30\n%\n"
    cmds = list(lathe_reader.interpret_text(text, "l.nc"))
    assert [(e[0], e[3]) for e in _events(cmds)] == [(131, 5), (24, 6)]


def test_siemens_m_codes_beyond_the_standard_set_and_m_equals() -> None:
    text = "G90 G71 G17\nG0 X0 Y0\nM31\nR1=262\nG1 X10 F100 M75\nM=R1\nM3 S1000\nM30\n"
    cmds = list(siemens_reader.interpret_text(text, "mf.mpf"))
    assert [(e[0], e[3], e[4]) for e in _events(cmds)] == [(31, 3, 1), (75, 5, 13), (262, 6, 1)]


def test_too_long_m_code_is_still_refused() -> None:
    with pytest.raises(Diagnostic) as info:
        list(fanuc_reader.interpret_text(FANUC.replace("M31", "M123456789"), "x.nc"))
    assert (info.value.code, info.value.location.line) == ("FANUC-UNKNOWN-M", 5)


@pytest.mark.parametrize(
    ("read", "code"),
    [(ngc.interpret_text, "NGC-UNKNOWN-M"), (grbl_reader.interpret_text, None)],
)
def test_rs274ngc_and_grbl_still_refuse_unknown_m_codes(read, code: str | None) -> None:  # noqa: ANN001
    with pytest.raises(Diagnostic) as info:
        list(read("G21 G90\nG0 X0 Y0\nM31\nM2\n", "x.ngc"))
    assert info.value.location.line == 3
    if code is not None:
        assert info.value.code == code
