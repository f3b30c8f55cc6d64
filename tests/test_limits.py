"""Resource limits (issue 19): hostile programs end quickly with a located ``LIMIT-*`` (or
the dialect's own) diagnostic, never a traceback, a hang or runaway memory.

Each case is a construct that used to raise OverflowError, ValueError (Python's 4,300-digit
limit) or RecursionError, loop for hours, or allocate gigabytes.
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

import kernel.limits as limits
from cli.main import cli
from gcode.readers import read_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

STEPNC = Path(__file__).parent / "stepnc"
BIG = "9" * 5000


@pytest.fixture(autouse=True)
def _defaults() -> Iterator[None]:
    limits.reset()
    yield
    limits.reset()


def _error(dialect: str, text: str) -> Diagnostic:
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, dialect, "p"))
    assert time.process_time() - start < 5.0
    return info.value


CASES = [
    # (dialect, program, code, line)
    ("rs274ngc", f"G21\nG0 X{BIG}\nM2\n", "LIMIT-DIGITS", 2),
    ("rs274ngc", f"#{BIG}=1\nM2\n", "LIMIT-DIGITS", 1),
    ("rs274ngc", f"G{BIG}\nM2\n", "LIMIT-DIGITS", 1),
    ("rs274ngc", f"G0 X1.{BIG}\nM2\n", "LIMIT-DIGITS", 1),
    ("rs274ngc", "#1=" + "[" * 300 + "1" + "]" * 300 + "\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "G0 X" + "[" * 300 + "1" + "]" * 300 + "\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "#1=[" + "+".join(["1"] * 3000) + "]\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "#1=" + "-" * 3000 + "1\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "#1=" + "#" * 3000 + "1\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "#1=" + "sin[" * 300 + "1" + "]" * 300 + "\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "o1 if [" + "[" * 300 + "1" + "]" * 300 + "]\no1 endif\nM2\n", "LIMIT-NESTING", 1),
    ("rs274ngc", "G21 G90\nG0 Z10\nG83 X0 Y0 Z-10 R1 Q0.000001 F100\nM2\n", "LIMIT-COUNT", 3),
    ("rs274ngc", "G21 G91\nG0 Z10\nG81 X1 Y0 Z-1 R1 L1000000000 F100\nM2\n", "LIMIT-COUNT", 3),
    ("rs274ngc", "G20 G90\nG0 Z1\nG73 X0 Y0 Z-1 R0.1 Q0.00000000001 F10\nM2\n", "LIMIT-COUNT", 3),
    ("rs274ngc", "o1 while [1]\n#1=1\no1 endwhile\nM2\n", "LOOP-NO-PROGRESS", 3),
    ("fanuc", f"%\nO1\nG0 X{BIG}\nM30\n%\n", "LIMIT-DIGITS", 3),
    ("fanuc", f"%\nO{BIG}\nG0 X1\nM30\n%\n", "LIMIT-DIGITS", 2),
    ("fanuc", f"%\nO1\nN{BIG} G0 X1\nM30\n%\n", "LIMIT-DIGITS", 3),
    ("fanuc", f"%\nO1\nM98 P{BIG}\nM30\n%\n", "LIMIT-DIGITS", 3),
    ("fanuc", f"%\nO1\nGOTO{BIG}\nM30\n%\n", "LIMIT-DIGITS", 3),
    ("fanuc", "%\nO1\n#1=" + "[" * 1100 + "1" + "]" * 1100 + "\nM30\n%\n", "LIMIT-NESTING", 3),
    ("fanuc", "%\nO1\n#1=" + "+".join(["1"] * 3000) + "\nM30\n%\n", "LIMIT-NESTING", 3),
    ("fanuc", "%\nO1\n#1=" + "-" * 3000 + "1\nM30\n%\n", "LIMIT-NESTING", 3),
    ("fanuc", "%\nO1\n#1=" + "SIN[" * 300 + "1" + "]" * 300 + "\nM30\n%\n", "LIMIT-NESTING", 3),
    (
        "fanuc",
        "%\nO1\nG21 G90\nG0 Z10\nG83 X0 Y0 Z-100000 R1 Q0.001 F100\nM30\n%\n",
        "LIMIT-COUNT",
        5,
    ),
    ("fanuc", "%\nO1\nWHILE[1EQ1]DO1\n#1=1\nEND1\nM30\n%\n", "LOOP-NO-PROGRESS", 5),
    ("siemens", f"G0 X{BIG}\nM30\n", "LIMIT-DIGITS", 1),
    ("siemens", f"GOTOF L{BIG}\nM30\n", "LIMIT-DIGITS", 1),
    ("siemens", "WHILE 1==1\nR1=1\nENDWHILE\nM30\n", "LOOP-NO-PROGRESS", 3),
]


@pytest.mark.parametrize(("dialect", "text", "code", "line"), CASES)
def test_hostile_program_ends_with_a_located_limit(
    dialect: str, text: str, code: str, line: int
) -> None:
    err = _error(dialect, text)
    assert err.code == code, err
    assert err.location.line == line, err


def test_nesting_within_the_limit_still_runs() -> None:
    text = "G21\n#1=" + "[" * 60 + "2" + "]" * 60 + "\nG0 X#1\nM2\n"
    moves = [c for c in read_text(text, "rs274ngc") if isinstance(c, canon.StraightTraverse)]
    assert moves[0].x == 2.0
    chain = "G21\n#1=[" + "+".join(["1"] * 200) + "]\nG0 X#1\nM2\n"
    moves = [c for c in read_text(chain, "rs274ngc") if isinstance(c, canon.StraightTraverse)]
    assert moves[0].x == 200.0


def test_limits_are_configurable() -> None:
    text = "G21\nG0 X" + "1" * 20 + "\nM2\n"
    list(read_text(text, "rs274ngc"))
    limits.configure(digits=10)
    assert _error("rs274ngc", text).code == "LIMIT-DIGITS"
    with pytest.raises(Diagnostic) as info:
        limits.configure(nonsense=3)
    assert info.value.code == "LIMIT-CONFIG"


def test_cli_limit_option_and_machine_profile(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text("G21\nG0 X" + "1" * 20 + "\nM2\n")
    ok = CliRunner().invoke(cli, ["canon", str(prog)])
    assert ok.exit_code == 0, ok.output
    res = CliRunner().invoke(cli, ["--limit", "digits=10", "canon", str(prog)])
    assert res.exit_code == 1 and "LIMIT-DIGITS" in res.output
    limits.reset()
    bad = CliRunner().invoke(cli, ["--limit", "digits", "canon", str(prog)])
    assert bad.exit_code == 2
    profile = tmp_path / "m.toml"
    profile.write_text(
        "[axes.x]\nmin = -1e9\nmax = 1e9\n[axes.y]\nmin = -1e9\nmax = 1e9\n"
        "[axes.z]\nmin = -1e9\nmax = 1e9\n[limits]\ndigits = 10\n"
    )
    res = CliRunner().invoke(cli, ["check", "-m", str(profile), str(prog)])
    assert "LIMIT-DIGITS" in res.output and f"{prog}:2:" in res.output


def _stepnc(tmp_path: Path, name: str, old: str, new: str) -> Path:
    src = (STEPNC / name).read_text()
    assert old in src
    out = tmp_path / name
    out.write_text(src.replace(old, new))
    return out


def _stepnc_error(path: Path) -> Diagnostic:
    from stepnc.to_canon import canon_from_file

    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(canon_from_file(str(path), mode="nist"))
    assert time.process_time() - start < 10.0
    return info.value


def test_stepnc_workplan_containing_itself(tmp_path: Path) -> None:
    p = _stepnc(
        tmp_path,
        "pocket_circular.stp",
        "#2=WORKPLAN('MAIN',(#129),$,#4,$);",
        "#2=WORKPLAN('MAIN',(#129,#2),$,#4,$);",
    )
    err = _stepnc_error(p)
    assert err.code == "STEPNC-CYCLE" and err.location.entity == 2
    res = CliRunner().invoke(cli, ["stepnc", "info", str(p)])
    assert res.exit_code != 0 and "STEPNC-CYCLE" in res.output


@pytest.mark.parametrize(
    ("old", "new", "code"),
    [
        ("(50.0,40.0,0.0)", f"({BIG},40.0,0.0)", "LIMIT-DIGITS"),
        ("(50.0,40.0,0.0)", "(" * 3000 + "50.0" + ")" * 3000, "LIMIT-NESTING"),
    ],
)
def test_stepnc_numbers_and_nesting(tmp_path: Path, old: str, new: str, code: str) -> None:
    err = _stepnc_error(_stepnc(tmp_path, "pocket_circular.stp", old, new))
    assert err.code == code and err.location.line == 18


@pytest.mark.parametrize("name", ["face_unidir_climb_minus_y.stp", "pocket_rotated.stp"])
def test_stepnc_tiny_tool_stops_at_the_toolpath_limit(tmp_path: Path, name: str) -> None:
    src = (STEPNC / name).read_text()
    import re

    out = tmp_path / name
    out.write_text(re.sub(r"MILLING_TOOL_DIMENSION\([0-9.]+", "MILLING_TOOL_DIMENSION(0.0001", src))
    err = _stepnc_error(out)
    assert err.code == "LIMIT-COUNT" and err.location.entity is not None


def test_canonical_text_digits_and_nurbs_count() -> None:
    lines = [f"STRAIGHT_TRAVERSE({BIG}, 0, 0)"]
    with pytest.raises(Diagnostic) as info:
        list(canon.read_text(lines, "c.canon"))
    assert info.value.code == "LIMIT-DIGITS" and info.value.location.line == 1
    tc = next(canon.read_text(["NURBS_FEED(1e12, ...)"], "c.canon"))
    with pytest.raises(Diagnostic) as info:
        canon.parse_command(tc, "c.canon")
    assert info.value.code == "CANON-SYNTAX"
    tc = next(canon.read_text(["CHANGE_TOOL(1e308)"], "c.canon"))
    canon.parse_command(tc, "c.canon")  # a tool named by the text, no overflow


def test_cpu_budget_per_program_in_check(tmp_path: Path) -> None:
    """``--limit seconds=1`` stops a program that moves for ever (the loop guard lifted, so
    only the CPU budget can stop it) with LIMIT-TIME, and the batch goes on. Run as its own
    process: the budget is a SIGPROF timer of the process, as in a real run."""
    busy = tmp_path / "busy.ngc"
    busy.write_text("o1 while [1]\n#1=[#1+1]\nG0 X[#1 MOD 10]\no1 endwhile\nM2\n")
    fine = tmp_path / "fine.ngc"
    fine.write_text("G21\nG0 X1\nM2\n")
    budget = ["--limit", "seconds=1", "--limit", "loop_passes=1000000000"]
    args = [sys.executable, "-m", "cli.main", *budget, "check", str(busy), str(fine)]
    start = time.monotonic()
    done = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert time.monotonic() - start < 60
    out = done.stdout + done.stderr
    assert "LIMIT-TIME" in out and "2 files checked: 1 error" in out
    assert done.returncode == 1
