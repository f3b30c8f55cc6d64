"""Tool length registers survive conversion (issue 15).

``G43 H n`` is kept as the target's own register form, never as a length from the
converter's tool table, and the machine's tool table is written only with
``--write-tool-table``. Every golden and corpus program that uses G43 is written from
RS274/NGC to each G-code target and read back with that target's reader, with and without
a tool table: the tool length offset (its register and its length) in force at every motion
is the same. Grbl has no ``G43 H``: a located CONV-TOOL-REGISTER.
"""

from __future__ import annotations

import dataclasses
import functools
import re
import shutil
import subprocess
from collections.abc import Iterable
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.core import linuxcnc as lc
from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.readers import read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import options, programs, rs274

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
G43 = re.compile(r"g\s*4\s*3", re.IGNORECASE)
PROGRAMS = [p for p in programs() if G43.search(p.read_text(errors="replace"))]
TARGETS = ["rs274ngc", "fanuc", "haas", "siemens840d", "nist_v3", "grbl"]
TABLE_WRITES = re.compile(r"G10 ?L1[01]?(?![0-9])")

State = tuple[str | None, int | None, float]


def marked_options(program: Path, table: bool) -> InterpreterOptions:
    base = options(program)
    return dataclasses.replace(
        base, register_marks=True, tool_table=base.tool_table if table else None
    )


@functools.cache
def source_ir(program: Path, table: bool) -> tuple[canon.Command, ...] | None:
    try:
        return tuple(interpret(program, marked_options(program, table)))
    except Diagnostic:
        return None


def states(commands: Iterable[canon.Command], lengths: bool = True) -> list[State]:
    """The tool length offset in force at each motion (register mark and Z length), with
    repeats collapsed: the writer may split or merge moves, never change the offset. G49
    is no offset, as before any G43; ``lengths`` False compares the registers only."""
    mark: tuple[str | None, int | None] = (None, None)
    length = 0.0
    out: list[State] = []
    for c in commands:
        if isinstance(c, ToolLengthRegister):
            mark = (None, None) if c.code == "G49" else (c.code, c.register)
        elif isinstance(c, canon.UseToolLengthOffset):
            length = c.length
        elif isinstance(c, lc.ToolLengthOffsets):
            length = c.offset[2]
        elif isinstance(c, canon.MOTIONS):
            state = (mark[0], mark[1], round(length, 4) if lengths else 0.0)
            if not out or out[-1] != state:
                out.append(state)
    return out


def converted(
    ir: Iterable[canon.Command], target: str, decimals: int = 5, write_tool_table: bool = False
) -> tuple[str | None, Diagnostic | None]:
    options = WriterOptions(decimals=decimals, write_tool_table=write_tool_table)
    try:
        text = "\n".join(write(ir, target, options, ConversionReport()))
    except Diagnostic as exc:
        return None, exc
    return text + "\n", None


@pytest.mark.parametrize("table", [True, False], ids=["tool-table", "no-table"])
@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_tool_length_register_survives_a_round_trip(
    program: Path, target: str, table: bool
) -> None:
    ir = source_ir(program, table)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    text, error = converted(ir, target)
    if error is not None:
        assert error.code.startswith("CONV-") and error.location.line > 0
        if error.code == "CONV-TOOL-REGISTER":
            assert target != "rs274ngc"  # G43.2 H n: LinuxCNC only
        if error.code == "CONV-TOOL-LENGTH":  # G43.1 by value
            assert target in ("siemens840d", "nist_v3", "grbl")
        refusals = ("CONV-TOOL-REGISTER", "CONV-TOOL-TABLE", "CONV-TOOL-LENGTH", "CONV-WORK-OFFSET")
        if error.code in refusals:
            return
        pytest.skip(f"the writer refuses this program for another reason ({error.code})")
    assert text is not None
    assert not TABLE_WRITES.search(text), "the machine's tool table was written"
    try:
        back = list(read_text(text, target, program.name, marked_options(program, table)))
    except Diagnostic as exc:
        pytest.skip(f"the {target} reader refuses the output ({exc.code})")
    # the Siemens reader scales a D edge's length from the inch table as the others do
    assert states(back) == states(ir)


def test_grbl_refuses_g43_h_at_its_line() -> None:
    ir = interpret(ROOT / "docs/examples/bracket.ngc", InterpreterOptions(register_marks=True))
    text, error = converted(ir, "grbl")
    assert text is None and error is not None
    assert error.code == "CONV-TOOL-REGISTER"
    assert (error.location.line, error.location.column) == (8, 1)
    assert "G43 H1" in error.message


def test_siemens_refuses_another_tools_register() -> None:
    src = "G21 G90\nT1 M6\nG43 H2\nG0 X0 Y0 Z5\nM2\n"
    ir = read_text(src, "rs274ngc", "p.ngc", InterpreterOptions(register_marks=True))
    text, error = converted(ir, "siemens840d")
    assert error is not None and error.code == "CONV-TOOL-REGISTER"
    assert error.location.line == 3


