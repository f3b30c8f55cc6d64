"""What the held-out hostile inputs campaign (bench/hostile.py, 2026-12-02) found, pinned:
each input now ends quickly with a located, coded diagnostic (or runs as it should).

The campaign runs the real ``cnc`` command on each input under 1 GB and 20 s; these tests
call the reader or the command in this process, each well under a second.
"""

from __future__ import annotations

import math
import os
import signal
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import kernel.limits as limits
from cli.errors import guarded
from cli.excerpt import _line_of, excerpt
from cli.main import cli
from cli.programs import load_machine, load_tool_table, read_head
from gcode.readers import read_text
from gcode.write.sandia_chords import batch_points
from kernel.diagnostics import Diagnostic, Location
from kernel.interp import interpolate
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE, parse_machine
from kernel.plan.models.grbl import segment_arcs
from kernel.plan.strategy import build, plan_program
from kernel.report.trace import setup as servo_setup
from kernel.tooltable import read_tool_table
from stepnc.part21 import parse
from stepnc.to_canon import canon_from_file


@pytest.fixture
def fresh_limits() -> Iterator[None]:
    limits.reset()
    yield
    limits.reset()


def _error(text: str, dialect: str = "rs274ngc") -> Diagnostic:
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, dialect, "hostile.ngc"))
    assert time.process_time() - start < 2.0
    return info.value


# rs274 2.9 stops on these with "Calculation resulted in 'infinity'" (or 'not a number');
# the reader wrote STRAIGHT_FEED(inf, ...) and STRAIGHT_FEED(nan, ...) and exited 0
@pytest.mark.parametrize(
    "line",
    [
        "G1 X[10**300*10**300] F100",
        "#1=[10**300*10**300]",
        "G1 X[[10**200*10**200]-[10**200*10**200]] F100",
        "G1 X[EXP[700]*EXP[700]] F100",
    ],
)
def test_a_calculation_resulting_in_infinity_is_a_located_error(line: str) -> None:
    diag = _error(f"G21\n{line}\nM2\n")
    assert (diag.code, diag.location.line) == ("NGC-NOT-FINITE", 2)


def test_a_large_finite_calculation_still_runs() -> None:
    cmds = list(read_text("G21\nG1 X[10**150*10**150] F100\nM2\n", "rs274ngc", "big.ngc"))
    assert any(getattr(c, "x", 0.0) == pytest.approx(1e300) for c in cmds)


# G76 cuts about (K/J)**R passes: a J of 1e-7 mm made ten million passes (minutes of CPU,
# over the 20 s limit); a huge H (spring passes) ran for ever
@pytest.mark.parametrize(
    "g76",
    ["G76 P1 Z-1000 I-1 J0.0000001 K1 Q29", "G76 P1 Z-10 I-1 J0.1 K1 H999999999999"],
)
def test_a_g76_of_millions_of_passes_is_refused_before_the_first(
    fresh_limits: None, g76: str
) -> None:
    diag = _error(f"G21 G18 G7\nS500 M3\nG0 X20 Z1\n{g76}\nM2\n")
    assert (diag.code, diag.location.line) == ("LIMIT-COUNT", 4)
    assert "G76" in diag.message


def test_an_ordinary_g76_is_not_limited(fresh_limits: None) -> None:
    text = "G21 G18 G7\nS500 M3\nG0 X20 Z1\nG76 P1.5 Z-20 I-1 J0.1 K1 R2 Q29 H2\nM2\n"
    assert len(list(read_text(text, "rs274ngc", "g76.ngc"))) > 100


