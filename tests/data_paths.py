"""Where the tests' reference data live (``tests/data``; origins in ``tests/data/README.md``).

Every path is inside the clone: the suite never reads a folder beside the project.
"""

from __future__ import annotations

from pathlib import Path

DATA = Path(__file__).resolve().parent / "data"
#: LinuxCNC 2.9 sample programs with the canonical commands its ``rs274`` printed for them.
CORPUS_NGC = DATA / "corpus" / "ngc"
#: ISO 14649 Example 1 with NIST's interpreter output and tool files.
CORPUS_STEPNC = DATA / "corpus" / "stepnc"


def corpus_programs() -> list[Path]:
    """The LinuxCNC corpus programs, sorted; an empty corpus is an error, never a skip."""
    programs = sorted(CORPUS_NGC.glob("*.ngc"))
    if not programs:
        raise FileNotFoundError(f"no programs in {CORPUS_NGC}")
    return programs
