"""Issue 15: ``cnc convert`` of several programs or a folder, as ``cnc check`` takes them:
``-o FOLDER`` receives one output per program with the target's suffix, a status line
says what became of each, a program that fails writes no file and the rest go on, and the
exit code says whether one failed (1) or could not be written (2)."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from cli.convert import output_suffix
from cli.main import cli

GOOD = "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG2 X20 Y0 R5\nM2\n"
SPINDLE = "G21 G90\nS1000 M3\nG0 X1\nM2\n"  # Sandia has no spindle: a loss
BROKEN = "G21 G90\nG1 X1 F100 Q\nM2\n"  # a word without a value: the reader refuses it


def run(*args: str):  # noqa: ANN201
    return CliRunner().invoke(cli, ["convert", *args], catch_exceptions=False)


def _tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def test_a_folder_becomes_one_output_per_program_with_the_targets_suffix(tmp_path: Path) -> None:
    src = _tree(tmp_path / "in", {"a.ngc": GOOD, "sub/b.ngc": GOOD, "notes.txt": "not a program"})
    out = tmp_path / "out"
    result = run(str(src), "--to", "fanuc", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()) == [
        "a.nc",
        "sub/b.nc",
    ]
    single = tmp_path / "single.nc"
    assert run(str(src / "a.ngc"), "--to", "fanuc", "-o", str(single)).exit_code == 0
    assert (out / "a.nc").read_text() == single.read_text()
    assert f"{src / 'a.ngc'}: converted to {out / 'a.nc'} (verified)" in result.output
    assert f"{src / 'sub' / 'b.ngc'}: converted to {out / 'sub' / 'b.nc'} (verified)" in (
        result.output
    )
    assert "2 of 2 programs converted to" in result.output


def test_a_failing_program_writes_nothing_and_the_others_go_on(tmp_path: Path) -> None:
    src = _tree(tmp_path / "in", {"a.ngc": GOOD, "b.ngc": SPINDLE, "c.ngc": BROKEN})
    out = tmp_path / "out"
    report = tmp_path / "r.json"
    files = [str(src / n) for n in ("a.ngc", "b.ngc", "c.ngc")]
    result = run(*files, "--to", "sandia", "-o", str(out), "--report", str(report))
    assert result.exit_code == 1, result.output
    assert sorted(p.name for p in out.iterdir()) == ["a.txt"]  # no temporary file either
    assert f"{files[1]}: not converted (CONV-LOSS)" in result.output
    assert "error[CONV-SPINDLE]" in result.output
    assert f"{files[2]}:2:" in result.output and f"{files[2]}: not converted (" in result.output
    assert "1 of 3 programs converted to" in result.output
    data = json.loads(report.read_text())
    assert [f["status"] for f in data["files"]] == ["converted", "failed", "failed"]
    assert data["files"][0]["verified"] is True
    assert data["files"][1]["losses"]


def test_an_existing_output_is_kept_without_force(tmp_path: Path) -> None:
    src = _tree(tmp_path / "in", {"a.ngc": GOOD, "b.ngc": GOOD})
    out = _tree(tmp_path / "out", {"a.gcode": "keep me"})
    result = run(str(src), "--to", "grbl", "-o", str(out))
    assert result.exit_code == 2, result.output
    assert "IO-EXISTS" in result.output
    assert (out / "a.gcode").read_text() == "keep me"
    assert (out / "b.gcode").read_text().startswith("G21")
    forced = run(str(src), "--to", "grbl", "-o", str(out), "--force")
    assert forced.exit_code == 0, forced.output
    assert (out / "a.gcode").read_text() == (out / "b.gcode").read_text()


def test_several_programs_need_an_output_folder(tmp_path: Path) -> None:
    src = _tree(tmp_path, {"a.ngc": GOOD, "b.ngc": GOOD, "o.nc": "x"})
    none = run(str(src / "a.ngc"), str(src / "b.ngc"), "--to", "fanuc")
    assert none.exit_code == 2 and f"{src / 'a.ngc'}: error[CONV-OPTION]" in none.output
    on_a_file = run(
        str(src / "a.ngc"), str(src / "b.ngc"), "--to", "fanuc", "-o", str(src / "o.nc")
    )
    assert on_a_file.exit_code == 2 and "IO-EXISTS" in on_a_file.output


def test_two_programs_of_one_name_do_not_overwrite_each_other(tmp_path: Path) -> None:
    src = _tree(tmp_path, {"x/p.ngc": GOOD, "y/p.ngc": GOOD.replace("X10", "X11")})
    out = tmp_path / "out"
    result = run(
        str(src / "x" / "p.ngc"), str(src / "y" / "p.ngc"), "--to", "fanuc", "-o", str(out)
    )
    assert result.exit_code == 2 and "is the output of" in result.output
    assert "X10." in (out / "p.nc").read_text()


def test_every_target_has_a_suffix() -> None:
    assert output_suffix("fanuc") == ".nc" and output_suffix("siemens840d") == ".mpf"
    assert output_suffix("grbl") == ".gcode" and output_suffix("rs274ngc") == ".ngc"
