"""``--cutter-comp keep``: G41/G42 stay in the converted program and compensate the same.

For every golden and corpus program with cutter compensation the RS274/NGC reader is run
in keep mode (gcode.ngc.comp.keep: NISTIR 5970 comp commands around the programmed path); the
program is written for LinuxCNC (G41.1/G42.1 D diameter), Fanuc and Haas (G10 L12 radius,
G41/G42 D register) and read back by that dialect's reader, which compensates it. The
result must be equivalent (1e-4, tests/canon_equiv.py) to the original program's IR with
compensation applied by the interpreter.
"""

from __future__ import annotations

import dataclasses
import functools
import re
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.ngc.interpreter import interpret, interpret_text
from gcode.readers import read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text, options, programs, read_ir
from tests.test_ngc_cutter_comp import ERROR_PROGRAMS

COMP = re.compile(r"G\s*4[12](?![0-9])", re.IGNORECASE)
PROGRAMS = [p for p in programs() if COMP.search(p.read_text(errors="replace"))]
DIALECTS = ["rs274ngc", "fanuc", "haas"]
ALLOWED = {"CONV-ARC-FORMAT", "CONV-CUTTER-COMP"}


@functools.cache
def kept_ir(program: Path) -> tuple[canon.Command, ...] | None:
    try:
        keep = dataclasses.replace(options(program), keep_cutter_comp=True)
        return tuple(interpret(program, keep))
    except Diagnostic:
        return None


def test_programs_with_compensation_are_there() -> None:
    assert len(PROGRAMS) >= 10


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_kept_compensation_reads_back_as_the_compensated_path(program: Path, dialect: str):
    ir, applied = kept_ir(program), read_ir(program)
    # keep mode refuses exactly what applying refuses (its shadow compensator checks)
    assert (ir is None) == (applied is None)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        text = "\n".join(write(ir, dialect, WriterOptions(decimals=6), report))
    except Diagnostic as exc:
        assert exc.code.startswith("CONV-") and exc.location.line > 0
        return
    if any(c.code not in ALLOWED for c in report.changes):
        pytest.skip("the writer changed the program (reported)")
    back = list(read_text(text + "\n", dialect, program.name, options(program)))
    assert canon_equiv.compare(fine_text(back), fine_text(applied)) == []


def test_most_compensation_programs_keep_g41() -> None:
    kept = 0
    for program in PROGRAMS:
        ir = kept_ir(program)
        if ir is None:
            continue
        try:
            text = "\n".join(write(ir, "fanuc"))
        except Diagnostic:  # an offset change under kept compensation: refused, located
            continue
        kept += bool(re.search(r"^G4[12] D\d+$", text, re.MULTILINE))
    assert kept >= 8


def test_fanuc_gets_the_radius_in_a_register_and_the_report_says_so() -> None:
    prog = (
        "G21 G90 G17\nT1 M6\nS1000 M3\nG0 X-10 Y-10 Z5\nG1 Z-1 F200\nG41.1 D6 G1 X0 Y0\n"
        "X40\nY30\nG40 G1 X50 Y40\nM2\n"
    )
    ir = list(
        interpret_text(
            prog, "c.ngc", dataclasses.replace(options(PROGRAMS[0]), keep_cutter_comp=True)
        )
    )
    report = ConversionReport()
    out = list(write(ir, "fanuc", WriterOptions(), report))
    i = out.index("G10 L12 P1 R3.")
    assert out[i + 1 : i + 3] == ["G41 D1", "X0. Y0."] and "G40" in out
    (change,) = report.changes
    assert change.code == "CONV-CUTTER-COMP" and change.source.line == 6
    assert "G41.1 D6\nX0 Y0\n" in "\n".join(write(ir, "rs274ngc"))


@pytest.mark.parametrize(("text", "code", "line"), ERROR_PROGRAMS)
def test_keep_mode_refuses_what_rs274_refuses_at_the_same_line(text: str, code: str, line: int):
    """The error programs of tests/test_ngc_cutter_comp.py (rs274's code and line): the
    shadow compensator makes keep mode stop exactly where applying compensation stops."""
    keep = dataclasses.replace(options(PROGRAMS[0]), keep_cutter_comp=True)
    with pytest.raises(Diagnostic) as exc:
        list(interpret_text(text, "e.ngc", keep))
    assert (exc.value.code, exc.value.location.line) == (code, line)
