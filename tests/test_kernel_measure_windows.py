"""``cnc plan`` measures window by window (issue 19, bounded memory): the report of
:func:`kernel.report.measure.measure_windows` over :func:`kernel.interp.interpolate.sample_windows`
equals :func:`kernel.report.measure.measure` over all the samples at once, whatever the window,
limit hits crossing window boundaries and arcs included."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import pytest

from cli.programs import program_commands
from kernel.interp.interpolate import sample_windows
from kernel.machine import DEFAULT_MACHINE, Machine, parse_machine
from kernel.report.measure import measure_windows
from kernel.simulation import measure_program, simulate

ROOT = Path(__file__).parent.parent

#: a small, slow machine: the golden programs leave its travel and exceed its axis limits,
#: so the reports have runs of limit hits, many crossing window boundaries
TIGHT = parse_machine(
    'name = "tight"\n'
    + "".join(
        f"[axes.{a}]\nmin = {lo}\nmax = {hi}\nvelocity = {v}\nacceleration = 100\njerk = 1000\n"
        for a, lo, hi, v in (("x", -1, 1000, 20), ("y", -1, 1000, 20), ("z", -1, 1000, 10))
    )
    + '[controller]\naccdec = "scurve"\n'
)

CASES = [
    ("docs/examples/bracket.ngc", DEFAULT_MACHINE),
    ("tests/golden/ngc/072_g20_arcs_planes.ngc", DEFAULT_MACHINE),
    ("tests/golden/ngc/067_g5_2_nurbs.ngc", TIGHT),
    ("tests/golden/ngc/060_helix_multi_turn_p.ngc", TIGHT),  # 10 runs of hits, 1e6 samples
]


@pytest.mark.parametrize(("name", "machine"), CASES, ids=[Path(n).stem for n, _ in CASES])
def test_windowed_measure_equals_measure(name: str, machine: Machine) -> None:
    program = str(ROOT / name)
    result = simulate(program_commands(program), machine, program)
    whole = asdict(result.measure())
    for chunk, window in ((4096, 4096), (1024, 12288)):
        parts = measure_windows(result.plan, sample_windows(result.plan, window, chunk=chunk))
        assert asdict(parts) == whole, (chunk, window)
    assert asdict(measure_program(program_commands(program), machine, program)) == whole


def test_tight_machine_reports_hits() -> None:
    program = str(ROOT / "tests" / "golden" / "ngc" / "060_helix_multi_turn_p.ngc")
    report = measure_program(program_commands(program), TIGHT, program)
    assert report.hits_total > 0 and report.hits
