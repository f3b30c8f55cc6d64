"""Diagnostics for people (cli.excerpt): the source line under the header with a caret at
the column, the user's own spelling, the values that failed, and ``-v``'s explanation.

Expected columns come from the program text written here (``str.index`` of the word), the
values from closed forms, the explanations from ``docs/errors.md`` read by this test.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli import excerpt, explain
from cli.explanations import EXPLANATIONS
from cli.main import cli
from gcode.ngc.interpreter import interpret_text
from kernel.diagnostics import Diagnostic, Location

ROOT = Path(__file__).resolve().parent.parent
DOC = (ROOT / "docs" / "errors.md").read_text(encoding="utf-8")


def _stderr(tmp_path: Path, text: str, *args: str, name: str = "p.ngc") -> list[str]:
    """``cnc [args] canon PROG`` on ``text``: its standard error, as lines (exit 1)."""
    prog = tmp_path / name
    prog.write_bytes(text.encode("utf-8"))
    res = CliRunner().invoke(cli, [*args, "canon", str(prog)])
    assert res.exit_code == 1, res.output
    return res.stderr.splitlines()


def _caret(lines: list[str], source: str) -> tuple[int, int, str]:
    """The excerpt under a header: (index in the shown line where the caret points, caret
    length, shown line), located by the gutter line that holds ``source``."""
    shown = next(i for i, line in enumerate(lines) if source in line and " | " in line)
    caret_line = lines[shown + 1]
    start = caret_line.index("^")
    length = len(caret_line) - start
    assert set(caret_line[start + 1 :]) <= {"~"}
    return start, length, lines[shown]


def _arc_radius_program() -> tuple[str, int]:
    text = "g21 g90\ng1 x1 f100\ng2 x2 y0 r0.1\nm2\n"
    return text, text.splitlines()[2].index("r0.1") + 1


def test_caret_under_the_r_word_in_the_users_own_case(tmp_path: Path) -> None:
    text, column = _arc_radius_program()
    lines = _stderr(tmp_path, text)
    assert lines[0].startswith(f"{tmp_path / 'p.ngc'}:3:{column}: error[NGC-ARC-R-TOO-SMALL]: ")
    start, length, shown = _caret(lines, "g2 x2 y0 r0.1")
    assert shown.startswith("3 | ")  # the line number in the gutter
    assert shown[start:] == "r0.1" and length == len("r0.1")


def test_arc_radius_too_small_gives_r_and_half_the_chord(tmp_path: Path) -> None:
    text, _ = _arc_radius_program()
    header = _stderr(tmp_path, text)[0]
    half = math.dist((1.0, 0.0), (2.0, 0.0)) / 2  # start X1 Y0, end X2 Y0
    assert header.split(": error[NGC-ARC-R-TOO-SMALL]: ")[1].startswith(
        "arc radius too small to reach end point"  # rs274's text first
    )
    assert f"|R| is {0.1:.4f}" in header and f"half the chord is {half:.4f}" in header


def test_arc_centre_mismatch_gives_both_radii() -> None:
    # from X0 Y0 round I3 J0 (centre X3 Y0) to X10 Y0
    r_start, r_end = math.dist((0, 0), (3, 0)), math.dist((10, 0), (3, 0))
    with pytest.raises(Diagnostic) as info:
        list(interpret_text("G21 G90\nG1 X0 Y0 F100\nG2 X10 Y0 I3 J0\nM2\n", "p.ngc"))
    assert info.value.code == "NGC-ARC-RADIUS"
    message = info.value.message
    assert message.startswith("radius to end of arc differs from radius to start")
    assert f"arc radius {r_start:.4f} but end point is {r_end:.4f} from the centre" in message


def test_comp_entry_too_short_gives_move_and_tool_radius() -> None:
    # G41.1 D4: a tool of radius 2; the entry move X0 -> X1 is 1 long
    program = "G21 G17 G90\nG0 X0 Y0\nG41.1 D4 G1 X1 Y0 F100\nM2\n"
    with pytest.raises(Diagnostic) as info:
        list(interpret_text(program, "p.ngc"))
    assert info.value.code == "NGC-COMP-ENTRY-TOO-SHORT"
    message = info.value.message
    assert f"{1.0:.4f} long" in message and f"tool radius {2.0:.4f}" in message


def test_unknown_code_is_quoted_as_written(tmp_path: Path) -> None:
    text = "G1 X1 F100\n\tg07.50 X1\n"
    lines = _stderr(tmp_path, text)
    column = text.splitlines()[1].index("g07.50") + 1
    assert f":2:{column}: error[NGC-UNKNOWN-G]: unknown G code used: g07.50" in lines[0]
    start, length, shown = _caret(lines, "g07.50 X1")
    assert "\t" not in shown  # a tab shows as blanks, the caret counts them alike
    assert shown[start:].startswith("g07.50") and length == len("g07.50")


def test_tabs_keep_the_caret_under_the_word(tmp_path: Path) -> None:
    text = "G21\nG1\tX1\tF100\nG2\tX2\tY0\tR0.1\n"
    lines = _stderr(tmp_path, text)
    start, length, shown = _caret(lines, "R0.1")
    assert shown[start : start + length] == "R0.1"


def test_long_line_is_cut_around_the_column(tmp_path: Path) -> None:
    comment = "(" + "a" * 400 + ")"
    text = f"G1 X1 F100\nG1 X2 {comment} G7.5 {comment}\n"
    lines = _stderr(tmp_path, text)
    column = text.splitlines()[1].index("G7.5") + 1
    assert f":2:{column}: error[NGC-UNKNOWN-G]" in lines[0]
    start, length, shown = _caret(lines, "G7.5")
    assert shown[start : start + length] == "G7.5"
    body = shown.split(" | ", 1)[1]
    assert body.startswith("…") and body.endswith("…") and len(body) <= excerpt.WIDTH + 2


def test_stepnc_diagnostic_shows_the_instance_line(tmp_path: Path) -> None:
    text = (
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n"
        "FILE_NAME('','',(''),(''),'','','');\nFILE_SCHEMA(('MACHINING_SCHEMA'));\nENDSEC;\n"
        "DATA;\n#1=PROJECT('p',#2,(#999),$,$,$);\n#2=WORKPLAN('w',(),$,$,$);\nENDSEC;\n"
        "END-ISO-10303-21;\n"
    )
    number = next(n for n, line in enumerate(text.splitlines(), 1) if line.startswith("#1="))
    lines = _stderr(tmp_path, text, name="p.stp")
    assert f"p.stp:#1:{number}:1: error[P21-DANGLING-REF]: #999" in lines[0]
    start, length, shown = _caret(lines, "#1=PROJECT")
    assert shown.startswith(f"{number} | ") and shown[start : start + length] == "#1"


def _documented_meaning(code: str) -> str:
    row = next(line for line in DOC.splitlines() if line.startswith(f"| `{code}` |"))
    return row.split(" | ", 1)[1].rstrip(" |").replace("`", "")


def test_verbose_adds_the_explanation_from_docs(tmp_path: Path) -> None:
    text, _ = _arc_radius_program()
    plain = _stderr(tmp_path, text)
    loud = _stderr(tmp_path, text, "-v")
    meaning = _documented_meaning("NGC-ARC-R-TOO-SMALL")
    assert not any("help:" in line for line in plain)
    assert any(line.strip() == f"= help: NGC-ARC-R-TOO-SMALL: {meaning}" for line in loud)


def test_quiet_prints_the_header_only(tmp_path: Path) -> None:
    text, _ = _arc_radius_program()
    lines = _stderr(tmp_path, text, "-q")
    assert len(lines) == 1 and "error[NGC-ARC-R-TOO-SMALL]" in lines[0]


def test_a_remembered_text_wins_over_the_file(tmp_path: Path) -> None:
    prog = tmp_path / "gone.ngc"  # no such file: the text came from standard input
    excerpt.remember(str(prog), "G0 X0\nG1 X1 Q5\n")
    out = excerpt.render("hdr", Location(str(prog), 2, 7), "NGC-Q-UNUSED").splitlines()
    assert out[2] == "2 | G1 X1 Q5" and out[3] == "  |       ^~"


def test_a_large_file_is_read_at_the_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(excerpt, "_CACHE_BYTES", 16)  # too big to keep: read by offset
    prog = tmp_path / "big.ngc"
    lines = [f"G1 X{n} F100" for n in range(1, 40)] + ["G1 X1\fY2 Q5"]
    prog.write_text("\r\n".join(lines) + "\r\n")
    for number in (1, 17, 40):
        out = excerpt.render("h", Location(str(prog), number, 1)).split("\n")
        assert out[2] == f"{number} | {lines[number - 1]}"


def test_explanations_module_matches_docs() -> None:
    assert (ROOT / "cli" / "explanations.py").read_text(encoding="utf-8") == explain.module_text(
        explain.parse(DOC)
    ), "docs/errors.md changed: run python -m cli.explain"


def test_every_documented_code_has_an_explanation() -> None:
    cells = re.findall(r"^\| ((?:`[A-Z][A-Z0-9.-]+`[ ,/or]*)+) \|", DOC, re.M)
    codes = {c for cell in cells for c in re.findall(r"`([A-Z][A-Z0-9.-]+)`", cell)}
    assert len(codes) > 300
    assert {c for c in codes if not EXPLANATIONS.get(c)} == set()


_RAISED = re.compile(
    r'(?:Diagnostic|DiagnosticRecord|_fail|error|fail|Finding|SimFinding|find)\(\s*f?"'
    r'([A-Z][A-Z0-9]*-[A-Z0-9.-]+)"'
)


def test_every_code_the_code_base_raises_is_documented() -> None:
    raised: dict[str, str] = {}
    for pkg in ("cli", "gcode", "kernel", "stepnc"):
        for path in sorted((ROOT / pkg).rglob("*.py")):
            for m in _RAISED.finditer(path.read_text(encoding="utf-8")):
                raised.setdefault(m.group(1), str(path.relative_to(ROOT)))
    assert len(raised) > 300
    missing = {c: p for c, p in raised.items() if f"`{c}`" not in DOC}
    assert missing == {}


def test_check_text_shows_the_excerpt_and_with_v_the_meaning(tmp_path: Path) -> None:
    text, column = _arc_radius_program()
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    res = CliRunner().invoke(cli, ["-v", "check", str(prog)])
    lines = res.output.splitlines()
    head = next(i for i, line in enumerate(lines) if "CNC001/NGC-ARC-R-TOO-SMALL" in line)
    assert f"p.ngc:3:{column}:" in lines[head]
    start, length, shown = _caret(lines[head:], "g2 x2 y0 r0.1")
    assert shown[start : start + length] == "r0.1"
    meaning = _documented_meaning("NGC-ARC-R-TOO-SMALL")
    assert f"= help: NGC-ARC-R-TOO-SMALL: {meaning}" in res.output
