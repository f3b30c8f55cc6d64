"""Regenerate the goldens of the shop-program suite (tests/realworld/shop/manifest.toml).

For every program the manifest expects to run: ``<program>.canon``, the IR our reader gives
(``cnc canon`` text), and, where LinuxCNC's ``rs274`` is installed, ``<program>.rs274.canon``:
the IR written as RS274/NGC by our writer (``cnc convert --to ngc``) and read back by
``rs274`` (the second, independent reading the suite compares the golden with). Run from the
repository root: ``python tests/realworld/shop/regen.py [name ...]``. Review the diffs by
hand before committing them: the goldens are expectations, not snapshots.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from kernel.ir import canon
from tests.convert_support import rs274
from tests.shop_suite import TOOL_TABLE, entries, ngc_text, our_ir


def main(names: list[str]) -> None:
    for entry in entries():
        if names and entry.name not in names:
            continue
        if entry.expect != "runs":
            continue
        ir = our_ir(entry)
        golden = entry.path.parent / (entry.path.name + ".canon")
        golden.write_text("\n".join(canon.write_text(ir)) + "\n")
        if entry.rs274 and shutil.which("rs274"):
            with tempfile.TemporaryDirectory() as tmp:
                lines = rs274(ngc_text(ir), TOOL_TABLE, Path(tmp))
            second = entry.path.parent / (entry.path.name + ".rs274.canon")
            second.write_text("\n".join(lines) + "\n")
        print(entry.name)


if __name__ == "__main__":
    main(sys.argv[1:])
