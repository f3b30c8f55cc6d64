"""``--dialect auto`` guesses a program's dialect from its content as well as its suffix.

The programs in ``tests/detect/`` are written as the common posts of each control write them
(a Fanuc 0i mill and lathe, a Haas mill with G187/G154 and a Haas lathe with M133 live
tooling, a Sinumerik 840D part program, a Grbl laser job, a LinuxCNC program with O-word
subroutines, the Sandia generic language); the truth is the control each was written for.
The larger corpora give the same answer the reader tests use: tests/dialects/fanuc reads
programs named ``lathe``/``turn`` in lathe mode (test_convert_fanuc_reader), the LinuxCNC
corpus is RS274/NGC, tests/dialects/siemens840d is Siemens.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from gcode import detect
from gcode.detect import Hint
from gcode.registry import REGISTRY, guess_dialect

HERE = Path(__file__).resolve().parent
PROGRAMS = HERE / "detect"


def head(path: Path) -> str:
    return path.read_bytes()[: detect.HEAD_BYTES].decode("utf-8", "replace")


@pytest.mark.parametrize(
    ("name", "dialect"),
    [
        ("fanuc_mill.nc", "fanuc"),
        ("fanuc_macro.nc", "fanuc"),
        ("fanuc_lathe.nc", "fanuc_lathe"),
        ("haas_mill.nc", "haas"),
        ("haas_lathe.nc", "haas_lathe"),
        ("siemens.mpf", "siemens840d"),
        ("siemens.nc", "siemens840d"),
        ("grbl.gcode", "grbl"),
        ("linuxcnc.nc", "rs274ngc"),
        ("sandia.txt", "sandia"),
        ("plain.nc", "rs274ngc"),
    ],
)
def test_each_dialect_is_recognised_from_its_content(name: str, dialect: str) -> None:
    path = PROGRAMS / name
    guess = guess_dialect(head(path), path.suffix)
    assert guess.dialect == dialect, guess
    assert not guess.conflict and not guess.plausible, guess
    if name != "plain.nc":
        assert guess.source == "content" and guess.reason


def test_a_program_without_markers_is_read_as_the_default_without_a_word() -> None:
    guess = guess_dialect(head(PROGRAMS / "plain.nc"), ".nc")
    assert (guess.dialect, guess.source) == ("rs274ngc", "default")


FANUC_DIR = HERE / "dialects" / "fanuc"


@pytest.mark.parametrize("path", sorted(FANUC_DIR.glob("*.nc")), ids=lambda p: p.stem)
def test_every_fanuc_test_program_is_read_as_its_reader_test_reads_it(path: Path) -> None:
    lathe = "lathe" in path.stem or "turn" in path.stem
    guess = guess_dialect(head(path), path.suffix)
    assert guess.dialect == ("fanuc_lathe" if lathe else "fanuc")


def test_the_linuxcnc_corpus_stays_rs274ngc_by_content_alone() -> None:
    programs = sorted((HERE / "data" / "corpus" / "ngc").glob("*.ngc"))
    assert len(programs) == 56
    wrong = {p.name: guess_dialect(head(p), "").dialect for p in programs}
    assert {k: v for k, v in wrong.items() if v != "rs274ngc"} == {}


def test_the_siemens_test_programs_stay_siemens() -> None:
    programs = sorted((HERE / "dialects" / "siemens840d").glob("*.[mMsS][pP][fF]"))
    assert programs
    for p in programs:
        assert guess_dialect(head(p), p.suffix).dialect == "siemens840d", p.name


def test_lathe_and_mill_evidence_together_is_ambiguous() -> None:
    text = "%\nO1000\nG21 G17 G96 S200 M3\nT0101 M6\nG0 X10. Y5. Z2.\nG43 H1 Z5.\nG1 W-2.\nM30\n%\n"
    guess = guess_dialect(text, ".nc")
    assert guess.dialect == "fanuc"
    assert len(guess.plausible) == 1 and guess.plausible[0].startswith("fanuc_lathe")


def test_content_that_contradicts_the_suffix_wins_and_says_so() -> None:
    guess = guess_dialect(head(PROGRAMS / "fanuc_macro.nc"), ".ngc")
    assert guess.dialect == "fanuc"  # WHILE [...] DO1 is no RS274/NGC
    assert "suffix .ngc names rs274ngc" in guess.conflict


def test_decisive_content_wins_over_a_suffix_it_has_no_evidence_for() -> None:
    guess = guess_dialect(head(PROGRAMS / "fanuc_mill.nc"), ".mpf")
    assert guess.dialect == "fanuc" and "siemens840d" in guess.conflict


def test_weak_content_leaves_the_suffix_in_charge_and_says_so() -> None:
    text = "%\nO1000\nG0 X10. Y5.\nM30\n%\n"  # LinuxCNC takes all of it too
    guess = guess_dialect(text, ".ngc")
    assert guess.dialect == "rs274ngc" and guess.source == "suffix"
    assert "looks like fanuc" in guess.conflict


def test_comments_do_not_count_as_code() -> None:
    text = "(o100 sub is how LinuxCNC would do it; WHILE [#1 LT 3] DO1)\nG0 X1\nM2\n"
    assert guess_dialect(text, "").source == "default"


def test_a_new_dialect_is_one_row_with_its_hints() -> None:
    """The sniffer is data driven: a row (name, suffix, hints) is all a dialect needs."""
    table = [(e.name, e.hints) for e in REGISTRY if e.reader is not None]
    table.append(
        ("mach3", (Hint(r"\bM98[ \t]*P", 2, "M98"), Hint(r"\(\s*MACH3", 3, "Mach3", raw=True)))
    )
    text = "(MACH3 post)\nG0 X1 Y1\nM98 P100\nM30\n"
    suffixes = {".tap": "mach3", ".ngc": "rs274ngc"}
    guess = detect.guess(text, ".nc", table, suffixes, "rs274ngc")
    assert guess.dialect == "mach3" and "Mach3" in guess.reason
    guess = detect.guess(head(PROGRAMS / "fanuc_macro.nc"), ".tap", table, suffixes, "rs274ngc")
    assert guess.dialect == "fanuc" and "suffix .tap names mach3" in guess.conflict


# --------------------------------------------------------------------------- the CLI
def cnc(*args: str):
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


def test_canon_reads_a_guessed_lathe_program_as_a_lathe_and_says_why() -> None:
    res = cnc("canon", str(PROGRAMS / "fanuc_lathe.nc"))
    assert res.exit_code == 0, res.output
    # X52. is a diameter on a Fanuc lathe: the canonical X is the radius, 26 mm
    assert "STRAIGHT_TRAVERSE(26.0000, 0.0000, 2.0000" in res.stdout
    (line,) = res.stderr.splitlines()
    assert line.startswith(f"{PROGRAMS / 'fanuc_lathe.nc'}: note[DIALECT-GUESS]: read as ")
    assert "fanuc_lathe" in line and ("G50 S" in line or "G70-G73" in line)


def test_quiet_says_nothing_and_a_plain_program_says_nothing_by_default() -> None:
    assert cnc("-q", "canon", str(PROGRAMS / "fanuc_lathe.nc")).stderr == ""
    assert cnc("canon", str(PROGRAMS / "plain.nc")).stderr == ""
    verbose = cnc("-v", "canon", str(PROGRAMS / "plain.nc")).stderr
    assert "read as rs274ngc (no dialect markers)" in verbose


def test_a_named_dialect_is_never_second_guessed(tmp_path: Path) -> None:
    res = cnc("canon", "--dialect", "rs274ngc", str(PROGRAMS / "fanuc_mill.nc"))
    assert res.exit_code == 0 and res.stderr == ""


def test_check_warns_on_stderr_when_two_dialects_fit(tmp_path: Path) -> None:
    src = tmp_path / "part.nc"
    src.write_text("%\nO1000\nG21 G17 G96 S200 M3\nT0101 M6\nG0 X10. Y5. Z2.\nM30\n%\n")
    res = cnc("check", "-f", "json", str(src))
    (line,) = res.stderr.splitlines()
    assert "warning[DIALECT-AMBIGUOUS]" in line and "--dialect" in line
    assert res.stdout.lstrip().startswith("{")  # the report itself is untouched


def test_a_hostile_head_is_sniffed_in_linear_time() -> None:
    start = time.perf_counter()
    for text in ("WHILE [" * 3000, "\n".join(["WHILE [ [ [ [ DO"] * 1100), "(" * 16000):
        assert guess_dialect(text[: detect.HEAD_BYTES], ".nc").dialect == "rs274ngc"
    assert time.perf_counter() - start < 5.0


def test_a_one_block_g71_with_d_is_a_haas_lathe() -> None:
    text = (
        "%\nO0002\nG28 U0 W0\nT101\nG50 S3000\nG96 S1100 M03\nG00 X2.5 Z.15\n"
        "G71 P100 Q200 U.01 W.005 D.025 F.012\nN100 G00 X1.2\nN200 G01 X2.5 Z-1.\nM30\n%\n"
    )
    assert guess_dialect(text, ".nc").dialect == "haas_lathe"


def test_a_lathe_profile_tips_a_close_fanuc_call_to_the_lathe_reader(tmp_path: Path) -> None:
    text = "%\nO1000\nG21\nG00 X50. Y0 Z2.\nS500 M03\nG01 Z-20. F100.\nM05\nM30\n%\n"
    assert guess_dialect(text, ".nc").dialect == "fanuc"
    guess = guess_dialect(text, ".nc", lathe=True)
    assert guess.dialect == "fanuc_lathe" and "machine profile is a lathe" in guess.reason
    src = tmp_path / "O1000.nc"
    src.write_text(text)
    profile = tmp_path / "lathe.toml"
    assert cnc("machine", "init", "--kind", "lathe", "-o", str(profile)).exit_code == 0
    res = cnc("canon", str(src))  # canon knows no machine: the mill reading
    assert "read as fanuc (" in res.stderr
    res = cnc("check", "-m", str(profile), str(src))
    assert "read as fanuc_lathe (" in res.stderr


def _sample_heads() -> list[str]:
    """Heads of every dialect: the detection programs and the start of a few of each
    corpus (4 KiB: a whole head of every file costs seconds of searching)."""
    heads = [head(p) for p in sorted(PROGRAMS.glob("*.*")) if p.suffix != ".md"]
    for folder in ("dialects/fanuc", "dialects/siemens840d", "dialects/mach3", "realworld/ngc"):
        files = sorted(p for p in (HERE / folder).rglob("*") if p.is_file() and p.suffix != ".md")
        heads += [head(p)[:4096] for p in files[:3]]
    # a non-ASCII head: the long s folds to "s" under re.I, which lower() does not do
    heads.append("%\nO0001\nTRAN\u017f X1\nG154 P\u017f\n\u017fUPA\nM30\n%\n")
    return heads


def test_hint_needles_are_what_the_patterns_need() -> None:
    """The strings a hint's pattern cannot match without (read from the pattern by hand)."""
    needles = detect._needles
    assert needles(r"\bM6[2-8][ \t]*P") == {f"m6{d}" for d in range(2, 9)}
    assert needles(r"\bG0?5\.1[ \t]*Q") == {"g05.1", "g5.1"}
    assert needles(r"\b(?:A?TRANS|A?ROT|A?SCALE|A?MIRROR)\b") == {"trans", "rot", "scale", "mirror"}
    assert needles(r"\bIF[ \t]*\[[^\n]*\][ \t]*(?:GOTO|THEN)") == {"goto", "then"}
    assert needles(r"#<[_a-z]") == {"#<"}
    assert needles(r"(?<![A-Z#])[UW][ \t]*-?\.?\d") == {"u", "w"}
    assert needles(r"(?:G1|\d)X") == {"x"}
    for nothing in (r"", r"\A(?![\s\S]*Y)(?=[\s\S]*Z)", r"[^\n]*\d+", r"(?:G1|\d)?"):
        assert needles(nothing) is None


def test_hint_needles_never_hide_a_match() -> None:
    """Wherever a hint's pattern matches a head, one of its needles is in that head, and
    every guess (with each dialect's score and matched hints) is the one made without
    needles."""
    heads = _sample_heads()
    patterns = {(h.pattern, h.raw) for entry in REGISTRY for h in entry.hints}
    for text in heads:
        view = detect._Head(text)
        for pattern, raw in patterns:
            found = detect._compiled(pattern).search(view.raw if raw else view.code)
            wanted = detect._needles(pattern)
            if found and wanted is not None and view.lower is not None:
                lowered = view.lower[0] if raw else view.lower[1]
                assert any(n in lowered for n in wanted), (pattern, text[:80])

    def guesses() -> list[tuple[object, ...]]:
        out: list[tuple[object, ...]] = []
        for text in heads:
            for lathe in (False, True):
                g = guess_dialect(text, ".nc", lathe)
                out.append((g, [(c.name, c.score, c.matched) for c in g.candidates]))
        return out

    with_needles = guesses()
    saved = detect._PARSE
    detect._needles.cache_clear()
    try:
        detect._PARSE = None
        assert guesses() == with_needles
    finally:
        detect._PARSE = saved
        detect._needles.cache_clear()
