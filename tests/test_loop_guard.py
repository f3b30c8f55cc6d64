"""The loop guard every reader shares (gcode.core.loopguard): an endless loop stops with a
located LOOP-NO-PROGRESS / LOOP-LIMIT error naming the loop, and `cnc canon` never hangs."""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

import kernel.limits as limits
from gcode.core.loopguard import LoopGuard
from gcode.fanuc.reader import interpret_text as fanuc_text
from gcode.ngc.interpreter import InterpreterOptions
from gcode.ngc.interpreter import interpret_text as ngc_text
from gcode.readers import read_text
from gcode.siemens.reader import interpret_text as siemens_text
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

ENDLESS = {
    "goto.mpf": ("G0 X0\nLAB1: R1=R1+1\nGOTOB LAB1\nM30\n", 3, "GOTOB LAB1"),
    "while.mpf": ("G0 X0\nWHILE 1\nR1=R1+1\nENDWHILE\nM30\n", 4, "WHILE (line 2)"),
    "loop.mpf": ("G0 X0\nLOOP\nR1=R1+1\nENDLOOP\nM30\n", 4, "LOOP (line 2)"),
    "fanuc.nc": (
        "%\nO1000\nG0 X0\n#1=0\nWHILE [1 EQ 1] DO1\n#1=#1+1\nEND1\nM30\n%\n",
        7,
        "DO1 (line 5) END1",
    ),
    "ngc.ngc": (
        "G0 X0\n#1=0\no100 while [1 EQ 1]\n#1=[#1+1]\no100 endwhile\nM2\n",
        5,
        "o100 while (line 3)",
    ),
}


Reader = Callable[[str, str, InterpreterOptions], Iterator[canon.Command]]


def _reader(name: str) -> Reader:
    return {"mpf": siemens_text, "nc": fanuc_text, "ngc": ngc_text}[name.rsplit(".", 1)[1]]


@pytest.mark.parametrize("name", sorted(ENDLESS))
def test_an_endless_loop_without_output_stops_at_its_jump(name: str) -> None:
    text, line, construct = ENDLESS[name]
    options = InterpreterOptions(max_idle_blocks=1000)
    with pytest.raises(Diagnostic) as info:
        list(_reader(name)(text, name, options))
    exc = info.value
    assert (exc.code, exc.location.file, exc.location.line) == ("LOOP-NO-PROGRESS", name, line)
    assert construct in exc.message


@pytest.mark.parametrize(
    ("name", "text", "line"),
    [
        ("mv.mpf", "LAB1: G1 X1 F100\nX0\nGOTOB LAB1\nM30\n", 3),
        ("mv.nc", "%\nO1\nN10 G1 X1. F100.\nX0\nGOTO10\nM30\n%\n", 5),
        ("mv.ngc", "o1 while [1]\nG1 X1 F100\nX0\no1 endwhile\nM2\n", 4),
    ],
)
def test_an_endless_loop_that_moves_stops_at_the_block_limit(
    name: str, text: str, line: int
) -> None:
    with pytest.raises(Diagnostic) as info:
        list(_reader(name)(text, name, InterpreterOptions(max_blocks=500)))
    assert (info.value.code, info.value.location.line) == ("LOOP-LIMIT", line)


def test_loops_that_end_are_left_alone() -> None:
    text = "R1=0\nWHILE R1<5000\nR1=R1+1\nENDWHILE\nG1 X=R1 F100\nM30\n"
    cmds = list(siemens_text(text, "ok.mpf", InterpreterOptions(max_idle_blocks=20_000)))
    assert any("5000" in str(c) for c in cmds)


def test_the_guard_counts_idle_blocks_from_the_last_output() -> None:
    guard = LoopGuard(max_blocks=10**6, max_idle_blocks=10)
    loc = Location("g", 1, 1)
    guard.blocks = 10
    guard.back("X", loc)
    guard.output, guard.blocks = 1, 15
    guard.back("X", loc)  # output since the last check: a fresh start
    guard.blocks = 25
    guard.back("X", loc)
    guard.blocks = 26
    with pytest.raises(Diagnostic) as info:
        guard.back("GOTOB L", loc)
    assert info.value.code == "LOOP-NO-PROGRESS"


@pytest.mark.parametrize("name", ["goto.mpf", "while.mpf", "fanuc.nc"])
def test_cnc_canon_never_hangs_on_an_endless_loop(tmp_path: Path, name: str) -> None:
    text, line, _ = ENDLESS[name]
    prog = tmp_path / name
    prog.write_text(text)
    args = [sys.executable, "-m", "cli.main", "canon", str(prog)]
    if name.endswith(".nc"):
        args += ["--dialect", "fanuc"]
    start = time.monotonic()
    done = subprocess.run(args, capture_output=True, text=True, timeout=60)
    assert time.monotonic() - start < 30  # a few seconds; the bound leaves room for a busy machine
    assert done.returncode == 1
    assert f"{name}:{line}:" in done.stderr and "LOOP-NO-PROGRESS" in done.stderr


