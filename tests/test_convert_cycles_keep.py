"""``--cycles keep``: drilling cycles stay cycle blocks and still make the same moves.

For every golden and corpus program with a canned cycle, the RS274/NGC reader is run with
cycle marks (gcode.core.cycle_marks); the program is written in each dialect whose cycles move
as RS274/NGC's (LinuxCNC, NIST v3, Fanuc, Haas) with the cycles kept, and read back by that
dialect's reader, which expands them again. The result must be equivalent (1e-4,
tests/canon_equiv.py) to the IR of the original, whose expansion no writer touched.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.core.cycle_marks import CycleEnd, CycleStart
from gcode.ngc.interpreter import InterpreterOptions, interpret, interpret_text
from gcode.readers import read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text, options, programs

CYCLE = re.compile(r"G\s*(73|8[1-9])(?![0-9.])", re.IGNORECASE)
PROGRAMS = [p for p in programs() if CYCLE.search(p.read_text(errors="replace"))]
DIALECTS = ["rs274ngc", "nist_v3", "fanuc", "haas"]
KEPT_CODES = {"CONV-CYCLE", "CONV-ARC-FORMAT"}


@functools.cache
def marked_ir(program: Path) -> tuple[canon.Command, ...] | None:
    try:
        marked = InterpreterOptions(**{**options(program).__dict__, "cycle_marks": True})
        return tuple(interpret(program, marked))
    except Diagnostic:
        return None


def plain(ir: tuple[canon.Command, ...]) -> list[canon.Command]:
    return [c for c in ir if not isinstance(c, CycleStart | CycleEnd)]


def test_programs_with_cycles_are_there() -> None:
    assert len(PROGRAMS) >= 15


def test_marks_bracket_exactly_the_expansion() -> None:
    """Without marks the reader gives the same IR: the marks only bracket it."""
    for program in PROGRAMS:
        ir = marked_ir(program)
        if ir is None:
            continue
        assert fine_text(plain(ir)) == fine_text(interpret(program, options(program)))
        starts = [c for c in ir if isinstance(c, CycleStart)]
        ends = [c for c in ir if isinstance(c, CycleEnd)]
        assert len(starts) == len(ends)


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_kept_cycles_read_back_as_the_same_moves(program: Path, dialect: str) -> None:
    ir = marked_ir(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        text = "\n".join(write(ir, dialect, WriterOptions(cycles="keep", decimals=5), report))
    except Diagnostic as exc:
        assert exc.code.startswith("CONV-") and exc.location.line > 0
        return
    if any(c.code not in KEPT_CODES for c in report.changes):
        pytest.skip("the writer changed the program (reported)")
    back = list(read_text(text + "\n", dialect, program.name, options(program)))
    assert canon_equiv.compare(fine_text(back), fine_text(plain(ir))) == []


def test_most_cycle_programs_keep_their_cycles() -> None:
    """The comparison above is not vacuous: most programs keep at least one cycle block."""
    kept = 0
    for program in PROGRAMS:
        ir = marked_ir(program)
        if ir is None:
            continue
        text = "\n".join(write(ir, "rs274ngc", WriterOptions(cycles="keep")))
        kept += bool(re.search(r"^(G9[89] )?G(73|8[1-9]) ", text, re.MULTILINE))
    assert kept >= 10


def test_expand_is_the_default_and_grbl_notes_the_expansion() -> None:
    prog = "G21 G90\nS1000 M3\nG0 X0 Y0 Z10\nG99 G81 X10 Y10 Z-5 R2 F100\nX20\nG80\nM2\n"
    ir = list(interpret_text(prog, "d.ngc", InterpreterOptions(cycle_marks=True)))
    assert not any(line.startswith("G99 G81") for line in write(ir, "rs274ngc"))
    kept = list(write(ir, "rs274ngc", WriterOptions(cycles="keep")))
    assert "G99 G81 X10 Y10 Z-5 R2 F100" in kept and "X20 Y10" in kept
    report = ConversionReport()
    grbl = list(write(ir, "grbl", WriterOptions(cycles="keep"), report))
    assert "G1 Z-5" in grbl
    notes = [(c.kind, c.source.line) for c in report.changes if c.code == "CONV-CYCLE"]
    assert notes == [("expanded", 4)]
