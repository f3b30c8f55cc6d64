"""Nothing a user has is overwritten without asking: ``check -o`` and ``run`` refuse an
existing output (IO-EXISTS, exit 2, the file untouched) unless given ``--force``."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from cli.main import cli

PROGRAM = Path(__file__).parent.parent / "docs" / "examples" / "bracket.ngc"  # a clean job


def test_check_refuses_to_overwrite_a_report(tmp_path: Path) -> None:
    out = tmp_path / "check.sarif"
    out.write_text("keep me")
    res = CliRunner().invoke(cli, ["check", "-f", "sarif", "-o", str(out), str(PROGRAM)])
    assert res.exit_code == 2 and "IO-EXISTS" in res.output
    assert out.read_text() == "keep me"
    res = CliRunner().invoke(cli, ["check", "-f", "sarif", "-o", str(out), "--force", str(PROGRAM)])
    assert res.exit_code == 0 and out.read_text().lstrip().startswith("{")


def test_run_refuses_before_any_work_when_a_report_exists(tmp_path: Path) -> None:
    report = tmp_path / f"{PROGRAM.stem}.report.json"
    report.write_text("keep me")
    res = CliRunner().invoke(cli, ["run", "-o", str(tmp_path), str(PROGRAM)])
    assert res.exit_code == 2 and "IO-EXISTS" in res.output
    assert report.read_text() == "keep me"
    res = CliRunner().invoke(cli, ["run", "-o", str(tmp_path), "--force", str(PROGRAM)])
    assert res.exit_code == 0, res.output
    assert report.read_text().lstrip().startswith("{")
