"""``cnc stepnc`` commands (cli/stepnc.py)."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from cli.main import cli
from kernel.ir import canon
from tests.data_paths import CORPUS_STEPNC

HERE = Path(__file__).resolve().parent
CORPUS = CORPUS_STEPNC
EX1, TOOLS = str(CORPUS / "ex1.stp"), str(CORPUS / "iso14649.tool_ex1")
FIG = str(HERE / "stepnc" / "book_fig_11_18.stp")


def run(*args: str):
    return CliRunner().invoke(cli, ["stepnc", *args])


def test_info_shows_workplan_features_operations_and_tools():
    r = run("info", EX1)
    assert r.exit_code == 0, r.output
    for text in (
        "MACHINING_WORKINGSTEP #13",
        "CLOSED_POCKET #18",
        "DRILLING #20",
        "'SPIRAL_DRILL_20MM'",
        "CONTOUR_PARALLEL #53",
    ):
        assert text in r.output


def test_canon_prints_nist_commands():
    r = run("canon", EX1, "--tool-file", TOOLS)
    assert r.exit_code == 0
    ours = [canon.parse_command(t).to_text() for t in canon.read_text(r.output.splitlines())]
    with open(CORPUS / "ex1.can") as fh:
        theirs = [canon.parse_command(t).to_text() for t in canon.read_text(fh)]
    assert ours == theirs


def test_check_reports_the_book_fragment_and_exits_1():
    r = run("check", FIG)
    assert r.exit_code == 1
    assert "book_fig_11_18.stp:#22:19:1: error[P21-EMPTY-PARAM]" in r.output
    assert "50 error(s), 2 warning(s)" in r.output


def test_canon_of_broken_file_is_a_diagnostic_not_a_traceback():
    r = run("canon", FIG)
    assert r.exit_code == 1 and "error[P21-SYNTAX]" in r.output and "Traceback" not in r.output


def test_to_gcode_writes_and_refuses_to_overwrite(tmp_path):
    out = tmp_path / "ex1.ngc"
    r = run("to-gcode", EX1, "--tool-file", TOOLS, "-o", str(out))
    assert r.exit_code == 0, r.output
    text = out.read_text()
    assert "T3 M6" in text and "F2400" in text
    assert "G2 X77.2 Y55 Z-5.9 I5.24598 J4.9315 P3" in text  # helix entry, 3 turns
    r = run("to-gcode", EX1, "--tool-file", TOOLS, "-o", str(out))
    assert r.exit_code == 2 and "--force" in r.output
    assert run("to-gcode", EX1, "-o", str(out), "--force").exit_code == 0


def test_part_exports_step(tmp_path):
    out = tmp_path / "part.step"
    r = run("part", EX1, "-o", str(out), "--raw", "0,0,-45,100,120,5")
    assert r.exit_code == 0, r.output
    assert "volume 405469.250" in r.output and out.exists()
    assert run("part", EX1, "-o", str(out)).exit_code == 2  # exists, no --force
    r = run("part", EX1, "-o", str(tmp_path / "p2.step"))
    assert r.exit_code == 1 and "STEPNC-NO-RAWPIECE" in r.output


def test_gouge_reports_each_workingstep():
    r = run("gouge", EX1, "--tool-file", TOOLS, "--raw", "0,0,-45,100,120,5")
    assert r.exit_code == 0
    assert r.output.count(": ok") == 5


def test_check_of_every_stepnc_program_has_no_false_travel_error_on_the_default_machine():
    """The ISO 14649 start state retracts to Z 250, above the built-in mill's 200 mm Z
    travel; the retract height is lowered to the travel, so no file gets CNC101."""
    files = [
        EX1,
        *sorted(str(p) for p in (HERE / "stepnc").glob("*.stp") if p.name != Path(FIG).name),
    ]
    result = CliRunner().invoke(cli, ["check", "--format", "json", *files])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert [
        f for entry in doc["files"] for f in entry["findings"] if f["severity"] == "error"
    ] == []


def test_stepnc_start_state_is_fitted_to_the_machine_travel_with_a_comment():
    from cli.programs import program_commands
    from kernel.machine import DEFAULT_MACHINE

    cmds = list(program_commands(EX1, machine=DEFAULT_MACHINE))
    assert isinstance(cmds[0], canon.Comment)
    assert "lowered to the machine's Z travel limit 200" in cmds[0].text
    offset, peak = 0.0, -1e9
    for c in cmds:
        if isinstance(c, canon.UseToolLengthOffset):
            offset = c.length
        elif isinstance(c, canon.StraightTraverse):
            peak = max(peak, c.z + offset)
    assert peak == 200.0  # the highest traverse is the travel limit itself
    # without a machine (cnc canon), the standard start state is kept
    assert not isinstance(next(iter(program_commands(EX1))), canon.Comment)
