"""Regenerate tests/stepnc/turning/<name>.stp and the golden canonical output <name>.can.

Run from the repository root: ``python tests/stepnc/turning/regen.py``. Review the diff of
the .can files before accepting them (README.md says how each program was checked by hand).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent.parent))
sys.path.insert(0, str(HERE))

from turning_programs import PROGRAMS, REFUSED, render  # noqa: E402

from kernel.ir import canon  # noqa: E402
from stepnc.to_canon import canon_from_file  # noqa: E402


def main() -> None:
    for name in PROGRAMS:
        stp = HERE / f"{name}.stp"
        stp.write_text(render(name))
        cmds = canon_from_file(str(stp), None, "default")
        (HERE / f"{name}.can").write_text("".join(f"{ln}\n" for ln in canon.write_text(cmds)))
        print(name)
    for name, (prog, _, _) in REFUSED.items():
        (HERE / f"refused_{name}.stp").write_text(render(name, prog))


if __name__ == "__main__":
    main()
