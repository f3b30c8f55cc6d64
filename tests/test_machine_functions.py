"""Machine functions (issue 14): M codes a control hands to its PLC become MACHINE_FUNCTION
events in the IR; the machine profile names and times them; check, plan and convert see them."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli import convert
from gcode.fanuc import reader as fanuc_reader
from gcode.fanuc_lathe import reader as lathe_reader
from gcode.grbl import reader as grbl_reader
from gcode.haas import reader as haas_reader
from gcode.ngc import interpreter as ngc
from gcode.readers import read_text
from gcode.siemens import reader as siemens_reader
from gcode.write.options import WriterOptions
from gcode.write.report import ConversionReport
from gcode.write.writer import write
from kernel.check import RULES, CheckContext, check_stream, config_from_dict
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, MCode, parse_machine
from kernel.path.build import build_path
from kernel.path.segments import HOLD, LINE, MACHINE_FUNCTION
from kernel.plan.planner import plan
from kernel.report.measure import cycle_time

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


@pytest.mark.parametrize(
    "bad", ["MACHINE_FUNCTION()", "MACHINE_FUNCTION(3, R=1)", "MACHINE_FUNCTION(3.5)"]
)
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


# --------------------------------------------------------------------------- the profile
PROFILE = """
name = "mf"
[axes.x]
min = -100.0
max = 100.0
[axes.y]
min = -100.0
max = 100.0
[axes.z]
min = -100.0
max = 100.0
[m_codes]
31 = { name = "chip conveyor on", time = 2.5 }
M75 = { time = 1.25 }
199 = { name = "door open", forbid = true }
"""


def _cuts(middle: canon.Command) -> list[canon.Command]:
    src = Location("p.nc", 7, 1)
    return [
        canon.SetFeedRate(600.0),
        canon.StraightFeed(10, 0, 0),
        replace(middle, source=src),
        canon.StraightFeed(20, 0, 0),
        canon.ProgramEnd(),
    ]


def test_profile_m_codes_are_read() -> None:
    m = parse_machine(PROFILE, "mf.toml")
    assert m.m_codes == {
        31: MCode("chip conveyor on", 2.5),
        75: MCode("", 1.25),
        199: MCode("door open", 0.0, True),
    }
    assert DEFAULT_MACHINE.m_codes == {}


@pytest.mark.parametrize(
    ("table", "code"),
    [
        ("31 = 2.0", "MACH-TYPE"),
        ("X31 = {}", "MACH-KEY"),
        ("31 = { wait = 1.0 }", "MACH-KEY"),
        ("31 = { time = -1.0 }", "MACH-RANGE"),
        ("31 = { forbid = 1 }", "MACH-TYPE"),
        ('31 = {}\n"M31" = {}', "MACH-KEY"),
    ],
)
def test_bad_m_codes_table_is_refused(table: str, code: str) -> None:
    with pytest.raises(Diagnostic) as info:
        parse_machine(PROFILE.split("[m_codes]")[0] + "[m_codes]\n" + table, "bad.toml")
    assert info.value.code == code


@pytest.mark.parametrize(("code", "seconds"), [(31, 2.5), (75, 1.25), (32, 0.0)])
def test_machine_function_is_a_hold_of_its_profile_time(code: int, seconds: float) -> None:
    m = parse_machine(PROFILE)
    event = cycle_time(plan(build_path(_cuts(canon.MachineFunction(code)), m), m))
    dwell = cycle_time(plan(build_path(_cuts(canon.Dwell(seconds)), m), m))
    # the machine stops there exactly as at a dwell of that time; counted as "other"
    assert event.total == pytest.approx(dwell.total, abs=1e-12)
    assert event.other == pytest.approx(seconds, abs=1e-12) and event.dwell == 0.0
    zero = cycle_time(plan(build_path(_cuts(canon.Dwell(0.0)), m), m))
    assert event.total - zero.total == pytest.approx(seconds, abs=1e-9)
    seg = build_path(_cuts(canon.MachineFunction(code)), m).segments
    assert list(seg["kind"]) == [LINE, HOLD, LINE, HOLD]
    assert seg["category"][1] == MACHINE_FUNCTION and seg["line"][1] == 7


def test_programs_without_machine_functions_keep_their_cycle_time() -> None:
    cmds = [c for c in _cuts(canon.Dwell(0.0)) if not isinstance(c, canon.Dwell)]
    m = parse_machine(PROFILE)
    plain = parse_machine(PROFILE.split("[m_codes]")[0])
    assert cycle_time(plan(build_path(cmds, m), m)) == cycle_time(
        plan(build_path(cmds, plain), plain)
    )


def test_forbidden_machine_function_is_a_located_error() -> None:
    m = parse_machine(PROFILE)
    with pytest.raises(Diagnostic) as info:
        build_path(_cuts(canon.MachineFunction(199)), m)
    d = info.value
    assert (d.code, d.location.file, d.location.line) == ("PLAN-M-FORBIDDEN", "p.nc", 7)
    assert "door open" in d.message


# --------------------------------------------------------------------------- cnc check
def _findings(config: dict[str, object]) -> list[tuple[str, str, int]]:
    m = parse_machine(PROFILE)
    ctx = CheckContext(m, config_from_dict(config, set(RULES)))
    found = check_stream(fanuc_reader.interpret_text(FANUC.replace("M32", "M199"), "mf.nc"), ctx)
    return [(f.rule, f.severity.value, f.location.line) for f in found if f.rule >= "CNC70"]


def test_check_notes_unnamed_machine_functions_and_refuses_forbidden_ones() -> None:
    # M31 and M75 are named; M262 is not (a note); M199 is forbidden (an error)
    assert _findings({}) == [("CNC702", "note", 7), ("CNC703", "error", 8)]


def test_check_unnamed_machine_function_severity_is_configurable() -> None:
    assert _findings({"rules": {"CNC702": "warning"}})[0] == ("CNC702", "warning", 7)
    assert _findings({"rules": {"CNC702": "off"}}) == [("CNC703", "error", 8)]


def test_check_unsupported_knows_machine_function_codes() -> None:
    assert ("CNC701", "error", 5) in _findings({"unsupported": ["M31"]})


# --------------------------------------------------------------------------- cnc convert
PROGRAM = FANUC.replace("M31\n", "M03 S1000\nM31\n").replace("M32", "M32 (conveyor off)")


def _round_trip(target: str) -> tuple[list[tuple[int, float | None, float | None]], list[str]]:
    report = ConversionReport()
    text = "\n".join(write(fanuc_reader.interpret_text(PROGRAM, "p.nc"), target, None, report))
    back = read_text(text, target, "out")
    events = [(c.code, c.p, c.q) for c in back if isinstance(c, canon.MachineFunction)]
    return events, [f"{c.code}:{c.source.line if c.source else 0}" for c in report.changes]


@pytest.mark.parametrize("target", ["fanuc", "haas"])
def test_convert_to_fanuc_family_keeps_the_m_codes(target: str) -> None:
    events, changes = _round_trip(target)
    assert events == [(31, None, None), (75, None, None), (262, 5.0, 2.0), (32, None, None)]
    assert changes == []


def test_convert_to_siemens_keeps_the_m_codes_and_reports_p_and_q() -> None:
    events, changes = _round_trip("siemens840d")
    assert events == [(31, None, None), (75, None, None), (262, None, None), (32, None, None)]
    assert changes == ["CONV-MACHINE-FUNCTION:8", "CONV-MACHINE-FUNCTION:8"]


def test_siemens_to_fanuc_keeps_the_m_codes() -> None:
    text = "G90 G71 G17\nG0 X0 Y0\nM31\nG1 X10 F100 M75\nM30\n"
    out = "\n".join(write(siemens_reader.interpret_text(text, "s.mpf"), "fanuc"))
    assert "M31" in out.splitlines() and "M75" in out.splitlines()


def test_a_code_the_target_defines_itself_is_not_written_through() -> None:
    text = FANUC.replace("M31", "M97 P100")  # a Fanuc's PLC code; Haas's local call
    report = ConversionReport()
    out = list(write(fanuc_reader.interpret_text(text, "p.nc"), "haas", None, report))
    assert not any(line.startswith("M97") for line in out)
    assert [(c.code, c.source.line if c.source else 0) for c in report.changes] == [
        ("CONV-MACHINE-FUNCTION", 5)
    ]


@pytest.mark.parametrize("target", ["rs274ngc", "grbl", "nist_v3", "sandia"])
def test_targets_that_would_refuse_them_report_every_one(target: str) -> None:
    report = ConversionReport()
    out = list(write(fanuc_reader.interpret_text(PROGRAM, "p.nc"), target, None, report))
    mf = [c for c in report.changes if c.code == "CONV-MACHINE-FUNCTION"]
    assert [(c.kind, c.source.line if c.source else 0) for c in mf] == [
        ("dropped", 6),
        ("dropped", 7),
        ("dropped", 8),
        ("dropped", 9),
    ]
    assert not any(line.split()[:1] in (["M31"], ["M75"]) for line in out)
    assert any("M31" in line and "not written" in line for line in out)  # a comment says so


@pytest.mark.parametrize("target", ["rs274ngc", "grbl", "sandia"])
def test_on_missing_refuse_makes_it_a_located_error(target: str) -> None:
    with pytest.raises(Diagnostic) as info:
        list(
            write(
                fanuc_reader.interpret_text(FANUC, "p.nc"),  # no spindle: Sandia has none
                target,
                WriterOptions(on_missing="refuse"),
            )
        )
    d = info.value
    assert (d.code, d.location.file, d.location.line) == ("CONV-MACHINE-FUNCTION", "p.nc", 5)


def test_rs274ngc_output_still_reads_in_the_rs274ngc_reader() -> None:
    out = "\n".join(write(fanuc_reader.interpret_text(PROGRAM, "p.nc"), "rs274ngc"))
    assert not any(isinstance(c, canon.MachineFunction) for c in ngc.interpret_text(out, "o.ngc"))


def test_cli_convert_refuses_with_on_missing_refuse(tmp_path: Path) -> None:
    src = tmp_path / "p.nc"
    src.write_text(PROGRAM)
    ok = CliRunner().invoke(convert.command, [str(src), "--from", "fanuc", "--to", "haas"])
    assert ok.exit_code == 0 and "M262 P5. Q2." in ok.output
    bad = CliRunner().invoke(
        convert.command,
        [str(src), "--from", "fanuc", "--to", "rs274ngc", "--on-missing", "refuse"],
    )
    assert bad.exit_code == 1
    assert "p.nc:6:1: error[CONV-MACHINE-FUNCTION]" in bad.output
