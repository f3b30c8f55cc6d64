"""The environment to run LinuxCNC's ``rs274`` in without crosstalk between runs.

rs274 2.9 shares its tool table through the file ``$HOME/.tool.mmap``: two runs at once
with different tool tables (parallel tests, other users of the machine) read each other's
tools ("Requested tool N not found in the tool table") or die. A HOME of the run's own
keeps each run to its table.
"""

from __future__ import annotations

import os
from pathlib import Path


def rs274_env(home: Path) -> dict[str, str]:
    """``os.environ`` with HOME set to ``home`` (a directory of this run's own)."""
    return {**os.environ, "HOME": str(home)}
