"""Work offsets keep their numbers through ``cnc convert``, and so do their settings (issue 15).

The expected blocks are the controls' own forms, from their manuals: Fanuc 0i-MF
"Additional workpiece coordinate systems" (``G54.1 P1``-``P48``, set by ``G10 L20 P n``),
Haas mill operator's manual G154 (``G154 P1``-``P99``, set by ``G10 L20 P n``), Siemens
840D sl fundamentals "Settable zero offset" (G54-G57, G505-G599), LinuxCNC G-codes
(G54-G59.3, ``G10 L2 P1``-``P9``). Where the target has no such offset, or cannot set its
values in a program (the 840D reader has no ``$P_UIFR``), the conversion is a located
``CONV-WORK-OFFSET`` loss: exit 1 and no file, unless ``--allow-loss`` names it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode.core.register_marks import WorkOffsetRegister, WorkOffsetValues
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Location
from kernel.ir import canon

MARKS = InterpreterOptions(register_marks=True)

FANUC = """%
O1000
G21 G90 G17
G10 L2 P2 X10. Y20. Z-5.
G10 L20 P3 X1. Y2. Z3.
G54.1 P3
G0 X0 Y0
G55
G1 X5. F100.
M30
%
"""


def _convert(text: str, source: str, target: str) -> tuple[list[str], ConversionReport]:
    report = ConversionReport()
    ir = read_text(text, source, "p", MARKS)
    return list(write(ir, target, WriterOptions(), report)), report


def _work(text: str, dialect: str) -> list[tuple[int, int | None]]:
    """(IR index, marked number) of every SET_G5X_OFFSET the reader emits."""
    out: list[tuple[int, int | None]] = []
    number: int | None = None
    for c in read_text(text, dialect, "p", MARKS):
        if isinstance(c, WorkOffsetRegister):
            number = c.number
        elif isinstance(c, canon.SetG5xOffset):
            out.append((c.index, number))
            number = None
    return out


def test_readers_mark_the_offset_number() -> None:
    # G54.1 P3 runs in RS274/NGC's ninth slot; its number is 100 + 3
    assert (9, 103) in _work(FANUC, "fanuc")
    assert (9, 142) in _work("G21 G154 P42\nG0 X1\nM30\n", "haas")
    assert (9, 12) in _work("G71\nG512\nG0 X1\nM30\n", "siemens840d")
    assert (8, 8) in _work("G21\nG59.2\nG0 X1\nM2\n", "rs274ngc")


def test_settings_are_marked_with_the_axes_given() -> None:
    marks = [c for c in read_text(FANUC, "fanuc", "p", MARKS) if isinstance(c, WorkOffsetValues)]
    assert [(m.number, m.axes, m.values) for m in marks] == [
        (2, "XYZ", (10.0, 20.0, -5.0)),
        (103, "XYZ", (1.0, 2.0, 3.0)),
    ]
    # incremental (G91): the value written is the offset's new absolute value
    inc = "G21 G90\nG10 L2 P2 X10.\nG91 G10 L2 P2 X5.\nG90 G0 X1\nM30\n"
    marks = [c for c in read_text(inc, "fanuc", "p", MARKS) if isinstance(c, WorkOffsetValues)]
    assert [(m.axes, m.values) for m in marks] == [("X", (10.0,)), ("X", (15.0,))]


@pytest.mark.parametrize(
    ("target", "select", "setting"),
    [
        ("fanuc", "G54.1 P3", "G10 L20 P3 X1. Y2. Z3."),
        ("haas", "G154 P3", "G10 L20 P3 X1. Y2. Z3."),
    ],
)
def test_additional_offsets_in_the_targets_form(target: str, select: str, setting: str) -> None:
    lines, report = _convert(FANUC, "fanuc", target)
    assert not report.refused(), report.refused()
    assert select in lines and setting in lines
    assert "G10 L2 P2 X10. Y20. Z-5." in lines and "G55" in lines
    assert lines.index(setting) < lines.index(select)


def test_linuxcnc_offsets_seven_to_nine_and_their_settings() -> None:
    text = "G21 G90\nG10 L2 P8 X1 Z-2\nG59.2\nG0 X1\nG59.3\nG0 X2\nM2\n"
    lines, report = _convert(text, "rs274ngc", "rs274ngc")
    assert not report.changes
    assert {"G10 L2 P8 X1 Z-2", "G59.2", "G59.3"} <= set(lines)
    lines, report = _convert(text, "rs274ngc", "siemens840d")
    assert {"G508", "G509"} <= set(lines)
    assert [c.code for c in report.refused()] == ["CONV-WORK-OFFSET"]  # the G10 L2 P8
    assert report.refused()[0].source == Location("p", 2, 1)


def test_siemens_frames_keep_their_numbers() -> None:
    text = "G71\nG506\nG0 X1\nG512\nG0 X2\nM30\n"
    lines, report = _convert(text, "siemens840d", "siemens840d")
    assert {"G506", "G512"} <= set(lines) and not report.refused()
    lines, report = _convert(text, "siemens840d", "rs274ngc")
    assert "G59" in lines  # G506: the sixth offset
    lost = report.refused()
    assert [(c.code, c.source.line if c.source else 0) for c in lost] == [("CONV-WORK-OFFSET", 4)]
    assert "G512" in lost[0].message


@pytest.mark.parametrize(
    ("text", "source", "target"),
    [
        (FANUC, "fanuc", "rs274ngc"),  # no G54.1 P3 in LinuxCNC
        (FANUC, "fanuc", "siemens840d"),  # no G54.1 P3, no G10 in a 840D program
        ("G21\nG154 P60\nG0 X1\nM30\n", "haas", "fanuc"),  # Fanuc has P1-P48
        ("G21 G90\nG59.1\nG0 X1\nM2\n", "rs274ngc", "haas"),  # G59.1 is not G154 P1
    ],
)
def test_an_offset_the_target_lacks_is_a_loss(text: str, source: str, target: str) -> None:
    _, report = _convert(text, source, target)
    lost = report.refused()
    assert lost and {c.code for c in lost} == {"CONV-WORK-OFFSET"}
    assert all(c.source is not None and c.source.line > 0 for c in lost)


def test_the_cli_refuses_and_accepts_a_lost_offset(tmp_path: Path) -> None:
    src = tmp_path / "p.nc"
    src.write_text(FANUC)
    out = tmp_path / "p.ngc"
    result = CliRunner().invoke(
        cli, ["convert", str(src), "--from", "fanuc", "--to", "rs274ngc", "-o", str(out)]
    )
    assert result.exit_code == 1 and "error[CONV-WORK-OFFSET]" in result.output
    assert f"{src}:6:1" in result.output and not out.exists()
    result = CliRunner().invoke(
        cli,
        ["convert", str(src), "--from", "fanuc", "--to", "rs274ngc", "-o", str(out)]
        + ["--allow-loss", "work-offset"],
    )
    assert result.exit_code == 0, result.output
    blocks = out.read_text().splitlines()
    assert "G55" in blocks and "G10 L2 P2 X10 Y20 Z-5" in blocks
    assert not [b for b in blocks if b.startswith(("G54.1", "G10 L20"))]


def test_settings_follow_the_output_units() -> None:
    report = ConversionReport()
    ir = read_text("G20 G90\nG10 L2 P2 X1.\nG55\nG0 X1\nM30\n", "fanuc", "p", MARKS)
    lines = list(write(ir, "fanuc", WriterOptions(units="mm"), report))
    assert "G10 L2 P2 X25.4" in lines
