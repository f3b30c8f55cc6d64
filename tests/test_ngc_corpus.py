"""Every LinuxCNC 2.9 program of tests/data/corpus/ngc gives output equivalent to the
``.canon`` rs274 printed for it (corpus README: tool table sim.tbl beside them, inch based).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.data_paths import corpus_programs
from tests.ngc_reference import differences

PROGRAMS = corpus_programs()


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_corpus_program_is_equivalent_to_rs274(program: Path) -> None:
    assert differences(program) == []
