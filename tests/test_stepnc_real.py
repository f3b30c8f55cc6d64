"""The real-file suite: STEP-NC files written by other tools (tests/stepnc/real/).

Every Part 21 file in the folder has an entry in ``manifest.json``: golden IR (the
canonical commands of the tool that wrote the reference output, compared command for
command in NIST's print form), or a construct that is refused with a located diagnostic.
The suite passes only at 100 %: a file without an entry fails, as does any unmet entry.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from cli.main import cli
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from stepnc.to_canon import canon_from_file

REAL = Path(__file__).resolve().parent / "stepnc" / "real"
MANIFEST: list[dict[str, Any]] = json.loads((REAL / "manifest.json").read_text())["files"]
SUFFIXES = {".stp", ".step", ".p21", ".stpnc", ".238"}


def test_every_real_file_has_an_expectation_and_a_source() -> None:
    files = sorted(p.name for p in REAL.iterdir() if p.suffix.lower() in SUFFIXES)
    assert files, "the real-file suite is empty"
    assert sorted(e["file"] for e in MANIFEST) == files
    sources = (REAL / "SOURCES.md").read_text()
    assert all(f"`{name}`" in sources for name in files)


@pytest.mark.parametrize("entry", MANIFEST, ids=[e["file"] for e in MANIFEST])
def test_real_file_meets_its_expectation(entry: dict[str, Any]) -> None:
    path = str(REAL / entry["file"])
    tools = str(REAL / entry["tools"]) if entry.get("tools") else None
    if entry["expect"] == "golden":
        ours = list(canon_from_file(path, tools, "nist"))
        with open(REAL / entry["golden"]) as fh:
            theirs = [canon.parse_command(t) for t in canon.read_text(fh)]
        assert len(ours) == len(theirs) == entry["commands"]
        diff = [
            (i, a.to_text(), b.to_text())
            for i, (a, b) in enumerate(zip(ours, theirs, strict=True))
            if a.to_text() != b.to_text()
        ]
        assert diff == []
    else:
        assert entry["expect"] == "refused"
        with pytest.raises(Diagnostic) as info:
            list(canon_from_file(path, tools, "nist"))
        assert info.value.code == entry["code"]
        assert entry["construct"] in info.value.message
        assert info.value.location is not None and info.value.location.line > 0


def test_real_files_read_have_no_false_check_error_on_the_default_machine() -> None:
    files = [str(REAL / e["file"]) for e in MANIFEST if e["expect"] == "golden"]
    result = CliRunner().invoke(cli, ["check", "--format", "json", *files])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    errors = [f for e in doc["files"] for f in e["findings"] if f["severity"] == "error"]
    assert errors == []
