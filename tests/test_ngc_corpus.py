"""Every LinuxCNC 2.9 program of ../shared/corpus/ngc gives output equivalent to the
``.canon`` rs274 printed for it (corpus README: tool table sim.tbl beside them, inch based).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.ngc_reference import differences

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "ngc"
PROGRAMS = sorted(CORPUS.glob("*.ngc"))

pytestmark = pytest.mark.skipif(not PROGRAMS, reason="../shared/corpus is not available")


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_corpus_program_is_equivalent_to_rs274(program: Path) -> None:
    assert differences(program) == []
