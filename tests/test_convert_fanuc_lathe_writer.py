"""The Fanuc lathe writer (gcode/fanuc_lathe/dialect.py): X as a diameter, G18, G99,
G32, G50 S, T0101, and every hand-derived turning program round-trips through it.

Round trip: each ``tests/dialects/fanuc/1NN_turn_*.nc`` is read by the lathe reader (its
cycles expanded into moves), written as a lathe program and read back; the IR must be
equivalent within 1e-4 (tests/canon_equiv.py). The hand-derived programs that feed per
revolution without starting the spindle are read with ``G97 S500 M03`` added after their
first block: the reader, like rs274, refuses a G01 per revolution with the spindle
stopped (``FANUC-ZERO-SPEED-FPR``), which it does not check inside a cycle. The writer
reports nothing: every turning construct has its lathe form.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.readers import read_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon as c
from tests.convert_support import fine_text

HERE = Path(__file__).resolve().parent
TURNING = sorted((HERE / "dialects" / "fanuc").glob("1*_turn_*.nc"))


def spindle_on(text: str) -> str:
    if re.search(r"\bS\d", text):
        return text
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("G"))
    return "\n".join([*lines[: first + 1], "G97 S500 M03", *lines[first + 1 :]]) + "\n"


def test_the_turning_programs_are_there() -> None:
    assert len(TURNING) >= 20


@pytest.mark.parametrize("program", TURNING, ids=lambda p: p.stem)
def test_turning_program_round_trips_through_the_lathe_writer(program: Path) -> None:
    ir = list(read_text(spindle_on(program.read_text()), "fanuc_lathe", program.name))
    report = ConversionReport()
    text = "\n".join(write(ir, "fanuc_lathe", WriterOptions(decimals=5), report)) + "\n"
    assert report.changes == []
    back = list(read_text(text, "fanuc_lathe", program.name))
    assert canon_equiv.compare(fine_text(back), fine_text(ir)) == []


MM = c.UseLengthUnits(c.Units.MM)


def test_lathe_blocks_by_hand() -> None:
    """x 20 (radius) is X40. (diameter); the arc centre increment I stays a radius;
    per revolution is G99; a tool change is T0202 without M06; a thread is G32 F."""
    cmds = [
        MM,
        c.SelectPlane(c.Plane.XZ),
        c.SetFeedMode(c.FeedMode.UNITS_PER_REVOLUTION),
        c.ChangeTool(2),
        c.SetSpindleSpeed(800),
        c.StartSpindleClockwise(),
        c.StraightTraverse(20, 0, 2),
        c.SetFeedRate(0.2),
        c.StraightFeed(20, 0, -10),
        c.ArcFeed(-15, 25, -15, 20, 1, 0),  # XZ plane: first = Z, second = X
        c.ProgramEnd(),
    ]
    out = list(write(cmds, "fanuc_lathe", WriterOptions()))
    assert "T0202" in out and "M06" not in " ".join(out)
    assert "G00 X40. Z2." in out and "G01 Z-10. F0.2" in out
    assert "G03 X50. Z-15. I0. K-5." in out
    assert "G90" not in " ".join(out)  # G code system A: G90 is a turning cycle
    report = ConversionReport()
    with pytest.raises(Diagnostic) as err:
        list(write([MM, c.StraightTraverse(1, 2, 3)], "fanuc_lathe", WriterOptions(), report))
    assert err.value.code == "CONV-AXIS"
