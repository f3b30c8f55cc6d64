"""``cnc convert --to sandia``'s check: the compiled read-back lane (gcode/sandia/lane.py)
reads as the general Sandia reader, and the chord comparison as arrays (kernel/ir/chords.py)
decides as ``first_difference`` does (issue 15).

* Lane: the lane forced on for every file (it normally starts at ``LANE_MIN_BYTES``), what
  it gives must be, command for command and source line for source line, what the general
  reader gives (the same commands, or the same error at the same place): every hand-derived
  Sandia program, every golden and corpus program written in Sandia (``slow``; a sample in
  the default run), a CAM-shaped program's chords, and random streams of MoveTo, SetSpeed
  and rapid lines with malformed ones among them (hypothesis).
* Chords: ``chords_equivalent`` says True only where ``first_difference`` finds nothing,
  and says it for the lossless conversions (it would be useless always saying False); a
  chord moved off its arc beyond the tolerance is found by ``cnc convert`` at the arc's
  source line.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cli.convert
import cli.verify
import gcode.sandia.reader as sandia_reader
from cli.verify import _chunks, _resolution
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.readers import read_chunks
from gcode.registry import get_dialect
from gcode.sandia import lane as sandia_lane
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon, chords
from kernel.ir.chords import chords_equivalent
from kernel.ir.equivalence import first_difference
from tests.convert_support import ir_of, options, programs
from tests.lane_support import general, through_lanes

HERE = Path(__file__).resolve().parent
SUITE = sorted((HERE / "dialects" / "sandia").glob("*.txt"))
PROGRAMS = programs()
#: the default run's sample of the corpus (every program with ``-m slow``)
SAMPLE = {p for i, p in enumerate(PROGRAMS) if i % 12 == 0}


@pytest.fixture
def lane_always(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    """The lane forced on for every file; counts the lines its runs took."""
    monkeypatch.setattr(sandia_reader, "LANE_MIN_BYTES", 0)
    seen = {"lines": 0}
    scan = sandia_lane.scan

    def spy(*args: Any, **kwargs: Any) -> Any:
        run, speed = scan(*args, **kwargs)
        seen["lines"] += run.lines
        return run, speed

    monkeypatch.setattr(sandia_lane, "scan", spy)
    return seen


def _ir(program: Path) -> tuple[canon.Command, ...] | None:
    """The program's IR: the corpus' with its tool table, a test's own with the defaults."""
    if program in PROGRAMS:
        return ir_of(program)
    return tuple(interpret(program))


def _options(program: Path) -> InterpreterOptions:
    return options(program) if program in PROGRAMS else InterpreterOptions()


def _sandia(program: Path, tmp_path: Path) -> Path | None:
    """The program written in Sandia (None where the interpreter or the writer refuses)."""
    ir = _ir(program)
    if ir is None:
        return None
    try:
        lines = list(write(ir, "sandia", WriterOptions(), ConversionReport()))
    except Diagnostic:
        return None
    path = tmp_path / f"{program.stem}.txt"
    path.write_text("".join(f"{line}\n" for line in lines))
    return path


@pytest.mark.parametrize("program", SUITE, ids=lambda p: p.stem)
def test_the_lane_reads_the_hand_derived_programs_as_the_general_reader(
    program: Path, lane_always: dict[str, int]
) -> None:
    opts = InterpreterOptions()
    assert through_lanes(program, "sandia", opts) == general(program, "sandia", opts)


