"""``cnc canon``: output forms, -o/--force, compiler-style errors and exit codes."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from cli.canon import fast_text
from cli.main import cli
from kernel.ir import canon
from tests.ngc_reference import run_program

GOLDEN = Path(__file__).parent / "golden" / "ngc"
TBL = str(GOLDEN / "sim.tbl")


def _program(tmp_path: Path, text: str) -> str:
    p = tmp_path / "p.ngc"
    p.write_text(text)
    return str(p)


def test_text_output_matches_the_golden(tmp_path: Path) -> None:
    prog = GOLDEN / "054_g2_centre_ij_xy.ngc"
    result = CliRunner().invoke(cli, ["canon", str(prog), "--tool-table", TBL])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines() == prog.with_suffix(".canon").read_text().splitlines()


def test_jsonl_output_reads_back_into_the_same_motions(tmp_path: Path) -> None:
    prog = _program(tmp_path, "G21\nG0 X1 Y2\nG1 X3 F100\nM2\n")
    result = CliRunner().invoke(cli, ["canon", prog, "--format", "jsonl", "--nist"])
    assert result.exit_code == 0, result.output
    cmds = [canon.from_json(json.loads(line)) for line in result.output.splitlines()]
    moves = [c for c in cmds if isinstance(c, canon.MOTIONS)]
    assert [(m.NAME, m.x, m.y) for m in moves] == [
        ("STRAIGHT_TRAVERSE", 1.0, 2.0),
        ("STRAIGHT_FEED", 3.0, 2.0),
    ]
    assert moves[0].source is not None and moves[0].source.line == 2


def test_output_file_is_not_overwritten_without_force(tmp_path: Path) -> None:
    prog = _program(tmp_path, "G21\nG0 X1\nM2\n")
    out = tmp_path / "out.canon"
    out.write_text("keep")
    runner = CliRunner()
    result = runner.invoke(cli, ["canon", prog, "-o", str(out)])
    assert result.exit_code == 2
    assert "IO-EXISTS" in result.output and out.read_text() == "keep"
    result = runner.invoke(cli, ["canon", prog, "-o", str(out), "--force"])
    assert result.exit_code == 0
    assert "STRAIGHT_TRAVERSE(1.0000" in out.read_text()


def test_program_error_prints_like_a_compiler_after_the_commands_before_it(
    tmp_path: Path,
) -> None:
    prog = _program(tmp_path, "G21\nG0 X1\nG0 X[1/0]\nM2\n")
    result = CliRunner().invoke(cli, ["canon", prog])
    assert result.exit_code == 1
    assert "STRAIGHT_TRAVERSE(1.0000" in result.output
    assert f"{prog}:3:" in result.output and "error[NGC-DIVIDE-BY-ZERO]" in result.output


def test_missing_program_is_a_usage_error(tmp_path: Path) -> None:
    result = CliRunner().invoke(cli, ["canon", str(tmp_path / "none.ngc")])
    assert result.exit_code == 2
    assert "IO-OPEN" in result.output


def test_fast_writer_prints_exactly_what_the_ir_writer_prints() -> None:
    for prog in sorted(GOLDEN.glob("0[5-9]*.ngc"))[:40]:
        lines, _ = run_program(prog)
        cmds = list(canon.read_commands(lines))
        assert list(fast_text(cmds)) == list(canon.write_text(cmds))
    tricky = [
        canon.StraightFeed(-0.00001, 1e-9, -2.5, 0.0, 0.0, 0.0),
        canon.SetFeedRate(-0.0),
        canon.StraightTraverse(-0.0, 0.00005, -0.00005, -0.0, 0.0, -0.0),
        canon.StraightTraverse(-0.00001, -0.00005, 1.00005, 0.0, 1e-5, 0.0),
        canon.StraightFeed(float("nan"), float("inf"), -float("inf"), 0.0, 0.0, 0.0),
        canon.StraightFeed(-0.00001, 1e-9, -2.5, 0.0, 0.0, 0.0),
    ]
    assert list(fast_text(tricky)) == list(canon.write_text(tricky))