def test_cnc_canon_max_blocks_option(tmp_path: Path) -> None:
    prog = tmp_path / "mv.mpf"
    prog.write_text("LAB1: G1 X1 F100\nX0\nGOTOB LAB1\nM30\n")
    args = [sys.executable, "-m", "cli.main", "canon", "--max-blocks", "300", str(prog)]
    done = subprocess.run(args, capture_output=True, text=True, timeout=60)
    assert done.returncode == 1 and "LOOP-LIMIT" in done.stderr


#: an endless loop that moves, in every dialect's loop constructs: (text, line of the jump
#: back, the loop named in the error)
MOVING = {
    "rs274ngc": ("G91\no100 while [1]\nG1 X1 F100\no100 endwhile\nM2\n", 4, "o100 while"),
    "rs274ngc-do": ("G91\no100 do\nG1 X1 F100\no100 while [1]\nM2\n", 4, "o100 do"),
    "fanuc": ("%\nO1\nG91\nWHILE[1EQ1]DO1\nG01 X1 F100\nEND1\nM30\n%\n", 6, "DO1 (line 4)"),
    "fanuc-goto": ("%\nO1\nG91\nN10 G01 X1 F100\nIF[1EQ1]GOTO10\nM30\n%\n", 5, "GOTO10"),
    "haas": ("%\nO1\nG91\nWHILE[1EQ1]DO2\nG01 X1 F100\nEND2\nM30\n%\n", 6, "DO2 (line 4)"),
    "siemens840d": ("G91\nWHILE 1\nG1 X1 F100\nENDWHILE\nM30\n", 4, "WHILE (line 2)"),
    "siemens840d-loop": ("G91\nLOOP\nG1 X1 F100\nENDLOOP\nM30\n", 4, "LOOP (line 2)"),
    "siemens840d-goto": ("G91\nLAB1: G1 X1 F100\nGOTOB LAB1\nM30\n", 3, "GOTOB LAB1"),
    "siemens840d-for": (
        "DEF INT I\nG91\nFOR I=1 TO 1000000000\nG1 X1 F100\nENDFOR\nM30\n",
        5,
        "FOR (line 3)",
    ),
}


@pytest.fixture
def few_passes() -> Iterator[None]:
    limits.configure(loop_passes=2_000)
    yield
    limits.reset()


@pytest.mark.parametrize("case", sorted(MOVING))
def test_an_endless_loop_that_moves_stops_at_the_loop_pass_budget(
    few_passes: None, case: str
) -> None:
    text, line, construct = MOVING[case]
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, case.split("-")[0], "mv"))
    exc = info.value
    assert (exc.code, exc.location.line) == ("LOOP-LIMIT", line), exc
    assert construct in exc.message and "loop_passes" in exc.message


@pytest.mark.parametrize(
    ("dialect", "text"),
    [
        # 3 rows of 1,500 points: 4,500 passes of the inner loop, 1,500 in a row
        (
            "rs274ngc",
            "#1=0\no1 while [#1 LT 3]\n#2=0\no2 while [#2 LT 1500]\nG1 X#2 Y#1 F100\n"
            "#2=[#2+1]\no2 endwhile\n#1=[#1+1]\no1 endwhile\nM2\n",
        ),
        (
            "fanuc",
            "%\nO1\n#1=0\nWHILE[#1LT3]DO1\n#2=0\nWHILE[#2LT1500]DO2\nG01 X#2 Y#1 F100\n"
            "#2=#2+1\nEND2\n#1=#1+1\nEND1\nM30\n%\n",
        ),
        (
            "siemens840d",
            "R1=0\nWHILE R1<3\nR2=0\nWHILE R2<1500\nG1 X=R2 Y=R1 F100\nR2=R2+1\nENDWHILE\n"
            "R1=R1+1\nENDWHILE\nM30\n",
        ),
    ],
)
def test_passes_of_a_nested_loop_count_per_entry(few_passes: None, dialect: str, text: str) -> None:
    moves = [c for c in read_text(text, dialect, "raster") if type(c).__name__ == "StraightFeed"]
    assert len(moves) == 4_500


@pytest.mark.slow
def test_the_default_loop_pass_budget_ends_a_moving_loop_within_seconds() -> None:
    text, line, _ = MOVING["rs274ngc"]
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, "rs274ngc", "mv"))
    assert info.value.code == "LOOP-LIMIT"
    assert "limit 100000" in info.value.message
    assert time.process_time() - start < 10  # about a second idle; room for a busy machine
