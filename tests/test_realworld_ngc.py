"""Real RS274/NGC programs from public repositories against LinuxCNC's ``rs274``.

The programs (tests/realworld/ngc, listed with their origins in tests/realworld/SOURCES.md)
are CAM output (Fusion 360, CamBam, pycam, Vectric, pcb2gcode, SketchUcam, ...) and
hand-written LinuxCNC programs. Their goldens were made by ``rs274 -t tools.tbl -g``
(tests/realworld/regen_ngc.py). A program rs274 accepts must give output equivalent to its
golden (tests/canon_equiv.py, the rule tests/test_ngc_golden.py uses); a program it rejects
must be rejected by us with an ``NGC-*`` diagnostic at the line rs274 stops at, or, for an
error inside a subroutine (where the prefix method finds the line of the call), at an
earlier line holding the very block rs274 printed. Programs with large outputs run under
``-m slow``; every fifth of them stays in the default run.

The programs of Mach3 posts (:data:`MACH3_POSTS`: CamBam's default post, Vectric's, pcb2gcode's
and SketchUcam's Mach3 output) are read again with ``--dialect mach3``: they use the subset
Mach3 shares with RS274/NGC, so that reading must be equivalent to rs274's golden too.
"""

from __future__ import annotations

import gzip
import json
import struct
from functools import lru_cache
from pathlib import Path

import pytest

from gcode.mach3 import reader as mach3
from gcode.ngc.interpreter import InterpreterOptions, interpret
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import ToolTable, read_tool_table
from tests.canon_equiv import compare

SUITE = Path(__file__).parent / "realworld" / "ngc"
SUFFIXES = (".ngc", ".nc", ".gcode", ".tap", ".cnc")
PROGRAMS = sorted(p for p in SUITE.iterdir() if p.suffix.lower() in SUFFIXES)
#: a golden whose text is larger than this marks a large program (run under -m slow)
LARGE_BYTES = 80_000

#: programs rs274 accepts that we knowingly do not run yet -> reason
KNOWN: dict[str, str] = {}

#: programs of posts for Mach3 (CamBam's default post is Mach3's; Vectric's "G-code"
#: and pcb2gcode's mach3 outputs; SketchUcam's); all are accepted by rs274
MACH3_POSTS = (
    "camotics__bear.nc",
    "camotics__scorpion.nc",
    "pcb2gcode__example_board_al_mach3__outline.ngc",
    "ugs__arc_rword_test.gcode",
    "ugs__communicator.nc",
    "ugs__electric_turtle.nc",
    "ugs__enclosure.nc",
    "ugs__ordbot_handle.nc",
)


def golden(program: Path) -> Path:
    return program.with_name(program.name + ".canon.gz")


def expected_error(program: Path) -> Path:
    return program.with_name(program.name + ".expected.json")


def _golden_size(program: Path) -> int:
    """The uncompressed size of a gzip golden (its trailer's ISIZE field)."""
    path = golden(program)
    if not path.exists():
        return 0
    with path.open("rb") as fh:
        fh.seek(-4, 2)
        size: int = struct.unpack("<I", fh.read(4))[0]
    return size


def _params() -> list[object]:
    large = [p for p in PROGRAMS if _golden_size(p) > LARGE_BYTES]
    sampled = set(large[::5])
    out = []
    for p in PROGRAMS:
        marks: list[pytest.MarkDecorator] = []
        if p in large and p not in sampled:
            marks.append(pytest.mark.slow)
        if p.name in KNOWN:
            marks.append(pytest.mark.xfail(strict=True, reason=KNOWN[p.name]))
        out.append(pytest.param(p, id=p.name, marks=marks))
    return out


@lru_cache(maxsize=1)
def tools() -> ToolTable:
    table = SUITE / "tools.tbl"
    return read_tool_table(table.read_text().splitlines(), str(table))


def run(program: Path, dialect: str = "rs274ngc") -> tuple[list[str], Diagnostic | None]:
    """Our canonical text for ``program`` and the diagnostic that stopped it (if any)."""
    commands: list[canon.Command] = []
    error = None
    read = mach3.interpret if dialect == "mach3" else interpret
    try:
        for cmd in read(program, InterpreterOptions(tool_table=tools())):
            commands.append(cmd)
    except Diagnostic as exc:
        error = exc
    return list(canon.write_text(commands)), error


def check_rejected(program: Path, error: Diagnostic | None) -> None:
    """``error`` is at the line rs274 stops at (module docstring)."""
    expected = json.loads(expected_error(program).read_text())
    where = f"rs274: line {expected['line']}: {expected['rs274_message']}"
    assert error is not None, f"we ran to the end ({where})"
    assert error.code.startswith("NGC-") or error.code.startswith("MACH3-"), error.code
    line = error.location.line
    assert line is not None
    if line != expected["line"]:
        text = program.read_bytes().decode("latin-1").splitlines()[line - 1]
        same_block = text.strip().lower() == expected["rs274_block"].strip().lower()
        assert same_block and line < expected["line"], f"{error} ({where})"


def check_accepted(program: Path, ours: list[str], error: Diagnostic | None) -> None:
    ref = gzip.decompress(golden(program).read_bytes()).decode().splitlines()
    out = compare(ours, ref)
    if error is not None:
        out.append(f"we stopped with {error} where rs274 ran to the end")
    assert out == []


@pytest.mark.parametrize("program", _params())
def test_real_program_matches_rs274(program: Path) -> None:
    ours, error = run(program)
    if expected_error(program).exists():
        check_rejected(program, error)
    else:
        check_accepted(program, ours, error)


@pytest.mark.parametrize(
    "program",
    [
        pytest.param(
            SUITE / n,
            id=n,
            marks=[pytest.mark.slow] if _golden_size(SUITE / n) > LARGE_BYTES else [],
        )
        for n in MACH3_POSTS
    ],
)
def test_mach3_post_read_as_mach3_matches_rs274(program: Path) -> None:
    ours, error = run(program, "mach3")
    check_accepted(program, ours, error)


def test_suite_is_there() -> None:
    assert len(PROGRAMS) >= 80
    missing = [p.name for p in PROGRAMS if not (golden(p).exists() or expected_error(p).exists())]
    assert missing == []
    assert all((SUITE / n).exists() and golden(SUITE / n).exists() for n in MACH3_POSTS)
    listed = (SUITE.parent / "SOURCES.md").read_text()
    assert [p.name for p in PROGRAMS if f"`{p.name}`" not in listed] == []
