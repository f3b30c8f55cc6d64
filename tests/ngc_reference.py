"""Shared helpers of the RS274/NGC reference tests: run our interpreter over a program the
way ``rs274 -t sim.tbl -g PROG OUT`` ran (tool table beside it, inch based; ``*_subfile*``
programs with the subroutine path ``subs``) and compare with the reference output by the
equivalence rule of ``tests/data/README.md`` (:mod:`tests.canon_equiv`)."""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from gcode.ngc.interpreter import InterpreterOptions, interpret
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import ToolTable, read_tool_table
from tests.canon_equiv import compare

ENDINGS = ("PROGRAM_END()", "FINISH()")


@lru_cache(maxsize=8)
def tool_table(path: Path) -> ToolTable:
    return read_tool_table(path.read_text().splitlines(), str(path))


def run_program(program: Path) -> tuple[list[str], Diagnostic | None]:
    """Our canonical text for ``program`` and the diagnostic that stopped it (if any)."""
    search = (str(program.parent / "subs"),) if "_subfile" in program.name else ()
    options = InterpreterOptions(
        tool_table=tool_table(program.parent / "sim.tbl"), search_path=search
    )
    commands: list[canon.Command] = []
    error = None
    try:
        for cmd in interpret(program, options):
            commands.append(cmd)
    except Diagnostic as exc:
        error = exc
    return list(canon.write_text(commands)), error


def differences(program: Path) -> list[str]:
    """Empty when our output is equivalent to the reference ``.canon`` beside ``program``.

    A reference that stops without ``PROGRAM_END``/``FINISH`` is rs274 stopping at an error:
    then we must stop with a diagnostic too, after the same commands.
    """
    ours, error = run_program(program)
    ref = program.with_suffix(".canon").read_text().splitlines()
    out = compare(ours, ref)
    ref_ended = any(line.rstrip().endswith(ENDINGS) for line in ref[-6:])
    if ref_ended and error is not None:
        out.append(f"we stopped with {error} where rs274 ran to the end")
    if not ref_ended and error is None:
        out.append("rs274 stopped at an error; we ran to the end")
    return out
