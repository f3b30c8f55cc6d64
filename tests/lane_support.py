"""What the read-back lane tests share: a program's commands as (text, source line) with
the error that ended them, read by the general path or through the compiled lanes as
``cnc convert``'s check reads them, and a spy that counts a lane's runs."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

from cli.verify import _chunks
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read, read_chunks
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.ir.equivalence import expanded

#: the commands as (text, source line), and the error that ended them
Listing = tuple[list[tuple[str, int]], str | None]


def listing(commands: Iterable[canon.Command]) -> Listing:
    out: list[tuple[str, int]] = []
    try:
        for cmd in commands:
            out.append((cmd.to_text(), cmd.source.line if cmd.source else 0))
    except Diagnostic as exc:
        return out, f"{exc.code} {exc.location} {exc.message}"
    return out, None


def general(path: Path, dialect: str, opts: InterpreterOptions) -> Listing:
    """The program read by the general path alone."""
    return listing(read(path, dialect, replace(opts, fast_lane=False)))


def through_lanes(path: Path, dialect: str, opts: InterpreterOptions) -> Listing:
    """The read-back as the check reads it: runs as arrays, then as commands."""
    chunks = _chunks(read_chunks(path, dialect, opts, arcs=True), str(path))
    return listing(expanded(chunks))


def spy_lane(monkeypatch: pytest.MonkeyPatch, lane: type, opener: str) -> dict[str, int]:
    """Count the lanes of class ``lane`` opened (by its static method ``opener``, which
    must give one: the compiled kernels loaded) and the lines their runs took."""
    seen = {"opened": 0, "lines": 0}
    open_lane, take = getattr(lane, opener), lane.take

    def spy_open(*args: Any, **kwargs: Any) -> Any:
        got = open_lane(*args, **kwargs)
        assert got is not None, "the compiled kernels did not load"
        seen["opened"] += 1
        return got

    def spy_take(self: Any, ex: Any, index: int) -> Any:
        run = take(self, ex, index)
        seen["lines"] += run.lines if run is not None else 0
        return run

    monkeypatch.setattr(lane, opener, staticmethod(spy_open))
    monkeypatch.setattr(lane, "take", spy_take)
    return seen
