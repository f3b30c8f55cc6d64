"""One option vocabulary across every command (issue 18, docs/cli.md).

Walks the commands in-process with click's CliRunner (no subprocess start-up per case) and
asserts that the shared options are spelled and behave the same everywhere: ``-m/--machine``,
``-t/--tool-table`` (``--tool-units``), ``-d/--dialect``, ``-q/-v`` after the subcommand,
``-`` for standard input (named ``<stdin>``), a usage error (exit 2) for an empty folder or a
pattern matching nothing, ``--fail-on``, and one wording for an output that exists.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import click
import pytest
from click.testing import CliRunner, Result

from cli.main import cli

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT / "tests" / "data" / "corpus"
SIM_TBL = CORPUS / "ngc" / "sim.tbl"  # LinuxCNC's sim tool table: T1 Z+0.511
EX1 = CORPUS / "stepnc" / "ex1.stp"
EX1_TOOLS = CORPUS / "stepnc" / "iso14649.tool_ex1"

PROGRAM = "G21 G90\nG0 X0 Y0 Z5\nM3 S1000\nG1 Z-1 F100\nG1 X2\nM5\nM2\n"
#: G1 with no feed rate: an error of the program on its line 2
BAD = "G21 G90\nG1 X1\nM2\n"
#: only a warning (CNC040, a dwell far above check.max_dwell)
WARNS = "G21 G90\nG0 X0 Y0 Z5\nM3 S1000\nG4 P5000\nG1 Z-1 F100\nM5\nM2\n"
#: only a note (CNC702, an M code for the PLC the profile does not name), read as Fanuc
NOTES = "G21 G90\nG0 X0. Y0. Z5.\nM50\nM30\n"
EXISTS = "exists; use --force to replace it"

#: every command that reads a program, with the arguments that make it valid besides
#: the program; the shared options each must accept
READERS: dict[str, tuple[str, ...]] = {
    "canon": (),
    "check": (),
    "run": (),
    "plan": (),
    "trace": ("-o", "OUT"),
    "sim": ("--stock", "box:-10,-10,-10,10,10,10"),
}
SHARED = ("-m", "--machine", "-t", "--tool-table", "-d", "--dialect", "-q", "-v")


def invoke(*args: str, stdin: str | bytes | None = None) -> Result:
    """``cnc ARGS`` in this process (stderr kept apart from stdout)."""
    return CliRunner().invoke(cli, list(args), input=stdin, catch_exceptions=False)


def walk(group: click.Group, prefix: tuple[str, ...] = ()) -> Iterator[tuple[str, click.Command]]:
    """Every command and subcommand under ``group``, loaded as ``cnc`` loads them."""
    ctx = click.Context(group)
    for name in group.list_commands(ctx):
        command = group.get_command(ctx, name)
        assert command is not None
        yield " ".join((*prefix, name)), command
        if isinstance(command, click.Group):
            yield from walk(command, (*prefix, name))


def options(command: click.Command) -> dict[str, click.Parameter]:
    """Every spelling of every option of ``command``, with its parameter."""
    return {o: p for p in command.params if isinstance(p, click.Option) for o in p.opts}


ALL = dict(walk(cli))


def test_every_command_is_walked() -> None:
    """The walk reaches every command named in the issue, subcommands included."""
    for name in ("canon", "check", "convert", "machine init", "machine show", "plan", "run"):
        assert name in ALL
    for name in ("sim", "stepnc canon", "stepnc gouge", "stepnc to-gcode", "trace"):
        assert name in ALL


@pytest.mark.parametrize("name", sorted(READERS))
def test_program_readers_share_the_options(name: str) -> None:
    have = options(ALL[name])
    missing = [o for o in SHARED if o not in have]
    assert not missing, f"cnc {name} lacks {missing}"
    assert have["-m"] is have["--machine"] and have["-t"] is have["--tool-table"]
    assert have["-d"] is have["--dialect"]


@pytest.mark.parametrize("name", sorted(ALL))
def test_one_spelling_everywhere(name: str) -> None:
    """Wherever an option exists, its short and long forms are the shared ones, and -q/-v
    work after the subcommand."""
    have = options(ALL[name])
    assert "-q" in have and "-v" in have, name
    for short, long in (("-m", "--machine"), ("-t", "--tool-table"), ("-o", "--output")):
        if long in have or short in have:
            assert have.get(short) is have.get(long), f"cnc {name}: {short} and {long}"
    if "--dialect" in have:
        assert have["--dialect"] is have.get("-d"), name
    if "--tool-table" in have:
        assert "--tool-units" in have or name.startswith(("stepnc", "convert")), name


def test_old_spellings_work_hidden() -> None:
    """stepnc's --tool-file and convert's --from keep working; --help shows -t and -d."""
    by_old = invoke("stepnc", "canon", str(EX1), "--tool-file", str(EX1_TOOLS))
    by_new = invoke("stepnc", "canon", str(EX1), "-t", str(EX1_TOOLS))
    assert by_old.exit_code == 0 and by_old.stdout == by_new.stdout
    help_text = invoke("stepnc", "canon", "--help").stdout
    assert "--tool-table" in help_text and "--tool-file" not in help_text
    assert options(ALL["convert"])["-d"] is options(ALL["convert"])["--from"]


@pytest.mark.parametrize("name", ["canon", "check", "plan"])
def test_verbosity_after_the_subcommand(tmp_path: Path, name: str) -> None:
    """``cnc X -v P`` is ``cnc -v X P``: -v tells the dialect guess, -q silences it."""
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    before = invoke("-v", name, str(prog))
    after = invoke(name, "-v", str(prog))
    assert "DIALECT-GUESS" in before.stderr
    assert (after.exit_code, after.stdout, after.stderr) == (
        before.exit_code,
        before.stdout,
        before.stderr,
    )
    quiet = invoke(name, "-q", str(prog))
    assert "DIALECT-GUESS" not in quiet.stderr
    assert invoke("-q", name, str(prog)).stderr == quiet.stderr


@pytest.mark.parametrize("name", ["canon", "check", "plan"])
def test_stdin_is_a_program(tmp_path: Path, name: str) -> None:
    """``-`` reads the program from standard input; diagnostics name it ``<stdin>``."""
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    json = ("--format", "json") if name == "plan" else ()  # no layout that wraps the name
    from_file = invoke(name, str(prog), *json)
    from_stdin = invoke(name, "-", *json, stdin=PROGRAM)
    assert from_stdin.exit_code == from_file.exit_code == 0
    assert from_stdin.stdout.replace("<stdin>", str(prog)) == from_file.stdout
    bad = invoke(name, "-", stdin=BAD)
    assert bad.exit_code == 1
    assert "<stdin>:2:" in bad.output


@pytest.mark.slow
@pytest.mark.parametrize("name", ["run", "trace", "sim"])
def test_stdin_is_a_program_slow(tmp_path: Path, name: str) -> None:
    """The simulating commands read ``-`` too, and name their outputs ``stdin``."""
    args = [a.replace("OUT", str(tmp_path / "out")) for a in READERS[name]]
    if name == "run":
        args = ["-o", str(tmp_path / "out")]
    result = invoke(name, "-", *args, stdin=PROGRAM)
    assert result.exit_code == 0, result.output
    if name in ("run", "trace"):
        assert any(p.name.startswith("stdin") for p in (tmp_path / "out").iterdir())


def test_convert_reads_stdin_as_it_reads_the_file(tmp_path: Path) -> None:
    """``cnc convert -`` writes what converting the same program from its file writes; a
    bad program on standard input is refused with a located diagnostic."""
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    from_file = invoke("convert", str(prog), "--to", "fanuc")
    from_stdin = invoke("convert", "-", "--to", "fanuc", stdin=PROGRAM)
    assert from_stdin.exit_code == from_file.exit_code == 0
    assert from_stdin.stdout == from_file.stdout
    bad = invoke("convert", "-", "--to", "fanuc", stdin=BAD)
    assert bad.exit_code == 1 and "stdin:2:" in bad.output
    both = invoke("convert", "-", str(prog), "--to", "fanuc", "-o", str(tmp_path / "o"))
    assert both.exit_code == 2


@pytest.mark.parametrize("args", [("canon",), ("plan",), ("convert", "--to", "fanuc")])
def test_binary_stdin_is_a_located_error(args: tuple[str, ...]) -> None:
    """Bytes that are not text on standard input are CHECK-BINARY at the program, exit 1, as
    for a file (catch_exceptions=False: a decoding traceback would fail the test)."""
    result = invoke(*args[:1], "-", *args[1:], stdin=b"\xff\xfe\x00\x01G1")
    assert result.exit_code == 1
    assert "error[CHECK-BINARY]" in result.output


def test_stdin_stepnc_and_dialect_by_content() -> None:
    """A STEP-NC program on standard input is told by content; G-code from -d."""
    text = EX1.read_text(encoding="latin-1")
    assert invoke("canon", "-", stdin=text).stdout == invoke("canon", str(EX1)).stdout
    assert invoke("stepnc", "info", "-", stdin=text).exit_code == 0
    fanuc = invoke("check", "-d", "fanuc", "-", stdin=NOTES)
    assert "<stdin>:3:1: note[CNC702]" in fanuc.stdout


@pytest.mark.parametrize("name", ["check", "run", "convert"])
def test_empty_folder_and_unmatched_pattern_are_usage_errors(tmp_path: Path, name: str) -> None:
    extra = ["--to", "fanuc", "-o", str(tmp_path / "out")] if name == "convert" else []
    if name == "run":
        extra = ["-o", str(tmp_path / "out")]
    empty = tmp_path / "empty"
    empty.mkdir()
    result = invoke(name, str(empty), *extra)
    assert result.exit_code == 2
    assert "no programs in this directory" in result.output
    pattern = str(tmp_path / "nothing" / "*.ngc")
    result = invoke(name, pattern, *extra)
    assert result.exit_code == 2
    assert "no file matches this pattern" in result.output


def test_quoted_pattern_is_expanded(tmp_path: Path) -> None:
    """A pattern the shell left alone is expanded here, ``**`` recursively."""
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "deep").mkdir()
    for p in ("one.ngc", "a/two.ngc", "a/deep/three.ngc"):
        (tmp_path / p).write_text(PROGRAM)
    flat = invoke("check", str(tmp_path / "*.ngc"))
    assert flat.exit_code == 0 and "1 file checked" in flat.stdout
    deep = invoke("check", str(tmp_path / "**" / "*.ngc"))
    assert deep.exit_code == 0 and "3 files checked" in deep.stdout


def test_fail_on(tmp_path: Path) -> None:
    """Exit 1 at or above --fail-on; the default stays errors only."""
    warns = tmp_path / "w.ngc"
    warns.write_text(WARNS)
    notes = tmp_path / "n.nc"
    notes.write_text(NOTES)
    assert invoke("check", str(warns)).exit_code == 0
    assert invoke("check", "--fail-on", "error", str(warns)).exit_code == 0
    assert invoke("check", "--fail-on", "warning", str(warns)).exit_code == 1
    assert invoke("check", "-d", "fanuc", "--fail-on", "warning", str(notes)).exit_code == 0
    assert invoke("check", "-d", "fanuc", "--fail-on", "note", str(notes)).exit_code == 1
    assert "--fail-on" in options(ALL["run"])


def test_default_machine_limits_the_spindle() -> None:
    """S40000 on the built-in mill is an error (its spindle range, as the init template)."""
    result = invoke("check", "-", stdin="G21\nM3 S40000\nM2\n")
    assert result.exit_code == 1
    assert "<stdin>:2:1: error[CNC501]" in result.stdout


def test_tool_units(tmp_path: Path) -> None:
    """A .tbl's lengths are read in --tool-units, else its header comment, else the
    command's default (canon: inch, as rs274). T1's Z offset 0.511 in mm is 0.511/25.4 in."""
    prog = tmp_path / "t.ngc"
    prog.write_text("G20\nT1 M6\nG43 H1\nG0 Z1\nM2\n")

    def offset(*args: str) -> float:
        out = invoke("canon", str(prog), *args).stdout
        line = next(s for s in out.splitlines() if "USE_TOOL_LENGTH_OFFSET" in s)
        return float(line.split("(")[1].split(",")[0].split()[2])

    assert offset("-t", str(SIM_TBL)) == pytest.approx(0.511)
    assert offset("-t", str(SIM_TBL), "--tool-units", "inch") == pytest.approx(0.511)
    assert offset("-t", str(SIM_TBL), "--tool-units", "mm") == pytest.approx(0.511 / 25.4, 1e-3)
    metric = tmp_path / "metric.tbl"
    metric.write_text("; units: mm\n" + SIM_TBL.read_text())
    assert offset("-t", str(metric)) == pytest.approx(0.511 / 25.4, 1e-3)
    assert offset("-t", str(metric), "--tool-units", "inch") == pytest.approx(0.511)


def test_one_wording_for_an_existing_output(tmp_path: Path) -> None:
    """Every command refuses an existing output the same way, exit 2."""
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    taken = tmp_path / "taken.txt"
    taken.write_text("keep")
    out = tmp_path / "out"
    out.mkdir()
    for name in ("p_trace.csv", "p_height.npy", "p.report.json"):
        (out / name).write_text("keep")
    cases = {
        "canon": ("canon", str(prog), "-o", str(taken)),
        "check": ("check", str(prog), "-o", str(taken)),
        "convert": ("convert", str(prog), "--to", "fanuc", "-o", str(taken)),
        "machine init": ("machine", "init", "-o", str(taken)),
        "stepnc to-gcode": ("stepnc", "to-gcode", str(EX1), "-o", str(taken)),
        "trace": ("trace", str(prog), "-o", str(out)),
        "sim": ("sim", str(prog), "--stock", "box:-10,-10,-10,10,10,10", "-o", str(out)),
        "run": ("run", str(prog), "-o", str(out)),
    }
    for name, args in cases.items():
        result = invoke(*args)
        assert result.exit_code == 2, (name, result.output)
        assert EXISTS in result.output, (name, result.output)
        assert "error[IO-EXISTS]" in result.output, (name, result.output)
    assert taken.read_text() == "keep"
