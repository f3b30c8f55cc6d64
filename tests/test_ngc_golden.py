"""Every feature program under tests/golden/ngc gives output equivalent to rs274's golden.

The goldens were made with LinuxCNC 2.9's stand-alone ``rs274`` (tests/golden/README.md);
equivalence is the corpus rule (motions, their end points and arc data within 1e-4, the
feed/speed/spindle/tool/coolant/units/plane each motion sees, and ordered events).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.ngc_reference import differences

GOLDEN = Path(__file__).parent / "golden" / "ngc"
PROGRAMS = sorted(GOLDEN.glob("*.ngc"))

KNOWN: dict[str, str] = {}  # stem -> reason, for goldens we knowingly do not match


def _param(p: Path) -> object:
    reason = KNOWN.get(p.stem)
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
    return pytest.param(p, id=p.stem, marks=marks)


@pytest.mark.parametrize("program", [_param(p) for p in PROGRAMS])
def test_golden_program_is_equivalent_to_rs274(program: Path) -> None:
    assert differences(program) == []


def test_goldens_are_there() -> None:
    assert len(PROGRAMS) >= 135
