"""Round trips through the Fanuc and Haas readers (issue 7, readers.md §1).

Every golden and corpus program the RS274/NGC interpreter accepts is written as Fanuc and
Haas (incremental IJK and R arcs) and read back with the dialect's own reader; where the
writer neither refused nor changed anything (empty conversion report, or only centres
written for arcs R cannot state, which is exact), the IR read back is equivalent to the
original (tests/canon_equiv.py, 1e-4).
"""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.fanuc import reader as fanuc_reader
from gcode.haas import reader as haas_reader
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text, options, programs, read_ir

PROGRAMS = programs()
READERS = {"fanuc": fanuc_reader, "haas": haas_reader}


@functools.cache
def ir_of(program: Path) -> tuple[canon.Command, ...] | None:
    ir = read_ir(program)
    return None if ir is None else tuple(ir)


@pytest.mark.parametrize(
    ("dialect", "arc_format"), [("fanuc", "ijk"), ("fanuc", "r"), ("haas", "r"), ("haas", "ijk")]
)
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_written_program_reads_back_equivalent(
    program: Path, dialect: str, arc_format: str
) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    try:
        text = "\n".join(
            write(ir, dialect, WriterOptions(arc_format=arc_format, decimals=5), report)
        )
    except Diagnostic:
        pytest.skip("the writer refuses this program")
    if {c.code for c in report.changes} - {"CONV-ARC-FORMAT"}:
        pytest.skip("the writer changed the program (reported)")
    back = list(READERS[dialect].interpret_text(text + "\n", program.name, options(program)))
    assert canon_equiv.compare(fine_text(back), fine_text(ir)) == []
