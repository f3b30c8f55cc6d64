"""The fast lane changes nothing: every program gives the same commands with it as without.

The interpreter uses the compiled lane (gcode/ngc/lane/fastlane.py via gcode/ngc/lane/lane.py)
only for files of ``LANE_MIN_BYTES`` and more; here it is forced on for every golden and
corpus program, whose outputs must be identical, command for command and source line for
source line, to the general path's. The bench's CAM program exercises long runs.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import gcode.ngc.interpreter as interp
from gcode.core.program import ProgramFile
from gcode.ngc.interpreter import InterpreterOptions, interpret
from gcode.ngc.lane.lane import Lane
from kernel.diagnostics import Diagnostic
from kernel.tooltable import read_tool_table

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent / "bench"))
from cam_program import write_program  # noqa: E402

from tests.data_paths import CORPUS_NGC  # noqa: E402

GOLDEN = ROOT / "golden" / "ngc"
CORPUS = CORPUS_NGC
PROGRAMS = sorted(GOLDEN.glob("*.ngc")) + sorted(CORPUS.glob("*.ngc"))
TOOLS = read_tool_table((GOLDEN / "sim.tbl").read_text().splitlines(), "sim.tbl")


def run(path: Path, lane: bool) -> tuple[list[tuple[str, int]], str | None]:
    options = InterpreterOptions(
        tool_table=TOOLS, search_path=(str(GOLDEN / "subs"),), fast_lane=lane
    )
    out: list[tuple[str, int]] = []
    try:
        for cmd in interpret(path, options):
            out.append((cmd.to_text(), cmd.source.line if cmd.source else 0))
    except Diagnostic as exc:
        return out, str(exc)
    return out, None


@pytest.fixture
def lane_always(monkeypatch: pytest.MonkeyPatch) -> list[Lane | None]:
    """The lane forced on for every file; returns the lanes the interpreter opened, so a test
    can tell that the compiled lane really ran (an equivalence with no lane proves nothing)."""
    monkeypatch.setattr(interp, "LANE_MIN_BYTES", 0)
    opened: list[Lane | None] = []
    for_file = Lane.for_file

    def spy(pf: ProgramFile) -> Lane | None:
        lane = for_file(pf)
        opened.append(lane)
        return lane

    monkeypatch.setattr(Lane, "for_file", staticmethod(spy))
    return opened


def assert_lane_ran(opened: list[Lane | None]) -> None:
    assert opened, "the interpreter never asked for the fast lane"
    assert all(lane is not None for lane in opened), "the compiled kernels did not load"


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_lane_output_is_identical_to_the_general_path(
    program: Path, lane_always: list[Lane | None]
) -> None:
    fast = run(program, lane=True)
    assert_lane_ran(lane_always)
    assert fast == run(program, lane=False)


def test_lane_on_a_cam_program_is_identical(tmp_path: Path, lane_always: list[Lane | None]) -> None:
    prog = write_program(tmp_path / "cam.ngc", 20_000)
    fast, err_fast = run(prog, lane=True)
    assert_lane_ran(lane_always)
    slow, err_slow = run(prog, lane=False)
    assert err_fast is None and err_slow is None
    assert len(fast) > 19_000
    assert fast == slow
