"""Regenerate tests/stepnc/<name>.stp and the golden canonical output <name>.can.

Run from the repository root: ``python tests/stepnc/regen.py``. Review the diff of the
.can files before accepting them: the goldens pin the toolpath generators' output, while
the tests also check each program independently (gouge check, depths reached).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))
sys.path.insert(0, str(HERE))

from programs import PROGRAMS, render  # noqa: E402

from kernel.ir import canon  # noqa: E402
from stepnc.to_canon import canon_from_file  # noqa: E402


def main() -> None:
    for name in PROGRAMS:
        stp = HERE / f"{name}.stp"
        stp.write_text(render(name))
        cmds = canon_from_file(str(stp), None, "default")
        (HERE / f"{name}.can").write_text("".join(f"{ln}\n" for ln in canon.write_text(cmds)))
        print(name)


if __name__ == "__main__":
    main()
