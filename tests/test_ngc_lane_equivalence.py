"""The fast lane changes nothing: every program gives the same commands with it as without.

The interpreter uses the compiled lane (gcode/ngc/lane/fastlane.py via gcode/ngc/lane/lane.py)
only for files of ``LANE_MIN_BYTES`` and more; here it is forced on for every golden and
corpus program, whose outputs must be identical, command for command and source line for
source line, to the general path's. The bench's CAM program exercises long runs.
"""

from __future__ import annotations

import math
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

    def spy(pf: ProgramFile, arcs: bool = False) -> Lane | None:
        lane = for_file(pf, arcs)
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


def _arc_program(plane: str, units: str, distance: str, centres: str, n: int) -> str:
    """Arcs among lines in one plane: in centre format half circles (explicit and modal
    G2/G3), helices, arcs on the edge of LinuxCNC's radius tolerance; in radius format
    quarter, three-quarter (negative R) and half circles; a bare G1, feed changes and rotary
    words; the last arc is just outside the tolerance (an error at its line)."""
    first, second, i, j = {
        "G17": ("X", "Y", "I", "J"),
        "G18": ("Z", "X", "K", "I"),
        "G19": ("Y", "Z", "J", "K"),
    }[plane]
    # LinuxCNC's default CENTER_ARC_RADIUS_TOLERANCE (inch, mm): 2 * 0.001 * sqrt(2) in
    tol = (0.002 if units == "G20" else 0.02) * math.sqrt(2)
    lines = [f"{units} {plane} {distance} {centres} G94 G40", "G0 X1 Y1 Z1", "G1 F300"]
    pos = {"X": 1.0, "Y": 1.0, "Z": 1.0}
    inc = distance == "G91"
    for k in range(n):
        r = 0.5 + (k % 7) * 0.125
        edge = (0.0, 0.0, tol / 2 * 0.9999, 0.0005 * r, 0.0004 * r)[k % 5]
        if k == n - 1:
            edge = max(tol / 2 * 1.001, 0.00051 * r)
        a0, b0 = pos[first], pos[second]
        if k % 8 == 7 and k != n - 1:
            shape = (k // 8) % 3
            da, db, radius = (2 * r, 0.0, r) if shape == 2 else (r, r, r if shape else -r)
            ea, eb = (da, db) if inc else (a0 + da, b0 + db)
            code = "G2" if (k // 8) % 2 else "G3"
            lines.append(f"{code} {first}{ea:.4f} {second}{eb:.4f} R{radius:.4f}")
            pos[first], pos[second] = a0 + da, b0 + db
            continue
        a1 = a0 + 2 * r
        ca, cb = (r + edge, 0.0) if centres == "G91.1" else (a0 + r + edge, b0)
        end = f"{first}{2 * r if inc else a1:.4f}"
        centre = f"{i}{ca:.7f} {j}{cb:.7f}"
        code = ("G2", "G3", "")[k % 3]
        helix = " " + ("XYZ".replace(first, "").replace(second, "")) + "-0.01" if k % 4 == 0 else ""
        if inc and helix:
            helix = helix.replace("-0.01", "0")
        lines.append(f"{code} {end} {centre}{helix} A{k % 3}".strip())
        pos[first] = a1
        if k % 3 == 1:
            continue  # the next arc is modal: no line between
        if k % 6 == 5:
            lines.append("G1")
        step = 0.25 if inc else pos[second] + 0.25
        lines.append(f"G1 {second}{step:.4f}" + (" F250" if k % 11 == 0 else ""))
        pos[second] += 0.25
    lines.append("M2")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    ("plane", "units", "distance", "centres"),
    [
        ("G17", "G21", "G90", "G91.1"),
        ("G17", "G20", "G91", "G91.1"),
        ("G18", "G21", "G90", "G90.1"),
        ("G19", "G20", "G90", "G91.1"),
        ("G17", "G21", "G90", "G90.1"),
    ],
)
def test_lane_arcs_are_identical_to_the_general_path(
    tmp_path: Path,
    lane_always: list[Lane | None],
    plane: str,
    units: str,
    distance: str,
    centres: str,
) -> None:
    prog = tmp_path / "arcs.ngc"
    prog.write_text(_arc_program(plane, units, distance, centres, 300))
    fast = run(prog, lane=True)
    assert_lane_ran(lane_always)
    slow = run(prog, lane=False)
    assert fast == slow
    assert sum(text.startswith("ARC_FEED") for text, _ in slow[0]) > 250
    assert slow[1] is not None and "NGC-ARC-RADIUS" in slow[1]


def test_lane_arc_after_g40_is_refused_and_after_a_line_allowed_as_rs274_does(
    tmp_path: Path, lane_always: list[Lane | None]
) -> None:
    head = "G21 G17 G90 F100\nT1 M6\nG0 X-20 Y-20\nG41 D1 G1 X0 Y0\nG1 X10\nG40\n"
    refused = tmp_path / "refused.ngc"
    refused.write_text(head + "G2 X12 Y0 I1 J0\nM2\n")
    fast = run(refused, lane=True)
    assert_lane_ran(lane_always)
    assert fast == run(refused, lane=False)
    assert fast[1] is not None and "NGC-COMP-ARC-AFTER-G40" in fast[1]
    allowed = tmp_path / "allowed.ngc"
    # lines the lane takes (past its back-off after the G40), then an arc
    lines = "".join(f"G1 X{11 + k}\n" for k in range(12))
    allowed.write_text(head + lines + "G2 X24 Y0 I1 J0\nM2\n")
    fast = run(allowed, lane=True)
    assert fast == run(allowed, lane=False)
    assert fast[1] is None and any(text.startswith("ARC_FEED") for text, _ in fast[0])


def test_lane_takes_lines_ending_in_several_carriage_returns(
    tmp_path: Path, lane_always: list[Lane | None], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Windows CAM output may end its lines in CR CR LF (PyCAM's on Windows does): the general
    path strips every CR before the LF, and so does the lane, which used to stop at such a
    line and leave the whole program to the general path."""
    taken: list[int] = []
    take = Lane.take

    def counting(self: Lane, ctx: interp.NgcContext) -> object:
        run = take(self, ctx)
        if run is not None:
            taken.append(run.lines)
        return run

    monkeypatch.setattr(Lane, "take", counting)
    body = "".join(f"X{k * 0.5:.4f} Y{(k % 7) * 0.25:.4f}\r\r\n" for k in range(200))
    prog = tmp_path / "crcrlf.ngc"
    prog.write_bytes(("G21 G90 G17\r\r\nG1 F300\r\n" + body + "M2\r\r\n").encode())
    fast = run(prog, lane=True)
    assert_lane_ran(lane_always)
    assert sum(taken) >= 190
    assert fast == run(prog, lane=False)
    assert fast[1] is None and len(fast[0]) > 200


def test_the_lane_is_loaded_only_for_large_programs_of_lines_it_takes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Loading the lane (numpy, the kernels) costs as much CPU as it saves on about
    ``LANE_LOAD_COST`` plain lines: a program of half as many (though over
    ``LANE_MIN_BYTES``), or a large one whose head is macro code the lane takes none of,
    runs on the general path alone; a program of twice as many opens the lane."""
    opened: list[str] = []
    for_file = Lane.for_file

    def spy(pf: ProgramFile, arcs: bool = False) -> Lane | None:
        opened.append(Path(pf.path).name)
        return for_file(pf, arcs)

    monkeypatch.setattr(Lane, "for_file", staticmethod(spy))
    n = int(interp.LANE_LOAD_COST)

    def cam(lines: int) -> str:
        return "".join(f"G1 X{k * 0.01:.4f} Y{k % 50 * 0.1:.4f} F300\n" for k in range(lines))

    macro = "#1 = 0\n" + "".join(f"#1 = [#1 + {k % 3}]\nG1 X[#1 / 100] F300\n" for k in range(n))
    for name, text in (("few.ngc", cam(n // 2)), ("cam.ngc", cam(2 * n)), ("macro.ngc", macro)):
        (tmp_path / name).write_text("G21 G90\n" + text + "M2\n")
        run(tmp_path / name, lane=True)
    assert (tmp_path / "few.ngc").stat().st_size >= interp.LANE_MIN_BYTES
    assert (tmp_path / "macro.ngc").stat().st_size >= interp.LANE_MIN_BYTES
    assert opened == ["cam.ngc"]
    # the same lines under cutter compensation, which the lane never takes
    comp = tmp_path / "comp.ngc"
    comp.write_text("G21 G90 G40\nG0 X-5 Y-5\nG42 D1 G1 X0 Y0 F300\n" + cam(2 * n) + "G40\nM2\n")
    assert interp._lane_pays(str(tmp_path / "cam.ngc"))
    assert not interp._lane_pays(str(comp))
