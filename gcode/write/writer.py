"""Writer: canonical commands (kernel.ir.canon IR) -> G-code text in a chosen dialect.

:func:`write` is a generator of lines (streaming, bounded memory). It keeps the machine
state the IR sets (units, plane, feed, spindle, coolant, modes) and writes a modal word
only when the emitted state differs, just before the next motion or event that needs it
(modal-minimal emission, research/seed-sandia-full.md §5.1). Positions are written in
absolute program coordinates (G90), as the IR holds them.

A construct the dialect lacks is expanded (multi-turn arcs into full circles),
approximated within ``tolerance`` (NURBS and ellipses by arcs or lines, see
:mod:`gcode.write.approximate`), substituted or dropped, each recorded in the
:class:`~gcode.write.report.ConversionReport`; with ``on_missing="refuse"`` the writer
raises a located ``CONV-*`` :class:`~kernel.diagnostics.Diagnostic` instead.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from gcode.core.cycle_marks import CycleEnd
from gcode.ngc.lane.fastlane import Run
from gcode.registry import get_dialect
from gcode.write import bulk as emit_bulk
from gcode.write.bulk import can_take, run_of, write_run
from gcode.write.context import WriterContext
from gcode.write.options import ARC_FORMATS, CYCLE_MODES, WriterOptions
from gcode.write.report import ConversionReport, loss_code, machinist
from gcode.write.sandia import SandiaWriter
from gcode.write.spec import Dialect
from gcode.write.table import BY_NAME as _BY_NAME
from gcode.write.table import HANDLERS as _HANDLERS
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

__all__ = ["ARC_FORMATS", "CYCLE_MODES", "BlockWriter", "WriterOptions", "write", "write_text"]

_PLAIN_MOTIONS = frozenset({canon.StraightFeed, canon.StraightTraverse, canon.ArcFeed})


def write(
    commands: Iterable[canon.Command],
    dialect: str | Dialect,
    options: WriterOptions | None = None,
    report: ConversionReport | None = None,
) -> Iterator[str]:
    """Yield the program text, one block per line (no line terminators)."""
    return _writer(dialect, options, report).run(commands)


def write_text(
    commands: Iterable[canon.Command],
    dialect: str | Dialect,
    options: WriterOptions | None = None,
    report: ConversionReport | None = None,
    batch: int = 4096,
    source: str | None = None,
) -> Iterator[str]:
    """The program text as chunks of whole lines, each line ending with a newline: what a
    file or a pipe wants (one write per line costs as much as formatting a Sandia line);
    still streamed, ``batch`` lines at a time."""
    writer = _writer(dialect, options, report)
    writer.file = source
    if isinstance(writer, BlockWriter):
        yield from writer.run_text(commands, batch)
    else:
        yield from writer.run_text(commands)  # Sandia: its chords are joined per run


def _writer(
    dialect: str | Dialect, options: WriterOptions | None, report: ConversionReport | None
) -> BlockWriter | SandiaWriter:
    """The writer for the dialect's structure, after checking the options."""
    d = get_dialect(dialect) if isinstance(dialect, str) else dialect
    opts = options or WriterOptions()
    if opts.arc_format not in ARC_FORMATS:
        raise Diagnostic("CONV-OPTION", f"arc format {opts.arc_format!r}: use {ARC_FORMATS}")
    if opts.on_missing not in ("approximate", "refuse") or opts.tolerance <= 0:
        raise Diagnostic("CONV-OPTION", "on_missing is approximate or refuse; tolerance > 0")
    if opts.cycles not in CYCLE_MODES:
        raise Diagnostic("CONV-OPTION", f"cycles {opts.cycles!r}: use {CYCLE_MODES}")
    if d.structure == "commands":
        return SandiaWriter(d, opts, report or ConversionReport())
    return BlockWriter(d, opts, report or ConversionReport())


