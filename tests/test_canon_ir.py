"""The IR's text and JSON-lines forms against the reference interpreters' outputs.

Every ``.canon`` file in the corpus (LinuxCNC rs274) and in our goldens must read back into
command objects, and writing those objects must reproduce each command's text exactly (the
NIST print-itself format: four decimals, NISTIR argument order), so goldens and round
trips can be compared as data.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.canon_equiv import compare
from tests.data_paths import DATA

ROOT = Path(__file__).resolve().parent
CORPUS = DATA / "corpus"
CANON_FILES = sorted((CORPUS / "ngc").glob("*.canon")) + sorted(
    (ROOT / "golden" / "ngc").glob("*.canon")
)


def _body(line: str) -> str:
    """``   12 N..... NAME(args)`` -> ``NAME(args)``."""
    return re.sub(r"^\s*\d+\s+N[.\d]*\s+", "", line).strip()


MOTION_NAMES = {c.NAME for c in canon.MOTIONS}


@pytest.mark.parametrize("path", CANON_FILES, ids=[p.name for p in CANON_FILES])
def test_reference_canon_text_reads_and_round_trips(path: Path) -> None:
    """Every command parses; motions print exactly as rs274 printed them; text round-trips."""
    lines = path.read_text().splitlines()
    texts = list(canon.read_text(lines, str(path)))
    assert texts, "no commands read"
    for tc in texts:
        if tc.name in canon.LINUXCNC_ONLY and tc.name not in canon.BY_NAME:
            continue  # LinuxCNC-only commands carry no IR meaning (corpus README)
        cmd = canon.parse_command(tc, str(path))
        if isinstance(cmd, canon.NurbsFeed) and cmd.elided:
            continue  # LinuxCNC prints NURBS_FEED without its data
        if tc.name in MOTION_NAMES:
            # rs274 prints a negative zero as -0.0000; we print 0.0000
            assert cmd.to_text() == _body(lines[tc.line - 1]).replace("-0.0000", "0.0000")
        (again,) = canon.read_text([cmd.to_text()])
        assert canon.parse_command(again).to_text() == cmd.to_text()


def test_jsonl_round_trip_keeps_every_command_and_its_source() -> None:
    path = CORPUS / "ngc" / "axis__images__axis.canon"
    commands = list(canon.read_commands(path.read_text().splitlines(), str(path)))
    rows = list(canon.to_jsonl(commands))
    back = [canon.from_json(json.loads(r)) for r in rows]
    assert back == commands
    assert all(b.source == c.source for b, c in zip(back, commands, strict=True))


def test_a_reference_output_is_equivalent_to_itself_and_not_to_a_moved_copy() -> None:
    path = CORPUS / "ngc" / "axis__images__axis.canon"
    lines = path.read_text().splitlines()
    assert compare(lines, lines) == []
    moved = [ln.replace("STRAIGHT_FEED(", "STRAIGHT_FEED(1", 1) for ln in lines]
    assert compare(moved, lines) != []


def test_malformed_canon_text_is_a_located_diagnostic() -> None:
    with pytest.raises(Diagnostic) as info:
        list(canon.read_commands(["STRAIGHT_FEED(1.0, 2.0, abc)"], "bad.canon"))
    assert info.value.location.line == 1
    assert info.value.location.file == "bad.canon"
