"""Bulk writing of the fast lane's runs (gcode.write.bulk) gives the per-command text.

For every golden and corpus program, with the fast lane forced on (``LANE_MIN_BYTES`` 0,
so even small files hand runs of plain lines to the writer as arrays), the text written
from ``read_chunks`` equals the text written from the command objects, for every G-code
dialect and with numbered, length-limited and unit-converted output.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import gcode.ngc.interpreter as interp
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.ngc.lane import fastlane
from gcode.readers import read_chunks
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write, write_text
from kernel.diagnostics import Diagnostic
from tests.convert_support import in_turn, options, programs

DIALECTS = ["rs274ngc", "nist_v3", "fanuc", "grbl", "haas", "siemens840d", "fanuc_lathe", "sandia"]
_SLOW = (pytest.mark.slow,)
VARIANTS = {
    "default": WriterOptions(),
    "numbered-inch": WriterOptions(line_numbers=5, units="inch", decimals=4),
    "short-lines": WriterOptions(max_line_length=24),
}


def _text(items, dialect: str, opts: WriterOptions, source: str) -> str:  # noqa: ANN001
    """The text written, then the report: its entries, and the blocks and commands counted."""
    report = ConversionReport()
    try:
        text = "".join(write_text(items, dialect, opts, report, source=source))
        changes = [(c.code, c.message, c.pieces) for c in report.changes]
        return text + repr((changes, report.blocks, report.commands))
    except Diagnostic as exc:
        return f"refused {exc.code} {exc.location.line}"


#: (dialect, variant) pairs of the plain runs' test: every dialect once and every variant in
#: the default run (a Latin-square pick), the rest marked slow
PLAIN_CASES = in_turn(DIALECTS, VARIANTS, 3)


@pytest.mark.parametrize(("dialect", "variant"), PLAIN_CASES)
def test_bulk_runs_write_what_the_commands_write(
    dialect: str, variant: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    assert _lane_against_commands(dialect, VARIANTS[variant]) >= 200


#: (dialect, variant) pairs of the arc runs' test; the block and the Sandia writers in the
#: default run (about a second each), the rest marked slow
ARC_CASES = [
    pytest.param(
        d, v, marks=() if (d, v) in {("fanuc", "default"), ("sandia", "default")} else _SLOW
    )
    for d in DIALECTS
    for v in ("default", "numbered-inch")
]


@pytest.mark.parametrize(("dialect", "variant"), ARC_CASES)
def test_bulk_runs_with_arcs_write_what_the_commands_write(
    dialect: str, variant: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Runs read with arcs (as cnc convert reads RS274/NGC) too: their plain stretches in
    bulk, each arc through its handler, the same text and report."""
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    assert _lane_against_commands(dialect, VARIANTS[variant], arcs=True) >= 200


def _lane_against_commands(dialect: str, opts: WriterOptions, arcs: bool = False) -> int:
    """Assert that every golden and corpus program the interpreter accepts is written the
    same from its fast-lane chunks (``arcs``: read with arcs) as from its commands; returns
    how many were compared."""
    compared = lane_runs = 0
    for program in programs():
        read = options(program)
        try:
            list(interpret(program, read))
        except Diagnostic:
            continue
        chunks = list(read_chunks(program, "rs274ngc", read, arcs=arcs))
        lane_runs += sum(
            isinstance(chunk, fastlane.Run) and (not arcs or chunk.arc is not None)
            for chunk in chunks
        )
        bulk = _text(chunks, dialect, opts, "p")
        plain = _text(interpret(program, read), dialect, opts, "p")
        assert bulk == plain, program.name
        compared += 1
    assert lane_runs > 0, "the fast lane gave no run: the comparison would prove nothing"
    return compared


DIALECT_DIR = Path(__file__).parent / "dialects"


def command_streams() -> list[tuple[str, str, Path]]:
    """(reader, text, name) of every hand-derived reader program, and of every golden and
    corpus program written in Grbl by our writer (which its reader reads back)."""
    fanuc = sorted((DIALECT_DIR / "fanuc").glob("*.nc"))
    out = [("fanuc_lathe" if "_turn_" in p.name else "fanuc", p) for p in fanuc]
    out += [("siemens840d", p) for p in sorted((DIALECT_DIR / "siemens840d").glob("*.mpf"))]
    out += [("sandia", p) for p in sorted((DIALECT_DIR / "sandia").glob("*.txt"))]
    streams = [(d, p.read_text(), p) for d, p in out]
    for program in programs():
        try:
            text = "\n".join(write(interpret(program, options(program)), "grbl")) + "\n"
        except Diagnostic:
            continue
        streams.append(("grbl", text, program))
    return streams


