"""Start-up cost: ``cnc canon`` of a plain program must not load the heavy libraries.

Every import is paid on each run; a CI job over many small programs spends most of its time
starting Python (issue 22). numpy is needed only by the fast lane (files of a mebibyte and
more) and by cutter compensation, so a two-line program runs without it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: libraries ``cnc canon`` of a plain program has no use for
HEAVY = (
    "matplotlib",
    "scipy",
    "rich",
    "cadquery",
    "OCP",
    "lark",
    "pandas",
    "pyarrow",
    "numba",
    "numpy",
)

#: our own modules (and what they alone import) that ``cnc canon`` without a machine profile
#: or a target dialect has no use for: the machine profile and its TOML reader, the writers
LAZY = ("kernel.machine", "tomllib", "gcode.write")

_PROBE = """
import json, sys, runpy, io, contextlib
sys.argv = ["cnc", *sys.argv[1:]]
out = io.StringIO()
with contextlib.redirect_stdout(out):
    try:
        runpy.run_module("cli.main", run_name="__main__")
    except SystemExit as e:
        code = e.code
    else:
        code = 0
print(json.dumps({"code": code, "out": out.getvalue(), "modules": sorted(sys.modules)}))
"""


def _modules_after(*args: str) -> dict[str, object]:
    """Exit code, output and the loaded modules of ``cnc ARGS`` run in a fresh interpreter."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [sys.executable, "-c", _PROBE, *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=120,
        check=True,
    )
    result: dict[str, object] = json.loads(proc.stdout.strip().splitlines()[-1])
    return result


@pytest.mark.parametrize(
    "program",
    [
        "G21 G90\nG0 X1 Y2\nG1 Z-1 F100\nM2\n",
        "G21\nG1 X1 F100\nG2 X2 Y1 R1\nG3 X1 Y0 I-1 J0\n#1=2\nG0 X[#1*2]\nM2\n",
    ],
    ids=["lines", "arcs-and-parameters"],
)
def test_canon_loads_no_heavy_module(tmp_path: Path, program: str) -> None:
    path = tmp_path / "small.ngc"
    path.write_text(program)
    result = _modules_after("canon", str(path))
    assert result["code"] in (0, None), result["out"]
    assert "STRAIGHT_FEED" in str(result["out"])
    modules = result["modules"]
    assert isinstance(modules, list)
    loaded = sorted({m.split(".")[0] for m in modules} & set(HEAVY))
    assert loaded == [], f"cnc canon of a small program imported {loaded}"
    own = sorted(m for m in modules if m.startswith(LAZY))
    assert own == [], f"cnc canon of a small program imported {own}"


def test_version_loads_no_front_end(tmp_path: Path) -> None:
    result = _modules_after("--version")
    modules = result["modules"]
    assert isinstance(modules, list)
    assert not [m for m in modules if m.split(".")[0] in ("gcode", "kernel", "stepnc")]
    assert not [m for m in modules if m.split(".")[0] in HEAVY]
