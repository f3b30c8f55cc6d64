"""Regenerate the expected outputs of LinuxCNC's interpreter test suite with ``rs274``.

Run by hand (``python tests/linuxcnc/regen.py``); needs LinuxCNC's stand-alone interpreter
``rs274`` on PATH (``apt-get install -y linuxcnc-uspace``); never run by CI. For every case of
``manifest.toml`` that is not skipped it runs, in a scratch copy of the case's folder,

    rs274 [-i INI] [-t TOOL_TABLE] [-v VAR] -g PROGRAM OUT

and writes ``expected/<id>.canon`` when rs274 runs the program to its end (with
``expected/<id>.print``, what its ``(PRINT, ...)`` comments printed, if any), or
``expected/<id>.expected.json`` (file, 1-based line and message of the error) when it rejects
it. The upstream ``expected`` files were made by other builds and are not used. Exits non-zero
when rs274's verdict disagrees with a case's status or an error line cannot be established.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
import tomllib
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXPECTED = HERE / "expected"
EOF_MESSAGES = ("File ended with no percent sign",)
TIMEOUT = 30
ATTEMPTS = 3
HUNG = -1  # Run.code when rs274 did not finish within TIMEOUT seconds


@dataclass(frozen=True)
class Case:
    """One row of ``manifest.toml``."""

    id: str
    dir: str
    program: str
    status: str
    tool_table: str | None = None
    ini: str | None = None
    var: str | None = None
    reason: str | None = None
    note: str | None = None
    terminates: bool = False  # skipped, but we must still finish it (upstream checks no more)

    @property
    def folder(self) -> Path:
        return HERE / self.dir

    @property
    def canon(self) -> Path:
        return EXPECTED / f"{self.id}.canon"

    @property
    def error(self) -> Path:
        return EXPECTED / f"{self.id}.expected.json"

    @property
    def printed(self) -> Path:
        """What rs274 printed for the case's ``(PRINT, ...)`` comments (when it printed)."""
        return EXPECTED / f"{self.id}.print"


def load_manifest(path: Path = HERE / "manifest.toml") -> list[Case]:
    """The cases of the manifest, in its order."""
    with path.open("rb") as f:
        rows = tomllib.load(f)["case"]
    return [Case(**row) for row in rows]


@dataclass(frozen=True)
class Run:
    """What one rs274 run gave."""

    code: int
    canon: str
    stderr: str
    stdout: str = ""  # what (PRINT, ...) comments printed

    @property
    def message(self) -> str:
        """rs274 prints ``executing``, then the error, then the offending block's text."""
        lines = [ln.strip() for ln in self.stderr.splitlines() if ln.strip()]
        lines = [ln for ln in lines if ln != "executing"]
        return lines[-2] if len(lines) >= 2 else (lines[0] if lines else "")

    @property
    def block(self) -> str:
        lines = [ln.strip() for ln in self.stderr.splitlines() if ln.strip()]
        return lines[-1] if lines else ""


def run_rs274(case: Case, text: str | None = None) -> Run:
    """Run rs274 on the case (or on ``text`` in place of its program) in a scratch folder."""
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp) / "case"
        shutil.copytree(case.folder, work)
        if text is not None:
            (work / case.program).write_text(text)
        cmd = ["rs274"]
        if case.ini:
            cmd += ["-i", case.ini]
        if case.tool_table:
            cmd += ["-t", case.tool_table]
        if case.var:
            shutil.copy(work / case.var, work / "run.var")
            cmd += ["-v", "run.var"]
        out = Path(tmp) / "out.canon"
        cmd += ["-g", case.program, str(out)]
        try:
            proc = subprocess.run(
                cmd,
                cwd=work,
                capture_output=True,
                text=True,
                timeout=TIMEOUT,
                stdin=subprocess.DEVNULL,
            )
        except subprocess.TimeoutExpired:
            return Run(HUNG, "", "")
        canon = out.read_text() if out.exists() else ""
    return Run(proc.returncode, canon, proc.stderr, proc.stdout)


