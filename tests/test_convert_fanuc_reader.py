"""Fanuc input (issue 7): hand-derived programs a future Fanuc reader must satisfy.

Each ``tests/dialects/fanuc/NNN_name.nc`` has ``NNN_name.canon`` beside it: the expected IR,
derived by hand from Fanuc 0i/30i semantics, with the derivation in its ``#`` comment
lines (docs/dialects.md lists what the reader needs). The reader is not written yet, so
the test is a strict xfail: it starts failing (XPASS) the day a reader passes it.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from kernel import canon

HERE = Path(__file__).resolve().parent / "dialects" / "fanuc"
PROGRAMS = sorted(HERE.glob("*.nc"))


def test_every_program_has_its_expected_ir_with_a_derivation() -> None:
    assert len(PROGRAMS) >= 27
    for program in PROGRAMS:
        expected = program.with_suffix(".canon").read_text().splitlines()
        assert expected[0].startswith("# "), program.name
        assert list(canon.read_commands(expected, str(program)))  # readable IR


@pytest.mark.xfail(strict=True, reason="Fanuc reader not implemented")
@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_fanuc_reader_gives_the_hand_derived_ir(program: Path) -> None:
    from gcode.dialects.fanuc_reader import interpret  # type: ignore[import-not-found]

    ours = list(canon.write_text(interpret(program)))
    expected = program.with_suffix(".canon").read_text().splitlines()
    assert canon_equiv.compare(ours, expected) == []