NESTED = {
    # eight nested loops of 1,000 passes: each loop within loop_passes, 10**24 moves in all
    "rs274ngc": "G21 G91 F100\n"
    + "".join(f"o{i} repeat [1000]\n" for i in range(1, 9))
    + "G1 X0.001\n"
    + "".join(f"o{i} endrepeat\n" for i in range(8, 0, -1))
    + "M2\n",
    "fanuc": "%\nO1\nG21 G91 F100.\n#1=0\nWHILE[#1LT1000]DO1\n#1=#1+1\n#2=0\n"
    "WHILE[#2LT1000]DO2\n#2=#2+1\n#3=0\nWHILE[#3LT1000]DO3\n#3=#3+1\nG01 X0.001\n"
    "END3\nEND2\nEND1\nM30\n%\n",
    "siemens840d": "G710 G91 F100\nR1=0\nWHILE R1<1000\nR1=R1+1\nR2=0\nWHILE R2<1000\n"
    "R2=R2+1\nR3=0\nWHILE R3<1000\nR3=R3+1\nG1 X0.001\nENDWHILE\nENDWHILE\nENDWHILE\nM30\n",
}


@pytest.mark.parametrize("dialect", sorted(NESTED))
def test_nested_loops_multiplying_into_hours_end_with_loop_limit(
    fresh_limits: None, dialect: str
) -> None:
    limits.configure(loop_total=1_000)  # the default is 10**6: a few seconds of CPU
    diag = _error(NESTED[dialect], dialect)
    assert diag.code == "LOOP-LIMIT" and "loop_total" in diag.message
    assert diag.location.line > 1


def test_loop_total_counts_every_pass_of_a_raster(fresh_limits: None) -> None:
    """3 rows of 200 points: 603 passes in all, the inner loop 200 in a row."""
    text = (
        "#1=0\no1 while [#1 LT 3]\n#2=0\no2 while [#2 LT 200]\nG1 X#2 Y#1 F100\n"
        "#2=[#2+1]\no2 endwhile\n#1=[#1+1]\no1 endwhile\nM2\n"
    )
    limits.configure(loop_total=603)
    assert len(list(read_text(text, "rs274ngc", "raster.ngc"))) > 600
    limits.configure(loop_total=602)
    assert _error(text).code == "LOOP-LIMIT"


# the Fanuc reader wrote STRAIGHT_FEED(inf, nan, ...) and exited 0; the control stops
# with alarm 111 (calculated data overflow)
@pytest.mark.parametrize(
    ("body", "line"),
    [
        ("#1=100000000000000000000000000000000000000000000000000.\n#2=#1*#1*#1*#1*#1*#1*#1", 6),
        ("#1=EXP[700]*EXP[700]", 5),
        ("#1=1.\nWHILE[#1GT0]DO1\n#1=#1*1000000000.*1000000000.*1000000000.\nEND1", 7),
    ],
)
def test_a_fanuc_macro_overflow_is_a_located_alarm(body: str, line: int) -> None:
    diag = _error(f"%\nO1\nG21 G90\nF100.\n{body}\nG01 X#1\nM30\n%\n", "fanuc")
    assert (diag.code, diag.location.line) == ("FANUC-OVERFLOW", line)


GRBL = Path(__file__).parent / "data" / "grbl_sim" / "machine.toml"


# the Grbl model made every chord of an arc a row of the segment table before planning:
# an arc of a million turns (1.6e8 chords, 57 GB) died with numpy's MemoryError, one of
# radius 1e99 with a ValueError (a negative repeat count) - tracebacks of cnc plan
@pytest.mark.parametrize("arc", ["G2 X0 Y0 I10 J0 P1000000", "G2 X0 Y0 I" + "9" * 99 + " J0"])
def test_a_grbl_arc_of_too_many_chords_is_refused_at_its_line(fresh_limits: None, arc: str) -> None:
    machine = parse_machine(GRBL.read_text())
    text = f"G21 G90 G17\nF100\nG0 X0 Y0\n{arc}\nG1 X1\nM2\n"
    built = build(read_text(text, "rs274ngc", "arc.ngc"), machine, "arc.ngc")
    with pytest.raises(Diagnostic) as info:
        segment_arcs(built.path, machine.controller.arc_tolerance)
    diag = info.value
    assert (diag.code, diag.location.file, diag.location.line) == ("LIMIT-COUNT", "arc.ngc", 4)
    assert "arc_chords" in diag.message