@pytest.mark.parametrize(
    "target", ["rs274ngc", "fanuc", "fanuc_lathe", "grbl", "siemens840d", "sandia"]
)
def test_batched_command_streams_write_what_the_commands_write(
    target: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A large stream of command objects (every reader but RS274/NGC's fast lane) is
    batched into runs for the compiled formatter; with batching from the first command and
    batches cut anywhere, every reader program converts to the same text as command by
    command, refusals included."""
    import gcode.write.sandia as sandia
    from gcode.readers import read_text
    from gcode.write import bulk as emit_bulk

    compared = 0
    for dialect, text, program in command_streams():
        opts = (
            options(program)
            if program.suffix == ".ngc"
            else InterpreterOptions(search_path=(str(program.parent),))
        )
        texts = []
        for after, batch in ((10**9, 4096), (0, 3)):
            monkeypatch.setattr(emit_bulk, "COMMANDS_BEFORE_BULK", after)
            monkeypatch.setattr(sandia, "COMMANDS_BEFORE_BULK", after)
            monkeypatch.setattr(emit_bulk, "BATCH", batch)
            monkeypatch.setattr(emit_bulk, "BATCH_MIN", 1)
            try:
                ir = list(read_text(text, dialect, str(program), opts))
            except Diagnostic:
                break  # the reader refuses it (a located error program)
            texts.append(_text(iter(ir), target, WriterOptions(), "p"))
        if texts:
            assert texts[0] == texts[1], (dialect, program.name)
            compared += 1
    assert compared >= 300


@pytest.mark.parametrize("queue", [1, pytest.param(2, marks=_SLOW), 7])
def test_sandia_queues_of_any_length_write_what_the_commands_write(
    queue: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The Sandia writer queues moves (and the lines written meanwhile, such as SetSpeed)
    up to ``RUN`` at a time; wherever the queue is cut, the compiled text of the fast
    lane's runs equals the per-command text."""
    import gcode.write.sandia as sandia

    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    monkeypatch.setattr(sandia, "RUN", queue)
    assert _lane_against_commands("sandia", WriterOptions()) >= 200


def test_a_large_plain_program_goes_through_the_bulk_path(tmp_path: Path) -> None:
    """The fast lane takes a large CAM file; its runs are written in bulk, and the text is
    the per-command text (the ``-0`` rule and unchanged moves included)."""
    lines = ["G21 G90 G17", "F500", "G0 X0 Y0 Z1", "G1 Z-0.0001"]
    for i in range(60000):
        lines.append(f"X{math.sin(i / 50) * 20:.4f} Y{(i % 97) * 0.5:.4f}")
        if i % 1000 == 999:
            lines.append(f"G0 X-0.0002 Y0\nG1 X-0.0002 Y0 F{400 + i % 7}")
    lines.append("M2")
    src = tmp_path / "big.ngc"
    src.write_text("\n".join(lines) + "\n")
    assert src.stat().st_size >= interp.LANE_MIN_BYTES
    chunks = list(read_chunks(src, "rs274ngc"))
    assert any(not hasattr(c, "NAME") for c in chunks)  # fast-lane runs are there
    for dialect in ("fanuc", "grbl", "rs274ngc", "sandia"):
        bulk = _text(iter(chunks), dialect, WriterOptions(), str(src))
        plain = _text(interpret(src), dialect, WriterOptions(), str(src))
        assert bulk == plain


@pytest.mark.parametrize("places", [0, 3, 4, 5])
@pytest.mark.parametrize("point", [False, True])
def test_compiled_numbers_are_the_formatters_even_at_rounding_ties(places: int, point: bool):
    """The kernel's word values (gcode.ngc.lane.fastlane_kernels._put_num) equal Formatter.number:
    decimal ties of 4-decimal CAM input written with 3 places, exact binary ties (0.0625),
    tiny negatives that must not print -0, and random values."""
    import random

    import numpy as np

    from gcode.ngc.lane import fastlane_kernels
    from gcode.registry import get_dialect
    from gcode.write.state import Formatter

    fmt = Formatter(get_dialect("fanuc" if point else "rs274ngc"), WriterOptions(decimals=places))
    rng = random.Random(places)
    values = [0.0625, -0.0625, 0.0005, -0.0005, -0.0004, 1.0005, 12.3455, 2.5, -2.5, 1e-9]
    values += [round(rng.uniform(-900, 900), places + 1) for _ in range(20000)]
    buf = np.empty(64, dtype=np.uint8)
    for v in values:
        n, flagged = fastlane_kernels._put_num(buf, 0, v, places, point)
        assert not flagged and bytes(buf[:n]).decode() == fmt._number(v, places), v


def test_a_too_long_block_in_a_bulk_run_is_refused_at_its_own_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    lines = ["G21 G90", "F500", "G1 X1 Y1", "X2 Y2", "X123.4567 Y765.4321 Z-11.1111", "X3", "M2"]
    src = tmp_path / "long.ngc"
    src.write_text("\n".join(lines) + "\n")
    assert any(not hasattr(c, "NAME") for c in read_chunks(src, "rs274ngc"))
    with pytest.raises(Diagnostic) as err:
        "".join(write_text(read_chunks(src, "rs274ngc"), "grbl", WriterOptions(max_line_length=20)))
    assert err.value.code == "CONV-LINE-LENGTH" and err.value.location.line == 5