@pytest.mark.parametrize(
    "program",
    [pytest.param(p, marks=() if p in SAMPLE else (pytest.mark.slow,)) for p in PROGRAMS],
    ids=lambda p: p.stem,
)
def test_the_lane_reads_every_converted_program_as_the_general_reader(
    program: Path, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    path = _sandia(program, tmp_path)
    if path is None:
        pytest.skip("the interpreter or the Sandia writer refuses this program")
    opts = options(program)
    assert through_lanes(path, "sandia", opts) == general(path, "sandia", opts)


def cam_program(lines: int, inch: bool) -> str:
    """A CAM-shaped RS274/NGC program: G1 zig-zags, R and IJ arcs, feed changes, a helix."""
    out = [f"{'G20' if inch else 'G21'} G17 G90 G94", "F600", "G0 X0 Y0 Z1", "G1 Z-0.5"]
    x = 0.0
    for i in range(lines):
        if i % 7 == 3:
            r = 2.0 + (i % 5) * 0.1
            out.append(f"G{2 + i % 2} X{x + 2 * r:.4f} R{r:.4f}")
            x += 2 * r
        elif i % 7 == 5:
            out.append(f"G{3 - i % 2} X{x + 3.0:.4f} Z-0.{i % 3 + 4} I1.5 J0")
            x += 3.0
        else:
            nx, ny = 1.0 + 0.25 * math.sin(i), 10.0 * math.sin(i * 0.05)
            out.append(f"G1 X{x + nx:.4f} Y{ny:.4f}" + (" F450" if i % 50 == 0 else ""))
            x += nx
    out += ["G0 Z5", "M2"]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("inch", [False, True], ids=["mm", "inch"])
def test_the_lane_takes_the_chords_of_a_cam_program(
    inch: bool, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    src = tmp_path / "cam.ngc"
    src.write_text(cam_program(300, inch))
    path = _sandia(src, tmp_path)
    assert path is not None
    opts = InterpreterOptions()
    lanes = through_lanes(path, "sandia", opts)
    assert lanes == general(path, "sandia", opts) and lanes[1] is None
    total = path.read_text().count("\n")
    assert lane_always["lines"] >= total - 12  # all but the units, tool and comment lines


_NUMBERS = st.one_of(
    st.floats(-1e4, 1e4, allow_nan=False).map(lambda v: f"{v:.4f}"),
    st.integers(-999, 999).map(str),
    st.sampled_from(
        ["1.", ".5", "-.25", "+3", "-0", "-0.0", "0", "", ".", "+", "1e3", "1..2", "0x1", "--1"]
    ),
    st.sampled_from(["12345678901234567", "1234567890123456.5", "0.0000000000000001"]),
)
_KEYS = st.sampled_from(["X", "Y", "Z", "X", "Y", "A", "x", "XY", "", "speed", "attributes"])
_BLANK = st.sampled_from([" ", " ", "  ", "\t", " \x0b"])


@st.composite
def _line(draw: st.DrawFn) -> str:
    kind = draw(st.integers(0, 9))
    if kind <= 4:
        words = draw(st.lists(st.tuples(_KEYS, _NUMBERS), max_size=4))
        name = "MoveTo" if kind < 4 else "point_to_point_positioning"
        parts = [name] + [f"{k}={v}" for k, v in words]
        if kind == 4 and draw(st.booleans()):
            parts.append(
                draw(
                    st.sampled_from(
                        [
                            "attributes=ABSOLUTE|CS_CURRENT",
                            "attributes=RELATIVE|CS_CURRENT",
                            "attributes=0",
                            "attributes=CS_G54",
                        ]
                    )
                )
            )
        text = draw(_BLANK).join(parts)
    elif kind <= 6:
        value = draw(_NUMBERS)
        text = draw(st.sampled_from(["SetSpeed {}", "SetSpeed speed={}", "SetSpeed {} 2"]))
        text = text.format(value)
    else:
        text = draw(
            st.sampled_from(
                [
                    "",
                    "   ",
                    "# a comment",
                    "MoveTo X=1 # trailing",
                    "  MoveTo X=2",
                    "SetUnits linear=inch",
                    "SetUnits linear=mm",
                    "GetTool 2",
                    "Deactivate",
                    "moveto X=1",
                    "MoveTo\tY=3",
                    "SetSpeed",
                    "MoveTo X=1 Y=2 Z=3 ",
                    "MoveTo X=1\x0cY=2",
                ]
            )
        )
    return text


def _same_reading(lines: list[str], speed: bool, end: bool, tmp_path: Path) -> None:
    """Plain and malformed lines: the same commands, or the same error at the same line and
    column with the same code and message."""
    head = ["SetSpeed 100.0"] if speed else []
    path = tmp_path / "random.txt"
    path.write_text("\n".join(head + lines) + ("\n" if end else ""))
    opts = InterpreterOptions()
    assert through_lanes(path, "sandia", opts) == general(path, "sandia", opts)


_STREAMS = {
    "lines": st.lists(_line(), min_size=1, max_size=30),
    "speed": st.booleans(),
    "end": st.booleans(),
}
_FIXTURE = [HealthCheck.function_scoped_fixture]


@settings(max_examples=40, deadline=None, suppress_health_check=_FIXTURE)
@given(**_STREAMS)
def test_random_streams_read_as_the_general_reader(
    lines: list[str], speed: bool, end: bool, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    _same_reading(lines, speed, end, tmp_path)


@pytest.mark.slow
@settings(max_examples=2000, deadline=None, suppress_health_check=_FIXTURE)
@given(**_STREAMS)
def test_many_random_streams_read_as_the_general_reader(
    lines: list[str], speed: bool, end: bool, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    _same_reading(lines, speed, end, tmp_path)


# ---------------------------------------------------------------- the chord comparison


def _both_rules(program: Path, tmp_path: Path) -> tuple[bool, bool] | None:
    """(chords_equivalent, first_difference found nothing) for the program's Sandia
    output read back through the lane, as cnc convert compares them."""
    ir = _ir(program)
    path = _sandia(program, tmp_path)
    if ir is None or path is None:
        return None
    opts = _options(program)
    try:
        back = list(_chunks(read_chunks(path, "sandia", opts, arcs=True), str(path)))
    except Diagnostic:
        return None
    tolerance = WriterOptions().tolerance
    rounding = _resolution(get_dialect("sandia"), None)
    fast = chords_equivalent(list(ir), back, tolerance, rounding)
    again = list(sandia_reader.interpret(path, opts))
    return fast, first_difference(ir, again, tolerance, rounding) is None


@pytest.mark.parametrize(
    "program",
    [pytest.param(p, marks=() if p in SAMPLE else (pytest.mark.slow,)) for p in PROGRAMS],
    ids=lambda p: p.stem,
)
def test_chords_equivalent_never_says_more_than_first_difference(
    program: Path, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    both = _both_rules(program, tmp_path)
    if both is None:
        pytest.skip("refused by the interpreter, the writer or the reader")
    fast, rule = both
    assert not fast or rule


@pytest.mark.parametrize("inch", [False, True], ids=["mm", "inch"])
def test_chords_equivalent_verifies_a_lossless_cam_program(
    inch: bool, tmp_path: Path, lane_always: dict[str, int]
) -> None:
    src = tmp_path / "cam.ngc"
    src.write_text(cam_program(300, inch))
    assert _both_rules(src, tmp_path) == (True, True)


def _moved(text: str, line: int, dx: float) -> str:
    """The text with the X of MoveTo line ``line`` (1-based) moved by ``dx``."""
    lines = text.split("\n")
    words = lines[line - 1].split(" ")
    for k, word in enumerate(words):
        if word.startswith("X="):
            words[k] = f"X={float(word[2:]) + dx:.4f}"
    lines[line - 1] = " ".join(words)
    return "\n".join(lines)


@pytest.mark.parametrize(("dx", "caught"), [(0.0005, False), (0.003, True)])
def test_a_chord_moved_off_its_arc_is_caught_at_the_arc_line(
    dx: float, caught: bool, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A chord point moved by more than the tolerance (0.001 mm) fails the check at the
    source line of its arc; moved by less, it passes (the tolerance is the rule's)."""
    monkeypatch.setattr(sandia_reader, "LANE_MIN_BYTES", 0)
    monkeypatch.setattr(cli.verify, "CHORDS_MIN", 0)
    spied = {"calls": 0}

    def spy(*args: Any, **kwargs: Any) -> bool:
        spied["calls"] += 1
        return chords_equivalent(*args, **kwargs)

    monkeypatch.setattr(cli.verify, "chords_equivalent", spy)
    src = tmp_path / "p.ngc"
    src.write_text("G21 G90 G17\nF100\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X10\nG2 X20 Y0 R5\nG1 X30\nM2\n")
    out = tmp_path / "p.txt"
    real = cli.convert.write_text

    def corrupted(*args: Any, **kwargs: Any) -> Iterator[str]:
        text = "".join(real(*args, **kwargs))
        lines = text.split("\n")
        arc = [i for i, t in enumerate(lines) if t.startswith("MoveTo X=1") and "Y=" in t]
        assert len(arc) > 40  # the arc's chords (X from 10 to 20)
        yield _moved(text, arc[20] + 1, dx)  # a chord half way round

    monkeypatch.setattr(cli.convert, "write_text", corrupted)
    result = CliRunner().invoke(cli.convert.command, [str(src), "--to", "sandia", "-o", str(out)])
    assert spied["calls"] == 1
    if caught:
        assert result.exit_code == 1
        assert "p.ngc:6:1: error[CONV-VERIFY]" in result.output
        assert "ends off the curve" in result.output
        assert not out.exists()
    else:
        assert result.exit_code == 0, result.output
        assert "p.ngc: verified" in result.output


@pytest.mark.slow
def test_the_jit_kernels_decide_as_the_compiled_ones(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, lane_always: dict[str, int]
) -> None:
    """Without a C compiler the kernels run through numba's JIT: the same reading and the
    same verdicts (a lossless program, and one with a chord moved off its arc)."""
    src = tmp_path / "cam.ngc"
    src.write_text(cam_program(200, False))
    path = _sandia(src, tmp_path)
    assert path is not None
    opts = InterpreterOptions()
    compiled = through_lanes(path, "sandia", opts), _both_rules(src, tmp_path)
    monkeypatch.setattr(sandia_lane.KERNELS, "_loaded", sandia_lane.KERNELS.load_jit())
    monkeypatch.setattr(chords.KERNELS, "_loaded", chords.KERNELS.load_jit())
    assert (through_lanes(path, "sandia", opts), _both_rules(src, tmp_path)) == compiled
    assert compiled[1] == (True, True)
