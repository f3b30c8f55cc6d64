"""``cnc convert``'s check of its own output: read it back with the target's reader and
compare it with the source at motion level (kernel.ir.equivalence, issue 15).

:class:`Recorder` keeps the source's commands as the writer consumes them;
:func:`verified_output` spools the written text to a temporary file, reads that file with
the target dialect's reader, and compares. A difference the conversion report does not
explain (it lists no loss) is the located error ``CONV-VERIFY`` at the first differing
source line, and nothing is written; otherwise the text is handed back to be written.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Generator, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

from cli.programs import load_tool_table
from gcode.ngc.interpreter import InterpreterOptions
from gcode.ngc.lane.fastlane import Run
from gcode.readers import read_chunks
from gcode.write.options import WriterOptions
from gcode.write.report import ConversionReport
from gcode.write.spec import Dialect
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.ir.chords import chords_equivalent
from kernel.ir.equivalence import Moves, equivalent, expanded, first_difference

#: report entries that change what the program does (the rest keep it equivalent)
LOSSES = frozenset({"dropped", "substituted"})
#: substitutions that state the same motion another way
SAME_MOTION = frozenset({"CONV-ARC-FORMAT"})
#: targets without arcs, whose writers turn them into chords, and the source size (commands)
#: from which kernel.ir.chords compares them (below it the rule alone is quick, and a small
#: conversion does not build the compiled kernel)
CHORDS = frozenset({"sandia"})
CHORDS_MIN = 4096


class Recorder:
    """The source stream, passed through unchanged while its commands are kept (a fast
    lane's run of plain lines kept as its arrays, :class:`kernel.ir.equivalence.Moves`,
    located in ``file``)."""

    def __init__(self, stream: Iterable[object], file: str) -> None:
        self.stream = stream
        self.file = file
        self.chunks: list[canon.Command | Moves] = []

    def __iter__(self) -> Iterator[object]:
        keep = self.chunks.append
        for item in self.stream:
            if isinstance(item, Run):
                keep(moves_of(item, self.file))
            else:
                keep(cast(canon.Command, item))
            yield item

    @property
    def commands(self) -> list[canon.Command]:
        """The source as command objects."""
        return list(expanded(self.chunks))


def moves_of(run: Run, file: str) -> Moves:
    """A fast lane's run as the equivalence check's arrays, copied: the lane's arrays are
    views of buffers sized for its longest run, which a kept short run would hold on to
    (a 200,000-line program's runs then held gigabytes)."""
    arc = None if run.arc is None else run.arc.copy()
    return Moves(run.kind.copy(), run.position.copy(), run.feed.copy(), run.line.copy(), file, arc)


@dataclass
class Verification:
    """What the read-back found: ``verified`` when the output is equivalent to the source;
    ``difference`` says what differs when it is not (and the report lists losses)."""

    verified: bool = False
    difference: str = ""
    compared: int = field(default=0)

    def summary(self, source: str) -> str:
        """The report's line: verified, or why not."""
        if self.verified:
            return f"{source}: verified: the output reads back as the source"
        return f"{source}: not verified (the report lists losses): {self.difference}"


def _chunks(stream: Iterable[object], file: str) -> Generator[canon.Command | Moves, None, None]:
    """The read-back's stream, its runs as :class:`Moves` not copied: the comparison
    consumes each as it comes and keeps none."""
    for item in stream:
        if isinstance(item, Run):
            yield Moves(item.kind, item.position, item.feed, item.line, file, item.arc)
        else:
            yield cast(canon.Command, item)


def _resolution(target: Dialect, decimals: int | None) -> dict[canon.Units | None, float]:
    """Half the last decimal the output writes, per length unit (how far rounding moves a
    written number)."""
    mm = target.decimals(False) if decimals is None else decimals
    inch = target.decimals(True) if decimals is None else decimals
    half = {canon.Units.MM: 0.5 * 10.0**-mm, canon.Units.INCHES: 0.5 * 10.0**-inch}
    return {**half, None: max(half.values())}


def reader_options(
    source: str, tool_table: str | None, cycle_marks: bool, keep_cutter_comp: bool
) -> InterpreterOptions:
    """The reader options the source was read with, for reading the output back."""
    table = load_tool_table(tool_table) if tool_table else None
    here = str(Path(source).resolve().parent)
    return InterpreterOptions(
        tool_table=table,
        search_path=(here,),
        cycle_marks=cycle_marks,
        keep_cutter_comp=keep_cutter_comp,
    )


def verified_output(
    chunks: Iterable[str],
    recorder: Recorder,
    target: Dialect,
    options: InterpreterOptions,
    writer: WriterOptions,
    report: ConversionReport,
    result: Verification,
) -> Iterator[str]:
    """The written text, once it reads back as the source (else ``CONV-VERIFY``).

    The text goes to a temporary file first (the readers read files); ``result`` is filled
    in before the first chunk is handed back."""
    fd, spool = tempfile.mkstemp(prefix=".cnc-verify-", suffix=".txt")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.writelines(chunks)
        _check(spool, recorder, target, options, writer, report, result)
    except BaseException:
        os.unlink(spool)
        raise
    return _replay(spool)


def _replay(spool: str) -> Iterator[str]:
    try:
        with open(spool, encoding="utf-8", newline="") as fh:
            while block := fh.read(1 << 16):
                yield block
    finally:
        os.unlink(spool)


def _check(
    spool: str,
    recorder: Recorder,
    target: Dialect,
    options: InterpreterOptions,
    writer: WriterOptions,
    report: ConversionReport,
    result: Verification,
) -> None:
    losses = [c for c in report.changes if c.kind in LOSSES and c.code not in SAME_MOTION]
    rounding = _resolution(target, writer.decimals)
    refused: list[Diagnostic] = []
    back = _until_refused(read_chunks(spool, target.name, options, arcs=True), refused)
    compared = sum(len(c.kind) if isinstance(c, Moves) else 1 for c in recorder.chunks)
    if target.name in CHORDS and compared >= CHORDS_MIN:  # arcs as chords: as arrays
        same = chords_equivalent(recorder.chunks, back, writer.tolerance, rounding)
    else:
        runs = _chunks(back, spool)
        same = equivalent(recorder.chunks, runs, rounding)
        runs.close()  # the comparison may stop reading at the first difference
    back.close()
    if same and not refused:
        result.compared = compared
        result.verified = True
        return
    # a difference, or what only the full rule compares: read back again, item by item
    source = expanded(recorder.chunks)
    refused.clear()
    again = expanded(
        _chunks(_until_refused(read_chunks(spool, target.name, options, arcs=True), refused), spool)
    )
    diff = first_difference(source, again, writer.tolerance, rounding)
    result.compared = compared
    if diff is None and not refused:
        result.verified = True
        return
    if refused and (diff is None or diff.message.startswith("the output ends")):
        # the reader stopped: the output is the source up to the command it could not read
        exc = refused[0]
        message = f"the output does not read back as {target.name} from here: {exc.message}"
    else:
        assert diff is not None
        message = f"the {target.name} output reads back differently here: {diff.message}"
    result.difference = message
    if not losses:
        where = diff.source if diff is not None else None
        raise Diagnostic("CONV-VERIFY", message, where or Location(recorder.file))


def _until_refused(
    stream: Iterable[object], refused: list[Diagnostic]
) -> Generator[object, None, None]:
    """The reader's stream up to its first error, which is kept in ``refused``."""
    try:
        yield from stream
    except Diagnostic as exc:
        refused.append(exc)
