"""Regenerate the goldens of the real-program suite with LinuxCNC's stand-alone ``rs274``.

Run by hand (``python tests/realworld/regen_ngc.py``); needs ``rs274`` on PATH; never run by
CI. Every program under ``ngc/`` is run as ``rs274 -t tools.tbl -g PROGRAM OUT`` in that
folder (the method of tests/golden/README.md, with this suite's tool table). A program it
accepts gets ``PROGRAM.canon.gz`` (its output, gzipped to keep the suite small); a program
it rejects gets ``PROGRAM.expected.json`` with the 1-based line rs274 stops at and its
message, and the text of the block it printed (an error inside a subroutine is found at the
line of the call by the prefix method, and rs274 names the block itself). The line is found
as in tests/golden/regen.py: the shortest prefix of the program
that fails with the same message (rs274 reads a program as a stream, so prefixes ending
before that line fail with the end-of-file message instead); the prefixes are searched by
bisection, which that monotonic property allows, and the answer is checked at both ends.

The programs of :data:`FIXED` meet a bug of rs274 2.9.0 that LinuxCNC has fixed since: their
goldens come from Debian's ``rs274`` running the interpreter library that
``rs274_fixed/build.sh`` builds (2.9.0 plus LinuxCNC's fix), found through the environment
variable ``RS274_FIXED_LIB`` (the folder holding that ``librs274.so.0``). Without it those
goldens are left as they are.
"""

from __future__ import annotations

import gzip
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
NGC = HERE / "ngc"
TOOL_TABLE = NGC / "tools.tbl"
SUFFIXES = (".ngc", ".nc", ".gcode", ".tap", ".cnc")
EOF_MESSAGES = ("File ended with no percent sign",)

#: programs whose golden needs the fixed interpreter library (module docstring) -> why
FIXED = {
    "lcnc__lathe_g70_71_demo.ngc": "G70 with cutter compensation: LinuxCNC issue #1785, "
    "fixed by b1f3e7d8b8 and f648d01c72 (v2.9.3)",
}


def programs() -> list[Path]:
    """The suite's programs, in name order."""
    return sorted(p for p in NGC.iterdir() if p.suffix.lower() in SUFFIXES)


def run_rs274(program: Path, out: Path, cwd: Path) -> tuple[int, str]:
    """Run ``rs274 -t tools.tbl -g PROGRAM OUT`` in ``cwd``; (exit code, stderr).

    rs274 2.9 shares its tool table through ``$HOME/.tool.mmap``: two runs at once with
    different tables read each other's tools. Each run gets a HOME of its own.
    """
    cmd = ["rs274", "-t", str(TOOL_TABLE), "-g", program.name, str(out)]
    env = dict(os.environ)
    if program.name in FIXED:
        env["LD_LIBRARY_PATH"] = os.environ["RS274_FIXED_LIB"]
    with tempfile.TemporaryDirectory() as home:
        proc = subprocess.run(
            cmd,
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=120,
            stdin=subprocess.DEVNULL,
            env={**env, "HOME": home},
        )
    return proc.returncode, proc.stderr


def error_message(stderr: str) -> str:
    """rs274 prints ``executing`` then the error text then the offending block's text."""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    if lines and lines[0] == "executing":
        lines = lines[1:]
    return lines[0].strip() if lines else ""


def error_block(stderr: str) -> str:
    """The text of the block rs274 stopped at (printed after its message)."""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    if lines and lines[0] == "executing":
        lines = lines[1:]
    return lines[1].strip() if len(lines) > 1 else ""


def _fails_with(program: Path, lines: list[str], k: int, message: str, tmp: Path) -> bool:
    trial = tmp / program.name
    trial.write_bytes("".join(lines[:k]).encode("latin-1"))
    rc, stderr = run_rs274(trial, tmp / "out.canon", tmp)
    return rc != 0 and error_message(stderr) == message


def error_line(program: Path, message: str) -> int:
    """The 1-based line rs274 rejects (module docstring)."""
    lines = program.read_bytes().decode("latin-1").splitlines(keepends=True)
    if message.startswith(EOF_MESSAGES):
        return max(i for i, ln in enumerate(lines, 1) if ln.strip())
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        lo, hi = 1, len(lines)
        if not _fails_with(program, lines, hi, message, tmp):
            raise RuntimeError(f"{program.name}: the whole program does not reproduce {message!r}")
        while lo < hi:
            mid = (lo + hi) // 2
            if _fails_with(program, lines, mid, message, tmp):
                hi = mid
            else:
                lo = mid + 1
        if lo > 1 and _fails_with(program, lines, lo - 1, message, tmp):
            raise RuntimeError(f"{program.name}: prefixes are not monotonic for {message!r}")
    return lo


def regen(program: Path) -> str | None:
    """Write the golden of one program; a problem description or None."""
    canon = program.with_name(program.name + ".canon.gz")
    expected = program.with_name(program.name + ".expected.json")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.canon"
        rc, stderr = run_rs274(program, out, program.parent)
        text = out.read_bytes() if out.exists() else b""
    canon.unlink(missing_ok=True)
    expected.unlink(missing_ok=True)
    if rc == 0:
        canon.write_bytes(gzip.compress(text, mtime=0))
        return None
    message = error_message(stderr)
    try:
        line = error_line(program, message)
    except RuntimeError as exc:
        return str(exc)
    found = {"line": line, "rs274_message": message, "rs274_block": error_block(stderr)}
    expected.write_text(json.dumps(found, indent=2) + "\n")
    return None


def main() -> int:
    todo = programs()
    if "RS274_FIXED_LIB" not in os.environ:
        kept = [p for p in todo if p.name in FIXED]
        todo = [p for p in todo if p.name not in FIXED]
        for p in kept:
            print(f"{p.name}: golden kept (set RS274_FIXED_LIB: {FIXED[p.name]})", file=sys.stderr)
    problems = [p for prog in todo if (p := regen(prog))]
    for p in problems:
        print(p, file=sys.stderr)
    accepted = len(list(NGC.glob("*.canon.gz")))
    rejected = len(list(NGC.glob("*.expected.json")))
    print(f"{accepted} accepted, {rejected} rejected, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
