"""Constructs of real Fanuc and Haas shop programs the readers refused (issue 14), each
checked against the control's manual:

* G71 type I with an arc tangent to the cutting axis at its start, its end points rounded
  to the program's four decimals: the centre the control computes sits a few millionths
  off the tangent point, so the arc passes the extreme by far less than one least input
  increment. The control, working in increments, sees a monotone contour and cuts it; a
  contour that really turns back is still refused (0i-TF "the figure must show a
  monotonous change along both axes").
* Haas ``IF [c] <block>`` without THEN (Haas mill operator's manual, "Macros", conditional
  execution: the rest of the block runs only when c holds); a Fanuc control alarms.
* External output commands POPEN, DPRNT[...], BPRNT[...], PCLOS (Fanuc custom macro
  manual, "External output commands"; Haas alike): text for a serial device, no motion.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

import pytest

from gcode.fanuc.reader import interpret_text as fanuc
from gcode.fanuc.turning.profile import Segment
from gcode.fanuc_lathe.reader import interpret_text as fanuc_lathe
from gcode.haas.reader import interpret_text as haas
from gcode.haas_lathe.reader import interpret_text as haas_lathe
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HEAD = "%\nO00020\nG18 G20 G40 G80 G99\nT101\nG97 S1000 M03\nG00 X1.6 Z0.1\n"
# Z-1.194 then a CW quarter arc R0.564 to X1.114 Z-1.7261: tangent to Z at its start
# (centre Z-1.194 X1.488 on paper; Z-1.1940032 from the rounded end point)
TANGENT_ARC = "N10 G00 X0.36\nG01 Z-1.194\nG02 X1.114 Z-1.7261 R0.564\nN20 G01 X1.6\n"
TAIL = "G00 X2. Z1.\nM30\n%\n"


def _points(commands: list[canon.Command]) -> list[tuple[float, float]]:
    """(x, z) of every move's end point."""
    out = []
    for c in commands:
        if isinstance(c, canon.StraightFeed | canon.StraightTraverse):
            out.append((c.x, c.z))
        elif isinstance(c, canon.ArcFeed):
            out.append((c.second_end, c.first_end))  # G18: first axis Z, second X
    return out


def test_arc_tangent_within_rounding_is_monotone_and_a_real_turn_is_not() -> None:
    # normalised frame (a up, b right): centre (0.75, 0), radius 0.75, clockwise from a
    # start ``offset`` to the right of the circle's lowest point to its leftmost point; the
    # arc dips below its start by 0.75 (1 - cos(offset / 0.75))
    r = 0.75
    for offset, turns in ((3.2e-6, False), (1e-3, True)):
        a0 = r - math.sqrt(r * r - offset * offset)
        seg = Segment("arc", a0, offset, r, -r, r, 0.0, False, 1)
        assert seg.turns_at(-math.pi / 2) is turns
        assert seg.monotone() is (not turns)


def test_g71_type_i_with_a_tangent_arc_runs_on_haas_and_fanuc_lathes() -> None:
    one = list(haas_lathe(HEAD + "G71 P10 Q20 U0.02 W0.01 D0.05 F0.008\n" + TANGENT_ARC + TAIL))
    two = list(
        fanuc_lathe(HEAD + "G71 U0.05\nG71 P10 Q20 U0.02 W0.01 F0.008\n" + TANGENT_ARC + TAIL)
    )
    pts = _points(one)
    assert pts == _points(two)
    # the rough boundary's last cut reaches the arc's end shifted by the allowances:
    # radius 0.557 + 0.01, Z -1.7261 + 0.01 (W towards +Z)
    assert any(abs(x - 0.567) < 1e-6 and abs(z + 1.7161) < 1e-6 for x, z in pts), (
        "the rough finishing pass does not follow the contour"
    )


def test_g71_type_i_contour_that_turns_back_is_still_refused() -> None:
    pocket = "N10 G00 X0.8\nG01 Z-0.5\nX0.6 Z-0.7\nN20 X1.6 Z-1.\n"
    with pytest.raises(Diagnostic) as info:
        list(haas_lathe(HEAD + "G71 P10 Q20 U0.02 W0.01 D0.05 F0.008\n" + pocket + TAIL))
    assert info.value.code == "FANUC-CYCLE-PROFILE"
    assert info.value.location.line == 10


IF_BLOCKS = """%
O00021
G21 G90 G17 G94
#1=1.
IF [#1 EQ 1.] G00 X10. Y5.
IF [#1 EQ 2.] G00 X20.
IF [#1 NE #0] #2=3.
G00 Y#2
IF [#1 GT 2.] #3=4. G00 Z7.
IF [#1 GT 0] #4=5. G00 Z#4
M30
%
"""


def test_haas_runs_the_rest_of_an_if_block_only_when_the_condition_holds() -> None:
    ends = [(c.x, c.y, c.z) for c in haas(IF_BLOCKS) if isinstance(c, canon.StraightTraverse)]
    assert ends == [(10.0, 5.0, 0.0), (10.0, 3.0, 0.0), (10.0, 3.0, 5.0)]


def test_fanuc_wants_goto_or_then_after_if() -> None:
    with pytest.raises(Diagnostic) as info:
        list(fanuc(IF_BLOCKS))
    err = info.value
    assert (err.code, err.location.line, err.location.column) == ("FANUC-SYNTAX", 5, 15)
    assert "GOTO or THEN" in err.message


@pytest.mark.parametrize("read", [fanuc, haas])
def test_external_output_commands_move_nothing(
    read: Callable[[str], Iterable[canon.Command]],
) -> None:
    output = "POPEN\nDPRNT[X#5041[44]*Y#5042[44]]\nBPRNT[A#1[3]]\nPCLOS\n"
    text = "%\nO00022\nG21 G90\n" + output + "G00 X1.\nM30\n%\n"
    with_output = [c for c in read(text) if isinstance(c, canon.StraightTraverse)]
    plain = "%\nO00022\nG21 G90\nG00 X1.\nM30\n%\n"
    assert with_output == [c for c in read(plain) if isinstance(c, canon.StraightTraverse)]


def test_an_unclosed_dprnt_is_a_located_syntax_error() -> None:
    with pytest.raises(Diagnostic) as info:
        list(fanuc("%\nO00023\nDPRNT[X#5041[44]\nM30\n%\n"))
    assert (info.value.code, info.value.location.line) == ("FANUC-SYNTAX", 3)


def test_a_program_name_after_o_is_a_located_syntax_error() -> None:
    # a CAM system writing the program's name where the control wants its number
    with pytest.raises(Diagnostic) as info:
        list(fanuc_lathe("%\nOsample( cncsample.TXT )\nG0 X1.\nM30\n%\n"))
    err = info.value
    assert (err.code, err.location.line, err.location.column) == ("FANUC-SYNTAX", 2, 2)
    assert "program number" in err.message
