"""The Sandia generic language reader (gcode/sandia/reader.py; issue 7).

Hand-derived programs (tests/dialects/sandia/*.txt with the expected IR and its derivation
from seed 003 and research/seed-sandia-full.md §5.3-5.4 in *.canon), located refusals,
a writer -> reader property on random IR, and a fuzz property: any text gives commands
or a located SANDIA-* Diagnostic, never another exception.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tests.canon_equiv as canon_equiv
import tests.chord_equiv as chord_equiv
from gcode.readers import read_text
from gcode.sandia.reader import interpret, interpret_text
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import fine_text

HERE = Path(__file__).resolve().parent / "dialects" / "sandia"
PROGRAMS = sorted(HERE.glob("*.txt"))


def test_every_program_has_its_hand_derived_ir() -> None:
    assert len(PROGRAMS) >= 8
    for program in PROGRAMS:
        expected = program.with_suffix(".canon").read_text().splitlines()
        assert expected[0].startswith("# "), program.name
        assert list(canon.read_commands(expected, str(program)))


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_reader_gives_the_hand_derived_ir(program: Path) -> None:
    ours = list(canon.write_text(interpret(program)))
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []
    # comments and the tool length are outside the equivalence rule: compare them too
    kinds = ("COMMENT", "USE_TOOL_LENGTH_OFFSET", "SELECT_TOOL", "STOP(")
    mine = [c.to_text() for c in interpret(program) if c.to_text().startswith(kinds)]
    theirs = [line for line in expected if line.startswith(kinds)]
    assert mine == theirs


def test_reader_is_registered_for_the_dialect_and_its_alias() -> None:
    text = "SetSpeed 5\nMoveTo X=1.0\n"
    for name in ("sandia", "generic"):
        cmds = list(read_text(text, name))
        assert cmds[-1] == canon.StraightFeed(1.0, 0.0, 0.0)
        assert cmds[-1].source.line == 2


@pytest.mark.parametrize(
    ("text", "code", "line", "column"),
    [
        ("moveTo X=1.0", "SANDIA-UNKNOWN-COMMAND", 1, 1),
        ("SetSpeed 10\nMoveTo X=1..2", "SANDIA-NUMBER", 2, 8),
        ("MoveTo X=1.0", "SANDIA-NO-SPEED", 1, 1),
        ("SetSpeed 0\nMoveTo X=1.0", "SANDIA-NO-SPEED", 2, 1),
        ("MoveReact Z=-1.0", "SANDIA-NO-SPEED", 1, 1),
        ("SetSpeed 10\n  MoveTo X=1.0 A=3.0", "SANDIA-WORLD-ROTARY", 2, 16),
        (
            "point_to_point_positioning X=1 attributes=ABSOLUTE|CS_G55",
            "SANDIA-ATTR-UNSUPPORTED",
            1,
            43,
        ),
        ("point_to_point_positioning X=1 attributes=64", "SANDIA-ATTR-INVALID", 1, 43),
        ("point_to_point_positioning X=1 attributes=21", "SANDIA-ATTR-INVALID", 1, 43),
        ("point_to_point_positioning attributes=ABSOLUTE|BOGUS", "SANDIA-ATTR-INVALID", 1, 39),
        ("point_to_point_positioning attributes=ABSOLUTE|RELATIVE", "SANDIA-ATTR-INVALID", 1, 39),
        ("point_to_point_positioning X=1 X=2", "SANDIA-ARG-REPEATED", 1, 32),
        ("point_to_point_positioning X=1 X=1", "SANDIA-ARG-REPEATED", 1, 32),
        ("SetSpeed S", "SANDIA-NUMBER", 1, 10),
        ("SetSpeed 5\nMoveTo X=1 Y=1 X=1..", "SANDIA-ARG-REPEATED", 2, 16),
        ("point_to_point_positioning Q=1", "SANDIA-ARG", 1, 28),
        ("point_to_point_positioning X", "SANDIA-ARG", 1, 28),
        ("MoveComply X=1", "SANDIA-UNSUPPORTED", 1, 1),
        ("\n\nSetAcceleration 5", "SANDIA-UNSUPPORTED", 3, 1),
        ("SetUnits linear=furlong", "SANDIA-UNITS", 1, 17),
        ("SetUnits angular=rad", "SANDIA-UNITS", 1, 18),
        ("SetUnits", "SANDIA-ARG", 1, 1),
        ("SetSpeed -5", "SANDIA-SPEED", 1, 10),
        ("SetSpeed", "SANDIA-ARG", 1, 1),
        ("SetSpeed 1 2", "SANDIA-ARG", 1, 12),
        ("StopMotion now", "SANDIA-ARG", 1, 12),
        ("SetToolLength 1e3", "SANDIA-NUMBER", 1, 15),
        ("SetSpeed 5\nMoveTo X=" + "9" * 400, "SANDIA-NUMBER", 2, 8),
    ],
)
def test_bad_input_is_refused_at_its_place(text: str, code: str, line: int, column: int) -> None:
    with pytest.raises(Diagnostic) as err:
        list(interpret_text(text, "bad.txt"))
    assert err.value.code == code
    loc = err.value.location
    assert (loc.file, loc.line, loc.column) == ("bad.txt", line, column)


def test_missing_file_is_a_diagnostic() -> None:
    with pytest.raises(Diagnostic) as err:
        list(interpret("/nonexistent/prog.txt"))
    assert err.value.code == "IO-OPEN"


def test_chord_check_finds_a_chord_that_leaves_the_arc() -> None:
    """The round-trip check itself: a vertex moved off the arc by 3x the tolerance fails."""
    arc = [canon.UseLengthUnits(canon.Units.MM), canon.StraightTraverse(10, 0, 0)]
    arc += [canon.SetFeedRate(50), canon.ArcFeed(0, 10, 0, 0, 1, 0)]
    report = ConversionReport()
    text = list(write(arc, "sandia", WriterOptions(decimals=5, tolerance=0.01), report))
    back = list(interpret_text("\n".join(text)))
    pieces = [report.changes[0].pieces]
    assert chord_equiv.compare(back, arc, pieces, 0.01) == []
    bad = list(back)
    i = next(k for k, c in enumerate(bad) if isinstance(c, canon.StraightFeed))
    v = bad[i]
    bad[i] = canon.StraightFeed(v.x * (1 + 0.03 / 10), v.y * (1 + 0.03 / 10), v.z)
    assert chord_equiv.compare(bad, arc, pieces, 0.01) != []
    assert chord_equiv.compare(back, arc, [pieces[0] - 1], 0.01) != []


# ---------------------------------------------------------------------------- properties
coord = st.floats(-500, 500, allow_nan=False).map(lambda v: round(v, 4))


@st.composite
def random_ir(draw: st.DrawFn) -> list[canon.Command]:
    units = draw(st.sampled_from([canon.Units.MM, canon.Units.INCHES]))
    cmds: list[canon.Command] = [canon.UseLengthUnits(units), canon.SetFeedRate(100.0)]
    pos = (0.0, 0.0, 0.0)
    for _ in range(draw(st.integers(1, 10))):
        kind = draw(st.sampled_from(["rapid", "line", "arc", "feed", "tool", "units"]))
        if kind == "units":  # the same place in the other units (G20/G21)
            new = canon.Units.INCHES if units == canon.Units.MM else canon.Units.MM
            pos = tuple(v * units.mm_per_unit / new.mm_per_unit for v in pos)
            units = new
            cmds.append(canon.UseLengthUnits(units))
        elif kind == "feed":
            cmds.append(canon.SetFeedRate(draw(st.floats(1, 5000).map(lambda v: round(v, 2)))))
        elif kind == "tool":
            slot = draw(st.integers(1, 99))
            cmds += [canon.SelectTool(slot), canon.ChangeTool(slot)]
        elif kind in ("rapid", "line"):
            pos = (draw(coord), draw(coord), draw(coord))
            cmds.append((canon.StraightTraverse if kind == "rapid" else canon.StraightFeed)(*pos))
        else:
            centre = (pos[0] + draw(coord) / 10 + 0.5, pos[1] + draw(coord) / 10)
            r = math.dist(pos[:2], centre)
            angle = draw(st.floats(-math.pi, math.pi))
            end = (centre[0] + r * math.cos(angle), centre[1] + r * math.sin(angle), draw(coord))
            turns = draw(st.sampled_from([-2, -1, 1, 2]))
            cmds.append(canon.ArcFeed(end[0], end[1], *centre, turns, end[2]))
            pos = end
    return cmds


@settings(max_examples=60, deadline=None)
@given(random_ir(), st.sampled_from([0.001, 0.01]))
def test_random_ir_survives_the_sandia_round_trip(ir: list[canon.Command], tol: float) -> None:
    report = ConversionReport()
    text = "\n".join(write(ir, "sandia", WriterOptions(decimals=6, tolerance=tol), report))
    back = list(interpret_text(text))
    pieces = [c.pieces for c in report.changes if c.code == "CONV-ARC-LINES"]
    assert len(pieces) == sum(isinstance(c, canon.ArcFeed) for c in ir)
    assert chord_equiv.compare(back, ir, pieces, tol) == []
    if not pieces:
        assert canon_equiv.compare(fine_text(back), fine_text(ir)) == []


@settings(max_examples=40, deadline=None)
@given(random_ir())
def test_writing_feeds_and_arcs_together_changes_no_line(ir: list[canon.Command]) -> None:
    """Runs of feeds and arcs are written at once; one at a time gives the same text."""
    import gcode.write.sandia as sandia

    together = list(write(ir, "sandia", WriterOptions(decimals=4)))
    saved, sandia.RUN = sandia.RUN, 1
    try:
        alone = list(write(ir, "sandia", WriterOptions(decimals=4)))
    finally:
        sandia.RUN = saved
    assert together == alone


@settings(max_examples=40, deadline=None)
@given(random_ir())
def test_arcs_written_one_by_one_take_the_queued_chords(ir: list[canon.Command]) -> None:
    """With no decimals the moves are written one by one (the queue's formatters keep one
    decimal); every arc still becomes the chords the queue computes: the same count per arc,
    and the same MoveTo lines in all."""
    chords: list[list[int]] = []
    moves: list[int] = []
    for decimals in (4, 0):
        report = ConversionReport()
        text = list(write(ir, "sandia", WriterOptions(decimals=decimals), report))
        chords.append([c.pieces for c in report.changes if c.code == "CONV-ARC-LINES"])
        moves.append(sum(line.startswith("MoveTo") for line in text))
    assert chords[0] == chords[1]
    assert moves[0] == moves[1]


WORDS = st.sampled_from(
    [
        "MoveTo",
        "SetSpeed",
        "SetUnits",
        "point_to_point_positioning",
        "GetTool",
        "PutTool",
        "MoveReact",
        "StopMotion",
        "Deactivate",
        "Lock",
        "X=1.5",
        "Y=-2",
        "Z=.5",
        "A=9",
        "X=",
        "=3",
        "attributes=RELATIVE|CS_CURRENT",
        "attributes=7",
        "linear=inch",
        "angular=deg",
        "10",
        "0",
        "-1",
        "#",
        "tool=",
        "1..",
    ]
)
LINES = st.one_of(st.lists(WORDS, max_size=5).map(" ".join), st.text(max_size=30))


@settings(max_examples=300, deadline=None)
@given(st.lists(LINES, max_size=12))
def test_any_text_gives_commands_or_a_located_diagnostic(lines: list[str]) -> None:
    try:
        for cmd in interpret_text("\n".join(lines), "fuzz.txt"):
            assert isinstance(cmd, canon.Command)
    except Diagnostic as exc:
        assert exc.code.startswith("SANDIA-")
        assert exc.location.file == "fuzz.txt" and exc.location.line >= 1
