"""``cnc convert`` verifies its output (issue 15): the output read back with the target's
reader is the source at motion level (kernel/ir/equivalence.py), or the conversion fails
at the first differing source line and writes nothing.

The kernel's comparison is cross-checked against the tests' own oracle
(tests/canon_equiv.py): both agree that LinuxCNC's ``rs274`` output of every corpus program
equals ours, and both accept every lossless round trip of the golden and corpus programs.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

import cli.convert
import tests.canon_equiv as canon_equiv
from cli.verify import LOSSES, SAME_MOTION, _resolution
from gcode.readers import read_text
from gcode.registry import get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.ir.equivalence import first_difference
from tests.convert_support import CORPUS, fine_text, in_turn, ir_of, options, programs

PROGRAMS = programs()
#: the dialects the round-trip tests write every program in (test_convert_roundtrip*.py)
TARGETS = [
    ("rs274ngc", "ijk"),
    ("rs274ngc", "r"),
    ("rs274ngc", "ijk-abs"),
    ("grbl", "ijk"),
    ("nist_v3", "r"),
    ("fanuc", "ijk"),
    ("haas", "r"),
    ("siemens840d", "ijk"),
    ("sandia", "ijk"),
]
#: a rotated work offset: Siemens states it as a frame, so the program coordinates the 840D
#: reader gives differ from LinuxCNC's (test_convert_roundtrip_siemens.py compares these by
#: frame points, which the motion-level rule does not)
ROTATED_FRAMES = {"086_g10_l2_rotation", "190_g10_l20_with_rotation"}

SQUARE = "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG2 X20 Y0 R5\nM2\n"


#: (program, dialect, arc format): every program with three targets in the default run, in
#: turn, and with all nine under ``-m slow``
CASES = in_turn(PROGRAMS, TARGETS, 3)


@pytest.mark.parametrize(("program", "dialect", "arc_format"), CASES)
def test_every_lossless_conversion_verifies(program: Path, dialect: str, arc_format: str) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    if dialect == "siemens840d" and program.stem in ROTATED_FRAMES:
        pytest.skip("a rotated frame: compared by frame points in its own test")
    report = ConversionReport()
    opts = WriterOptions(arc_format=arc_format)
    try:
        text = "".join(f"{line}\n" for line in write(ir, dialect, opts, report))
    except Diagnostic:
        pytest.skip("the writer refuses this program")
    if any(c.kind in LOSSES and c.code not in SAME_MOTION for c in report.changes):
        pytest.skip("the report lists losses: not expected to be equivalent")
    try:
        back = list(read_text(text, dialect, program.name, options(program)))
    except Diagnostic as exc:
        pytest.skip(f"the {dialect} reader refuses the writer's output: {exc.code}")
    rounding = _resolution(get_dialect(dialect), None)
    assert first_difference(ir, back, opts.tolerance, rounding) is None
    if not report.changes and dialect != "sandia":  # the oracle's rule, without chords
        fine = WriterOptions(arc_format=arc_format, decimals=5)
        text = "".join(f"{line}\n" for line in write(ir, dialect, fine, ConversionReport()))
        back = list(read_text(text, dialect, program.name, options(program)))
        assert canon_equiv.compare(fine_text(back), fine_text(ir)) == []
        assert first_difference(ir, back, fine.tolerance) is None


def _linuxcnc(path: Path) -> Iterator[canon.Command]:
    """rs274's printed commands as IR, its LinuxCNC-only commands dropped."""
    with open(path, encoding="utf-8") as fh:
        for tc in canon.read_text(fh, str(path)):
            if tc.name in canon.LINUXCNC_ONLY:
                continue
            try:
                yield canon.parse_command(tc, str(path))
            except Diagnostic:
                continue  # a command outside the IR: outside the rule too


@pytest.mark.parametrize("reference", sorted(CORPUS.glob("*.canon")), ids=lambda p: p.stem)
def test_kernel_rule_agrees_with_the_oracle_on_rs274_output(reference: Path) -> None:
    ir = ir_of(reference.with_suffix(".ngc"))
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    oracle = canon_equiv.compare(fine_text(ir), reference.read_text().splitlines())
    ours = first_difference(_linuxcnc(reference), ir, 1e-4)
    assert (oracle == []) == (ours is None), (oracle, ours)


