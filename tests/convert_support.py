"""Helpers for the convert tests: the program corpus, reading it, and comparing IR.

Canonical text is normally printed with four decimals; two values 1e-6 apart can print
1e-4 apart and then fail the 1e-4 rule by a rounding hair. :func:`fine_text` prints
motions, feeds and speeds with six decimals so the equivalence rule of
``tests/canon_equiv.py`` measures the real difference.
"""

from __future__ import annotations

import functools
import shutil
import subprocess
from collections.abc import Iterable
from pathlib import Path

import pytest

from gcode.ngc.interpreter import InterpreterOptions, interpret, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table
from tests.data_paths import CORPUS_NGC
from tests.rs274_home import rs274_env

HERE = Path(__file__).resolve().parent
GOLDEN = HERE / "golden" / "ngc"
CORPUS = CORPUS_NGC


def programs() -> list[Path]:
    return sorted(GOLDEN.glob("*.ngc")) + sorted(CORPUS.glob("*.ngc"))


def canon_files() -> list[Path]:
    return sorted(GOLDEN.glob("*.canon")) + sorted(CORPUS.glob("*.canon"))


def options(program: Path) -> InterpreterOptions:
    table = program.parent / "sim.tbl"
    return InterpreterOptions(
        tool_table=read_tool_table(table.read_text().splitlines(), str(table)),
        search_path=(str(program.parent), str(program.parent / "subs")),
    )


def read_ir(program: Path) -> list[canon.Command] | None:
    """The interpreter's IR of a program, or None when the interpreter rejects it."""
    try:
        return list(interpret(program, options(program)))
    except Diagnostic:
        return None


@functools.cache
def ir_of(program: Path) -> tuple[canon.Command, ...] | None:
    """:func:`read_ir` as a tuple, read once per program and test process."""
    ir = read_ir(program)
    return None if ir is None else tuple(ir)


def reread(text: str, program: Path) -> list[canon.Command]:
    return list(interpret_text(text, program.name, options(program)))


def fine_text(commands: Iterable[canon.Command]) -> list[str]:
    out = []
    for c in commands:
        if isinstance(c, canon.MOTIONS + (canon.SetFeedRate, canon.SetSpindleSpeed)):
            args = []
            for v in c.args():
                if isinstance(v, float):
                    args.append(f"{v:.6f}")
                else:
                    args.append(str(v.value) if hasattr(v, "value") else str(v))
            out.append(f"{c.NAME}({', '.join(args)})")
        else:
            out.append(c.to_text())
    return out


def rs274(text: str, tool_table: Path, workdir: Path) -> list[str]:
    """LinuxCNC's stand-alone interpreter on ``text``: its canonical output lines.

    ``rs274`` occasionally dies without a message, or loses its tool table, when several
    run at once (its tool data live in shared memory); such runs are retried.
    """
    exe = shutil.which("rs274")
    assert exe is not None
    (workdir / "conv.ngc").write_text(text)
    shutil.copy(tool_table, workdir / "sim.tbl")  # rs274 may write its tool table back
    for _ in range(5):
        proc = subprocess.run(
            [exe, "-t", "sim.tbl", "-g", "conv.ngc", "conv.canon"],
            cwd=workdir,
            capture_output=True,
            text=True,
            timeout=60,
            env=rs274_env(workdir),
        )
        if proc.returncode == 0:
            return (workdir / "conv.canon").read_text().splitlines()
        if proc.stderr.strip() not in ("", "executing") and not _transient(proc.stderr):
            raise AssertionError(f"rs274 rejected the converted program: {proc.stderr}")
    raise AssertionError(f"rs274 failed five times: {proc.stderr}")


def _transient(stderr: str) -> bool:
    """rs274 keeps its tool data in shared memory: concurrent runs can lose their table."""
    return "not found in the tool table" in stderr


def in_turn(values: Iterable[object], options: Iterable[object], every: int) -> list[object]:
    """(value, option) test cases for ``pytest.mark.parametrize``: one option in ``every``
    per value in the default run, taken in turn so that every option is run there too, and
    the others under ``-m slow``. A tuple option gives several arguments."""
    opts = list(options)

    def name(x: object) -> str:
        parts = x if isinstance(x, tuple) else (x,)
        return "-".join(p.stem if isinstance(p, Path) else str(p) for p in parts)

    return [
        pytest.param(
            v,
            *(o if isinstance(o, tuple) else (o,)),
            id=f"{name(v)}-{name(o)}",
            marks=() if (i + j) % every == 0 else pytest.mark.slow,
        )
        for i, v in enumerate(values)
        for j, o in enumerate(opts)
    ]