class BlockWriter(WriterContext):
    """The state machine behind :func:`write` for block-structured (RS274-like) dialects."""

    def run(self, commands: Iterable[canon.Command]) -> Iterator[str]:
        """The program, a line at a time. ``commands`` may hold the interpreter's runs of
        plain lines (:class:`gcode.ngc.lane.fastlane.Run`, from ``interpret_chunks``): those are
        written in bulk where :mod:`gcode.write.bulk` can, else command by command."""
        for lines in self.run_lines(commands):
            for line in lines:
                if "\n" in line:  # a bulk run's blocks (gcode.write.bulk)
                    yield from line.split("\n")
                else:
                    yield line

    def run_text(self, commands: Iterable[canon.Command], batch: int = 4096) -> Iterator[str]:
        """The program as text chunks of whole lines, each ending with a newline, about
        ``batch`` lines a chunk (what a file wants: no generator step per line)."""
        pending: list[str] = []
        for lines in self.run_lines(commands):
            pending.extend(lines)
            if len(pending) >= batch:
                pending.append("")
                yield "\n".join(pending)
                pending.clear()
        if pending:
            pending.append("")
            yield "\n".join(pending)

    def run_lines(self, commands: Iterable[canon.Command]) -> Iterator[list[str]]:
        """The blocks of each command or run, as lists (emptied after each step); an entry
        holds several blocks, joined by newlines, where a run was written in bulk."""
        yield list(self.d.header if self.o.header is None else self.o.header)
        plain: list[canon.Command] = []  # plain moves of a large command stream, batched
        report, kinds = self.report, emit_bulk.KIND
        after, batch = emit_bulk.COMMANDS_BEFORE_BULK, emit_bulk.BATCH
        for item in commands:
            batched = type(item) in kinds and report.commands >= after
            if batched:
                plain.append(item)
                if len(plain) < batch:
                    continue
            if plain:
                self.commands_in_bulk(plain)
                plain.clear()
            if isinstance(item, Run):
                self.bulk(item, None)
            elif not batched:
                self.command(item)
            if self.out:
                yield self.out
                self.out.clear()
        if plain:
            self.commands_in_bulk(plain)
        yield [*self.out, *(self.d.footer if self.o.footer is None else self.o.footer)]
        self.out.clear()

    def commands_in_bulk(self, plain: list[canon.Command]) -> None:
        """Plain moves and feed rates of a command stream written as one run (compiled, as
        the fast lane's runs are), else command by command."""
        if len(plain) < emit_bulk.BATCH_MIN or (run := run_of(plain, self.feed)) is None:
            for cmd in plain:
                self.command(cmd)
        else:
            self.bulk(run, plain)

    def bulk(self, run: Run, commands: list[canon.Command] | None) -> None:
        """A run (a fast-lane run of ``self.file``, or made of ``commands``) written by
        :mod:`gcode.write.bulk` where it can take it exactly, else command by command; a
        run with arcs (read with ``arcs``) as its stretches of plain events in bulk and
        each arc through its handler."""
        if run.arc is not None and commands is None:
            if can_take(self, run) and write_run(self, run, self.file, None):
                return
            for part in emit_bulk.stretches(run, self.file):
                if isinstance(part, Run):
                    self.bulk(part, None)
                else:
                    self.command(part)
            return
        if not (can_take(self, run) and write_run(self, run, self.file, commands)):
            for cmd in commands if commands is not None else run.commands(self.file):
                self.command(cmd)

    def command(self, cmd: canon.Command) -> None:
        """One canonical command through its handler (its blocks land in ``self.out``)."""
        self.report.commands += 1
        self.src = cmd.source
        if self.ended:
            return  # LinuxCNC prints M2's resets after it: nothing more to write
        if self.skipping and type(cmd) is not CycleEnd:
            return  # a kept cycle's own moves: the target expands the block itself
        if self.pending_select is not None and not isinstance(
            cmd, canon.ChangeTool | canon.Comment | canon.StartChange | canon.StopSpindleTurning
        ):  # T alone only when no change follows (M6 is SELECT, START_CHANGE, ...)
            self.block(f"T{self.pending_select}")
            self.pending_select = None
        if type(cmd) not in _PLAIN_MOTIONS:
            self.dirty = True  # it may set state that the next flush must write
        handler = _HANDLERS.get(type(cmd)) or _BY_NAME.get(cmd.NAME)
        if handler is None:
            self.lacking(loss_code(cmd.NAME), f"equivalent of {machinist(cmd.NAME)}")
        else:
            handler(self, cmd)