def test_siemens_keeps_the_length_across_a_tool_change() -> None:
    """G43 H1 stays in force across M6 in RS274/NGC; the 840D's M6 D0 would end it."""
    src = "G21 G90\nT1 M6\nG43 H1\nT1 M6\nG0 X0 Y0 Z5\nM2\n"
    ir = list(read_text(src, "rs274ngc", "p.ngc", InterpreterOptions(register_marks=True)))
    text, error = converted(ir, "siemens840d")
    assert error is None and text is not None
    assert text.splitlines().count("T1 M6 D1") == 1 and "T1 M6 D0" in text
    back = read_text(text, "siemens840d", "p.mpf", InterpreterOptions(register_marks=True))
    assert states(back) == states(ir) == [("G43", 1, 0.0)]
    other = src.replace("T1 M6\nG0", "T2 M6\nG0")
    ir = list(read_text(other, "rs274ngc", "p.ngc", InterpreterOptions(register_marks=True)))
    text, error = converted(ir, "siemens840d")
    assert error is not None and error.code == "CONV-TOOL-REGISTER"
    assert error.location.line == 4


def test_a_lathe_has_no_tool_length_to_cancel() -> None:
    ir = read_text(
        "G21 G90\nG49\nG1 X1 F100\nM2\n",
        "rs274ngc",
        "p.ngc",
        InterpreterOptions(register_marks=True),
    )
    for target in ("fanuc_lathe", "haas_lathe"):
        text, error = converted(ir, target)
        assert error is None and text is not None and "G49" not in text
        assert list(read_text(text, target, "p.nc", InterpreterOptions()))


def test_canon_text_has_no_marks() -> None:
    ir = interpret(ROOT / "docs/examples/bracket.ngc", InterpreterOptions())
    assert not any(isinstance(c, ToolLengthRegister) for c in ir)


def cnc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["cnc", *args], capture_output=True, text=True, cwd=ROOT, check=False)


def test_readme_tour_writes_g43_h1() -> None:
    run = cnc("convert", "docs/examples/bracket.ngc", "--to", "fanuc")
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert "G43 H1" in lines and "G43 H3" in lines
    assert not TABLE_WRITES.search(run.stdout)
    assert lines[lines.index("T1 M06") + 1] == "G43 H1"


@pytest.mark.parametrize("target", ["fanuc", "haas", "rs274ngc", "nist_v3"])
def test_with_a_tool_table_the_register_is_still_kept(target: str, tmp_path: Path) -> None:
    table = tmp_path / "t.tbl"
    table.write_text("T1 P1 Z2 D0.2\nT3 P3 Z1.5 D0.1\n")
    run = cnc("convert", "docs/examples/bracket.ngc", "--to", target, "--tool-table", str(table))
    assert run.returncode == 0, run.stderr
    assert "G43 H1" in run.stdout.splitlines()
    assert not TABLE_WRITES.search(run.stdout)


def test_write_tool_table_writes_the_lengths_before_g43(tmp_path: Path) -> None:
    table = tmp_path / "t.tbl"
    table.write_text("T1 P1 Z2 D0.2\nT3 P3 Z1.5 D0.1\n")
    args = ["docs/examples/bracket.ngc", "--tool-table", str(table), "--write-tool-table"]
    fanuc = cnc("convert", *args, "--to", "fanuc").stdout.splitlines()
    i = fanuc.index("G43 H1")
    assert fanuc[i - 1] == "G10 L10 P1 R50.8"
    ngc = cnc("convert", *args, "--to", "rs274ngc").stdout.splitlines()
    assert ngc[ngc.index("G43 H1") - 1].startswith("G10 L1 P1 Z50.8")


def test_program_tool_table_edit_needs_write_tool_table(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 G90\nG10 L1 P1 Z1 R0.1\nT1 M6\nG43\nG0 X0 Y0 Z5\nM2\n")
    run = cnc("convert", str(prog), "--to", "rs274ngc")
    assert run.returncode != 0 and "CONV-TOOL-TABLE" in run.stderr
    assert f"{prog}:2:1" in run.stderr
    run = cnc("convert", str(prog), "--to", "rs274ngc", "--write-tool-table")
    assert run.returncode == 0 and "G10 L1 P1" in run.stdout


def test_missing_work_offset_is_an_error(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text("G21 G90\nG59.1\nG0 X1 Y1 Z1\nM2\n")
    run = cnc("convert", str(prog), "--to", "fanuc")
    assert run.returncode != 0 and "CONV-WORK-OFFSET" in run.stderr
    assert f"{prog}:2:1" in run.stderr


@pytest.mark.reference
@pytest.mark.skipif(shutil.which("rs274") is None, reason="needs LinuxCNC's rs274")
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_rs274_reads_our_linuxcnc_output_as_the_original(program: Path, tmp_path: Path) -> None:
    """With registers kept (G43 H n), rs274 with the same tool table prints the canon it
    prints for the original program."""
    ir = source_ir(program, True)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    text, error = converted(ir, "rs274ngc", decimals=6)
    if error is not None:
        assert error.code == "CONV-TOOL-TABLE"  # the program edits its tool table
        text, error = converted(ir, "rs274ngc", decimals=6, write_tool_table=True)
    assert text is not None, error
    ours = rs274(text, program.parent / "sim.tbl", tmp_path)
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []
