"""Behaviour of the RS274/NGC interpreter beyond the golden files: API contract (streaming,
sources, options), rules with hand-computed expectations, and robustness (hypothesis)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gcode.core.linuxcnc import SetG5xOffset
from gcode.ngc.interpreter import InterpreterOptions, interpret, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table

GOLDEN = Path(__file__).parent / "golden" / "ngc"
TOOLS = read_tool_table((GOLDEN / "sim.tbl").read_text().splitlines())


def motions(text: str, **kw: object) -> list[canon.Command]:
    opts = InterpreterOptions(tool_table=TOOLS, **kw)  # type: ignore[arg-type]
    return [c for c in interpret_text(text, "t.ngc", opts) if isinstance(c, canon.MOTIONS)]


def error(text: str) -> Diagnostic:
    with pytest.raises(Diagnostic) as info:
        list(interpret_text(text, "t.ngc", InterpreterOptions(tool_table=TOOLS)))
    return info.value


# ------------------------------------------------------------------ API contract
def test_commands_carry_their_source_line_and_column() -> None:
    cmds = list(interpret_text("G21\n  G0 X1\nM2\n", "p.ngc"))
    move = next(c for c in cmds if isinstance(c, canon.StraightTraverse))
    assert (move.source.file, move.source.line, move.source.column) == ("p.ngc", 2, 3)


def test_interpretation_streams_commands_before_a_later_error() -> None:
    body = "".join(f"G1 X{i} F100\n" for i in range(1, 2001))
    gen = interpret_text("G21\n" + body + "G1 X[1/0]\nM2\n")
    first = [next(gen) for _ in range(20)]  # produced without reading to the error
    assert any(isinstance(c, canon.StraightFeed) for c in first)
    rest = []
    with pytest.raises(Diagnostic) as info:
        for c in gen:
            rest.append(c)
    assert info.value.code == "NGC-DIVIDE-BY-ZERO"
    assert info.value.location.line == 2002
    assert sum(isinstance(c, canon.StraightFeed) for c in first + rest) == 2000


def test_nist_mode_gives_origin_offsets_and_no_linuxcnc_commands() -> None:
    text = "G21\nG10 L2 P1 X5\nG92 X1\nG0 X0\nM2\n"
    cmds = list(interpret_text(text, options=InterpreterOptions(linuxcnc_compat=False)))
    names = {c.NAME for c in cmds}
    assert not names & canon.LINUXCNC_ONLY
    origins = [c for c in cmds if isinstance(c, canon.SetOriginOffsets)]
    # G92 X1 at program X-5 (machine 0): G92 offset -6, so the origin is 5 - 6 = -1
    assert origins[-2].x == pytest.approx(-1.0)
    compat = list(interpret_text(text))
    assert any(isinstance(c, SetG5xOffset) for c in compat)


def test_a_var_file_sets_the_starting_work_offset_in_inches() -> None:
    # rs274 keeps stored offsets in inches: #5221 = 1 is 25.4 mm in a G21 program
    # (checked with rs274 -v): the machine starts at its origin, program X -25.4
    got = motions("G21\nG0 Y1\nM2\n", parameters={5221: 1.0})
    assert (got[0].x, got[0].y) == pytest.approx((-25.4, 1.0))


def test_file_api_and_subroutine_search_path(tmp_path: Path) -> None:
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "dbl.ngc").write_text("o<dbl> sub\nG0 X[#1*2]\no<dbl> endsub\nM2\n")
    prog = tmp_path / "main.ngc"
    prog.write_text("G21\no<dbl> call [3]\nM2\n")
    opts = InterpreterOptions(search_path=(str(tmp_path / "subs"),))
    xs = [c.x for c in interpret(prog, opts) if isinstance(c, canon.StraightTraverse)]
    assert xs == [6.0]


def test_fast_lane_gives_the_same_commands_as_the_general_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import gcode.ngc.interpreter as interpreter

    monkeypatch.setattr(interpreter, "LANE_MIN_BYTES", 0)
    from gcode.ngc.lane import lane

    monkeypatch.setattr(lane.Lane, "WINDOW", 2048)  # many window refills
    cam = "".join(f"X{i * 0.5:.3f} Y{(i % 7) * 1.25:.3f} Z-1\n" for i in range(300))
    text = (
        "%\nG21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F300\n"
        + cam
        + "G1\nF500\n"
        + cam
        + "G3 X159.5 Y6.25 I5 J0\nG1\nG91\nX1 Y1\nG0 X-1\nG90 G1 F200\n"
        + cam
        + "G94\nX3\n"
        + cam
        + "M2\n%\n"
    )
    prog = tmp_path / "cam.ngc"
    prog.write_text(text)

    def run(lane: bool) -> tuple[list[tuple[str, int]], str]:
        got: list[tuple[str, int]] = []
        try:
            for c in interpret(prog, InterpreterOptions(fast_lane=lane)):
                got.append((c.to_text(), c.source.line))
        except Diagnostic as exc:  # G94 zeroes the feed: X3 stops both at line 914
            return got, str(exc)
        return got, ""

    fast, slow = run(True), run(False)
    assert fast == slow
    assert "NGC-ZERO-FEED" in fast[1] and ":914:" in fast[1]
    # the lane really ran
    runs = []
    with pytest.raises(Diagnostic):
        for item in interpreter.interpret_chunks(prog, InterpreterOptions()):
            runs.append(item)
    assert any(not isinstance(r, canon.Command) for r in runs)


# ------------------------------------------------------------------ semantics
def test_numbered_assignments_take_effect_after_the_line_is_read() -> None:
    got = motions("G21\n#1=5\n#1=2 G0 X#1\nG0 X#1 #1=7 Y#1\nM2\n")
    assert [(m.x, m.y) for m in got] == [(5.0, 0.0), (2.0, 2.0)]


def test_o_word_loops_and_subroutine_return_value() -> None:
    text = (
        "G21\no<sq> sub\no<sq> return [#1*#1]\no<sq> endsub\n"
        "#1=0\no1 while [#1 LT 3]\no<sq> call [#1]\nG0 X#<_value>\n#1=[#1+1]\no1 endwhile\nM2\n"
    )
    assert [m.x for m in motions(text)] == [0.0, 1.0, 4.0]


def test_radius_format_arc_centre_is_on_the_chord_bisector() -> None:
    # quarter circle R10 from (10,0) to (0,10) counterclockwise: centre at the origin
    (arc,) = [m for m in motions("G21 F10\nG0 X10 Y0\nG3 X0 Y10 R10\nM2\n") if m.NAME == "ARC_FEED"]
    assert (arc.first_axis, arc.second_axis, arc.rotation) == pytest.approx((0.0, 0.0, 1))


def test_xz_plane_arc_puts_z_first() -> None:
    got = motions("G21 F10 G18\nG0 X0 Z0\nG2 X10 Z10 I5 K5\nM2\n")
    arc = got[-1]
    # NISTIR 5970 §3.6.1: in the XZ plane the first axis is Z and the second X
    assert (arc.first_end, arc.second_end, arc.first_axis, arc.second_axis) == (10, 10, 5, 5)


def test_inverse_time_feed_is_length_times_f() -> None:
    got = list(interpret_text("G21 G93\nG1 X3 Y4 F2\nM2\n"))
    rates = [c.rate for c in got if isinstance(c, canon.SetFeedRate)]
    assert 10.0 in rates  # length 5 at F2 (1/2 minute): 10 mm/min


def test_probe_continues_from_the_backed_off_point() -> None:
    got = motions("G21 F10\nG38.2 X10 Y10\nG1 Z1\nM2\n")
    back = 0.254 / math.sqrt(2)  # rs274's canon backs the probe off 0.254 mm
    assert (got[-1].x, got[-1].y) == pytest.approx((10 - back, 10 - back))


def test_g83_pecks_retract_to_r_and_return_above_the_last_depth() -> None:
    got = motions("G21 F100\nG0 Z10\nG99 G83 X0 Y0 Z-3 R1 Q1.5\nM2\n")
    zs = [round(m.z, 4) for m in got]
    assert zs == [10.0, 10.0, 1.0, -0.5, 1.0, -0.246, -2.0, 1.0, -1.746, -3.0, 1.0]


def test_g99_block_after_g98_moves_in_the_plane_above_r_first() -> None:
    """rs274's CYCLE_MACRO (interp_internal.hh): a block's first hole starts at the current
    height when that is above R, then goes down to R; LinuxCNC's recording of
    tests/data/lcnc_tp own_drill_rapids runs that move as a pure Y rapid (50 mm/s)."""
    got = motions("G21 F100\nG0 Z5\nG98 G81 X0 Y0 Z-2 R1\nG99 G81 Y7 Z-2 R0.5\nM2\n")
    pts = [(m.y, m.z) for m in got[-4:]]
    assert pts == [(7.0, 5.0), (7.0, 0.5), (7.0, -2.0), (7.0, 0.5)]


def test_g28_goes_through_the_given_point_to_the_stored_home() -> None:
    got = motions("G21\nG0 X4 Y5 Z6\nG28.1\nG0 X0 Y0 Z0\nG28 Z1\nM2\n")
    assert [(m.x, m.y, m.z) for m in got[-2:]] == [(0, 0, 1), (0, 0, 6)]


# ------------------------------------------------------------------ diagnostics
@pytest.mark.parametrize(
    ("text", "code", "line", "column"),
    [
        ("G21\nG1 X1 G0 Y1\nM2\n", "NGC-G-GROUP-CONFLICT", 2, 7),
        ("G21\nG0 X1 X2\nM2\n", "NGC-DUPLICATE-WORD", 2, 7),
        ("G21\nG0 X#<nope>\nM2\n", "NGC-NAMED-UNDEFINED", 2, 4),
        ("G21 F10\nG2 X10 Y0 I3\nM2\n", "NGC-ARC-RADIUS", 2, 1),
        ("G21 F10\nG0 X1\nG2 X1 Y0 R2\nM2\n", "NGC-ARC-R-SAME-POINT", 3, 1),
        ("G21\nG1 X1\nM2\n", "NGC-ZERO-FEED", 2, 1),
        ("G21\no9 endif\nM2\n", "NGC-OWORD-UNEXPECTED", 2, 1),
        ("G21\nG0 X1\n", "NGC-NO-END", 2, 1),
        ("G21\nG0 P1 X1\nM2\n", "NGC-P-UNUSED", 2, 4),
        ("G21\nG5.3\nM2\n", "NGC-NURBS-POINTS", 2, 1),
    ],
)
def test_errors_have_stable_codes_and_locations(
    text: str, code: str, line: int, column: int
) -> None:
    diag = error(text)
    assert (diag.code, diag.location.line, diag.location.column) == (code, line, column)


# ------------------------------------------------------------------ robustness
_PROGRAMS = sorted(GOLDEN.glob("*.ngc"))
_CHARS = "GXYZIJKRPQFSMT0123456789.-+[]#<>=/()*; \nOo"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    index=st.integers(0, len(_PROGRAMS) - 1),
    cuts=st.lists(
        st.tuples(st.integers(0, 2000), st.integers(0, 6), st.text(_CHARS, max_size=6)), max_size=4
    ),
)
def test_mutated_programs_give_commands_or_a_diagnostic(
    index: int, cuts: list[tuple[int, int, str]]
) -> None:
    text = _PROGRAMS[index].read_text()
    for at, length, insert in cuts:
        at %= len(text) + 1
        text = text[:at] + insert + text[at + length :]
    try:
        for _ in interpret_text(text, "m.ngc", InterpreterOptions(tool_table=TOOLS)):
            pass
    except Diagnostic as diag:
        assert diag.code.startswith(("NGC-", "IO-"))


def test_a_user_m_code_is_an_unknown_m_code_before_its_words_are_checked() -> None:
    """rs274 2.9 says "Unknown m code used: M100" for a user M code without a program file,
    even with P and Q words (which it would pass to that program)."""
    diag = error("G20\nM100 P1 Q2\nM2\n")
    assert diag.code == "NGC-USER-M" and diag.location.line == 2
    assert "unknown M code used: M100" in diag.message
