"""What the held-out hostile inputs campaign (bench/hostile.py, 2026-12-02) found, pinned:
each input now ends quickly with a located, coded diagnostic (or runs as it should).

The campaign runs the real ``cnc`` command on each input under 1 GB and 20 s; these tests
call the reader or the command in this process, each well under a second.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest

import kernel.limits as limits
from gcode.readers import read_text
from kernel.diagnostics import Diagnostic


@pytest.fixture
def fresh_limits() -> Iterator[None]:
    limits.reset()
    yield
    limits.reset()


def _error(text: str, dialect: str = "rs274ngc") -> Diagnostic:
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        list(read_text(text, dialect, "hostile.ngc"))
    assert time.process_time() - start < 2.0
    return info.value


# rs274 2.9 stops on these with "Calculation resulted in 'infinity'" (or 'not a number');
# the reader wrote STRAIGHT_FEED(inf, ...) and STRAIGHT_FEED(nan, ...) and exited 0
@pytest.mark.parametrize(
    "line",
    [
        "G1 X[10**300*10**300] F100",
        "#1=[10**300*10**300]",
        "G1 X[[10**200*10**200]-[10**200*10**200]] F100",
        "G1 X[EXP[700]*EXP[700]] F100",
    ],
)
def test_a_calculation_resulting_in_infinity_is_a_located_error(line: str) -> None:
    diag = _error(f"G21\n{line}\nM2\n")
    assert (diag.code, diag.location.line) == ("NGC-NOT-FINITE", 2)


def test_a_large_finite_calculation_still_runs() -> None:
    cmds = list(read_text("G21\nG1 X[10**150*10**150] F100\nM2\n", "rs274ngc", "big.ngc"))
    assert any(getattr(c, "x", 0.0) == pytest.approx(1e300) for c in cmds)


# G76 cuts about (K/J)**R passes: a J of 1e-7 mm made ten million passes (minutes of CPU,
# over the 20 s limit); a huge H (spring passes) ran for ever
@pytest.mark.parametrize(
    "g76",
    ["G76 P1 Z-1000 I-1 J0.0000001 K1 Q29", "G76 P1 Z-10 I-1 J0.1 K1 H999999999999"],
)
def test_a_g76_of_millions_of_passes_is_refused_before_the_first(
    fresh_limits: None, g76: str
) -> None:
    diag = _error(f"G21 G18 G7\nS500 M3\nG0 X20 Z1\n{g76}\nM2\n")
    assert (diag.code, diag.location.line) == ("LIMIT-COUNT", 4)
    assert "G76" in diag.message


def test_an_ordinary_g76_is_not_limited(fresh_limits: None) -> None:
    text = "G21 G18 G7\nS500 M3\nG0 X20 Z1\nG76 P1.5 Z-20 I-1 J0.1 K1 R2 Q29 H2\nM2\n"
    assert len(list(read_text(text, "rs274ngc", "g76.ngc"))) > 100


NESTED = {
    # eight nested loops of 1,000 passes: each loop within loop_passes, 10**24 moves in all
    "rs274ngc": "G21 G91 F100\n"
    + "".join(f"o{i} repeat [1000]\n" for i in range(1, 9))
    + "G1 X0.001\n"
    + "".join(f"o{i} endrepeat\n" for i in range(8, 0, -1))
    + "M2\n",
    "fanuc": "%\nO1\nG21 G91 F100.\n#1=0\nWHILE[#1LT1000]DO1\n#1=#1+1\n#2=0\n"
    "WHILE[#2LT1000]DO2\n#2=#2+1\n#3=0\nWHILE[#3LT1000]DO3\n#3=#3+1\nG01 X0.001\n"
    "END3\nEND2\nEND1\nM30\n%\n",
    "siemens840d": "G710 G91 F100\nR1=0\nWHILE R1<1000\nR1=R1+1\nR2=0\nWHILE R2<1000\n"
    "R2=R2+1\nR3=0\nWHILE R3<1000\nR3=R3+1\nG1 X0.001\nENDWHILE\nENDWHILE\nENDWHILE\nM30\n",
}


@pytest.mark.parametrize("dialect", sorted(NESTED))
def test_nested_loops_multiplying_into_hours_end_with_loop_limit(
    fresh_limits: None, dialect: str
) -> None:
    limits.configure(loop_total=1_000)  # the default is 10**6: a few seconds of CPU
    diag = _error(NESTED[dialect], dialect)
    assert diag.code == "LOOP-LIMIT" and "loop_total" in diag.message
    assert diag.location.line > 1


def test_loop_total_counts_every_pass_of_a_raster(fresh_limits: None) -> None:
    """3 rows of 200 points: 603 passes in all, the inner loop 200 in a row."""
    text = (
        "#1=0\no1 while [#1 LT 3]\n#2=0\no2 while [#2 LT 200]\nG1 X#2 Y#1 F100\n"
        "#2=[#2+1]\no2 endwhile\n#1=[#1+1]\no1 endwhile\nM2\n"
    )
    limits.configure(loop_total=603)
    assert len(list(read_text(text, "rs274ngc", "raster.ngc"))) > 600
    limits.configure(loop_total=602)
    assert _error(text).code == "LOOP-LIMIT"


# the Fanuc reader wrote STRAIGHT_FEED(inf, nan, ...) and exited 0; the control stops
# with alarm 111 (calculated data overflow)
@pytest.mark.parametrize(
    ("body", "line"),
    [
        ("#1=100000000000000000000000000000000000000000000000000.\n#2=#1*#1*#1*#1*#1*#1*#1", 6),
        ("#1=EXP[700]*EXP[700]", 5),
        ("#1=1.\nWHILE[#1GT0]DO1\n#1=#1*1000000000.*1000000000.*1000000000.\nEND1", 7),
    ],
)
def test_a_fanuc_macro_overflow_is_a_located_alarm(body: str, line: int) -> None:
    diag = _error(f"%\nO1\nG21 G90\nF100.\n{body}\nG01 X#1\nM30\n%\n", "fanuc")
    assert (diag.code, diag.location.line) == ("FANUC-OVERFLOW", line)
