"""Fanuc input (issue 7): hand-derived programs read by the Fanuc reader.

Each ``tests/dialects/fanuc/NNN_name.nc`` has ``NNN_name.canon`` beside it: the expected IR,
derived by hand from Fanuc 0i/30i semantics, with the derivation in its ``#`` comment
lines (docs/dialects.md lists what the reader needs; docs/readers/fanuc.md what it does).
Programs whose name holds ``lathe`` or ``turn`` are read in lathe mode, those holding
``book`` with the book's G15/G16 convention; ``NNN_error_*.nc`` programs must be refused
with the diagnostic code and line their ``.canon`` file names (``# expect CODE line N``).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from gcode.fanuc.reader import interpret
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HERE = Path(__file__).resolve().parent / "dialects" / "fanuc"
PROGRAMS = sorted(HERE.glob("*.nc"))
GOOD = [p for p in PROGRAMS if "_error_" not in p.name]
BAD = [p for p in PROGRAMS if "_error_" in p.name]


def _mode(program: Path) -> dict[str, bool]:
    name = program.name
    return {
        "lathe": "lathe" in name or "turn" in name,
        "polar_book_convention": "book" in name,
    }


def test_every_program_has_its_expected_ir_with_a_derivation() -> None:
    assert len(PROGRAMS) >= 27
    for program in PROGRAMS:
        expected = program.with_suffix(".canon").read_text().splitlines()
        assert expected[0].startswith("# "), program.name
        if program in GOOD:
            assert list(canon.read_commands(expected, str(program)))  # readable IR


@pytest.mark.parametrize("program", GOOD, ids=lambda p: p.stem)
def test_fanuc_reader_gives_the_hand_derived_ir(program: Path) -> None:
    ours = list(canon.write_text(interpret(program, **_mode(program))))
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []


@pytest.mark.parametrize("program", BAD, ids=lambda p: p.stem)
def test_fanuc_reader_refuses_the_bad_program_at_its_line(program: Path) -> None:
    text = program.with_suffix(".canon").read_text()
    found = re.search(r"# expect (\S+) line (\d+)", text)
    assert found is not None, "an error program names the expected code and line"
    with pytest.raises(Diagnostic) as info:
        list(interpret(program, **_mode(program)))
    assert info.value.code == found.group(1)
    assert info.value.location.line == int(found.group(2))
    assert info.value.location.file == str(program)
