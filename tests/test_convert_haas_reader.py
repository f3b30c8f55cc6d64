"""The Haas reader: the Fanuc reader with Haas's differences (gcode/fanuc/options.py HAAS).

Expected values are derived from the Haas mill operator's manual (G-code and M-code
chapters): G04 P with a decimal point is seconds, without one milliseconds; M97 P calls a
local subprogram at sequence P of the same program, L times; M98 P is a five-digit program
number (no repeat count hidden in P); G187 sets smoothness (continuous blending here);
M19 P orients the spindle to P degrees; M50 changes pallets.
"""

from __future__ import annotations

import pytest

from gcode.fanuc import reader as fanuc_reader
from gcode.haas import reader as haas_reader
from kernel.ir import canon


def _run(text: str, reader=haas_reader) -> list[canon.Command]:  # noqa: ANN001
    return list(reader.interpret_text("%\nO00001 (TEST)\nG21 G90 G17\n" + text + "M30\n%\n"))


def _of(cmds: list[canon.Command], kind: type) -> list[canon.Command]:
    return [c for c in cmds if isinstance(c, kind)]


def test_dwell_p_is_seconds_with_a_point_and_milliseconds_without() -> None:
    dwells = _of(_run("G04 P1.5\nG04 P250\n"), canon.Dwell)
    assert [d.seconds for d in dwells] == pytest.approx([1.5, 0.25])


def test_fanuc_dwell_p_is_always_milliseconds() -> None:
    dwells = _of(_run("G04 P1500\nG04 X2.\n", fanuc_reader), canon.Dwell)
    assert [d.seconds for d in dwells] == pytest.approx([1.5, 2.0])


def test_m97_runs_the_local_subprogram_l_times_and_returns() -> None:
    text = "G00 X0 Y0\nM97 P200 L3\nG00 X50.\nM30\nN200 G91 G01 X2. F100.\nG90\nM99\n"
    moves = _of(_run(text), canon.StraightFeed) + _of(_run(text), canon.StraightTraverse)
    feeds = [m.x for m in moves if isinstance(m, canon.StraightFeed)]
    rapids = [m.x for m in moves if isinstance(m, canon.StraightTraverse)]
    assert feeds == pytest.approx([2.0, 4.0, 6.0])
    assert rapids == pytest.approx([0.0, 50.0])


def test_m98_p_is_a_five_digit_program_number() -> None:
    text = "G00 X0 Y0\nM98 P10200\nM30\nO10200\nG01 X7. F100.\nM99\n"
    feeds = _of(_run(text), canon.StraightFeed)
    assert [f.x for f in feeds] == pytest.approx([7.0])


def test_g187_smoothness_sets_continuous_blending_with_its_tolerance() -> None:
    modes = _of(_run("G187 P2 E0.02\n"), canon.SetMotionControlMode)
    assert modes[-1].mode is canon.MotionMode.CONTINUOUS
    assert modes[-1].tolerance == pytest.approx(0.02)


def test_m19_p_orients_to_the_angle_and_m50_changes_pallets() -> None:
    cmds = _run("S100 M03\nM19 P90.\nM50\n")
    assert _of(cmds, canon.OrientSpindle)[0].orientation == pytest.approx(90.0)
    assert _of(cmds, canon.PalletShuttle)


def test_g154_p_selects_an_additional_work_offset_set_by_g10_l20() -> None:
    cmds = _run("G00 X0 Y0\nG10 L20 P60 X40.\nG154 P60\nG01 X1. Y0 F100.\n")
    origins = _of(cmds, canon.SetG5xOffset)  # which offset is selected, and its values
    assert origins[-2].x == pytest.approx(40.0)  # G154 P60 active, M30 resets to G54
    assert origins[-1].index == 1 and origins[-1].x == 0.0
    assert [f.x for f in _of(cmds, canon.StraightFeed)] == pytest.approx([1.0])
