"""``cnc convert``'s read-back through the fast lanes changes nothing (issue 15).

The check reads its output back with the target's reader in runs of arrays
(``gcode.readers.read_chunks(..., arcs=True)``): the RS274/NGC lane with arcs for
rs274ngc, Grbl and NIST v3, the Fanuc lane (gcode/fanuc/lane.py) for the Fanuc and Haas
mills, and the 840D lane (gcode/siemens/lane.py; its own tests:
tests/test_readback_siemens_lane.py). Here the lanes are forced on for every file (they
normally start at ``LANE_MIN_BYTES``), and what they give must be, command for command and
source line for source line, what the general path of the same reader gives:

* every hand-derived Fanuc program and real Fanuc/Haas shop program, read both ways
  (the same commands, or the same error at the same place);
* every golden and corpus program converted to each lane's dialect and read back both ways
  (``slow``: hundreds of conversions), and a CAM-shaped program in every unit and distance
  mode in the default run;
* a corrupted output read back through the lanes still fails the check at its source line.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

import cli.convert
import gcode.fanuc.flow as fanuc_flow
import gcode.ngc.interpreter as ngc_interpreter
import gcode.siemens.reader as siemens_reader
from cli.verify import _chunks, _resolution
from gcode.fanuc.lane import FanucLane
from gcode.ngc.interpreter import InterpreterOptions
from gcode.readers import read, read_chunks
from gcode.registry import get_dialect
from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.ir.equivalence import Moves, equivalent, first_difference
from tests.convert_support import ir_of, options, programs
from tests.lane_support import general, listing, spy_lane, through_lanes

HERE = Path(__file__).resolve().parent
FANUC_SUITE = sorted((HERE / "dialects" / "fanuc").glob("*.nc"))
SHOP = [(p, "fanuc") for p in sorted((HERE / "realworld" / "shop" / "fanuc").glob("*.nc"))] + [
    (p, "haas") for p in sorted((HERE / "realworld" / "shop" / "haas").glob("*.nc"))
]
#: the dialects whose read-back goes through a lane, with the arc format the round-trip
#: suites write them in
LANE_TARGETS = [
    ("rs274ngc", "ijk"),
    ("rs274ngc", "r"),
    ("grbl", "ijk"),
    ("nist_v3", "r"),
    ("fanuc", "ijk"),
    ("fanuc", "r"),
    ("haas", "r"),
    ("mach3", "ijk"),
    ("siemens840d", "ijk"),
]


@pytest.fixture
def lanes_always(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    """Every lane forced on for every file; counts the Fanuc lanes opened and the lines
    their runs took, so a test can tell the compiled lane really ran."""
    monkeypatch.setattr(ngc_interpreter, "LANE_MIN_BYTES", 0)
    monkeypatch.setattr(fanuc_flow, "LANE_MIN_BYTES", 0)
    monkeypatch.setattr(siemens_reader, "LANE_MIN_BYTES", 0)
    return spy_lane(monkeypatch, FanucLane, "for_source")


def _fanuc_mode(program: Path) -> str | None:
    name = program.name
    if "lathe" in name or "turn" in name:
        return None  # the lathe reader has no lane
    return "fanuc"


@pytest.mark.parametrize("program", FANUC_SUITE, ids=lambda p: p.stem)
def test_fanuc_lane_reads_the_hand_derived_programs_as_the_general_path(
    program: Path, lanes_always: dict[str, int]
) -> None:
    dialect = _fanuc_mode(program)
    if dialect is None or "book" in program.name:
        pytest.skip("a lathe or polar-convention program: read by another flavour")
    opts = InterpreterOptions(search_path=(str(program.parent),))
    assert through_lanes(program, dialect, opts) == general(program, dialect, opts)
    assert lanes_always["opened"] == 1


@pytest.mark.parametrize(("program", "dialect"), SHOP, ids=lambda p: getattr(p, "stem", p))
def test_fanuc_lane_reads_the_shop_programs_as_the_general_path(
    program: Path, dialect: str, lanes_always: dict[str, int]
) -> None:
    opts = InterpreterOptions(search_path=(str(program.parent),))
    assert through_lanes(program, dialect, opts) == general(program, dialect, opts)
    # the commands interface of the reader takes the same lane
    assert listing(read(program, dialect, opts)) == general(program, dialect, opts)


@pytest.mark.parametrize(
    "program", sorted((HERE / "dialects" / "mach3").glob("*.tap")), ids=lambda p: p.stem
)
def test_mach3_lane_reads_the_hand_derived_programs_as_the_general_path(
    program: Path, lanes_always: dict[str, int]
) -> None:
    """Scaling (G51) keeps the lane aside; the rest reads as the general path does."""
    opts = InterpreterOptions(search_path=(str(program.parent),))
    assert through_lanes(program, "mach3", opts) == general(program, "mach3", opts)


def cam_program(lines: int, inch: bool, incremental: bool) -> str:
    """A CAM-shaped RS274/NGC program: G1 zig-zags, R and IJ arcs, feed changes."""
    out = [f"{'G20' if inch else 'G21'} G17 G90 G94", "F600 S8000 M3", "G0 X0 Y0 Z1", "G1 Z-0.5"]
    if incremental:
        out.append("G91")
    x = y = 0.0
    for i in range(lines):
        if i % 7 == 3:
            r = 2.0 + (i % 5) * 0.1
            nx = 2 * r if incremental else x + 2 * r
            out.append(f"G{2 + i % 2} X{nx:.4f} R{r:.4f}")
            x += 2 * r
        elif i % 7 == 5:
            nx = 3.0 if incremental else x + 3.0
            out.append(f"G{3 - i % 2} X{nx:.4f} I1.5 J0")
            x += 3.0
        else:
            nx, ny = 1.0 + 0.25 * math.sin(i), 10.0 * math.sin(i * 0.05)
            step = (nx, ny - y) if incremental else (x + nx, ny)
            out.append(f"G1 X{step[0]:.4f} Y{step[1]:.4f}" + (" F450" if i % 50 == 0 else ""))
            x, y = x + nx, ny
    out += ["G90 G0 Z5", "M2"]
    return "\n".join(out) + "\n"


def converted(ir: Any, dialect: str, arc_format: str) -> str | None:
    """The program written in ``dialect`` (None where the writer refuses it)."""
    try:
        lines = write(ir, dialect, WriterOptions(arc_format=arc_format), ConversionReport())
        return "".join(f"{line}\n" for line in lines)
    except Diagnostic:
        return None


def check_readback(ir: Any, text: str, dialect: str, path: Path, opts: InterpreterOptions) -> None:
    """The lanes' read-back of ``text`` is the general path's, and the array comparison
    says equivalent only where the item-by-item rule does."""
    path.write_text(text)
    lanes = through_lanes(path, dialect, opts)
    assert lanes == general(path, dialect, opts)
    if lanes[1] is None:
        rounding = _resolution(get_dialect(dialect), None)
        back = list(read_chunks(path, dialect, opts, arcs=True))
        fast = equivalent(ir, _chunks(back, str(path)), rounding)
        full = list(read(path, dialect, replace(opts, fast_lane=False)))
        if fast:
            assert first_difference(ir, full, WriterOptions().tolerance, rounding) is None


@pytest.mark.parametrize(("dialect", "arc_format"), LANE_TARGETS)
@pytest.mark.parametrize(("inch", "incremental"), [(False, False), (True, False), (False, True)])
def test_lanes_read_back_a_cam_program_as_the_general_path(
    tmp_path: Path,
    lanes_always: dict[str, int],
    dialect: str,
    arc_format: str,
    inch: bool,
    incremental: bool,
) -> None:
    source = tmp_path / "cam.ngc"
    source.write_text(cam_program(300, inch, incremental))
    opts = InterpreterOptions(search_path=(str(tmp_path),))
    ir = list(ngc_interpreter.interpret(source, replace(opts, fast_lane=False)))
    text = converted(ir, dialect, arc_format)
    assert text is not None
    check_readback(ir, text, dialect, tmp_path / "out.txt", opts)
    runs = [c for c in read_chunks(tmp_path / "out.txt", dialect, opts, arcs=True)]
    moves = [len(c.kind) for c in _chunks(runs, "out") if isinstance(c, Moves)]
    assert sum(moves) > 250, "the lane took (nearly) every line, arcs included"
    if dialect in ("fanuc", "haas"):
        assert lanes_always["lines"] > 250


@pytest.mark.slow
@pytest.mark.parametrize(("dialect", "arc_format"), LANE_TARGETS)
@pytest.mark.parametrize("program", programs(), ids=lambda p: p.stem)
def test_lanes_read_back_every_golden_conversion_as_the_general_path(
    tmp_path: Path, lanes_always: dict[str, int], program: Path, dialect: str, arc_format: str
) -> None:
    ir = ir_of(program)
    if ir is None:
        pytest.skip("the interpreter rejects this program")
    text = converted(ir, dialect, arc_format)
    if text is None:
        pytest.skip("the writer refuses this program")
    check_readback(ir, text, dialect, tmp_path / f"out{program.suffix}", options(program))


def corrupt(monkeypatch: pytest.MonkeyPatch, line: int, old: str, new: str) -> None:
    """Make the writer's ``line``-th output line (1-based) read ``new`` for ``old``."""
    real = cli.convert.write_text

    def broken(*args: Any, **kwargs: Any) -> Iterator[str]:
        text = "".join(real(*args, **kwargs)).splitlines()
        assert old in text[line - 1], text[line - 1]
        text[line - 1] = text[line - 1].replace(old, new)
        yield "".join(f"{t}\n" for t in text)

    monkeypatch.setattr(cli.convert, "write_text", broken)


@pytest.mark.parametrize(
    ("old", "new", "what"),
    [
        ("X", "X1", "STRAIGHT_FEED argument 1"),
        ("I1.5", "I1.6", "arc radius 1.6000 but end point is 1.4000 from the centre"),
        ("G03", "G02", "of this ARC_FEED leaves the curve"),
    ],
    ids=["coordinate", "arc-centre", "arc-direction"],
)
def test_a_corrupted_output_read_through_the_lanes_fails_at_its_source_line(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    lanes_always: dict[str, int],
    old: str,
    new: str,
    what: str,
) -> None:
    src = tmp_path / "cam.ngc"
    src.write_text(cam_program(300, False, False))
    out = tmp_path / "cam.nc"
    clean = CliRunner().invoke(cli.convert.command, [str(src), "--to", "fanuc", "-o", str(out)])
    assert clean.exit_code == 0, clean.output
    written = out.read_text().splitlines()
    out.unlink()
    # a line in the middle of the program holding ``old``, and the source line it came from
    at = next(i for i in range(len(written) // 2, len(written)) if old in written[i]) + 1
    corrupt(monkeypatch, at, old, new)
    result = CliRunner().invoke(cli.convert.command, [str(src), "--to", "fanuc", "-o", str(out)])
    assert result.exit_code == 1
    assert "error[CONV-VERIFY]" in result.output and what in result.output
    assert not out.exists()
    assert lanes_always["lines"] > 250  # the read-back went through the lane


def test_an_arc_the_other_way_round_is_a_difference() -> None:
    """G02 for G03 between the same points about the same centre ends on the source arc, and
    is still another path: the middle of an arc piece must lie on the source curve too."""
    start = [canon.UseLengthUnits(canon.Units.MM), canon.SetFeedRate(100.0)]
    start.append(canon.StraightFeed(0.0, 0.0, 0.0))
    half = canon.ArcFeed(10.0, 0.0, 5.0, 0.0, 1, 0.0, 0.0, 0.0, 0.0)
    other_way = canon.ArcFeed(10.0, 0.0, 5.0, 0.0, -1, 0.0, 0.0, 0.0, 0.0)
    diff = first_difference([*start, half], [*start, other_way], 0.001)
    assert diff is not None and "leaves the curve at (5.0000, 5.0000" in diff.message
    assert first_difference([*start, half], [*start, half], 0.001) is None
