"""``--dialect`` on the commands that read programs: the same text means what its control
means (Fanuc: ``X10`` without a point is 10 least increments = 0.010 mm; lathe: X is a
diameter; Siemens: ``;`` comments, chosen by the ``.mpf`` suffix)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli

FANUC = "O1000\nG21 G90 G17\nG0 X0 Y0 Z5.\nG1 X10 Y2.5 F100.\nM30\n"


def cnc(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


def feeds(output: str) -> list[str]:
    return [
        line.split("STRAIGHT_FEED")[1] for line in output.splitlines() if "STRAIGHT_FEED" in line
    ]


@pytest.mark.parametrize(
    ("dialect", "x"), [("fanuc", "0.0100"), ("haas", "0.0100"), ("rs274ngc", "10.0000")]
)
def test_canon_reads_a_program_in_the_dialect_named(tmp_path: Path, dialect: str, x: str):
    src = tmp_path / "O1000.nc"
    src.write_text(FANUC if dialect != "rs274ngc" else FANUC.replace("O1000\n", ""))
    res = cnc("canon", str(src), "--dialect", dialect)
    assert res.exit_code == 0, res.output
    assert feeds(res.output) == [f"({x}, 2.5000, 5.0000, 0.0000, 0.0000, 0.0000)"]


def test_fanuc_lathe_reads_x_as_a_diameter(tmp_path: Path):
    src = tmp_path / "turn.nc"
    src.write_text("G18 G21\nG97 S500 M3\nG0 X50. Z2.\nG99 G1 X40. Z0 F0.2\nG1 W-20.\nM30\n")
    res = cnc("canon", str(src), "-d", "fanuc_lathe")
    assert res.exit_code == 0, res.output
    assert feeds(res.output) == [
        "(20.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        "(20.0000, 0.0000, -20.0000, 0.0000, 0.0000, 0.0000)",
    ]


def test_siemens_is_chosen_by_the_mpf_suffix(tmp_path: Path):
    src = tmp_path / "part.mpf"
    src.write_text("G710 G90 ; metric\nG0 X0 Y0 Z5\nG1 X10 Y2.5 F100 ; cut\nM30\n")
    res = cnc("canon", str(src))
    assert res.exit_code == 0, res.output
    assert feeds(res.output) == ["(10.0000, 2.5000, 5.0000, 0.0000, 0.0000, 0.0000)"]


def test_check_reports_an_error_of_the_dialect_at_its_line(tmp_path: Path):
    src = tmp_path / "bad.nc"
    src.write_text(
        "G21 G90\nS1000 M3\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 F100\nM5\nM2\n"
    )  # no G81 in Grbl
    res = cnc("check", "-f", "json", "--dialect", "grbl", str(src))
    assert res.exit_code == 1, res.output
    (found,) = [d for f in json.loads(res.output)["files"] for d in f["findings"]]
    assert found["code"] == "GRBL-UNSUPPORTED" and found["line"] == 4
    assert cnc("check", "--dialect", "rs274ngc", str(src)).exit_code == 0


def test_plan_runs_a_fanuc_program(tmp_path: Path):
    src = tmp_path / "O1000.nc"
    src.write_text(FANUC)
    res = cnc("plan", str(src), "--dialect", "fanuc")
    assert res.exit_code == 0, res.output


def test_an_unknown_dialect_is_a_usage_error(tmp_path: Path):
    src = tmp_path / "p.nc"
    src.write_text(FANUC)
    res = cnc("canon", str(src), "--dialect", "heidenhain")
    assert res.exit_code == 2 and "heidenhain" in res.output
