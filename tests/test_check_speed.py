"""``cnc check`` costs at most 3x the CPU of ``cnc canon`` on a CAM program (issue 19): a
million-line program of bench/cam_program.py, both commands as processes, their CPU times
(user + system) compared, so the machine's load matters much less than for wall time.
bench/bench_check.py has the figures at 200,000, 1M and 10M lines and the peak RSS."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from bench.bench_check import cpu_of
from bench.cam_program import write_program


@pytest.mark.slow
def test_check_costs_at_most_three_times_canon_on_a_million_line_cam_program(
    tmp_path: Path,
) -> None:
    prog = write_program(tmp_path / "cam.ngc", 1_000_000)
    cnc = [sys.executable, "-m", "cli.main"]
    canon, _ = cpu_of([*cnc, "canon", str(prog), "-o", str(tmp_path / "cam.canon")])
    check, _ = cpu_of([*cnc, "check", str(prog)])
    assert check <= 3.0 * canon, f"check {check:.2f} s of CPU, canon {canon:.2f} s"
