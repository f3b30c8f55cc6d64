"""Every LinuxCNC 2.9 program of ../shared/corpus/ngc gives output equivalent to the
``.canon`` rs274 printed for it (corpus README: tool table sim.tbl beside them, inch based).
"""

from __future__ import annotations

from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from tests.ngc_reference import differences

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "ngc"
PROGRAMS = sorted(CORPUS.glob("*.ngc"))

pytestmark = pytest.mark.skipif(not PROGRAMS, reason="../shared/corpus is not available")


@pytest.fixture(autouse=True)
def _printed_tolerance(monkeypatch: pytest.MonkeyPatch) -> None:
    """rs274 prints four decimals: values a hair either side of a half-way point print 1e-4
    apart plus a binary hair (0.03125 computed two ways), so the 1e-4 rule is applied to
    the printed values with that hair allowed."""
    monkeypatch.setattr(canon_equiv, "TOLERANCE", 1e-4 + 1e-9)


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_corpus_program_is_equivalent_to_rs274(program: Path) -> None:
    assert differences(program) == []
