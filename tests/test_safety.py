"""Nothing is read or written outside what the user named (issue 19, safety).

Called subroutine and sub-program files come only from the search directories (no absolute
names, no ``..``, no symlink out of them); an output that is an input is refused even with
``--force``; outputs replace a symlink instead of writing through it, and a dangling symlink
counts as an existing file; the fast-kernel cache is private.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode.core.search import find_in_dirs, unsafe_name
from gcode.fanuc.reader import interpret as fanuc_interpret
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.ngc.lane import fastlane
from gcode.siemens.reader import interpret as siemens_interpret
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

SUB = "o<{name}> sub\nG0 X77\no<{name}> endsub\nM2\n"


def _xs(commands: list[canon.Command]) -> list[float]:
    return [c.x for c in commands if isinstance(c, canon.StraightTraverse)]


@pytest.fixture()
def tree(tmp_path: Path) -> Path:
    """``prog/`` (the program), ``prog/subs/`` (the search path) and ``outside/`` (a
    subroutine file no program may reach)."""
    (tmp_path / "prog" / "subs").mkdir(parents=True)
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "x.ngc").write_text(SUB.format(name="x"))
    return tmp_path


@pytest.mark.parametrize(
    "name", ["../outside/x", "subs/../../outside/x", "{abs}/outside/x", "~/x", "..\\outside\\x"]
)
def test_a_called_name_is_never_a_path_out_of_the_search_path(tree: Path, name: str) -> None:
    name = name.format(abs=tree)
    prog = tree / "prog" / "main.ngc"
    prog.write_text(f"G21\no<{name}> call\nM2\n")
    opts = InterpreterOptions(search_path=(str(tree / "prog" / "subs"),))
    with pytest.raises(Diagnostic) as info:
        list(interpret(prog, opts))
    assert info.value.code == "NGC-OWORD-UNDEFINED"
    assert info.value.location.line == 2


def test_a_symlink_out_of_the_search_path_is_not_followed(tree: Path) -> None:
    os.symlink(tree / "outside" / "x.ngc", tree / "prog" / "subs" / "x.ngc")
    prog = tree / "prog" / "main.ngc"
    prog.write_text("G21\no<x> call\nM2\n")
    opts = InterpreterOptions(search_path=(str(tree / "prog" / "subs"),))
    with pytest.raises(Diagnostic) as info:
        list(interpret(prog, opts))
    assert info.value.code == "NGC-OWORD-UNDEFINED"


def test_a_symlink_inside_the_search_path_is_followed(tree: Path) -> None:
    (tree / "prog" / "subs" / "real").mkdir()
    (tree / "prog" / "subs" / "real" / "y.ngc").write_text(SUB.format(name="x"))
    os.symlink(tree / "prog" / "subs" / "real" / "y.ngc", tree / "prog" / "subs" / "x.ngc")
    prog = tree / "prog" / "main.ngc"
    prog.write_text("G21\no<x> call\nM2\n")
    opts = InterpreterOptions(search_path=(str(tree / "prog" / "subs"),))
    assert _xs(list(interpret(prog, opts))) == [77.0]


def test_the_program_directory_is_searched_only_without_a_search_path(tree: Path) -> None:
    (tree / "prog" / "x.ngc").write_text(SUB.format(name="x"))
    prog = tree / "prog" / "main.ngc"
    prog.write_text("G21\no<x> call\nM2\n")
    assert _xs(list(interpret(prog))) == [77.0]  # no path configured: the program's directory
    opts = InterpreterOptions(search_path=(str(tree / "prog" / "subs"),))
    with pytest.raises(Diagnostic):
        list(interpret(prog, opts))


def test_cli_subroutine_path_replaces_the_program_directory(tree: Path) -> None:
    (tree / "prog" / "x.ngc").write_text(SUB.format(name="x"))
    prog = tree / "prog" / "main.ngc"
    prog.write_text("G21\no<x> call\nM2\n")
    ok = CliRunner().invoke(cli, ["canon", str(prog)])
    assert ok.exit_code == 0 and "STRAIGHT_TRAVERSE(77" in ok.output
    res = CliRunner().invoke(cli, ["canon", "-I", str(tree / "prog" / "subs"), str(prog)])
    assert res.exit_code != 0 and "NGC-OWORD-UNDEFINED" in res.output


def test_fanuc_m98_file_symlinked_out_of_the_search_path(tree: Path) -> None:
    (tree / "outside" / "O0077.nc").write_text("%\nO0077\nG91 G01 X3. F100.\nG90\nM99\n%\n")
    os.symlink(tree / "outside" / "O0077.nc", tree / "prog" / "O0077.nc")
    prog = tree / "prog" / "main.nc"
    prog.write_text("%\nO0001\nG21 G90\nM98 P77\nM30\n%\n")
    with pytest.raises(Diagnostic) as info:
        list(fanuc_interpret(prog))
    assert info.value.code == "FANUC-NO-PROGRAM"


def test_siemens_subprogram_symlinked_out_of_the_search_path(tree: Path) -> None:
    (tree / "outside" / "L7.SPF").write_text("G0 X1\nM17\n")
    os.symlink(tree / "outside" / "L7.SPF", tree / "prog" / "L7.SPF")
    prog = tree / "prog" / "MAIN.MPF"
    prog.write_text("L7\nM30\n")
    with pytest.raises(Diagnostic) as info:
        list(siemens_interpret(prog))
    assert info.value.code == "SIEM-SUBPROGRAM"


def test_unsafe_names() -> None:
    for bad in ("", "/etc/passwd", "../x", "a/../../x", "~root/x", "c:x", "a\0b"):
        assert unsafe_name(bad), bad
    for good in ("x", "sub/x", "O1234.nc", "a..b"):
        assert not unsafe_name(good), good
    assert find_in_dirs(["/"], ["etc/../etc/passwd"]) is None


# outputs --------------------------------------------------------------------------------

PROGRAM = "G21\nG0 X1\nM2\n"


def _canon(*args: str) -> tuple[int, str]:
    res = CliRunner().invoke(cli, ["canon", *args])
    return res.exit_code, res.output


def test_an_output_that_is_the_input_is_refused_even_with_force(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    code, out = _canon(str(prog), "-o", str(prog), "--force")
    assert code == 2 and "IO-SAME-FILE" in out
    assert prog.read_text() == PROGRAM
    link = tmp_path / "alias.canon"
    os.symlink(prog, link)  # the same file under another name
    code, out = _canon(str(prog), "-o", str(link), "--force")
    assert code == 2 and "IO-SAME-FILE" in out
    assert prog.read_text() == PROGRAM
    res = CliRunner().invoke(
        cli, ["convert", str(prog), "--to", "fanuc", "-o", str(link), "--force"]
    )
    assert res.exit_code == 2 and "IO-SAME-FILE" in res.output
    assert prog.read_text() == PROGRAM


def test_a_dangling_symlink_output_is_refused_without_force(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    target = tmp_path / "elsewhere" / "victim.txt"
    target.parent.mkdir()
    link = tmp_path / "out.canon"
    os.symlink(target, link)
    code, out = _canon(str(prog), "-o", str(link))
    assert code == 2 and "IO-EXISTS" in out
    assert not target.exists() and link.is_symlink()
    code, out = _canon(str(prog), "-o", str(link), "--force")
    assert code == 0, out
    assert not target.exists()  # the link itself was replaced, not written through
    assert not link.is_symlink() and "STRAIGHT_TRAVERSE" in link.read_text()


def test_force_replaces_a_symlink_without_touching_its_target(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    target = tmp_path / "precious.txt"
    target.write_text("keep")
    link = tmp_path / "out.canon"
    os.symlink(target, link)
    res = CliRunner().invoke(cli, ["check", "-f", "json", "-o", str(link), "--force", str(prog)])
    assert res.exit_code == 0, res.output
    assert target.read_text() == "keep"
    assert not link.is_symlink() and link.read_text().lstrip().startswith("{")


def test_a_failed_run_leaves_no_output_and_no_temporary(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text("G21\nG0 X1\nG1 X2\nM2\n")  # G1 without a feed rate: an error on line 3
    out = tmp_path / "out.canon"
    code, text = _canon(str(prog), "-o", str(out))
    assert code != 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.ngc"]


def test_run_reports_a_missing_program_as_io_open(tmp_path: Path) -> None:
    res = CliRunner().invoke(cli, ["run", "-o", str(tmp_path / "r"), str(tmp_path / "none.ngc")])
    assert res.exit_code == 2
    assert "error[IO-OPEN]" in res.output


def test_the_kernel_cache_is_private_and_overridable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("CNC_CACHE_DIR", str(tmp_path / "c" / "d"))
    assert fastlane.cache_dir() == tmp_path / "c" / "d"
    assert fastlane.private_dir(fastlane.cache_dir())
    assert stat.S_IMODE((tmp_path / "c" / "d").stat().st_mode) == 0o700
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    assert not fastlane.private_dir(shared)  # never load code others could have put there
    ok, error = fastlane.KERNELS.build_aot(shared, "x")
    assert not ok and "not a private directory" in error
    assert list(shared.iterdir()) == []
