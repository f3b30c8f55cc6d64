"""Round trips through the Sandia generic language (issue 7 "Done when"; readers.md §1).

Every golden and corpus program the interpreter accepts is written in the generic language
(gcode/write/sandia.py, 5 decimals) and read back (gcode/sandia/reader.py).
The language has no arcs and no spindle, coolant, dwell or stop commands, so:

* a conversion with an empty report must be equivalent by tests/canon_equiv.py (1e-4);
* otherwise every change must be a located chord approximation (``CONV-ARC-LINES``) or a
  located drop (``CONV-UNSUPPORTED``), and the re-read IR must match the original on what
  the language carries, each arc or NURBS replaced by chords that stay within the writer's
  tolerance of it (tests/chord_equiv.py: closed form for arcs, dense sampling for NURBS).

A refusal must be a located ``CONV-*`` error (rotary axes in world space, feed per rev).
"""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
import tests.chord_equiv as chord_equiv
from gcode.sandia.reader import interpret_text
from gcode.write.report import LOSS_OF, ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text, options, programs, read_ir

PROGRAMS = programs()
TOLERANCE = 0.001


@functools.cache
def ir_of(program: Path) -> tuple[canon.Command, ...] | None:
    ir = read_ir(program)
    return None if ir is None else tuple(ir)


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_sandia_round_trip_keeps_motions_within_the_chord_tolerance(program: Path) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    report = ConversionReport()
    opts = WriterOptions(decimals=5, tolerance=TOLERANCE)
    try:
        text = "\n".join(write(ir, "sandia", opts, report)) + "\n"
    except Diagnostic as exc:
        assert exc.code in ("CONV-AXIS", "CONV-FEED-PER-REV", "CONV-NURBS", "CONV-THREAD")
        assert exc.location.line > 0
        return
    back = list(interpret_text(text, program.name, options(program)))
    if not report.changes:
        # the plane only matters to arcs, which the language lacks
        flat = [c for c in ir if not isinstance(c, canon.SelectPlane)]
        assert canon_equiv.compare(fine_text(back), fine_text(flat)) == []
        return
    assert all(c.source is not None and c.source.line > 0 for c in report.changes)
    # spindle, coolant, stops, offsets...: each dropped command with its loss code
    assert {c.code for c in report.changes} <= {"CONV-ARC-LINES", "CONV-MESSAGE", *LOSS_OF.values()}
    pieces = [c.pieces for c in report.changes if c.code == "CONV-ARC-LINES"]
    assert chord_equiv.compare(back, ir, pieces, TOLERANCE) == []
