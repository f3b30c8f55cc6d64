"""The round-trip pairs that changed a program's state (tests/test_convert_roundtrip_pairs.py,
``slow``), each fixed at its cause (issue 15), one cheap case each in the default run:

* Sandia has no tool length register: ``G43 H n`` (the length the machine measured) is the
  loss ``CONV-TOOL-LENGTH``, not a ``SetToolLength`` of the table's value or of 0; a length
  by value (G43.1) is Sandia's own ``SetToolLength``, which reads back as G43.1 (G49 for 0);
* a Fanuc program writing its offset memory (G10 L10/L11) writes the machine's tool table:
  ``CONV-TOOL-TABLE`` without ``--write-tool-table`` (it was dropped, so ``G43 H3`` took
  the machine's own length where the program had set 119.5);
* an 840D ``MSG("...")`` cannot hold ``"``: the text the operator reads changes, which the
  report says (a ``CONV-MESSAGE`` substitution, as for a message written as a comment);
* a thread's feed rate (G95 F) is stated before a ``G33 ... K`` thread: the thread ran with
  F0 in force and the F came with the next rapid.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read, read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HERE = Path(__file__).resolve().parent
MARKS = InterpreterOptions(register_marks=True)


def written(
    ir: Iterable[canon.Command], target: str
) -> tuple[list[str] | None, ConversionReport, Diagnostic | None]:
    report = ConversionReport()
    try:
        return list(write(ir, target, WriterOptions(), report)), report, None
    except Diagnostic as exc:
        return None, report, exc


def test_sandia_lists_g43_h_as_a_tool_length_loss_at_its_line() -> None:
    src = "G21 G90\nT1 M6\nG43 H1\nG1 X1 Z-1 F100\nM2\n"
    text, report, error = written(read_text(src, "rs274ngc", "p.ngc", MARKS), "sandia")
    assert error is None and text is not None
    losses = [c for c in report.refused() if c.loss_code == "CONV-TOOL-LENGTH"]
    assert losses and losses[0].source is not None and losses[0].source.line == 3
    assert "G43 H1" in losses[0].message


def test_sandia_set_tool_length_reads_back_as_a_length_by_value() -> None:
    src = "G21 G90\nG43.1 Z2.5\nG1 X1 F100\nG49\nG1 X2\nM2\n"
    ir = list(read_text(src, "rs274ngc", "p.ngc", MARKS))
    text, report, error = written(ir, "sandia")
    assert error is None and text is not None and not report.refused()
    back = list(read_text("\n".join(text) + "\n", "sandia", "p.txt", MARKS))
    marks = [(c.code, c.register) for c in back if isinstance(c, ToolLengthRegister)]
    assert marks == [("G43.1", None), ("G49", None)]
    lengths = [c.length for c in back if isinstance(c, canon.UseToolLengthOffset)]
    assert lengths == [2.5, 0.0]
    # cnc canon reads no marks: its text is unchanged
    plain = list(read_text("\n".join(text) + "\n", "sandia", "p.txt"))
    assert not any(isinstance(c, ToolLengthRegister) for c in plain)


def test_fanuc_offset_memory_written_by_the_program_needs_write_tool_table() -> None:
    program = HERE / "dialects" / "fanuc" / "057_g10_l10_length.nc"
    ir = list(read(program, "fanuc", MARKS))
    entries = [c for c in ir if isinstance(c, canon.SetToolTableEntry)]
    assert [(c.tool, round(c.offset[2] * 25.4, 6)) for c in entries] == [(3, 120.0), (3, 119.5)]
    text, _, error = written(ir, "rs274ngc")
    assert text is None and error is not None and error.code == "CONV-TOOL-TABLE"
    assert error.location.line == 5  # G10 L10 P3 R120.
    # cnc canon's commands are rs274's: no table entry without marks
    assert not any(isinstance(c, canon.SetToolTableEntry) for c in read(program, "fanuc"))


def test_a_siemens_message_with_double_quotes_is_reported() -> None:
    src = 'G21 G90\n(MSG, tool "A" in)\nG0 X1\nM2\n'
    text, report, error = written(read_text(src, "rs274ngc", "p.ngc", MARKS), "siemens840d")
    assert error is None and text is not None
    assert [line for line in text if line.startswith("MSG(")] == ["MSG(\" tool 'A' in\")"]
    notes = [c for c in report.changes if c.code == "CONV-MESSAGE"]
    assert len(notes) == 1 and notes[0].kind == "substituted" and not notes[0].loss


def test_a_thread_sees_the_source_feed_rate() -> None:
    program = HERE / "dialects" / "fanuc" / "110_turn_g32_thread.nc"
    ir = list(read(program, "fanuc_lathe", MARKS))
    for target in ("rs274ngc", "siemens840d"):
        text, _, error = written(ir, target)
        assert error is None and text is not None
        first = next(i for i, line in enumerate(text) if line.startswith("G33"))
        assert text[first - 1] == "F1", text  # LinuxCNC refuses an F word in a G33 block
        back = list(read_text("\n".join(text) + "\n", target, "p", MARKS))
        sync = next(i for i, c in enumerate(back) if isinstance(c, canon.StartSpeedFeedSynch))
        rates = [c.rate for c in back[:sync] if isinstance(c, canon.SetFeedRate)]
        assert rates[-1] == 1.0
