"""LinuxCNC 2.9's own interpreter test suite, run through our RS274/NGC interpreter.

Every case of ``tests/linuxcnc/manifest.toml`` (tests/interp, tests/ccomp and tests/oword of
LinuxCNC v2.9.10; see tests/linuxcnc/README.md) is checked by its status:

* ``equivalent``: rs274 runs it; our output is equivalent to rs274's (``expected/<id>.canon``)
  by the corpus rule of :mod:`tests.canon_equiv`, and its ``(PRINT, ...)`` comments print
  what rs274 printed (``expected/<id>.print``);
* ``rejected``: rs274 rejects it; we reject it with an ``NGC-*`` diagnostic in the same file
  and at the same line (``expected/<id>.expected.json``);
* ``skipped``: rs274 stand-alone cannot run it (the manifest says why); a skipped case marked
  ``terminates`` must still end (with or without a diagnostic), which is all its upstream test
  checks.

The expected outputs were made with Debian's ``rs274`` by tests/linuxcnc/regen.py; the
``reference`` test at the end (also ``slow``: it runs rs274 over every case) runs rs274 again
and compares with them.
"""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import pytest

from gcode.core.params import read_var_text
from gcode.ngc.ini import read_ini_text, with_ini
from gcode.ngc.interpreter import InterpreterOptions, interpret
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from kernel.tooltable import read_tool_table
from tests.canon_equiv import compare
from tests.linuxcnc.regen import Case, load_manifest, run_rs274

CASES = load_manifest()
STATUSES = ("equivalent", "rejected", "skipped")
ATTEMPTS = 5  # rs274 runs of a case that differs before the reference test counts it


def options(case: Case, printed: list[str] | None = None) -> InterpreterOptions:
    """Our interpreter's options for a case, from the files rs274 was given (-t, -v, -i);
    ``(PRINT, ...)`` texts go to ``printed``."""
    tools = None
    if case.tool_table:
        path = case.folder / case.tool_table
        tools = read_tool_table(path.read_text().splitlines(), str(path))
    parameters = None
    if case.var:
        path = case.folder / case.var
        parameters = read_var_text(path.read_text().splitlines(), str(path))
    sink = printed.append if printed is not None else None
    opts = InterpreterOptions(tool_table=tools, parameters=parameters, print_sink=sink)
    if case.ini:
        opts = with_ini(opts, read_ini_text((case.folder / case.ini).read_text(), str(case.folder)))
    return opts


def run_ours(case: Case) -> tuple[list[str], Diagnostic | None, list[str]]:
    """Our canonical text for the case, the diagnostic that stopped it (if any), and what
    its ``(PRINT, ...)`` comments printed."""
    commands: list[canon.Command] = []
    printed: list[str] = []
    error = None
    try:
        for cmd in interpret(case.folder / case.program, options(case, printed)):
            commands.append(cmd)
    except Diagnostic as exc:
        error = exc
    return list(canon.write_text(commands)), error, printed


def _param(case: Case) -> object:
    return pytest.param(case, id=case.id)


RUN = [_param(c) for c in CASES if c.status == "equivalent"]
REJECTED = [_param(c) for c in CASES if c.status == "rejected"]
TERMINATES = [_param(c) for c in CASES if c.status == "skipped" and c.terminates]


@pytest.mark.parametrize("case", RUN)
def test_equivalent_to_rs274(case: Case) -> None:
    ours, error, printed = run_ours(case)
    ref = case.canon.read_text().splitlines()
    assert error is None, f"we stopped with {error} where rs274 ran to the end"
    assert compare(ours, ref) == []
    ref_printed = case.printed.read_text().splitlines() if case.printed.exists() else []
    assert [p.rstrip() for p in printed] == [p.rstrip() for p in ref_printed]


@pytest.mark.parametrize("case", REJECTED)
def test_rejected_at_the_line_rs274_rejects(case: Case) -> None:
    expected = json.loads(case.error.read_text())
    with pytest.raises(Diagnostic) as info:
        run_ours_strict(case)
    diag = info.value
    where = f"{diag} (rs274: {expected['file']}:{expected['line']}: {expected['rs274_message']})"
    assert diag.code.startswith("NGC-"), where
    assert diag.location.file is not None, where
    assert Path(diag.location.file).resolve() == (case.folder / expected["file"]).resolve(), where
    assert diag.location.line == expected["line"], where


def run_ours_strict(case: Case) -> None:
    """Run the case to its end, letting a diagnostic out."""
    for _cmd in interpret(case.folder / case.program, options(case)):
        pass


@pytest.mark.parametrize("case", TERMINATES)
def test_ends(case: Case) -> None:
    """Upstream only checks that these end (Debian's rs274 never does): we end, with or
    without a diagnostic (the loop guard bounds any loop)."""
    _ours, error, _printed = run_ours(case)
    assert error is None or error.code.startswith(("NGC-", "LOOP-"))


def test_manifest_is_complete() -> None:
    """Every case has a known status, a reason when skipped, its files and its reference."""
    assert len(CASES) >= 120
    assert len({c.id for c in CASES}) == len(CASES)
    for case in CASES:
        assert case.status in STATUSES, case.id
        if case.status == "skipped":
            assert case.reason, case.id
            continue
        for name in (case.program, case.tool_table, case.ini, case.var):
            assert name is None or (case.folder / name).is_file(), (case.id, name)
        reference = case.error if case.status == "rejected" else case.canon
        assert reference.is_file(), case.id


def _rs274_differs(case: Case) -> str | None:
    """None when rs274 run now gives the case's expected output (the canon, or the error)."""
    run = run_rs274(case)
    if case.status == "rejected":
        message = json.loads(case.error.read_text())["rs274_message"]
        return None if run.code != 0 and run.message == message else f"{case.id}: {run.message}"
    return None if run.code == 0 and run.canon == case.canon.read_text() else f"{case.id}: differs"


@pytest.mark.slow
@pytest.mark.reference
@pytest.mark.skipif(shutil.which("rs274") is None, reason="LinuxCNC's rs274 is not installed")
def test_expected_outputs_are_rs274s() -> None:
    """rs274 run now gives every committed expected output.

    One test running the cases one after the other: rs274 runs at the same moment disturb
    one another (its tool data is shared between processes), so a case that differs is run
    up to ATTEMPTS times, a second apart, before it counts.
    """
    differing = []
    for case in CASES:
        if case.status == "skipped":
            continue
        for _attempt in range(ATTEMPTS):
            problem = _rs274_differs(case)
            if problem is None:
                break
            time.sleep(1.0)
        else:
            differing.append(problem)
    assert differing == []
