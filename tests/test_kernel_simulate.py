"""kernel.simulate: the path -> plan -> samples pipeline the CLI commands share.

It must be exactly the stages assembled by hand (same rows, same plan, same samples, same
measurements and servo trace), be reachable as ``kernel.simulate`` and stay out of the way
of the front ends: importing the IR does not load the motion pipeline.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np

import kernel
from kernel.axes.accdec import planning_machine
from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE
from kernel.path.build import build_path
from kernel.plan.planner import plan
from kernel.report.measure import measure
from kernel.report.trace import Trace, setup
from kernel.simulation import SimulationResult, simulate


def _program() -> list[canon.Command]:
    return [
        canon.SetFeedRate(1200.0),
        canon.StraightTraverse(0.0, 0.0, 2.0),
        canon.StraightFeed(10.0, 0.0, 0.0),
        canon.ArcFeed(10.0, 10.0, 10.0, 5.0, 1, 0.0),
        canon.Dwell(0.05),
        canon.StraightFeed(0.0, 10.0, 0.0),
        canon.ProgramEnd(),
    ]


def test_simulate_is_the_stages_assembled_by_hand() -> None:
    got = simulate(_program(), DEFAULT_MACHINE, "p.ngc")
    path = build_path(_program(), DEFAULT_MACHINE, "p.ngc")
    pl = plan(path, planning_machine(DEFAULT_MACHINE))
    s = sample(pl)
    assert got.path.segments.tobytes() == path.segments.tobytes()
    assert got.path.file == "p.ngc"
    assert got.plan.total_time == pl.total_time
    assert np.array_equal(got.plan.v_junction, pl.v_junction)
    for name in ("t", "position", "velocity", "acceleration", "jerk", "segment", "source_line"):
        assert np.array_equal(getattr(got.samples, name), getattr(s, name)), name
    assert got.measure() == measure(pl, s)


def test_the_servo_stage_is_the_trace_of_the_samples() -> None:
    got = simulate(_program(), DEFAULT_MACHINE)
    mine = got.servo(chunk=1000)
    ref = Trace(sample(got.plan), setup(DEFAULT_MACHINE, got.samples.period), got.path.segments)
    assert isinstance(mine, Trace) and mine.chunk == 1000
    got_x = np.concatenate([t["x_act_pos"] for t in mine.chunks()])
    assert np.array_equal(got_x, np.concatenate([t["x_act_pos"] for t in ref.chunks()]))
    assert len(got_x) == mine.rows
    assert mine.errors.to_dict() == ref.errors.to_dict()


def test_kernel_exports_simulate() -> None:
    assert kernel.simulate is simulate
    assert kernel.SimulationResult is SimulationResult
    assert isinstance(kernel.simulate(_program(), DEFAULT_MACHINE), SimulationResult)


def test_importing_the_ir_does_not_load_the_pipeline() -> None:
    probe = "import sys, kernel.ir.canon; print('kernel.simulation' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
