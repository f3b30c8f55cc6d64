"""Malformed input never produces a traceback (issue 2).

Hypothesis feeds random text, random word soups and mutations of the golden programs to
the interpreter; each run must either finish or raise the project's one diagnostic type
(:class:`kernel.diagnostics.Diagnostic`) with a code and a location inside the program.
"""

from __future__ import annotations

import string
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gcode.ngc.interpreter import InterpreterOptions, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.tooltable import read_tool_table

GOLDEN = Path(__file__).parent / "golden" / "ngc"
PROGRAMS = [p.read_text() for p in sorted(GOLDEN.glob("*.ngc")) if "_subfile" not in p.name]
TOOLS = read_tool_table((GOLDEN / "sim.tbl").read_text().splitlines(), "sim.tbl")
OPTIONS = InterpreterOptions(tool_table=TOOLS)
MAX_COMMANDS = 20_000  # a mutated loop may never end; stop reading it after this many

LETTERS = "GMXYZABCIJKRFSTPQDHLNOUVW#[]<>()/;%.=-+*" + string.digits
WORDS = st.builds(
    lambda letter, value: f"{letter}{value}",
    st.sampled_from("GMXYZABCIJKFSTPQDHLR"),
    st.one_of(
        st.integers(-200, 200).map(str),
        st.floats(-1e4, 1e4, allow_nan=False).map(lambda v: f"{v:.4f}"),
        st.sampled_from(["#1", "#<a>", "[1/0]", "[SQRT[-1]]", "[2**3]", "#5220", ""]),
    ),
)


def run(text: str) -> None:
    """Interpret ``text``; only a located Diagnostic may escape."""
    try:
        for n, _ in enumerate(interpret_text(text, "fuzz.ngc", OPTIONS)):
            if n > MAX_COMMANDS:
                break
    except Diagnostic as diag:
        assert diag.code and diag.code == diag.code.upper()
        assert diag.location.line >= 0
        assert diag.location.line <= text.count("\n") + 2


fuzz = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@fuzz
@given(st.text(alphabet=LETTERS + " \n\t", max_size=300))
def test_random_text_is_accepted_or_diagnosed(text: str) -> None:
    run(text)


@fuzz
@given(st.lists(st.lists(WORDS, min_size=1, max_size=6).map(" ".join), max_size=15))
def test_random_word_soup_is_accepted_or_diagnosed(lines: list[str]) -> None:
    run("G21 G90\n" + "\n".join(lines) + "\nM2\n")


@fuzz
@given(
    st.sampled_from(PROGRAMS),
    st.lists(st.tuples(st.integers(0, 10_000), st.sampled_from(LETTERS + " \n")), max_size=6),
    st.lists(st.integers(0, 10_000), max_size=4),
)
def test_mutated_golden_programs_are_accepted_or_diagnosed(
    program: str, inserts: list[tuple[int, str]], deletions: list[int]
) -> None:
    text = program
    for pos, ch in inserts:
        i = pos % (len(text) + 1)
        text = text[:i] + ch + text[i:]
    for pos in deletions:
        if text:
            i = pos % len(text)
            text = text[:i] + text[i + 1 :]
    run(text)
