"""CNC050: Fanuc-style numbers without a decimal point (parameter No. 3401#0 DPI = 0).

The reference is the Fanuc 0i-MF/0i-TF operator's manuals ("Decimal point programming",
the G04, G51, G68 and canned-cycle sections): with DPI = 0 a number without a point counts
least input increments for the addresses that take a point (X Y Z U V W I J K R Q, A B C;
G04 X in 0.001 s), while G M N O P T D H L S F are integers by meaning, G51 P I J K are
magnifications, a drilling cycle's K a repeat count, the lathe cycles' P Q sequence numbers
(G74-G76: increments written without a point by definition) and G73 R a number of
divisions. The value the rule reports is checked against the Fanuc reader (an independent
implementation of the same rule in gcode/fanuc/words.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode.fanuc.decimal_point import bare_numbers
from gcode.fanuc.reader import interpret_text as fanuc
from gcode.fanuc_lathe.reader import interpret_text as fanuc_lathe


def words(text: str, lathe: bool = False) -> list[tuple[str, float, str]]:
    return [(b.word, round(b.value, 6), b.unit) for b in bare_numbers(text.splitlines(), lathe)]


@pytest.mark.parametrize(
    ("text", "found"),
    [
        ("G21\nG01 X100 F300.\n", [("X100", 0.1, "mm")]),
        ("G20\nG01 X100 F30.\n", [("X100", 0.01, "in")]),
        ("G21\nG00 B90\n", [("B90", 0.09, "deg")]),
        ("G04 X5\n", [("X5", 0.005, "s")]),
        ("G68 X0 Y0 R30\n", [("R30", 0.03, "deg")]),
        ("G83 X10. Y10. Z-20. R2. Q2500 F100.\n", [("Q2500", 2.5, "mm")]),
        ("G65 P9000 X2500\n", [("X2500", 2.5, "mm")]),  # G65 arguments follow their address
        ("G02 X10. Y0 I5 J0\n", [("I5", 0.005, "mm")]),
        ("G01 X50. ,R5000 F500.\n", [(",R5000", 5.0, "mm")]),  # corner R and chamfer too
    ],
)
def test_lengths_angles_and_dwell_x_without_a_point_are_found(text: str, found: list) -> None:
    assert words(text) == found


@pytest.mark.parametrize(
    "text",
    [
        "O1000\nN10 G00 G90 G54 X0 Y0\nT12 M06\nG43 H12 Z50.\nS1200 M03\nM08\n",
        "G01 X0 Y0 Z0 F300\n",  # zero is zero either way; F is a feed as written
        "G04 P500\n",  # P is milliseconds
        "#1=100\nG01 X#1 Y[10] F100.\n",  # variables and expressions carry their value
        "G51 X0 Y0 P1500\nG51 X0 Y0 I2000 J1000\n",  # magnifications
        "G81 X10. Y10. Z-5. R2. K3 F100.\nX20. K2\nG80\n",  # repeat counts, modal cycle
        "M98 P1000 L3\nG65 P9010 L2\nD1 H1 T0101\n",
        "G06.2 P3 K0 X0 Y0 R1 K0\n",  # NURBS order, knots, weights
    ],
)
def test_integer_words_by_meaning_are_never_found(text: str) -> None:
    assert words(text) == []


@pytest.mark.parametrize(
    "text",
    [
        "G71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nG70 P10 Q20\n",
        "G73 U3. W0.5 R3\nG73 P10 Q20 U0.4 W0.1 F0.2\n",
        "G74 R1.\nG74 X0 Z-30. P2000 Q5000 F0.1\n",
        "G76 P020060 Q100 R0.05\nG76 X27.6 Z-30. P1200 Q400 F2.\n",
    ],
)
def test_lathe_cycle_p_q_and_g73_divisions_are_never_found(text: str) -> None:
    assert words(text, lathe=True) == []


def test_the_lathe_x_and_u_are_lengths() -> None:
    assert words("G00 X50 Z2.\nG01 U-2 F0.2\n", lathe=True) == [
        ("X50", 0.05, "mm"),
        ("U-2", -0.002, "mm"),
    ]


def test_the_value_reported_is_what_the_reader_moves_to() -> None:
    mill = "G21 G90\nG00 X0 Y0 Z5.\nG01 X50 F600.\nM30\n"
    ((_, value, _),) = words(mill)
    feed = next(c for c in fanuc(mill) if c.NAME == "STRAIGHT_FEED")
    assert feed.x == pytest.approx(value)
    lathe = "G21 G99\nS500 M03\nG00 X60. Z2.\nG01 Z-40 F0.2\nM30\n"
    ((_, value, _),) = words(lathe, lathe=True)
    feed = next(c for c in fanuc_lathe(lathe) if c.NAME == "STRAIGHT_FEED")
    assert feed.z == pytest.approx(value)


def test_inch_mode_follows_g20_and_g21_through_the_program() -> None:
    found = words("G20\nG01 X10 F10.\nG21\nG01 X10 F100.\n")
    assert found == [("X10", 0.001, "in"), ("X10", 0.01, "mm")]


# --------------------------------------------------------------------------- cnc check
def cnc(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


PROGRAM = (
    "%\nO0001\nG21 G90 G54\nG00 X0 Y0 Z5.\nS1000 M03\nG01 Z-1. F100.\n"
    "G01 X100 Y5\nX20.\nY50\nM05\nM30\n%\n"
)


def test_check_reports_the_first_word_with_the_count_of_the_others(tmp_path: Path) -> None:
    src = tmp_path / "O0001.nc"
    src.write_text(PROGRAM)
    res = cnc("-q", "check", "-f", "json", str(src))
    found = [f for f in json.loads(res.stdout)["files"][0]["findings"] if f["rule"] == "CNC050"]
    assert len(found) == 1
    (f,) = found
    assert (f["line"], f["column"], f["severity"]) == (7, 5, "warning")
    assert f["message"].startswith("X100 has no decimal point: the control reads 0.1 mm")
    assert f["message"].endswith("(and 2 more words without a decimal point)")


def test_check_judges_it_only_on_the_fanuc_family(tmp_path: Path) -> None:
    src = tmp_path / "O0001.nc"
    src.write_text(PROGRAM)
    for dialect, fires in (("fanuc", True), ("haas", True), ("rs274ngc", False)):
        res = cnc("check", "-f", "json", "--dialect", dialect, str(src))
        rules = {f["rule"] for f in json.loads(res.stdout)["files"][0]["findings"]}
        assert ("CNC050" in rules) is fires, dialect


def test_the_rule_can_be_switched_off(tmp_path: Path) -> None:
    src = tmp_path / "O0001.nc"
    src.write_text(PROGRAM)
    cfg = tmp_path / "pyproject.toml"
    cfg.write_text('[tool.cnc.check]\ndisable = ["CNC050"]\n')
    res = cnc("-q", "check", "-f", "json", "--config", str(cfg), str(src))
    rules = {f["rule"] for f in json.loads(res.stdout)["files"][0]["findings"]}
    assert "CNC050" not in rules
