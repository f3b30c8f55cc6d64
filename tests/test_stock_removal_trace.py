"""Removed volume and removal rate over time (``cnc trace --stock``: the ``removed_mm3`` and
``mrr_mm3_s`` columns) against the closed form of a slot: a flat end mill of diameter D
plunged h deep and fed L along at F mm/min removes D·h·L over the feed move (plus the
plunge's disc π D² h / 4), at D·h·F/60 mm³/s while the feed is steady. Volumes within the
grid bound of tests/test_stock_sim.py (perimeter × cell diagonal × depth)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from cli.main import cli

D, H, L, F = 6.0, 3.0, 40.0, 600.0
RES = 0.2
PROGRAM = f"""G21 G90 G94 G17
G0 X10.03 Y20.03 Z5
G1 Z-{H:g} F200
G1 X{10.03 + L:.2f} F{F:g}
G0 Z5
M2
"""


def _trace(tmp_path: Path) -> dict[str, np.ndarray]:
    prog = tmp_path / "slot.ngc"
    prog.write_text(PROGRAM)
    out = tmp_path / "out"
    res = CliRunner().invoke(
        cli,
        ["trace", str(prog), "-o", str(out), "--stock", "box:0,0,-10,60,40,0"]
        + ["--resolution", str(RES)],
    )
    assert res.exit_code == 0, res.output
    with open(out / "slot_trace.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    head, body = rows[0], np.asarray(rows[1:], float)
    return {name: body[:, k] for k, name in enumerate(head)}


def test_slot_volume_and_rate_over_time(tmp_path: Path) -> None:
    t = _trace(tmp_path)
    removed, rate, line = t["removed_mm3"], t["mrr_mm3_s"], t["source_line"]
    assert np.all(np.diff(removed) >= -1e-9)  # cumulative
    diag = math.hypot(RES, RES)
    disc = math.pi * D * D / 4 * H
    total = D * H * L + disc
    assert abs(removed[-1] - total) <= (2 * L + math.pi * D) * diag * H
    # the feed move (line 4) alone: D·h·L
    on_slot = np.flatnonzero(line == 4)
    before = removed[on_slot[0] - 1]
    assert abs(removed[on_slot[-1]] - before - D * H * L) <= (2 * L + 2 * D) * diag * H
    assert abs(before - disc) <= math.pi * D * diag * H  # the plunge made the disc
    # steady feed: the commanded speed is F/60; there the rate is D·h·F/60
    speed = np.hypot(t["x_cmd_vel"], t["y_cmd_vel"])
    cruise = np.abs(speed - F / 60) < 1e-6
    steady = on_slot[cruise[on_slot] & cruise[on_slot - 1]]  # over the whole period
    assert len(steady) > 100
    assert np.allclose(rate[steady], D * H * F / 60, rtol=0.02)
    # nothing is removed on the retract and after it
    assert np.all(rate[line == 5] == 0.0)


def test_no_stock_no_removal_columns(tmp_path: Path) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text(PROGRAM)
    res = CliRunner().invoke(cli, ["trace", str(prog), "-o", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    head = (tmp_path / "o" / "p_trace.csv").read_text().splitlines()[0].split(",")
    assert head[-1] == "contour_error"