def _where_block(case: Case, block: str, main_line: int, mains: set[str]) -> tuple[str, int]:
    """The file and line of the block rs274 rejected.

    The main program's line found by the prefix search is the answer when its text is the
    block rs274 printed. Otherwise the error is in a loop or subroutine reached from that line,
    and the block is looked up in the program and the folder's subroutine files (``mains``,
    the programs of the folder's other cases, are not searched); it must be there once.
    """
    lines = (case.folder / case.program).read_text().splitlines()
    if lines[main_line - 1].strip() == block:
        return case.program, main_line
    hits = [
        (p.relative_to(case.folder).as_posix(), i)
        for p in sorted(case.folder.rglob("*.ngc"))
        if p.name == case.program or p.name not in mains
        for i, ln in enumerate(p.read_text().splitlines(), 1)
        if ln.strip() == block
    ]
    if len(hits) != 1:
        raise RuntimeError(f"{case.id}: block {block!r} found {len(hits)} times")
    return hits[0]


def error_place(case: Case, run: Run, mains: set[str]) -> tuple[str, int]:
    """File and 1-based line where rs274 stops.

    rs274 reads a program as a stream, so an error found while executing line L is raised by
    every prefix of the program that contains L and by none that stops before it; the line is
    the shortest prefix failing with the same message. For the end-of-file message itself it
    is the last non-blank line.
    """
    lines = (case.folder / case.program).read_text().splitlines(keepends=True)
    if run.message.startswith(EOF_MESSAGES):
        return case.program, max(i for i, ln in enumerate(lines, 1) if ln.strip())
    for _attempt in range(ATTEMPTS):
        for k in range(1, len(lines) + 1):
            trial = run_rs274(case, "".join(lines[:k]))
            if trial.code != 0 and trial.message == run.message:
                return _where_block(case, run.block, k, mains)
    raise RuntimeError(f"{case.id}: no prefix reproduces {run.message!r}")


def settled_run(case: Case) -> Run:
    """rs274's run of the case, repeated until two runs agree (runs of rs274 started at the
    same moment by other users of the machine have been seen to disturb one another)."""
    run = run_rs274(case)
    for _attempt in range(ATTEMPTS):
        again = run_rs274(case)
        if again == run:
            return run
        run = again
    raise RuntimeError(f"{case.id}: rs274 gives a different result at each run")


def regen(case: Case, mains: set[str]) -> str | None:
    """Write the case's expected output; a problem description, or None."""
    try:
        run = settled_run(case)
    except RuntimeError as exc:
        return str(exc)
    case.canon.unlink(missing_ok=True)
    case.error.unlink(missing_ok=True)
    case.printed.unlink(missing_ok=True)
    case.canon.parent.mkdir(parents=True, exist_ok=True)
    if run.code == 0:
        case.canon.write_text(run.canon)
        if run.stdout:
            case.printed.write_text(run.stdout)
        if case.status == "rejected":
            return f"{case.id}: accepted by rs274, but its status is rejected"
        return None
    try:
        file, line = error_place(case, run, mains)
    except RuntimeError as exc:
        return str(exc)
    expected = {"file": file, "line": line, "rs274_message": run.message, "block": run.block}
    case.error.write_text(json.dumps(expected, indent=2) + "\n")
    if case.status != "rejected":
        return f"{case.id}: rejected by rs274 ({run.message}), but its status is {case.status}"
    return None


def main(argv: list[str]) -> int:
    cases = [c for c in load_manifest() if c.status != "skipped"]
    if argv:
        cases = [c for c in cases if any(c.id.startswith(a) for a in argv)]
    mains: dict[str, set[str]] = {}
    for c in load_manifest():
        mains.setdefault(c.dir, set()).add(c.program)
    problems = [p for case in cases if (p := regen(case, mains[case.dir]))]
    for p in problems:
        print(p, file=sys.stderr)
    print(f"{len(cases)} cases, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