def test_a_grbl_arc_within_the_chord_limit_is_cut_into_its_chords(fresh_limits: None) -> None:
    """mc_arc: floor(|phi r/2| / sqrt(tol (2r - tol))) chords; the limit counts the same."""
    machine = parse_machine(GRBL.read_text())
    chords = math.floor(math.pi * 10 / math.sqrt(0.002 * (20 - 0.002)))
    text = "G21 G90 G17\nF100\nG0 X0 Y0\nG2 X0 Y0 I10 J0\nM2\n"
    built = build(read_text(text, "rs274ngc", "arc.ngc"), machine, "arc.ngc")
    limits.configure(arc_chords=chords)
    assert len(segment_arcs(built.path, 0.002).segments) >= chords
    limits.configure(arc_chords=chords - 1)
    with pytest.raises(Diagnostic):
        segment_arcs(built.path, 0.002)


POCKET = (Path(__file__).parent / "stepnc" / "pocket_zigzag.stp").read_text()


# a Part 21 real of 1.0E999 was read as infinity: cnc stepnc canon wrote moves to inf and
# exited 0, cnc stepnc gouge failed with "cannot convert float NaN to integer" and no line
@pytest.mark.parametrize("real", ["1.0E999", "1.E+400", "-17.5E0309"])
def test_a_part21_real_beyond_the_floats_is_a_located_error(real: str) -> None:
    text = POCKET.replace("(50.0,40.0,0.0)", f"({real},40.0,0.0)")
    line = text[: text.index(real)].count("\n") + 1
    with pytest.raises(Diagnostic) as info:
        parse(text, "inf.stp")
    diag = info.value
    assert (diag.code, diag.location.line, diag.location.column) == ("P21-NUMBER", line, 26)


def test_a_part21_real_within_the_floats_is_read() -> None:
    text = POCKET.replace("(50.0,40.0,0.0)", "(1.0E300,40.0,-2.5E-320)")
    point = parse(text, "big.stp").instances[105]
    assert point.params[1] == (1e300, 40.0, -2.5e-320)


BSPLINE = (Path(__file__).parent / "stepnc" / "explicit_bspline.stp").read_text()


def _stepnc_error(tmp_path: Path, text: str) -> Diagnostic:
    prog = tmp_path / "hostile.stp"
    prog.write_text(text)
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(canon_from_file(str(prog), mode="nist"))
    assert time.process_time() - start < 2.0
    return info.value


# knot multiplicities were expanded before they were counted: (1000000000,4) listed a
# billion knots (MemoryError traceback); degree 0, a missing or a negative multiplicity
# were not refused
@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("(4,4),(0.0,1.0)", "(1000000000,4),(0.0,1.0)"),
        ("(4,4),(0.0,1.0)", "(-4,12),(0.0,1.0)"),
        ("(4,4),(0.0,1.0)", "(4,4,4),(0.0,1.0)"),
        ("B_SPLINE_CURVE_WITH_KNOTS('',3,", "B_SPLINE_CURVE_WITH_KNOTS('',0,"),
    ],
)
def test_a_bspline_with_impossible_knots_is_a_located_error(
    tmp_path: Path, old: str, new: str
) -> None:
    assert old in BSPLINE
    diag = _stepnc_error(tmp_path, BSPLINE.replace(old, new))
    assert diag.code == "STEPNC-CURVE" and diag.location.entity is not None


# a tool of diameter 0 or -10 and a feedrate of -0.02 m/s gave a program (exit 0)
@pytest.mark.parametrize(
    ("old", "new", "code"),
    [
        ("MILLING_TOOL_DIMENSION(10.0", "MILLING_TOOL_DIMENSION(0.0", "STEPNC-TOOL-DIAMETER"),
        ("MILLING_TOOL_DIMENSION(10.0", "MILLING_TOOL_DIMENSION(-10.0", "STEPNC-TOOL-DIAMETER"),
        ("MILLING_TECHNOLOGY(0.02", "MILLING_TECHNOLOGY(-0.02", "STEPNC-NO-FEED"),
    ],
)
def test_a_stepnc_tool_or_feed_that_cannot_cut_is_a_located_error(
    tmp_path: Path, old: str, new: str, code: str
) -> None:
    assert old in POCKET
    diag = _stepnc_error(tmp_path, POCKET.replace(old, new))
    assert diag.code == code and diag.location.entity is not None


