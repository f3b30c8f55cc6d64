"""Issue 15, losses are errors: a conversion that changes what the machine does exits 1 and
writes nothing, unless ``--allow-loss`` names the loss; notes come once per kind, in the
control's terms, with the first source line and a count."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode.write.report import LOSS_CODES, Change, ConversionReport, group
from kernel.diagnostics import Location

UNITS_CANON = "    1 N..... STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
COMP_CANON = (
    "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
    "    2 N..... SET_CUTTER_RADIUS_COMPENSATION(1.0000)\n"
    "    3 N..... START_CUTTER_RADIUS_COMPENSATION(CANON_COMP_LEFT)\n"
    "    4 N..... STRAIGHT_FEED(10.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
    "    5 N..... STOP_CUTTER_RADIUS_COMPENSATION()\n"
    "    6 N..... PROGRAM_END()\n"
)

#: (loss class, program, suffix, options, the code of the error)
LOSSES = [
    ("spindle", "G21 G90\nS1000 M3\nG0 X1\nM2\n", ".ngc", ["--to", "sandia"], "CONV-SPINDLE"),
    ("coolant", "G21 G90\nM8\nG0 X1\nM2\n", ".ngc", ["--to", "sandia"], "CONV-COOLANT"),
    ("tool change", "G21 G90\nT1 M6\nG0 X1\nM2\n", ".ngc", ["--to", "grbl"], "CONV-TOOL-CHANGE"),
    (
        "tool length",
        "G21 G90\nG43.1 Z2\nG0 X1\nM2\n",
        ".ngc",
        ["--to", "siemens840d"],
        "CONV-TOOL-LENGTH",
    ),
    (
        "tool table",
        "G21 G90\nG10 L1 P1 Z2\nG0 X1\nM2\n",
        ".ngc",
        ["--to", "grbl"],
        "CONV-TOOL-TABLE",
    ),
    ("offset", "G21 G90\nG92 X1\nG0 X1\nM2\n", ".ngc", ["--to", "sandia"], "CONV-ORIGIN"),
    ("work offset", "G21 G90\nG59.1\nG0 X1\nM2\n", ".ngc", ["--to", "grbl"], "CONV-WORK-OFFSET"),
    (
        "work offset setting",
        "G21 G90\nG10 L2 P2 X1\nG0 X1\nM2\n",
        ".ngc",
        ["--to", "siemens840d"],
        "CONV-WORK-OFFSET",
    ),
    ("units", UNITS_CANON, ".canon", ["--to", "fanuc", "--units", "inch"], "CONV-OPTION"),
    (
        "feed mode",
        "G21 G90\nS1000 M3\nG95 F0.1\nG1 X1\nM2\n",
        ".ngc",
        ["--to", "sandia"],
        "CONV-FEED-PER-REV",
    ),
    ("compensation", COMP_CANON, ".canon", ["--to", "grbl"], "CONV-CUTTER-COMP"),
    (
        "blending beyond the tolerance",
        "G21 G90\nG64 P0.01\nG1 X10 F100\nM2\n",
        ".ngc",
        ["--to", "fanuc"],
        "CONV-MOTION-MODE",
    ),
    ("stop", "G21 G90\nG1 X10 F100\nM1\nM2\n", ".ngc", ["--to", "sandia"], "CONV-STOP"),
    ("dwell", "G21 G90\nG1 X10 F100\nG4 P1\nM2\n", ".ngc", ["--to", "sandia"], "CONV-DWELL"),
    ("override", "G21 G90\nM48\nG1 X1 F100\nM2\n", ".ngc", ["--to", "sandia"], "CONV-OVERRIDE"),
    ("output", "G21 G90\nM62 P1\nG1 X1 F100\nM2\n", ".ngc", ["--to", "fanuc"], "CONV-OUTPUT"),
    ("pallet", "G21 G90\nG1 X1 F100\nM60\nM2\n", ".ngc", ["--to", "grbl"], "CONV-PALLET"),
    (
        "tool register",
        "G21 G90\nT1 M6\nG43 H1\nG1 X1 F100\nM2\n",
        ".ngc",
        ["--to", "grbl"],
        "CONV-TOOL-REGISTER",
    ),
]


def run(*args: str):
    return CliRunner().invoke(cli, ["convert", *args])


def _program(tmp_path: Path, text: str, suffix: str) -> Path:
    src = tmp_path / f"p{suffix}"
    src.write_text(text)
    return src


@pytest.mark.parametrize(("what", "text", "suffix", "opts", "code"), LOSSES, ids=lambda v: v)
def test_a_loss_exits_1_and_writes_no_file(
    tmp_path: Path, what: str, text: str, suffix: str, opts: list[str], code: str
) -> None:
    src = _program(tmp_path, text, suffix)
    out = tmp_path / "out.nc"
    result = run(str(src), *opts, "-o", str(out))
    assert result.exit_code == 1, result.output
    assert f"error[{code}]" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == [src.name]  # no file, no partial file
    to_stdout = CliRunner().invoke(cli, ["convert", str(src), *opts])
    assert to_stdout.exit_code == 1 and to_stdout.stdout == ""


def test_allow_loss_accepts_exactly_the_named_losses(tmp_path: Path) -> None:
    src = _program(tmp_path, "G21 G90\nS1000 M3\nM8\nG0 X1\nM5 M9\nM2\n", ".ngc")
    out = tmp_path / "out.txt"
    spindle_only = run(str(src), "--to", "sandia", "-o", str(out), "--allow-loss", "CONV-SPINDLE")
    assert spindle_only.exit_code == 1 and not out.exists()
    assert "error[CONV-COOLANT]" in spindle_only.output
    assert "error[CONV-SPINDLE]" not in spindle_only.output
    report = tmp_path / "r.json"
    both = run(
        str(src),
        "--to",
        "sandia",
        "-o",
        str(out),
        "--allow-loss",
        "spindle",
        "--allow-loss",
        "CONV-COOLANT,CONV-DWELL",
        "--report",
        str(report),
    )
    assert both.exit_code == 0, both.output
    assert out.exists()
    assert "warning[CONV-SPINDLE]: accepted loss" in both.output
    assert "warning[CONV-COOLANT]: accepted loss" in both.output
    data = json.loads(report.read_text())
    assert data["allowed"] == ["CONV-COOLANT", "CONV-DWELL", "CONV-SPINDLE"]
    assert {g["code"] for g in data["accepted"]} == {"CONV-SPINDLE", "CONV-COOLANT"}
    assert data["losses"] == []
    bad = run(str(src), "--to", "sandia", "--allow-loss", "CONV-ARC-LINES")
    # a usage error (exit 2), located at the program like every other error
    assert bad.exit_code == 2 and f"{src}: error[CONV-OPTION]" in bad.output
    assert "CONV-ARC-LINES: not a loss code" in bad.output


def test_notes_come_once_per_kind_with_the_first_line_and_a_count(tmp_path: Path) -> None:
    arcs = "".join(f"G2 X{10 + i} Y0 I0.5 J0\nG0 X{10 + i + 1} Y0\n" for i in range(0, 6, 2))
    src = _program(tmp_path, "G21 G90 G17\nG0 X10 Y0\nF100\n" + arcs + "M2\n", ".ngc")
    result = run(str(src), "--to", "sandia", "-o", str(tmp_path / "o.txt"))
    assert result.exit_code == 0, result.output
    notes = [line for line in result.output.splitlines() if "note[" in line]
    assert len(notes) == 1
    assert "p.ngc:4:1: note[CONV-ARC-LINES]" in notes[0] and "(3 times, first here)" in notes[0]
    assert "G02/G03 (arc) as MoveTo chords" in notes[0]


def test_m30_on_fanuc_has_no_pallet_note_and_m60_is_a_loss(tmp_path: Path) -> None:
    src = _program(tmp_path, "G21 G90\nG1 X10 F100\nM30\n", ".ngc")
    result = run(str(src), "--to", "fanuc")
    assert result.exit_code == 0 and "M30" in result.output
    assert "pallet" not in result.output.lower() and "note[" not in result.output
    m60 = _program(tmp_path, "G21 G90\nG1 X10 F100\nM60\nM2\n", ".nc")
    refused = run(str(m60), "--from", "rs274ngc", "--to", "fanuc")
    assert refused.exit_code == 1 and "error[CONV-PALLET]" in refused.output


def test_sandia_gives_a_short_list_in_machinist_terms(tmp_path: Path) -> None:
    program = (
        "G21 G90 G17\nG64 P0.01 Q0.01\nS1000 M3\nM8\nG0 X0 Y0\nG1 X10 F100\n"
        "G2 X20 I5\nG2 X30 I5\nM1\nM5\nM9\nM1\n(MSG, hello)\nM30\n"
    )
    src = _program(tmp_path, program, ".ngc")
    report = tmp_path / "r.json"
    result = run(
        str(src),
        "--to",
        "sandia",
        "--allow-loss",
        "spindle,coolant,stop,motion-mode",
        "--report",
        str(report),
    )
    assert result.exit_code == 0, result.output
    lines = [line for line in result.output.splitlines() if "[CONV-" in line]
    assert len(lines) <= 10, lines  # 31 notes before issue 15
    text = "\n".join(lines)
    for word in ("M03 (spindle clockwise)", "M08 (flood coolant)", "M01 (optional stop)"):
        assert word in text
    for internal in ("SET_NAIVECAM_TOLERANCE", "START_SPINDLE", "FLOOD_ON", "PALLET", "ON_RESET"):
        assert internal not in text
    assert "M01 (optional stop) (2 times, first here)" in text
    data = json.loads(report.read_text())
    assert {"losses", "accepted", "notes", "allowed", "changes", "summary"} <= set(data)
    first = data["notes"][0]
    assert {"code", "kind", "message", "file", "line", "count", "pieces", "deviation"} <= set(first)
    assert all("loss" in c for c in data["changes"])


def test_every_loss_code_is_documented_and_beyond_tolerance_is_a_loss() -> None:
    errors = (Path(__file__).resolve().parent.parent / "docs" / "errors.md").read_text()
    for code in [*LOSS_CODES, "CONV-LOSS", "CONV-MESSAGE", "CONV-PATH-MODE"]:
        assert f"`{code}`" in errors, code
    where = Location("p.ngc", 3, 1)
    inside = Change("CONV-ARC-LINES", "approximated", "arc", where, 4, 0.0009, 0.001)
    outside = Change("CONV-ARC-LINES", "approximated", "arc", where, 4, 0.002, 0.001)
    assert not inside.loss and outside.loss_code == "CONV-TOLERANCE"
    report = ConversionReport(changes=[inside, outside, inside])
    assert report.refused() == [outside]
    report.allowed = frozenset({"CONV-TOLERANCE"})
    assert report.refused() == [] and report.accepted() == [outside]
    [g] = group(report.notes())
    assert g.count == 2 and g.pieces == 8 and g.first.source == where
