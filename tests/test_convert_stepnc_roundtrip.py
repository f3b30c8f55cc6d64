"""STEP-NC to every G-code dialect and back: the motions survive (issue 7, round trips).

ISO 14649 programs (the corpus's Example 1 and the STEP-NC test programs) are executed into
canonical commands, written in each dialect that has a reader, and read back by that
reader. G-code knows tools by number, not by the STEP-NC tool's name, and has no
``SPINDLE_RETRACT``; the writer says so in its report (the name as a comment, the retract
dropped). Everything else must come back equivalent within 1e-4 (tests/canon_equiv.py).
The Sandia generic language is left out here: it has no arcs, so its round trip is
within a chord tolerance and is tested on its own (tests/test_convert_sandia_reader.py).
"""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.readers import read_text
from gcode.registry import readable
from gcode.write.report import Change, ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.to_canon import canon_from_file
from tests.convert_support import fine_text
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).resolve().parent
CORPUS = CORPUS_STEPNC
PROGRAMS = sorted(CORPUS.glob("*.stp")) + sorted((HERE / "stepnc").glob("*.stp"))
DIALECTS = [d for d in readable() if d != "sandia"]
#: what a G-code target cannot say of a STEP-NC program (reported, not silently lost)
EXPECTED_CHANGES = {"CONV-TOOL-CHANGE", "CONV-TOOL-LENGTH"}


def expected_change(change: Change) -> bool:
    """A change every G-code target makes to STEP-NC input: no spindle retract command,
    and (Grbl) no tool changer or tool length by value."""
    if change.code == "CONV-UNSUPPORTED":
        return "SPINDLE_RETRACT" in change.message
    return change.code in EXPECTED_CHANGES


@functools.cache
def ir_of(program: Path) -> tuple[canon.Command, ...] | None:
    try:
        return tuple(canon_from_file(str(program), mode="default"))
    except Diagnostic:
        return None


def as_gcode_sees_it(
    ir: tuple[canon.Command, ...], stop_for_tool: bool = False
) -> list[canon.Command]:
    """The IR with what G-code cannot carry taken out: tool names, spindle retracts; with
    ``stop_for_tool`` (a dialect without a tool changer) a tool change is a program stop."""
    out: list[canon.Command] = []
    for c in ir:
        if isinstance(c, canon.SpindleRetract):
            continue
        if isinstance(c, canon.ChangeTool):
            c = (
                canon.ProgramStop(source=c.source)
                if stop_for_tool
                else (canon.ChangeTool(c.slot, source=c.source))
            )
        out.append(c)
    return out


def test_the_stepnc_corpus_is_there() -> None:
    assert len(PROGRAMS) >= 30 and any(p.name == "ex1.stp" for p in PROGRAMS)
    assert "rs274ngc" in DIALECTS


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_stepnc_program_round_trips_through_each_dialect(program: Path, dialect: str) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the STEP-NC executor rejects this program (its own tests say why)")
    report = ConversionReport()
    try:
        text = "\n".join(write(ir, dialect, WriterOptions(decimals=5), report)) + "\n"
    except Diagnostic as exc:  # a refusal names the STEP-NC source of the construct
        assert exc.code.startswith("CONV-") and exc.location.file, exc
        return
    if not all(expected_change(c) for c in report.changes):
        # approximations (NURBS, ellipses) are checked by tests/test_convert_approx.py
        assert all(c.source is not None for c in report.changes)
        return
    back = list(read_text(text, dialect, program.name))
    stop_for_tool = any(c.code == "CONV-TOOL-CHANGE" for c in report.changes)
    expected = as_gcode_sees_it(ir, stop_for_tool)
    assert canon_equiv.compare(fine_text(back), fine_text(expected)) == []