def _no_memory(count: int, nax: int) -> tuple[np.ndarray, ...]:
    raise MemoryError(f"cannot allocate {count} samples")


# G93 G1 X10 F0 (a 6,000 s move: 6e6 samples, 640 MB) under a 1 GB address space: cnc
# trace and cnc run died with a MemoryError traceback from kernel/interp/bulk.py
def test_samples_that_do_not_fit_in_memory_are_a_located_error(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    text = "G21 G90 G17 G94\nF100\nG1 X10\nG93 G1 X20 F0\nG94 G1 X0 F100\nM2\n"
    commands = read_text(text, "rs274ngc", "slow.ngc")
    _, plan = plan_program(commands, DEFAULT_MACHINE, file="slow.ngc")
    monkeypatch.setattr(interpolate, "_outputs", _no_memory)
    with pytest.raises(Diagnostic) as info:
        interpolate.sample(plan)
    diag = info.value
    assert (diag.code, diag.location.file, diag.location.line) == ("LIMIT-MEMORY", "slow.ngc", 4)
    assert "6,0" in diag.message  # 6,000 s of samples at 1 ms


# str.isdigit() and a str regex's \d take every Unicode digit: "X１０" (fullwidth) and
# "X١٠" (Arabic-Indic) were read as X10 (Fanuc: X0.01) and cnc canon exited 0; rs274 says
# "bad number format"
@pytest.mark.parametrize(
    ("dialect", "line", "code"),
    [
        ("rs274ngc", "G1 X\uff11\uff10 F100", "NGC-BAD-VALUE"),
        ("rs274ngc", "N\uff11 G1 X1 F100", "NGC-BAD-VALUE"),
        ("rs274ngc", "G1 X[\u0661+1] F100", "NGC-BAD-VALUE"),
        ("fanuc", "G01 X\uff11\uff10. F100.", "FANUC-SYNTAX"),
        ("fanuc", "#1=\u0661\u0660.", "FANUC-SYNTAX"),
        ("siemens840d", "G1 X\u0661\u0660 F100", "SIEM-CHARACTER"),
        ("siemens840d", "G1 X=\uff11\uff10 F100", "SIEM-CHARACTER"),
    ],
)
def test_a_unicode_digit_is_no_digit_of_a_program(dialect: str, line: str, code: str) -> None:
    end = "M30" if dialect != "rs274ngc" else "M2"
    diag = _error(f"G90\n{line}\n{end}\n", dialect)
    assert (diag.code, diag.location.line) == (code, 2)


@pytest.fixture
def fifo(tmp_path: Path) -> Iterator[str]:
    """A FIFO nobody writes to; a test that opens it for reading would block, so an alarm
    ends the test after 5 s instead."""
    path = tmp_path / "prog.ngc"
    os.mkfifo(path)

    def expire(signum: int, frame: object) -> None:
        raise TimeoutError("blocked on the FIFO")

    old = signal.signal(signal.SIGALRM, expire)
    signal.alarm(5)
    yield str(path)
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


# a FIFO given as the program (cnc check, plan, run, stepnc ...), profile, tool table or
# configuration blocked for ever; /dev/zero as a profile was read until memory ran out
@pytest.mark.parametrize(
    ("load", "what"),
    [
        (read_head, "program"),
        (load_machine, "machine profile"),
        (load_tool_table, "tool table"),
    ],
)
def test_a_fifo_or_device_is_refused_before_it_is_opened(
    fifo: str, load: Callable[[str], object], what: str
) -> None:
    for path in (fifo, "/dev/zero"):
        with pytest.raises(Diagnostic) as info:
            load(path)
        diag = info.value
        assert (diag.code, diag.location.file) == ("IO-OPEN", path)
        assert f"cannot read {what}" in diag.message


def test_cnc_check_of_a_fifo_is_an_io_error(fifo: str) -> None:
    res = CliRunner().invoke(cli, ["check", fifo])
    assert res.exit_code == 1, res.output  # one failed file of the batch
    assert "error[CNC001/IO-OPEN]: cannot read program" in res.output


# float() takes nan, inf, 1e999 and Unicode digits: a LinuxCNC tool table's Z1e999 was a
# tool length of infinity, and "Tinf" an OverflowError traceback (int(inf))
@pytest.mark.parametrize(
    ("row", "column"),
    [
        ("T1 P1 Z1e999 D1", 7),
        ("T1 P1 Znan D1", 7),
        ("T1 P1 Z1 D-inf", 10),
        ("T1 P1 Z\uff11 D1", 7),
        ("T1e999 P1 Z1", 1),
    ],
)
def test_a_tool_table_number_must_be_finite(row: str, column: int) -> None:
    with pytest.raises(Diagnostic) as info:
        read_tool_table([row + "\n"], "t.tbl")
    diag = info.value
    assert (diag.code, diag.location.line, diag.location.column) == ("TOOL-SYNTAX", 1, column)


def test_a_nist_tool_file_number_must_be_finite() -> None:
    with pytest.raises(Diagnostic) as info:
        read_tool_table(["header\n", "\n", "1 1 inf 10.0 end mill\n"], "t.tool")
    assert (info.value.code, info.value.location.line) == ("TOOL-SYNTAX", 3)


def test_a_command_out_of_memory_is_a_coded_error_at_its_program(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The last net of every command (cli.errors.guarded): a stage that holds the whole
    program and runs out (the linuxcnc model in one endless G64 run) ends with LIMIT-MEMORY
    at the program and exit 1, not a MemoryError traceback."""

    @guarded
    def command(program: str) -> None:
        raise MemoryError

    with pytest.raises(SystemExit) as info:
        command(program="big.ngc")
    assert info.value.code == 1
    assert "big.ngc: error[LIMIT-MEMORY]: out of memory" in capsys.readouterr().err


AP238 = (Path(__file__).parent / "stepnc" / "ap238" / "cc1_two_tools.stp").read_text()


def test_an_ap238_negative_feedrate_is_a_located_error(tmp_path: Path) -> None:
    """NUMERIC_MEASURE(-500.) as the feed speed gave SET_FEED_RATE(-500) and exit 0."""
    text = AP238.replace("NUMERIC_MEASURE(500.)", "NUMERIC_MEASURE(-500.)")
    diag = _stepnc_error(tmp_path, text)
    assert (diag.code, diag.location.entity) == ("STEPNC-AP238", 54)
    assert "-500" in diag.message


# a 100 MB line (one comment, or words) was decoded, lower-cased and split whole: cnc canon
# passed 1 GB of memory
@pytest.mark.parametrize("dialect", ["rs274ngc", "grbl", "mach3", "nist_v3"])
def test_a_line_over_the_line_limit_is_refused_before_it_is_parsed(
    fresh_limits: None, dialect: str
) -> None:
    limits.configure(line_chars=1000)
    diag = _error("G21\n(" + "a" * 2000 + ")\nM2\n", dialect)
    assert (diag.code, diag.location.line, diag.location.column) == ("LIMIT-LINE", 2, 1001)
    limits.configure(line_chars=2002)
    list(read_text("G21\n(" + "a" * 2000 + ")\nM2\n", dialect, "long.ngc"))


# Fanuc, Haas, 840D and Sandia programs are read whole: a 100 MB line had no limit at all
@pytest.mark.parametrize(
    ("dialect", "text"),
    [
        ("fanuc", "O1000\nG0 X1 (" + "a" * 2000 + ")\nM30\n"),
        ("haas", "%\nO1000\nG0 X1 (" + "a" * 2000 + ")\nM30\n%\n"),
        ("siemens840d", "G0 X1\nG1 X2 F100 ;" + "a" * 2000 + "\nM30\n"),
        ("sandia", "Activate\nSetSpeed 10\nMoveTo X=1 Y=2 Z=3 #" + "a" * 2000 + "\nDeactivate\n"),
    ],
)
def test_a_line_over_the_line_limit_is_refused_in_every_dialect(
    fresh_limits: None, dialect: str, text: str
) -> None:
    long_line = text.count("\n", 0, text.index("a" * 2000)) + 1
    limits.configure(line_chars=1000)
    diag = _error(text, dialect)
    assert (diag.code, diag.location.line, diag.location.column) == ("LIMIT-LINE", long_line, 1001)
    assert f"a line of {len(text.splitlines()[long_line - 1]):,} characters" in diag.message
    limits.configure(line_chars=2100)
    list(read_text(text, dialect, "long.nc"))


AXES = "".join(f"[axes.{a}]\nvelocity = 100.0\nacceleration = 1000.0\n" for a in "xyz")


# hostile profiles: lookahead 2**63-1 was an IndexError in the plan's stream, an
# interpolation period of 1e300 s a LinAlgError in the servo model, [limits] NaN a
# ValueError (int(nan)), a settle of 1e5 s a trace of 1e8 samples per axis (minutes)
@pytest.mark.parametrize(
    ("table", "code", "words"),
    [
        ("[controller]\nlookahead = 9223372036854775807\n", "MACH-RANGE", "10**6"),
        ("[controller]\ninterpolation_period = 1e300\n", "MACH-RANGE", "at most 1 s"),
    ],
)
def test_a_profile_value_beyond_any_control_is_machine_range(
    table: str, code: str, words: str
) -> None:
    with pytest.raises(Diagnostic) as info:
        parse_machine(AXES + table, "m.toml")
    assert (info.value.code, info.value.location.file) == (code, "m.toml")
    assert words in info.value.message


@pytest.mark.parametrize("value", [math.nan, math.inf, -1.0])
def test_a_limit_that_is_not_a_finite_count_is_limit_config(
    fresh_limits: None, value: float
) -> None:
    with pytest.raises(Diagnostic) as info:
        limits.configure(samples_per_move=value)
    assert info.value.code == "LIMIT-CONFIG"


def test_a_servo_settle_of_hours_is_refused() -> None:
    machine = parse_machine(AXES + "[servo]\nsettle = 100000.0\n", "m.toml")
    with pytest.raises(Diagnostic) as info:
        servo_setup(machine, machine.controller.interpolation_period)
    assert info.value.code == "SERVO-PARAM" and "settle" in info.value.message


def test_the_excerpt_of_a_huge_line_lays_out_only_its_window() -> None:
    """A display position per character of a 100 MB line (a list of 10**8 ints) ran the
    reporting of LIMIT-LINE out of memory: a MemoryError traceback."""
    start = time.process_time()
    text = "a" * 5_000_000 + "\tX1" + "b" * 5_000_000
    gutter, line, caret = excerpt(7, 5_000_002, text)
    assert time.process_time() - start < 0.5
    assert line.startswith("7 | …a") and line.endswith("b…") and len(line) < 120
    assert line[caret.index("^")] == "X"


def test_a_huge_line_of_a_large_file_is_read_for_its_excerpt_in_linear_time(
    tmp_path: Path,
) -> None:
    """_read_line re-counted (and re-copied) all it had read at each 64 KB: a 100 MB line
    took 53 s of CPU in cnc check's report."""
    path = tmp_path / "long.ngc"
    path.write_bytes(b"G21\n(" + b"a" * 9_000_000 + b")\nM2\n")  # over the 8 MB kept whole
    start = time.process_time()
    assert _line_of(str(path), 3) == "M2"
    line = _line_of(str(path), 2)
    assert time.process_time() - start < 1.0
    assert line is not None and len(line) == 9_000_002


# cnc convert --to sandia made every chord of an arc before writing: an arc of a million
# turns (2.2e8 chords) or of radius 1e99 was a ValueError traceback (a negative repeat)
@pytest.mark.parametrize(("radius", "turns"), [(10.0, 1_000_000), (1e99, 1)])
def test_a_sandia_arc_of_too_many_chords_is_refused_at_its_line(
    fresh_limits: None, radius: float, turns: int
) -> None:
    where = Location("arc.ngc", 4, 1)
    arc = canon.ArcFeed(0.0, 0.0, radius, 0.0, turns, 0.0, 0.0, 0.0, 0.0, source=where)
    with pytest.raises(Diagnostic) as info:
        batch_points([arc], (0, 1, 2), (0.0, 0.0, 0.0), 0.001)
    assert (info.value.code, info.value.location) == ("LIMIT-COUNT", where)
    assert "arc_chords" in info.value.message


# cnc convert to a control without a turns word wrote an arc of a million turns as a
# million full circles and read them all back: 23 s of CPU before CONV-VERIFY
@pytest.mark.parametrize("target", ["fanuc", "grbl"])
def test_an_arc_of_a_million_turns_is_refused_at_its_line_before_it_is_written(
    fresh_limits: None, tmp_path: Path, target: str
) -> None:
    program = tmp_path / "turns.ngc"
    program.write_text("G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10 F500\nG2 X10 Y0 I-10 J0 P1000000\nM2\n")
    out = tmp_path / "turns.out"
    start = time.process_time()
    result = CliRunner().invoke(cli, ["convert", str(program), "--to", target, "-o", str(out)])
    assert time.process_time() - start < 5.0
    assert result.exit_code == 1 and not out.exists()
    assert "turns.ngc:4:1: error[LIMIT-COUNT]" in result.output
    assert "arc_turns" in result.output


def test_an_arc_of_a_few_turns_is_still_written_as_full_circles(
    fresh_limits: None, tmp_path: Path
) -> None:
    program = tmp_path / "turns.ngc"
    program.write_text("G21 G90 G17\nG0 X0 Y0 Z0\nG1 X10 F500\nG2 X10 Y0 I-10 J0 P3\nM2\n")
    out = tmp_path / "turns.nc"
    result = CliRunner().invoke(cli, ["convert", str(program), "--to", "fanuc", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert (
        sum(line.startswith("G02") or " G02" in line for line in out.read_text().splitlines()) >= 1
    )
    assert out.read_text().count("I-10.") == 3  # three full circles, each its own block


# cnc stepnc check validated the model only: a program every toolpath command refuses
# passed it (exit 0), and an AP238 AIM file, which stepnc canon reads, was refused
@pytest.mark.parametrize(
    ("name", "old", "new", "code"),
    [
        ("explicit_bspline.stp", "(4,4),(0.0,1.0)", "(-4,12),(0.0,1.0)", "STEPNC-CURVE"),
        (
            "pocket_zigzag.stp",
            "MILLING_TECHNOLOGY(0.02",
            "MILLING_TECHNOLOGY(-0.02",
            "STEPNC-NO-FEED",
        ),
        (
            "ap238/cc1_two_tools.stp",
            "NUMERIC_MEASURE(500.)",
            "NUMERIC_MEASURE(-500.)",
            "STEPNC-AP238",
        ),
    ],
)
def test_stepnc_check_refuses_what_the_toolpath_generators_refuse(
    tmp_path: Path, name: str, old: str, new: str, code: str
) -> None:
    text = (Path(__file__).parent / "stepnc" / name).read_text()
    good, bad = tmp_path / "good.stp", tmp_path / "bad.stp"
    good.write_text(text)
    bad.write_text(text.replace(old, new))
    runner = CliRunner()
    ok = runner.invoke(cli, ["stepnc", "check", str(good)])
    assert ok.exit_code == 0, ok.output
    refused = runner.invoke(cli, ["stepnc", "check", str(bad)])
    assert refused.exit_code == 1
    assert f"error[{code}]" in refused.output and f"{bad}:#" in refused.output
