"""INI settings of the RS274/NGC interpreter (gcode.ngc.ini), against LinuxCNC's INI rules:
[RS274NGC] SUBROUTINE_PATH, INI_VARS (on by default), DISABLE_FANUC_STYLE_SUB, and
#<_ini[section]name> reading the file's numbers, read-only."""

from __future__ import annotations

import os

import pytest

from gcode.ngc.ini import read_ini_text, with_ini
from gcode.ngc.interpreter import InterpreterOptions, interpret_text
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

INI = """
# a comment
[RS274NGC]
SUBROUTINE_PATH = subs:more/subs
; another comment
[Tool]
CHANGE_X = 10
change_x = 99
CHANGE_Y = 2.5 inches
NAME = left
"""


def _moves(text: str, options: InterpreterOptions) -> list[canon.StraightTraverse]:
    return [
        c for c in interpret_text(text, "t.ngc", options) if isinstance(c, canon.StraightTraverse)
    ]


def test_settings_read_like_linuxcnc() -> None:
    ini = read_ini_text(INI, "/machine")
    assert ini.subroutine_path == (
        os.path.join("/machine", "subs"),
        os.path.join("/machine", "more/subs"),
    )
    assert ini.get("tool", "change_x") == "10"  # the first of repeated names wins
    assert ini.ini_vars == {("TOOL", "CHANGE_X"): 10.0, ("TOOL", "CHANGE_Y"): 2.5}
    assert read_ini_text("[RS274NGC]\nINI_VARS = 0\n[A]\nB = 1\n").ini_vars == {}
    assert with_ini(InterpreterOptions(), ini).fanuc_subs
    off = read_ini_text("[RS274NGC]\nDISABLE_FANUC_STYLE_SUB = yes\n")
    assert not with_ini(InterpreterOptions(), off).fanuc_subs


def test_ini_parameters_are_read_case_insensitively_and_read_only() -> None:
    options = with_ini(InterpreterOptions(), read_ini_text(INI))
    moves = _moves("G20 G0 X#<_ini[tool]change_x> Y#<_INI[TOOL]Change_Y>\nM2\n", options)
    assert (moves[-1].x, moves[-1].y) == (10.0, 2.5)
    with pytest.raises(Diagnostic) as info:
        _moves("#<_ini[tool]change_x> = 1\nM2\n", options)
    assert info.value.code == "NGC-NAMED-READONLY"
    with pytest.raises(Diagnostic) as info:
        _moves("G0 X#<_ini[tool]name>\nM2\n", options)  # not a number: not defined
    assert info.value.code == "NGC-NAMED-UNDEFINED"
    with pytest.raises(Diagnostic):  # no INI file: not defined
        _moves("G0 X#<_ini[tool]change_x>\nM2\n", InterpreterOptions())


def test_disabled_fanuc_subs_refuse_m98() -> None:
    options = with_ini(
        InterpreterOptions(), read_ini_text("[RS274NGC]\nDISABLE_FANUC_STYLE_SUB=1\n")
    )
    with pytest.raises(Diagnostic) as info:
        _moves("G20\nM98 P1\nM30\nO1\nG0 X1\nM99\n", options)
    assert (info.value.code, info.value.location.line) == ("NGC-FANUC-SUBS-DISABLED", 2)
