"""Haas lathe programs (issue 14): the ``haas_lathe`` dialect.

Expected behaviour from the Haas lathe operator's manual (NGC): G71/G72 take the whole
roughing cycle in one block, ``P Q U W D F`` with D the depth of cut (a radius); G73 takes
``P Q U W I K D F`` with I/K the relief along X (radius) and Z and D the number of passes.
These are the first-block words of the Fanuc 0i-TF two-block forms (G71 U R / G71 P Q U W
F; G73 U W R / G73 P Q U W F), so a Haas one-block program must move exactly as the Fanuc
lathe reader moves its two-block twin. M88/M89 are through-spindle coolant, the IR's
THROUGH_TOOL_ON/OFF; the other documented machine functions are named in comments.
"""

from __future__ import annotations

import pytest

from gcode import registry
from gcode.fanuc_lathe.reader import interpret_text as fanuc_lathe
from gcode.haas_lathe.reader import interpret_text as haas_lathe
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

HEAD = "%\nO00010\nG18 G20 G40 G80 G99\nT101\nG97 S1000 M03\nG00 X2.1 Z0.1\n"
CONTOUR = "N1 G00 X1.0\nG01 Z-1.0 F0.008\nX2.0\nN2 G01 Z-2.0\nG70 P1 Q2\nM30\n%\n"
CONTOUR_FACE = "N1 G00 Z-1.0\nG01 X1.0 F0.008\nZ-0.5\nN2 X0.\nG70 P1 Q2\nM30\n%\n"


def _moves(commands: list[canon.Command]) -> list[canon.Command]:
    motions = ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "ARC_FEED", "SET_FEED_RATE")
    return [c.__class__(*c.args()) for c in commands if c.NAME in motions]


def test_haas_lathe_is_a_registered_dialect() -> None:
    assert "haas_lathe" in registry.NAMES
    assert registry.reader_module("haas_lathe").__name__ == "gcode.haas_lathe.reader"


def test_one_block_g71_moves_as_the_fanuc_two_block_form() -> None:
    haas = list(haas_lathe(HEAD + "G71 P1 Q2 U0.02 W0.005 D0.1 F0.012\n" + CONTOUR))
    fanuc = list(fanuc_lathe(HEAD + "G71 U0.1\nG71 P1 Q2 U0.02 W0.005 F0.012\n" + CONTOUR))
    assert _moves(haas) == _moves(fanuc)
    cuts = [c for c in haas if c.NAME == "STRAIGHT_FEED"]
    assert cuts[0].x == pytest.approx(0.95)  # first pass: 1.05 - D0.1 (radius)


def test_one_block_g72_moves_as_the_fanuc_two_block_form() -> None:
    haas = list(haas_lathe(HEAD + "G72 P1 Q2 U0.02 W0.005 D0.1 F0.012\n" + CONTOUR_FACE))
    fanuc = list(fanuc_lathe(HEAD + "G72 W0.1\nG72 P1 Q2 U0.02 W0.005 F0.012\n" + CONTOUR_FACE))
    assert _moves(haas) == _moves(fanuc)


def test_one_block_g73_moves_as_the_fanuc_two_block_form() -> None:
    haas = list(haas_lathe(HEAD + "G73 P1 Q2 U0.02 W0.005 I0.3 K0.1 D3 F0.012\n" + CONTOUR))
    fanuc = list(fanuc_lathe(HEAD + "G73 U0.3 W0.1 R3\nG73 P1 Q2 U0.02 W0.005 F0.012\n" + CONTOUR))
    assert _moves(haas) == _moves(fanuc)


def test_the_rough_pass_allowance_of_g71_is_refused_at_its_line() -> None:
    with pytest.raises(Diagnostic) as info:
        list(haas_lathe(HEAD + "G71 P1 Q2 U0.02 W0.005 I0.01 D0.1 F0.012\n" + CONTOUR))
    assert info.value.code == "HAAS-CYCLE-WORD"
    assert info.value.location is not None and info.value.location.line == 7


def test_through_spindle_coolant_and_machine_functions() -> None:
    text = HEAD + "M88\nM12\nM21\nM31\nM59 P1101\nM85\nG01 Z-0.5 F0.01\nM89\nM13\nM30\n%\n"
    kept = ("THROUGH_TOOL_ON", "THROUGH_TOOL_OFF", "COMMENT", "MACHINE_FUNCTION")
    out = [c for c in haas_lathe(text) if c.NAME in kept]
    assert [c.to_text() for c in out] == [
        "THROUGH_TOOL_ON()",
        'COMMENT("M12: auto air jet on")',
        "MACHINE_FUNCTION(12)",
        'COMMENT("M21: tailstock advance")',
        "MACHINE_FUNCTION(21)",
        'COMMENT("M31: chip conveyor forward")',
        "MACHINE_FUNCTION(31)",
        'COMMENT("M59: output relay set")',
        "MACHINE_FUNCTION(59, P=1101.0000)",
        'COMMENT("M85: automatic door open")',
        "MACHINE_FUNCTION(85)",
        "THROUGH_TOOL_OFF()",
        'COMMENT("M13: auto air jet off")',
        "MACHINE_FUNCTION(13)",
    ]


def test_haas_dwell_p_with_a_point_is_seconds() -> None:
    dwells = [c for c in haas_lathe(HEAD + "G04 P1.5\nG04 P500\nM30\n%\n") if c.NAME == "DWELL"]
    assert [d.seconds for d in dwells] == [1.5, 0.5]
