"""Programs passed to a worker as bytes instead of a path (a library generated on the client,
or a cluster whose workers do not share the client's filesystem).

The readers seek in files (O-word loops, subprograms), so a worker writes the bytes to a file
in its own scratch directory, checks that file with the ordinary task function, and reports
the result under the program's name. Only small programs should travel this way: each one is
pickled into its task.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

from cli.formats.base import FileResult

_SCRATCH: list[str] = []  # this process's scratch directory, made on first use


@dataclass(frozen=True, slots=True)
class InlineProgram:
    """A program as bytes: ``name`` is what its result is reported under (its file name
    also gives the suffix the dialect guess reads)."""

    name: str
    data: bytes


def _scratch() -> str:
    if not _SCRATCH or not os.path.isdir(_SCRATCH[0]):
        _SCRATCH[:] = [tempfile.mkdtemp(prefix="cnc-inline-")]
    return _SCRATCH[0]


def remove_scratch() -> None:
    """Remove this process's scratch directory (tests; a worker's goes with its /tmp)."""
    if _SCRATCH:
        shutil.rmtree(_SCRATCH.pop(), ignore_errors=True)


@contextmanager
def materialised(program: InlineProgram) -> Iterator[str]:
    """A path in this process's scratch directory holding ``program``'s bytes for the length
    of the block (removed after)."""
    local = os.path.join(_scratch(), Path(program.name).name or "program.ngc")
    with open(local, "wb") as fh:
        fh.write(program.data)
    try:
        yield local
    finally:
        os.unlink(local)


def renamed(result: FileResult, local: str, name: str) -> FileResult:
    """``result`` of the scratch file ``local`` as the result of ``name``: its file and the
    locations that named ``local`` say ``name``."""
    findings = tuple(
        replace(f, location=replace(f.location, file=name)) if f.location.file == local else f
        for f in result.findings
    )
    return replace(result, file=name, findings=findings)