def test_a_changed_motion_is_a_difference_at_its_source_line() -> None:
    loc = canon.Location("p.ngc", 7, 1)
    src = [
        canon.UseLengthUnits(canon.Units.MM),
        canon.SetFeedRate(100.0),
        canon.StraightFeed(1.0, 2.0, 3.0, source=loc),
    ]
    out = [canon.UseLengthUnits(canon.Units.MM), canon.SetFeedRate(100.0)]
    moved = [*out, canon.StraightFeed(1.0, 2.0005, 3.0)]
    diff = first_difference(src, moved, 0.001)
    assert diff is not None and diff.source == loc and "argument 2" in diff.message
    assert first_difference(src, [*out, canon.StraightFeed(1.0, 2.00005, 3.0)], 0.001) is None
    inch = [canon.UseLengthUnits(canon.Units.INCHES), canon.SetFeedRate(100.0 / 25.4)]
    same = canon.StraightFeed(1 / 25.4, 2 / 25.4, 3 / 25.4)
    assert first_difference(src, [*inch, same], 0.001) is None  # compared in millimetres
    assert first_difference(src, [*out], 0.001) is not None


def run(*args: str):  # noqa: ANN201
    return CliRunner().invoke(cli.convert.command, list(args), catch_exceptions=False)


def corrupt(monkeypatch: pytest.MonkeyPatch, old: str, new: str) -> None:
    """Make the writer's text wrong: every line ``old`` becomes ``new`` (None: dropped)."""
    real = cli.convert.write_text

    def broken(*args: Any, **kwargs: Any) -> Iterator[str]:
        for chunk in real(*args, **kwargs):
            yield "".join(
                (new + "\n" if new else "") if line == old else line + "\n"
                for line in chunk.splitlines()
            )

    monkeypatch.setattr(cli.convert, "write_text", broken)


@pytest.mark.parametrize(
    ("old", "new", "line", "what"),
    [
        ("G00 X0. Y0. Z5.", "", 2, "STRAIGHT_FEED where the source has STRAIGHT_TRAVERSE"),
        ("X10.", "", 4, "does not read back as fanuc from here"),
        ("X10.", "X10.5", 4, "STRAIGHT_FEED argument 1: 10.5 where the source has 10"),
        ("G01 Z-1. F100.", "G01 Z-1. F110.", 3, "feed rate 110 where the source has 100"),
    ],
    ids=["dropped-move", "unreadable", "changed-coordinate", "changed-feed"],
)
def test_a_corrupted_output_fails_at_the_source_line_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, old: str, new: str, line: int, what: str
) -> None:
    src = tmp_path / "p.ngc"
    src.write_text(SQUARE)
    out = tmp_path / "p.nc"
    corrupt(monkeypatch, old, new)
    result = run(str(src), "--to", "fanuc", "-o", str(out), "--report", str(tmp_path / "r.json"))
    assert result.exit_code == 1
    assert f"p.ngc:{line}:1: error[CONV-VERIFY]" in result.output
    assert what in result.output
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["p.ngc"]
    stdout = run(str(src), "--to", "fanuc")
    assert stdout.exit_code == 1 and "%" not in stdout.output.splitlines()
    unchecked = run(str(src), "--to", "fanuc", "-o", str(out), "--no-verify")
    assert unchecked.exit_code == 0 and out.exists()
    assert (new or "") in out.read_text() and "verified" not in unchecked.output


def test_json_report_says_whether_the_output_was_verified(tmp_path: Path) -> None:
    src = tmp_path / "p.ngc"
    src.write_text(SQUARE)
    for extra, verified in (((), True), (("--no-verify",), False)):
        rep = tmp_path / f"r{verified}.json"
        out = tmp_path / f"p{verified}.nc"
        result = run(str(src), "--to", "sandia", "-o", str(out), "--report", str(rep), *extra)
        assert result.exit_code == 0, result.output
        assert json.loads(rep.read_text())["verified"] is verified
        assert ("p.ngc: verified" in result.output) is verified


def test_a_lossy_conversion_is_reported_not_verified(tmp_path: Path) -> None:
    """A loss the user accepted by name is written, but never called verified."""
    src = tmp_path / "p.ngc"
    src.write_text("G21 G90\nT1 M6\nG0 X1 Y2\nG1 X3 F500\nM2\n")
    rep = tmp_path / "r.json"
    out = str(tmp_path / "p.gcode")
    refused = run(str(src), "--to", "grbl", "-o", out)
    assert refused.exit_code == 1 and not (tmp_path / "p.gcode").exists()
    accept = ("--allow-loss", "CONV-TOOL-CHANGE")
    result = run(str(src), "--to", "grbl", "-o", out, "--report", str(rep), *accept)
    assert result.exit_code == 0, result.output
    assert "p.ngc: not verified (the report lists losses)" in result.output
    assert json.loads(rep.read_text())["verified"] is False
