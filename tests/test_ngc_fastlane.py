"""The compiled fast lane gives exactly what the general RS274/NGC semantics give.

References: Python's own ``float()`` for number parsing and ``f"{v:.4f}"`` (via
``kernel.ir.canon.write_text``) for the text form; a direct transcription of the NIST v3
rules for plain lines (F before motion, G0/G1 modal, G90/G91) as the model.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gcode.core import arcs
from gcode.ngc.lane import fastlane
from kernel.diagnostics import Location
from kernel.ir import canon

AXES = "XYZABC"


def lane(text: str, *, feed: float = 0.0, traverse: bool = True, incremental: bool = False):
    buf = np.frombuffer(text.encode(), dtype=np.uint8)
    return fastlane.scan(
        buf, 0, (0.0,) * 6, feed, incremental=incremental, traverse=traverse, first_line=1
    )


def model(lines: list[list[tuple[str, str]]], feed: float, traverse: bool, incremental: bool):
    """NIST v3 §3.8 for plain lines: feed rate first, then the motion; G0/G1 modal."""
    pos = [0.0] * 6
    out: list[str] = []
    for words in lines:
        d = {letter.upper(): text for letter, text in words}
        if "G" in d:
            traverse = float(d["G"]) == 0.0
        if "F" in d:
            feed = float(d["F"])
            out.append(canon.SetFeedRate(feed).to_text())
        moved = [a for a in AXES if a in d]
        if moved:
            assert traverse or feed > 0
            for a in moved:
                v = float(d[a].replace(" ", ""))
                pos[AXES.index(a)] = pos[AXES.index(a)] + v if incremental else v
            cls = canon.StraightTraverse if traverse else canon.StraightFeed
            out.append(cls(*pos).to_text())
    return out


NUMBER = st.builds(
    lambda sign, whole, frac: f"{sign}{whole}{'.' + frac if frac is not None else ''}",
    st.sampled_from(["", "-", "+"]),
    st.integers(0, 99999).map(str),
    st.one_of(st.none(), st.text("0123456789", min_size=0, max_size=6)),
)


def _word(letter: str, number: str) -> tuple[str, str]:
    """Make F a positive feed and G a 0 or 1, keeping the drawn number otherwise."""
    if letter.upper() == "F":
        return letter, f"{abs(float(number)) + 1:.4f}"
    if letter.upper() == "G":
        return letter, str(int(float(number)) % 2)
    return letter, number


LINE = (
    st.lists(
        st.tuples(st.sampled_from(list(AXES) + ["x", "z", "F", "G"]), NUMBER),
        min_size=0,
        max_size=5,
        unique_by=lambda w: w[0].upper(),
    )
    .map(lambda words: [_word(letter, number) for letter, number in words])
    .filter(
        # a G0/G1 needs an axis word beside it to be a plain line (see the bare-G test below)
        lambda words: (
            not any(a.upper() == "G" for a, _ in words) or any(a.upper() in AXES for a, _ in words)
        )
    )
)


@settings(max_examples=300, deadline=None)
@given(st.lists(LINE, max_size=12), st.booleans(), st.booleans())
def test_plain_lines_follow_the_rs274_rules(lines, traverse: bool, incremental: bool) -> None:
    text = "".join(" ".join(f"{a}{n}" for a, n in words) + "\n" for words in lines)
    run = lane(text, feed=100.0, traverse=traverse, incremental=incremental)
    assert run.lines == len(lines)
    assert run.consumed == len(text)
    assert [c.to_text() for c in run.commands()] == model(lines, 100.0, traverse, incremental)


@settings(max_examples=300, deadline=None)
@given(NUMBER)
def test_numbers_parse_to_the_same_double_as_float(number: str) -> None:
    run = lane(f"X{number}\n")
    if sum(ch.isdigit() for ch in number) == 0:
        assert run.lines == 0
    else:
        assert run.position[0, 0] == float(number)


def test_text_form_is_identical_to_the_ir_writer_including_ties_and_huge_values() -> None:
    rng = np.random.default_rng(5970)
    special = [5e-5, -5e-5, 1.23445, -1.23445, 0.5, -0.0, 1e12, -3e13, 0.99995, 123456.78905]
    vals = np.concatenate([rng.normal(0, 500, 6000), special, special])
    vals = np.resize(vals, (len(vals) // 6 + 1) * 6).reshape(-1, 6)
    kinds = np.resize(np.array([0, 1, 2], np.int8), len(vals))
    run = fastlane.Run(
        kinds, vals, vals[:, 0].copy(), np.arange(len(vals)), 0, 0, (0.0,) * 6, 0.0, False
    )
    expected = "".join(line + "\n" for line in canon.write_text(run.commands(), 7))
    assert fastlane.events_text(run, 7) == expected


def test_run_stops_before_lines_the_general_interpreter_must_take() -> None:
    stoppers = [
        "G2 X1 Y1 I1",  # another motion code
        "X1 (comment)",
        "X#1",
        "X[1+1]",
        "/X1",  # block delete
        "X1 X2",  # repeated letter: an error for the general path
        "X1 N5",  # N not first
        "N1.5 X1",
        "F-10",
        "F0",
        "M3",
        "X1.2.3",
        "X",
        "%",
    ]
    for bad in stoppers:
        run = lane(f"X5\n{bad}\nX6\n", feed=10.0)
        assert run.lines == 1, bad
        assert run.end_position[0] == 5.0


def test_feed_move_with_zero_feed_is_left_to_the_interpreter() -> None:
    run = lane("G0 X1\nG1 Y1\n", feed=0.0)
    assert run.lines == 1
    assert run.end_traverse is True
    run = lane("G0 X1\nG1 F50 Y1\n", feed=0.0)
    assert run.lines == 2 and run.end_feed == 50.0 and run.end_traverse is False


def test_blanks_inside_words_are_ignored_as_rs274_does() -> None:
    run = lane("x 1 . 5  y - 2\r\nN12 G 0 Z3\n", feed=1.0, traverse=False)
    assert run.lines == 2
    assert run.position[0].tolist() == [1.5, -2.0, 0.0, 0.0, 0.0, 0.0]
    assert run.kind.tolist() == [fastlane.FEED_MOVE, fastlane.TRAVERSE]


def test_g0_or_g1_without_axis_words_is_left_to_the_interpreter() -> None:
    # rs274 still moves to the current point for a bare ``G1`` (or ``G1 F100``)
    for bare in ("G1", "G1 F100", "G0", "N5 G00"):
        run = lane(f"X5\n{bare}\nX6\n", feed=10.0, traverse=False)
        assert run.lines == 1, bare


def test_r_arcs_have_the_centres_the_general_interpreter_computes_to_the_last_bit() -> None:
    """R-format arcs through the lane against gcode.core.arcs.radius_format (which uses
    math.hypot, atan2, acos, sin and cos): the same doubles, semicircles included."""
    rng = np.random.default_rng(22)
    lines, expected = [], []
    x = y = 0.0
    for k in range(3000):
        ex = round(x + float(rng.uniform(-20, 20)), 4)
        ey = round(y + float(rng.uniform(-20, 20)), 4)
        half = float(np.hypot(ex - x, ey - y)) / 2
        r = round(half * float(rng.choice([1.0, 1.0, 1.2, 3.0])) + 0.0001, 4)
        if k % 7 == 0:
            r = -r
        code = "G2" if k % 2 else "G3"
        lines.append(f"{code} X{ex:.4f} Y{ey:.4f} R{r:.4f}")
        centre = arcs.radius_format((x, y), (ex, ey), r, code == "G2", Location("t", k + 1))
        expected.append([ex, ey, *centre, -1.0 if code == "G2" else 1.0, 0.0])
        x, y = ex, ey
    buf = np.frombuffer(("\n".join(lines) + "\n").encode(), dtype=np.uint8)
    run = fastlane.scan(
        buf, 0, (0.0,) * 6, 100.0, incremental=False, traverse=False, first_line=1,
        arcs=True, arc_tolerance=(0.028, 0.002, 0.00127),
    )  # fmt: skip
    assert run.lines == len(lines)
    assert run.kind.tolist() == [fastlane.ARC] * len(lines)
    assert run.arc is not None and run.arc.tolist() == expected
