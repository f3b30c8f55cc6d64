"""The README's 5-minute tour works as written (issue 6).

Every ``cnc ...`` line of the README's tour is run as a newcomer would type it after the
install command, in a fresh directory that sees the repository's ``docs/`` and ``tests/``.
It must exit 0, or the code its comment line announces with ``(exit code N)``; it must
never print a Python traceback.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()


def tour_commands() -> list[tuple[str, int]]:
    """(command line, expected exit code) of each ``cnc`` line in the tour's code blocks."""
    tour = README.split("## A 5-minute tour", 1)[1].split("\n## ", 1)[0]
    out: list[tuple[str, int]] = []
    for block in re.findall(r"```sh\n(.*?)```", tour, flags=re.S):
        comment = ""
        for line in block.splitlines():
            line = line.strip()
            if line.startswith("#"):
                comment = line
            elif line.startswith("cnc "):
                m = re.search(r"\(exit code (\d)\)", comment)
                out.append((line, int(m.group(1)) if m else 0))
    return out


TOUR = tour_commands()


def test_the_tour_has_commands() -> None:
    assert len(TOUR) >= 5


def test_tour_commands_work_as_written_in_order(tmp_path: Path) -> None:
    """The commands run one after the other in one fresh directory, as a newcomer types
    them (later ones use files earlier ones wrote); it sees the repository's docs/ and
    tests/, so a second run never meets the files of the first."""
    for name in ("docs", "tests"):
        (tmp_path / name).symlink_to(ROOT / name)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    for line, code in TOUR:
        argv = shlex.split(line)
        cmd = [sys.executable, "-m", "cli.main", *argv[1:]]
        proc = subprocess.run(
            cmd, cwd=tmp_path, capture_output=True, text=True, timeout=300, env=env
        )
        assert "Traceback" not in proc.stderr, f"{line}\n{proc.stderr}"
        assert proc.returncode == code, f"{line}\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}"
