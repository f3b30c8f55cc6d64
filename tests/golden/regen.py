"""Regenerate the golden outputs with LinuxCNC's stand-alone interpreter ``rs274``.

Run by hand (``python tests/golden/regen.py``); needs ``rs274`` on PATH; never run by CI.
See README.md beside this file for the method. Exits non-zero if a feature program is
rejected, an error program is accepted, or an error line cannot be established.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
NGC = HERE / "ngc"
ERRORS = HERE / "ngc_errors"
TOOL_TABLE = NGC / "sim.tbl"
SUB_INI = "subpath.ini"  # [RS274NGC] SUBROUTINE_PATH = subs (relative to the working dir)
EOF_MESSAGES = ("File ended with no percent sign",)


def uses_sub_files(program: Path) -> bool:
    """Programs calling subroutines kept in files on the search path (``subs/``)."""
    return "_subfile" in program.stem


def run_rs274(program: Path, out: Path, cwd: Path, ini: bool = False) -> tuple[int, str]:
    """Run ``rs274 [-i subpath.ini] -t sim.tbl -g PROGRAM OUT`` in ``cwd``; (exit code, stderr)."""
    cmd = ["rs274"]
    if ini:
        cmd += ["-i", SUB_INI]
    cmd += ["-t", str(TOOL_TABLE), "-g", program.name, str(out)]
    with tempfile.TemporaryDirectory() as home:  # rs274 shares $HOME/.tool.mmap between runs
        env = {**os.environ, "HOME": home}
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=30, env=env)
    return proc.returncode, proc.stderr


def error_message(stderr: str) -> str:
    """rs274 prints ``executing`` then the error text then the offending block's text."""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    if lines and lines[0] == "executing":
        lines = lines[1:]
    return lines[0].strip() if lines else ""


def regen_feature(program: Path) -> str | None:
    out = program.with_suffix(".canon")
    rc, stderr = run_rs274(program, out, program.parent, ini=uses_sub_files(program))
    if rc != 0:
        return f"{program.name}: rejected by rs274: {error_message(stderr)}"
    return None


def _message_of_prefix(program: Path, lines: list[str], k: int, tmp: Path) -> str:
    trial = tmp / program.name
    trial.write_text("".join(lines[:k]))
    rc, stderr = run_rs274(trial, tmp / "out.canon", tmp)
    return error_message(stderr) if rc != 0 else ""


def error_line(program: Path, message: str) -> int:
    """The 1-based line rs274 rejects: the shortest prefix of the program that fails the same way.

    rs274 interprets a file as a stream, so an error found while executing line L is raised
    by every prefix that contains L and by none that stops before it (those end with
    "File ended with no percent sign or program end" instead). For that end-of-file message
    itself the line is the program's last non-blank line, where rs274 stops.
    """
    lines = program.read_text().splitlines(keepends=True)
    if message.startswith(EOF_MESSAGES):
        return max(i for i, ln in enumerate(lines, 1) if ln.strip())
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(1, len(lines) + 1):
            if _message_of_prefix(program, lines, k, Path(tmp)) == message:
                return k
    raise RuntimeError(f"{program.name}: no prefix reproduces {message!r}")


def regen_error(program: Path) -> str | None:
    with tempfile.TemporaryDirectory() as tmp:
        rc, stderr = run_rs274(program, Path(tmp) / "out.canon", program.parent)
    if rc == 0:
        return f"{program.name}: accepted by rs274, but it is an error program"
    message = error_message(stderr)
    try:
        line = error_line(program, message)
    except RuntimeError as exc:
        return str(exc)
    expected = {"line": line, "rs274_message": message}
    program.with_suffix(".expected.json").write_text(json.dumps(expected, indent=2) + "\n")
    return None


def main() -> int:
    problems = [p for prog in sorted(NGC.glob("*.ngc")) if (p := regen_feature(prog))]
    problems += [p for prog in sorted(ERRORS.glob("*.ngc")) if (p := regen_error(prog))]
    for p in problems:
        print(p, file=sys.stderr)
    n_feat, n_err = len(list(NGC.glob("*.ngc"))), len(list(ERRORS.glob("*.ngc")))
    print(f"{n_feat} feature programs, {n_err} error programs, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
