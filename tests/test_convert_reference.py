"""Converted programs accepted by an independent reader: LinuxCNC's ``rs274``.

Two checks per golden/corpus program (marked ``reference``: they need ``rs274`` on PATH):

* from the program: our interpreter's IR written as RS274/NGC (and as Grbl when the
  conversion report is empty) and run through ``rs274`` gives canon equivalent to
  ``rs274``'s own output for the original program (the committed ``.canon``);
* from the committed ``.canon`` (``cnc convert --from canon``): the same, so the writer is
  checked without our interpreter in the loop. LinuxCNC prints ``NURBS_FEED(n, ...)``
  without its data, so those files must be refused with ``CONV-NURBS``.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
import tests.test_convert_comp_keep as comp_keep
import tests.test_convert_cycles_keep as cycles_keep
from cli.convert import read_canon
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from tests.convert_support import canon_files, in_turn, programs, read_ir, rs274

pytestmark = [
    pytest.mark.reference,
    pytest.mark.skipif(shutil.which("rs274") is None, reason="needs LinuxCNC's rs274"),
]


@pytest.mark.parametrize(("program", "dialect"), in_turn(programs(), ["rs274ngc", "grbl"], 2))
def test_rs274_reads_our_output_as_it_reads_the_original(
    program: Path, dialect: str, tmp_path: Path
) -> None:
    ir = read_ir(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        # the program's own tool table edits (G10 L1) are part of it: asked for here
        opts = WriterOptions(decimals=6, write_tool_table=True)
        text = "\n".join(write(ir, dialect, opts, report)) + "\n"
    except Diagnostic:
        assert dialect == "grbl"
        return
    if dialect == "grbl":
        if report.changes:
            return  # substitutions: not equivalent by design (checked in the round trips)
        text = f"%\n{text}%\n"
    ours = rs274(text, program.parent / "sim.tbl", tmp_path)
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []


@pytest.mark.parametrize(("canon_file", "arc_format"), in_turn(canon_files(), ["ijk", "r"], 2))
def test_from_canon_text_through_rs274(canon_file: Path, arc_format: str, tmp_path: Path) -> None:
    text_in = canon_file.read_text()
    report = ConversionReport()
    opts = WriterOptions(arc_format=arc_format, write_tool_table=True)
    try:
        text = "\n".join(write(read_canon(str(canon_file), report), "rs274ngc", opts, report))
    except Diagnostic as exc:
        assert "NURBS_FEED(" in text_in and exc.code == "CONV-NURBS"
        assert exc.location.line > 0
        return
    ours = rs274(text + "\n", canon_file.parent / "sim.tbl", tmp_path)
    assert canon_equiv.compare(ours, text_in.splitlines()) == []


CYCLE_PROGRAMS = [pytest.param(p, id=p.stem) for p in cycles_keep.PROGRAMS]


@pytest.mark.parametrize("program", CYCLE_PROGRAMS)
def test_rs274_expands_our_kept_cycles_as_the_original(program: Path, tmp_path: Path) -> None:
    """``--cycles keep``: the cycle blocks we write make ``rs274`` print the canon it prints
    for the original program."""
    ir = cycles_keep.marked_ir(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    opts = WriterOptions(decimals=6, cycles="keep")
    text = "\n".join(write(ir, "rs274ngc", opts, report)) + "\n"
    ours = rs274(text, program.parent / "sim.tbl", tmp_path)
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []


COMP_PROGRAMS = [pytest.param(p, id=p.stem) for p in comp_keep.PROGRAMS]


@pytest.mark.parametrize("program", COMP_PROGRAMS)
def test_rs274_compensates_our_kept_g41_as_the_original(program: Path, tmp_path: Path) -> None:
    """``--cutter-comp keep``: our G41.1/G42.1 with the programmed path make ``rs274`` print
    the compensated canon it prints for the original program."""
    ir = comp_keep.kept_ir(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    try:
        opts = WriterOptions(decimals=6, write_tool_table=True)  # the program's G10 L1
        text = "\n".join(write(ir, "rs274ngc", opts)) + "\n"
    except Diagnostic as exc:  # an offset change under kept compensation
        assert exc.code == "CONV-CUTTER-COMP" and exc.location.line > 0
        return
    ours = rs274(text, program.parent / "sim.tbl", tmp_path)
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []
