"""``cnc canon PROG``: the canonical machining commands of a G-code or STEP-NC program.

Prints (or writes with ``-o``) the canonical text form, one command per line as LinuxCNC's
``rs274`` prints it, or JSON lines. A program error prints as a compiler diagnostic after
the commands before it were written, and exits 1 (``cli.errors``).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any, TextIO

import click

from cli.errors import guarded
from cli.options import (
    force_option,
    machine_option,
    output_option,
    program_argument,
    tool_table_option,
    tool_units_option,
)
from cli.outputs import open_output, refuse_output
from cli.programs import (
    detect_kind,
    dialect_option,
    inch_tool_table,
    is_stdin,
    load_machine,
    load_tool_table,
    profile_tools,
    program_dialect,
    read_head,
    regular_input,
    stdin_text,
    tool_table_units,
)
from gcode.core.loopguard import MAX_BLOCKS
from gcode.core.params import read_var_text
from gcode.ngc.interpreter import InterpreterOptions, interpret_chunks
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.tooltable import ToolTable

_BATCH = 4096
_WRITE_CHARS = 1 << 18  # text is written in blocks of about this size (fewer, larger writes)
_MOVE = "%5d N..... %s(%.4f, %.4f, %.4f, %.4f, %.4f, %.4f)"
#: a move without rotary axes (most): three numbers fewer to format; -0.0 prints 0.0000 too
_MOVE_XYZ = "%5d N..... %s(%.4f, %.4f, %.4f, 0.0000, 0.0000, 0.0000)"
_RATE = "%5d N..... SET_FEED_RATE(%.4f)"


class _Numbers(dict[float, str]):
    """Numbers as the text form prints them (four decimals, ``-0.0000`` as ``0.0000``),
    kept: a program's coordinates repeat (depths, grids, contours cut again one level
    lower), and a look-up costs less than formatting. Bounded: cleared at 65,536 numbers."""

    def __missing__(self, value: float) -> str:
        if len(self) >= 65536:
            self.clear()
        text = f"{value:.4f}"
        if text == "-0.0000":
            text = "0.0000"
        self[value] = text
        return text


_ARC = "%5d N..... ARC_FEED(%.4f, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f)"
_FLOATS = {float}
INCH = 25.4  # mm: the unit rs274 reads a tool table in, canon's default (--tool-units)


def _options(
    tools: ToolTable | None,
    params: str | None,
    search: tuple[str, ...],
    nist: bool,
    max_blocks: int = MAX_BLOCKS,
) -> InterpreterOptions:
    values = None
    if params is not None:
        regular_input(params, "parameter file")
        values = read_var_text(Path(params).read_text().splitlines(), params)
    return InterpreterOptions(
        tool_table=tools,
        parameters=values,
        search_path=search,
        linuxcnc_compat=not nist,
        max_blocks=max_blocks,
    )


def _f(v: float, digits: int = 4) -> str:
    s = f"{v:.{digits}f}"
    return s[1:] if s.startswith("-") and not s.strip("-0.") else s


#: rs274's own spelling of the commands whose NISTIR form differs (spindle index 0 first)
_LINUXCNC_FORMS: dict[str, Callable[[Any], str]] = {
    "SET_SPINDLE_SPEED": lambda c: f"SET_SPINDLE_SPEED(0, {_f(c.speed)})",
    "START_SPINDLE_CLOCKWISE": lambda c: "START_SPINDLE_CLOCKWISE(0)",
    "START_SPINDLE_COUNTERCLOCKWISE": lambda c: "START_SPINDLE_COUNTERCLOCKWISE(0)",
    "STOP_SPINDLE_TURNING": lambda c: "STOP_SPINDLE_TURNING(0)",
    "DISABLE_SPEED_OVERRIDE": lambda c: "DISABLE_SPEED_OVERRIDE(0)",
    "ENABLE_SPEED_OVERRIDE": lambda c: "ENABLE_SPEED_OVERRIDE(0)",
    "SET_FEED_MODE": lambda c: (
        f"SET_FEED_MODE(0, {0 if c.mode.value == 1 else c.mode.value - 1})"
        if c.mode.value
        else "SET_FEED_MODE(0, 0)"
    ),
    "SET_SPINDLE_MODE": lambda c: f"SET_SPINDLE_MODE(0 {_f(c.css_max)})",
    "START_SPEED_FEED_SYNCH": lambda c: (
        f"START_SPEED_FEED_SYNC({_f(c.feed_per_revolution, 6)},{int(c.velocity_mode)})"
    ),
    "SET_MOTION_CONTROL_MODE": lambda c: (
        f"SET_MOTION_CONTROL_MODE({c.mode.value}, {_f(c.tolerance, 6)})"
        if c.mode is canon.MotionMode.CONTINUOUS
        else f"SET_MOTION_CONTROL_MODE({c.mode.value})"
    ),
    "ORIENT_SPINDLE": lambda c: (
        f"ORIENT_SPINDLE(0, {_f(c.orientation)}, "
        f"{2 if c.direction is canon.Direction.COUNTERCLOCKWISE else 1})"
    ),
}


_NUMBERS = _Numbers()


def _arc_text(n: int, c: canon.ArcFeed) -> str | None:
    """``ARC_FEED`` formatted inline, or None unless its numbers are floats and its turn
    count an int (the generic writer prints an int without decimals)."""
    v = (c.first_end, c.second_end, c.first_axis, c.second_axis, c.axis_end_point, c.a, c.b, c.c)
    if type(c.rotation) is not int or {type(x) for x in v} != _FLOATS:
        return None
    return _ARC % (n, *v[:4], c.rotation, *v[4:])


def fast_text(
    commands: Iterable[canon.Command], start: int = 1, linuxcnc: bool = False
) -> Iterator[str]:
    """:func:`kernel.ir.canon.write_text` with the commonest commands formatted inline.

    CAM programs are mostly ``STRAIGHT_FEED`` lines and arcs; formatting them with one
    %-format instead of the generic per-field path triples the writer's speed. Same text;
    with ``linuxcnc`` the commands rs274 spells differently (spindle index, feed mode)
    print as rs274 prints them.
    """
    n = start
    feed, trav, rate = canon.StraightFeed, canon.StraightTraverse, canon.SetFeedRate
    arc = canon.ArcFeed
    forms = _LINUXCNC_FORMS if linuxcnc else {}
    nums = _NUMBERS
    for cmd in commands:
        if type(cmd) is feed or type(cmd) is trav:  # exact types: a subclass prints its own
            a, b, c = cmd.a, cmd.b, cmd.c
            if a == 0.0 and b == 0.0 and c == 0.0 and type(a) is type(b) is type(c) is float:
                x, y, z = cmd.x, cmd.y, cmd.z
                if type(x) is type(y) is type(z) is float:
                    yield (
                        f"{n:5d} N..... {cmd.NAME}({nums[x]}, {nums[y]}, {nums[z]}, "
                        "0.0000, 0.0000, 0.0000)"
                    )
                    n += 1
                    continue
                s = _MOVE_XYZ % (n, cmd.NAME, x, y, z)
            else:
                s = _MOVE % (n, cmd.NAME, cmd.x, cmd.y, cmd.z, a, b, c)
        elif type(cmd) is rate:
            s = _RATE % (n, cmd.rate)
        else:
            text = _arc_text(n, cmd) if type(cmd) is arc else None
            if text is None:
                form = forms.get(cmd.NAME)
                yield f"{n:5d} N..... {form(cmd) if form else cmd.to_text()}"
                n += 1
                continue
            s = text
        yield s.replace("-0.0000", "0.0000") if "-0.0000" in s else s
        n += 1


def _commands(chunks: Iterable[object], path: str) -> Iterator[canon.Command]:
    """The commands of a chunk stream (``interpret_chunks``): commands as they come, and
    the fast lane's runs of plain lines, which only large programs have, expanded."""
    for item in chunks:
        if isinstance(item, canon.Command):
            yield item
        else:
            from gcode.ngc.lane.fastlane import Run

            assert isinstance(item, Run), item
            yield from item.commands(path)


def _text_blocks(chunks: Iterable[object], linuxcnc: bool) -> Iterator[str]:
    """Canonical text in blocks: runs of the compiled fast lane formatted by it, the
    other commands by :func:`fast_text` (sequence numbers continue across both)."""
    n = 1
    pending: list[canon.Command] = []
    try:
        for item in chunks:
            if isinstance(item, canon.Command):
                pending.append(item)
                if len(pending) >= _BATCH:
                    yield "".join(line + "\n" for line in fast_text(pending, n, linuxcnc))
                    n += len(pending)
                    pending.clear()
                continue
            from gcode.ngc.lane import fastlane

            if pending:
                yield "".join(line + "\n" for line in fast_text(pending, n, linuxcnc))
                n += len(pending)
                pending.clear()
            assert isinstance(item, fastlane.Run), item
            yield fastlane.events_text(item, n)
            n += len(item)
    except Exception:
        # a program error: what came before it is written first (rs274 streams too)
        if pending:
            yield "".join(line + "\n" for line in fast_text(pending, n, linuxcnc))
        raise
    if pending:
        yield "".join(line + "\n" for line in fast_text(pending, n, linuxcnc))


def file_chunks(program: str, language: str, options: InterpreterOptions) -> Iterator[object]:
    """What ``cnc canon`` reads from a G-code file in ``language``: RS274/NGC as commands and
    the compiled fast lane's runs (arcs included), formatted in bulk by :func:`_text_blocks`;
    another dialect as its reader's commands (bench/convert_bench.py times this very path)."""
    if language != "rs274ngc":
        from gcode.readers import read

        return iter(read(program, language, options))
    return interpret_chunks(program, options, arcs=True)


def _write(chunks: Iterator[object], path: str, fmt: str, linuxcnc: bool, out: TextIO) -> None:
    try:
        if fmt == "jsonl":
            batch: list[str] = []
            for line in canon.to_jsonl(_commands(chunks, path)):
                batch.append(line)
                if len(batch) >= _BATCH:
                    out.write("\n".join(batch) + "\n")
                    batch.clear()
            if batch:
                out.write("\n".join(batch) + "\n")
        else:
            blocks: list[str] = []
            size = 0
            try:
                for text in _text_blocks(chunks, linuxcnc):
                    blocks.append(text)
                    size += len(text)
                    if size >= _WRITE_CHARS:
                        data = "".join(blocks)
                        blocks.clear()
                        size = 0
                        out.write(data)
            finally:  # what came before a program error is written too
                if blocks:
                    data = "".join(blocks)
                    blocks.clear()
                    out.write(data)
    finally:
        out.flush()


@click.command(name="canon")
@program_argument()
@machine_option(
    help="Machine profile (TOML): its [tools] table and units when -t is not given, and a "
    "lathe's dialect wins a close --dialect auto call."
)
@tool_table_option(
    help="Tool table: LinuxCNC .tbl or NIST tool file (a STEP-NC program's tools).",
    must_exist=False,
)
@tool_units_option(default="inch, as rs274 reads it")
@click.option(
    "--params",
    type=click.Path(dir_okay=False),
    help="Parameter file (.var) with the starting values of #1..#5602.",
)
@click.option(
    "-I",
    "--subroutine-path",
    "search",
    multiple=True,
    type=click.Path(file_okay=False),
    help="Directory searched for o<name> call, M98 and CALL sub-program files (repeatable; "
    "default: the program's own directory). Names never reach outside these directories.",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "jsonl"]),
    default="text",
    show_default=True,
    help="Canonical text (as rs274 prints it) or JSON lines.",
)
@click.option(
    "--nist",
    is_flag=True,
    help="Only NISTIR 5970 commands (no LinuxCNC-only SET_G5X_OFFSET, ON_RESET, ...).",
)
@output_option()
@force_option(help="Overwrite an existing output file.")
@click.option(
    "--max-blocks",
    type=click.IntRange(min=1),
    default=MAX_BLOCKS,
    show_default=True,
    help="Stop with LOOP-LIMIT after this many G-code blocks executed (endless loops).",
)
@dialect_option
@guarded
def command(
    program: str,
    machine_path: str | None,
    tool_table: str | None,
    tool_units: str | None,
    params: str | None,
    search: tuple[str, ...],
    fmt: str,
    nist: bool,
    output: str | None,
    force: bool,
    max_blocks: int,
    dialect: str,
) -> None:
    """Interpret PROGRAM into canonical machining commands (NISTIR 5970).

    PROGRAM is G-code (RS274/NGC as LinuxCNC reads it, or the --dialect given) or an
    ISO 14649 STEP-NC Part 21 file, told apart by content. Output is the canonical text as
    LinuxCNC's rs274 prints it, or JSON lines.

    \b
    Examples:
      cnc canon part.ngc
      cnc canon part.ngc -t sim.tbl -o part.canon
      cnc canon ex1.stp -t iso14649.tool_ex1
      cnc canon part.ngc --format jsonl | head
      cnc canon O1234.nc -d fanuc
      generate.py | cnc canon -
    """
    regular_input(program)
    if not is_stdin(program) and not os.path.isfile(program):
        raise Diagnostic("IO-OPEN", "cannot open program: no such file", Location(program))
    machine = load_machine(machine_path) if machine_path else None
    units = INCH
    if machine is not None and machine_path is not None:
        listed, units = profile_tools(machine, machine_path)
        tool_table = tool_table or listed
    if output is not None:
        refuse_output(output, force, (program, tool_table or "", params or ""))
    chunks: Iterator[object]
    # the subroutine search path (LinuxCNC's SUBROUTINE_PATH): the -I directories, or the
    # program's own directory when none is given
    dirs = search or (str(Path(program).resolve().parent),)
    stepnc = detect_kind(read_head(program)) == "part21"
    linuxcnc = not nist and not stepnc  # STEP-NC prints as NIST's ISO 14649 interpreter
    if stepnc:
        # ISO 14649 STEP-NC (content, not the extension, decides); --tool-table names the
        # NIST ISO 14649 tool file, and the workplan runs in NIST-compatible mode
        from stepnc.model import load_text
        from stepnc.to_canon import canon_from_file, canon_from_model
        from stepnc.tooling import load_tool_file

        if tool_table:
            regular_input(tool_table, "tool file")
        if is_stdin(program):
            tools = load_tool_file(tool_table) if tool_table else None
            chunks = iter(canon_from_model(load_text(stdin_text(), program), tools, "nist"))
        else:
            chunks = iter(canon_from_file(program, tool_file=tool_table, mode="nist"))
    else:
        table = None
        if tool_table is not None:
            table = load_tool_table(tool_table)
            table = inch_tool_table(table, tool_table_units(tool_table, tool_units, units))
        options = _options(table, params, dirs, nist, max_blocks)
        lathe = machine is not None and machine.kind == "lathe"
        language = program_dialect(program, dialect, lathe=lathe)
        if is_stdin(program):
            from gcode.readers import read_text

            chunks = iter(read_text(stdin_text(), language, program, options))
        else:
            chunks = file_chunks(program, language, options)
    if output is None:
        try:
            _write(chunks, program, fmt, linuxcnc, sys.stdout)
        except BrokenPipeError:  # e.g. piped into `head`: stop quietly
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        return
    with open_output(output) as fh:
        _write(chunks, program, fmt, linuxcnc, fh)
