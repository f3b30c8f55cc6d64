"""``cnc canon`` reads STEP-NC by content and matches NIST's ISO 14649 interpreter (issue 5).

``cnc canon tests/data/corpus/stepnc/ex1.stp`` with NIST's tool file must print NIST's
``ex1.can`` command for command; a Part 21 file named ``.ngc`` is still read as Part 21.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from click.testing import CliRunner

from cli.main import cli
from kernel.ir import canon
from tests.data_paths import CORPUS_STEPNC

CORPUS = CORPUS_STEPNC


def _commands(text: str) -> list[str]:
    return [canon.parse_command(tc).to_text() for tc in canon.read_text(text.splitlines())]


def test_cnc_canon_of_example_1_is_nists_output_command_for_command() -> None:
    res = CliRunner().invoke(
        cli, ["canon", str(CORPUS / "ex1.stp"), "--tool-table", str(CORPUS / "iso14649.tool_ex1")]
    )
    assert res.exit_code == 0, res.output
    ours = _commands(res.output)
    ref = _commands((CORPUS / "ex1.can").read_text())
    assert len(ours) == len(ref) == 538
    assert ours == ref


def test_part21_is_recognised_by_content_not_extension(tmp_path: Path) -> None:
    disguised = tmp_path / "ex1.ngc"
    shutil.copy(CORPUS / "ex1.stp", disguised)
    res = CliRunner().invoke(
        cli, ["canon", str(disguised), "--tool-table", str(CORPUS / "iso14649.tool_ex1")]
    )
    assert res.exit_code == 0, res.output
    assert "STRAIGHT_FEED" in res.output
