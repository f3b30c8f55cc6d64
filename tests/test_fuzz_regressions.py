"""Every distinct failure the fuzzing campaigns (tests/fuzzing.py) found, pinned: each case
must now end with success or a located, coded diagnostic, in this process and quickly.

The hostile inputs of issue 19 found by hand (long numbers, deep nesting, endless cycles,
self-containing workplans, tiny tools) are pinned in tests/test_limits.py; this file holds
what the campaigns found on top of them, with the campaign and seed that found it.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from click.testing import CliRunner

import kernel.limits as limits
from cli.main import cli
from kernel.diagnostics import Diagnostic
from tests.fuzzing import case, check_one, run_reader

PINNED = [
    # haas_lathe, seed 180982 of the reader campaign: G75 with 13,000 pecks at each of
    # 2,000 plunges (each under its own bound of 100,000) made 2.6e7 moves, over the CPU
    # limit; the pecks in all are bounded now
    (
        "haas_lathe",
        "%\nO0108\nG21 G18 G99\nG00 X4. Z-10.\nG75 R0.5\nG75 X30. Z-16. P2 Q3 F0.1\nM30\n%\n",
    ),
    # stepnc, seed 221090 of the reader campaign: a MULTISTEP_DRILLING with a 1e-7 mm
    # depth_of_step pecked tens of millions of times (over the 10 s CPU limit); its pecks
    # are cycle_passes now
    (
        "stepnc",
        (Path(__file__).parent / "stepnc" / "multistep_drilling.stp")
        .read_text()
        .replace("1.0,5.0,4.0,0.2);", "1.0,5.0,0.0000001,0.2);"),
    ),
    # siemens840d, seed 11732 of the reader campaign: a block number of 5,000 digits made
    # the jump table's int() fail past Python's 4,300-digit limit (a ValueError traceback)
    # before the line's own LIMIT-DIGITS
    ("siemens840d", "G0 X0\nGOTOF N10\nN1" + "4" * 5_000 + " G1 X1\nN10 G0 X0\nM30\n"),
    # fanuc_lathe, seed 104081 of the reader campaign: a block of eight L1000000000 words
    # and a % took 17 s of CPU in the plain-block pattern (\d+\.?\d* splits each run of
    # digits many ways, and the words multiply the splits); the worker was stopped as hung
    ("fanuc_lathe", "%\n%\n%\n" + "L1000000000" * 8 + "%\n" + "L1000000000" * 4),
    # haas, seed 77067 of the reader campaign: L1000000000 on a G76 listed a billion holes
    # (10 GB) before the first move; the Fanuc-family G74/G76/G84/G87 repeats are
    # cycle_passes now, as the other cycles' are
    (
        "haas",
        "%\nO0054\nG21 G90 G17\nS500 M03\nG00 X0 Y0 Z5.\n"
        "L1000000000G76 X0 Y0 Z-10. R2. Q500 P500 F100.\nG80\nM30\n%\n",
    ),
    # canon, seed 1910 of `python -m tests.fuzzing canon 2000`: NURBS_FEED with a control
    # point count of 1e9 and nine values built a billion-point tuple (worker out of memory)
    (
        "canon",
        "    1 N..... STRAIGHT_FEED(49, inf, 154.40695, -91.7465, 32.2705, 90, -110.212, 28.11)\n"
        "    2 N..... NURBS_FEED(149.0501, 1000000000, -47.4, 80, -125.084, 166, -21.06, 79.31,"
        " -86)\n",
    ),
    # siemens840d, seed 376227 of `python -m tests.fuzzing siemens840d 100000 reader
    # 300000`: `N160.WHILE` (a block number with a point) ran as a WHILE, but the program's
    # structure scan read no keyword on that line (a KeyError traceback)
    ("siemens840d", "R1=0\nN160.WHILE R1<2\nR1=R1+1\nENDWHILE\nM30\n"),
]


@pytest.mark.parametrize(("dialect", "text"), PINNED)
def test_pinned_fuzz_failure_is_diagnosed(dialect: str, text: str) -> None:
    start = time.process_time()
    out = check_one("reader", dialect, text)
    assert out.ok, out
    assert time.process_time() - start < 5.0


STEPNC = Path(__file__).parent / "stepnc"
ZIGZAG = (STEPNC / "pocket_zigzag.stp").read_text()
HELIX = (STEPNC / "pocket_finish_helix.stp").read_text()
RAMP = (STEPNC / "pocket_ramp.stp").read_text()

#: stepnc, seeds 24904 and 64859 of the slow reader campaign (start 1,000): a pocket's
#: PLUNGE_ZIGZAG of -5 degrees climbed for ever while looking for its start (over the 10 s
#: CPU limit). The same approach code failed on a zigzag of width 0 (a hang), a helix of
#: radius 0 or a ramp of 0 degrees (ZeroDivisionError as STEPNC-UNSUPPORTED with no reason)
#: and a helix of 1e-320 degrees (an OverflowError traceback): an approach angle must be in
#: (0, 90] degrees and a width or radius positive (STEPNC-ENTRY), and the zigzag strokes or
#: helix turns fit toolpath_passes (LIMIT-COUNT)
PINNED_APPROACH = [
    (ZIGZAG.replace("PLUNGE_ZIGZAG($,15.0,8.0)", "PLUNGE_ZIGZAG($,-5.0,8.0)"), "STEPNC-ENTRY"),
    (ZIGZAG.replace("PLUNGE_ZIGZAG($,15.0,8.0)", "PLUNGE_ZIGZAG($,15.0,0.0)"), "STEPNC-ENTRY"),
    (ZIGZAG.replace("PLUNGE_ZIGZAG($,15.0,8.0)", "PLUNGE_ZIGZAG($,1.0E-300,8.0)"), "LIMIT-COUNT"),
    (HELIX.replace("PLUNGE_HELIX($,4.0,5.0)", "PLUNGE_HELIX($,0.0,5.0)"), "STEPNC-ENTRY"),
    (HELIX.replace("PLUNGE_HELIX($,4.0,5.0)", "PLUNGE_HELIX($,4.0,1.0E-320)"), "LIMIT-COUNT"),
    (RAMP.replace("PLUNGE_RAMP($,20.0)", "PLUNGE_RAMP($,0.0)"), "STEPNC-ENTRY"),
]


@pytest.mark.parametrize(("text", "code"), PINNED_APPROACH)
def test_pinned_pocket_approach_is_diagnosed_at_its_operation(text: str, code: str) -> None:
    assert text not in (ZIGZAG, HELIX, RAMP)  # the seed program did change
    start = time.process_time()
    with pytest.raises(Diagnostic) as info:
        run_reader("stepnc", text)
    assert time.process_time() - start < 2.0
    assert info.value.code == code
    # located at the pocket's milling operation: its instance and line
    loc = info.value.location
    assert text.splitlines()[loc.line - 1].startswith(f"#{loc.entity}=")
    assert "_MILLING(" in text.splitlines()[loc.line - 1]


def test_cases_are_reproducible_from_their_seed() -> None:
    assert case("rs274ngc", 17) == case("rs274ngc", 17)
    assert case("stepnc", 3) == case("stepnc", 3)


#: found through ``cnc check`` (``python -m tests.fuzzing DIALECT 120 cli``): loops that move
#: for ever (incremental moves in a WHILE whose condition never changes) ran until
#: LOOP-LIMIT, 10**8 blocks, minutes of CPU; the batch budget now ends them
PINNED_CLI = [
    (
        "fanuc",
        "%\nO5066\nG20 G91\nG01 X-127.52508 Z45 F1276.\n#7=#5001\n"
        "WHILE[[[ABS[[#4001]*162.6264]]]]DO2\nG01 X11\nEND2\nM30\n%\n",
    ),
    (
        "siemens840d",
        "G70 G91\nG3 J=171.981 Z=61 F2552\nWHILE R5<0.0000001\nG1 X=-119\nENDWHILE\nM30\n",
    ),
    (
        "haas",
        "%\nO8516\nG21 G90 G17\nG01 X175.7624 F425.\n"
        "WHILE[#0MOD#5001EQ[[[[-88.71164GT#4001]]]]]DO1\nG01 X-150.135\nEND1\nM30\n%\n",
    ),
]


#: found through ``cnc check`` on canonical text (``python -m tests.fuzzing canon 100 cli``,
#: seed 634 and others): an enum argument given as a number (``USE_LENGTH_UNITS(-144.3)``,
#: ``SELECT_PLANE(3)``) or an enum name where a number goes was read into the command, and
#: the checker's arithmetic on it ended in CHECK-INTERNAL; they are CANON-SYNTAX now
PINNED_CHECK = [
    "    1 N..... USE_LENGTH_UNITS(-144.33237)\n    2 N..... STRAIGHT_FEED(82, 63.4, 29)\n",
    "    1 N..... SELECT_PLANE(-184.07)\n    2 N..... ARC_FEED(1, 2, 0, 0, 1, 0)\n",
    "    1 N..... STRAIGHT_FEED(CANON_PLANE_XY, 1, 2)\n",
    # seed 22461 of `python -m tests.fuzzing canon 100 cli 22400`: an arc with a NaN centre
    # made the travel rule's quadrant points a ValueError (CHECK-INTERNAL)
    "    1 N..... ARC_FEED(104.826, -89, 2.6, nan, -190.4, -6.5146, -183.9222, 59.464)\n",
]


@pytest.mark.parametrize("text", PINNED_CHECK)
def test_pinned_canonical_text_is_diagnosed_by_check(text: str) -> None:
    out = check_one("cli", "canon", text)
    assert out.ok, out


def test_a_lone_carriage_return_counts_as_a_line() -> None:
    # sandia, seeds of `python -m tests.fuzzing sandia 1000 reader 7000`: the reader counts
    # CR as a line end, the harness did not, and took a right line number for a wrong one
    assert check_one("reader", "sandia", "\r\rk7").ok


@pytest.mark.parametrize(("dialect", "text"), PINNED_CLI)
def test_pinned_endless_moving_loops_end_in_check(tmp_path: Path, dialect: str, text: str) -> None:
    path = tmp_path / ("p.mpf" if dialect == "siemens840d" else "p.nc")
    path.write_text(text)
    start = time.process_time()
    res = CliRunner().invoke(
        cli, ["--limit", "seconds=1", "check", "--dialect", dialect, str(path)]
    )
    limits.reset()
    assert time.process_time() - start < 15
    assert res.exit_code == 1, res.output
    # stopped by the time budget or, on a fast machine first, by the loop guard: either way
    # a located, coded error
    stopped = "LIMIT-TIME" in res.output or "LOOP-LIMIT" in res.output
    assert stopped and "CHECK-INTERNAL" not in res.output


#: siemens840d, seed 7427 of the reader campaign (about 10,000 digits after ``M3`` on a
#: plain block): the plain-block expressions of the readers read a number as ``\d+\.?\d*``,
#: whose two digit runs split a long run of digits in quadratically many ways, and the
#: match took 36 s of CPU; ``\d+(?:\.\d*)?`` reads the same numbers with one split
LONG_DIGITS = "N10 G1 G90 S1000 M3" + "9" * 20_000 + "Q\n"


@pytest.mark.parametrize(
    "dialect", ["rs274ngc", "grbl", "fanuc", "haas", "fanuc_lathe", "siemens840d", "sandia"]
)
def test_a_run_of_twenty_thousand_digits_is_read_at_once(dialect: str) -> None:
    start = time.process_time()
    out = check_one("reader", dialect, LONG_DIGITS)
    assert out.ok, out
    assert time.process_time() - start < 2.0
