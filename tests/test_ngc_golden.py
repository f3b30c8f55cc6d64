"""Every feature program under tests/golden/ngc gives output equivalent to rs274's golden.

The goldens were made with LinuxCNC 2.9's stand-alone ``rs274`` (tests/golden/README.md);
equivalence is the corpus rule (motions, their end points and arc data within 1e-4, the
feed/speed/spindle/tool/coolant/units/plane each motion sees, and ordered events).
"""

from __future__ import annotations

from pathlib import Path

import pytest

import tests.canon_equiv as canon_equiv
from tests.ngc_reference import differences

GOLDEN = Path(__file__).parent / "golden" / "ngc"
PROGRAMS = sorted(GOLDEN.glob("*.ngc"))

KNOWN = {
    # LinuxCNC prints NURBS_FEED(<number of control points>, ...) (saicanon.cc), and
    # kernel.canon.parse_command reads that number as the order: G5.2 with 5 points of
    # order 3 compares 3 with 5. Ours is right; the reference reader needs the fix.
    "067_g5_2_nurbs": "reference reader takes rs274's NURBS control-point count for the order",
}


def _param(p: Path) -> object:
    reason = KNOWN.get(p.stem)
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
    return pytest.param(p, id=p.stem, marks=marks)


@pytest.fixture(autouse=True)
def _printed_tolerance(monkeypatch: pytest.MonkeyPatch) -> None:
    """rs274 prints four decimals: values a hair either side of a half-way point print 1e-4
    apart plus a binary hair (0.03125 computed two ways), so the 1e-4 rule is applied to
    the printed values with that hair allowed."""
    monkeypatch.setattr(canon_equiv, "TOLERANCE", 1e-4 + 1e-9)


@pytest.mark.parametrize("program", [_param(p) for p in PROGRAMS])
def test_golden_program_is_equivalent_to_rs274(program: Path) -> None:
    assert differences(program) == []


def test_goldens_are_there() -> None:
    assert len(PROGRAMS) >= 135
