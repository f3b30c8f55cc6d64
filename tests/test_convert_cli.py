"""``cnc convert``: files, refusals, reports and exit codes (DESIGN.md: 0 / 1 / 2)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.convert import command
from tests.convert_support import GOLDEN

SQUARE = "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG2 X20 Y0 R5\nM2\n"


def run(*args: str):  # noqa: ANN201
    return CliRunner().invoke(command, list(args), catch_exceptions=False)


def test_converts_to_a_file_and_refuses_to_overwrite_without_force(tmp_path: Path) -> None:
    src = tmp_path / "p.ngc"
    src.write_text(SQUARE)
    out = tmp_path / "p.nc"
    assert run(str(src), "--to", "fanuc", "-o", str(out)).exit_code == 0
    text = out.read_text()
    assert text.splitlines()[:3] == ["%", "O0001", "G21"]
    assert "G02 X20. Y0. I5. J0." in text
    out.write_text("keep me")
    result = run(str(src), "--to", "fanuc", "-o", str(out))
    assert result.exit_code == 2 and "IO-EXISTS" in result.output
    assert out.read_text() == "keep me"
    assert run(str(src), "--to", "fanuc", "-o", str(out), "--force").exit_code == 0
    assert out.read_text() == text


def test_refusal_is_located_and_leaves_no_output(tmp_path: Path) -> None:
    src = GOLDEN / "067_g5_2_nurbs.ngc"
    out = tmp_path / "n.nc"
    result = run(str(src), "--to", "haas", "--on-missing", "refuse", "-o", str(out))
    assert result.exit_code == 1
    # the interpreter locates NURBS_FEED at the G5.3 that ends the G5.2 block (line 8)
    assert "067_g5_2_nurbs.ngc:8:1: error[CONV-NURBS]" in result.output
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_report_lists_each_approximation_with_its_source_line(tmp_path: Path) -> None:
    src = GOLDEN / "067_g5_2_nurbs.ngc"
    rep = tmp_path / "r.json"
    result = run(
        str(src),
        "--to",
        "haas",
        "-o",
        str(tmp_path / "n.nc"),
        "--report",
        str(rep),
        "--tolerance",
        "0.002",
    )
    assert result.exit_code == 0
    data = json.loads(rep.read_text())
    assert data["from"] == "rs274ngc" and data["to"] == "haas"
    (change,) = data["changes"]
    assert change["code"] == "CONV-NURBS" and change["line"] == 8
    assert change["deviation"] <= 0.002 and change["tolerance"] == 0.002
    assert "note[CONV-NURBS]" in result.output


def test_from_canon_and_options(tmp_path: Path) -> None:
    src = GOLDEN / "001_words_basic.canon"
    result = run(
        str(src),
        "--from",
        "canon",
        "--to",
        "rs274ngc",
        "--line-numbers",
        "5",
        "--no-frame",
        "--units",
        "inch",
        "--decimals",
        "3",
    )
    assert result.exit_code == 0
    lines = result.output.splitlines()
    assert lines[:3] == ["N5 G20", "N10 G90 G17", "N15 G0 X0 Y0 Z0.197"]


def test_unknown_dialect_and_missing_reader_are_errors(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from gcode import registry

    src = tmp_path / "p.ngc"
    src.write_text(SQUARE)
    assert run(str(src), "--to", "heidenhain").exit_code == 2
    # every dialect has a reader today; one uninstalled must be an error, not a traceback
    monkeypatch.setitem(registry.READER_MODULES, "fanuc", "gcode.dialects.no_such_reader")
    result = run(str(src), "--from", "fanuc", "--to", "rs274ngc")
    assert result.exit_code == 1 and "CONV-READER" in result.output


def test_program_error_is_reported_at_its_line(tmp_path: Path) -> None:
    src = tmp_path / "bad.ngc"
    src.write_text("G21\nG2 X10 Y0 R1 F10\nM2\n")  # radius smaller than half the chord
    result = run(str(src), "--to", "grbl")
    assert result.exit_code == 1 and "bad.ngc:2:" in result.output


def test_grbl_input_needs_no_program_end(tmp_path: Path) -> None:
    src = tmp_path / "g.nc"
    src.write_text("G21 G90\nG0 X1 Y2\nG1 X3 F500\n")
    result = run(str(src), "--from", "grbl", "--to", "rs274ngc")
    assert result.exit_code == 0
    assert result.output.splitlines()[-3:] == ["G0 X1 Y2 Z0", "G1 X3 F500", "%"]
    assert run(str(src), "--to", "rs274ngc").exit_code == 1  # RS274/NGC does need one


def test_from_json_lines_keeps_source_lines_for_the_report(tmp_path: Path) -> None:
    from kernel.diagnostics import Location
    from kernel.ir import canon

    cmds = [
        canon.UseLengthUnits(canon.Units.MM),
        canon.StraightTraverse(10, 0, 0),  # on the ellipse: a = 10 along X
        canon.SetFeedRate(100),
        canon.EllipseFeed(20, 10, 0, -10, 0, 0, 0, 1, 0, source=Location("part.ngc", 9, 1)),
    ]
    src = tmp_path / "p.jsonl"
    src.write_text("\n".join(canon.to_jsonl(cmds)) + "\n")
    result = run(str(src), "--from", "jsonl", "--to", "fanuc", "--no-frame")
    assert result.exit_code == 0
    assert "part.ngc:9:1: note[CONV-ELLIPSE]" in result.output
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"cmd": "STRAIGHT_FEED", "x": 1}\nnot json\n')
    result = run(str(bad), "--from", "jsonl", "--to", "fanuc")
    assert result.exit_code == 1 and "bad.jsonl:" in result.output


def test_a_closed_pipe_stops_quietly(tmp_path: Path) -> None:
    """``cnc convert big.ngc --to fanuc | head``: no traceback, no error message, the
    status of a tool stopped by SIGPIPE."""
    import subprocess
    import sys

    src = tmp_path / "big.ngc"
    src.write_text("G21 G90\n" + "".join(f"G1 X{i} Y{i % 7} F500\n" for i in range(50000)) + "M2\n")
    cmd = [sys.executable, "-c", "from cli.main import main; main()", "convert", str(src)]
    proc = subprocess.Popen([*cmd, "--to", "fanuc"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout is not None and proc.stderr is not None
    assert proc.stdout.readline() == b"%\n"
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 141 and err == ""


DRILL_AND_CONTOUR = (
    "G21 G90 G17\nT1 M6\nS1000 M3\nG0 X-10 Y-10 Z5\nG99 G81 X0 Y0 Z-3 R1 F100\nG0 X-10 Y-10 Z5\n"
    "G1 Z-1 F200\nG41.1 D6 G1 X0 Y0\nX40\nY30\nG40 G1 X50 Y40\nG0 Z5\nM2\n"
)


def test_cycles_and_compensation_are_kept_by_default_and_expanded_on_request(
    tmp_path: Path,
) -> None:
    src = tmp_path / "p.ngc"
    src.write_text(DRILL_AND_CONTOUR)
    kept = run(str(src), "--to", "fanuc", "--no-frame")
    assert kept.exit_code == 0, kept.output
    assert "G99 G81 X0. Y0. Z-3. R1. F100." in kept.output
    assert "G41 D1" in kept.output and "note[CONV-CUTTER-COMP]" in kept.output
    plain = run(str(src), "--to", "fanuc", "--no-frame", "--cycles", "expand")
    assert "G81" not in plain.output and "G01 Z-3." in plain.output
    applied = run(str(src), "--to", "fanuc", "--cutter-comp", "apply")
    assert applied.exit_code == 0 and "G41" not in applied.output and "G40" not in applied.output
    grbl = run(str(src), "--to", "grbl")  # no cycles, no compensation: both applied here
    assert grbl.exit_code == 1 and "error[CONV-TOOL-CHANGE]" in grbl.output  # M6: M0
    grbl = run(str(src), "--to", "grbl", "--allow-loss", "CONV-TOOL-CHANGE")
    assert grbl.exit_code == 0, grbl.output
    assert "G41" not in grbl.output and "note[CONV-CYCLE]" in grbl.output
    bad = tmp_path / "short.ngc"  # entry move shorter than the radius: refused as rs274 does
    bad.write_text(DRILL_AND_CONTOUR.replace("G41.1 D6 G1 X0 Y0", "G41.1 D6 G1 X-9 Y-9"))
    refused = run(str(bad), "--to", "fanuc")
    assert refused.exit_code == 1 and "short.ngc:8:1: error[NGC-COMP-ENTRY-TOO-SHORT]" in (
        refused.output
    )
