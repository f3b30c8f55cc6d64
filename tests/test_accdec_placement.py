"""Where acc/dec happens changes the feed profile as the book's fig. 4.1 says.

Acc/dec *after* interpolation (ADCAI): the interpolator runs at the programmed feed from the
first period and the linear filter of width tau alone accelerates, so a long line takes
``L/F + tau`` and its speed ramps linearly over ``tau`` (book §4.2, eq. 4.11). Acc/dec
*before* (ADCBI): the planner's trapezoid with the axis acceleration, and the filter stage is
idle.
"""

from __future__ import annotations

import numpy as np
import pytest

from kernel.axes.accdec import planning_machine
from kernel.interp.interpolate import sample
from kernel.ir import canon
from kernel.machine import parse_machine
from kernel.path.build import build_path
from kernel.plan.planner import plan
from kernel.report.trace import Trace, setup

L, F = 100.0, 6000.0  # mm, mm/min: 100 mm/s for 1 s
TAU = 0.05
AXES = "[axes.x]\nvelocity = 200.0\nacceleration = 1000.0\n[axes.y]\n[axes.z]\n"
LINE = [
    canon.UseLengthUnits(canon.Units.MM),
    canon.SetFeedRate(F),
    canon.StraightFeed(L, 0.0, 0.0),
]


def commanded(placement: str):
    m = parse_machine(AXES + f'[accdec]\ntype = "linear"\ntau = {TAU}\nplacement = "{placement}"\n')
    path = build_path(LINE, m)
    samples = sample(plan(path, planning_machine(m)))
    return Trace(samples, setup(m, samples.period), path.segments).commanded()


def test_after_interpolation_the_filter_alone_accelerates_and_adds_tau() -> None:
    cmd = commanded("after")
    moving = np.flatnonzero(np.abs(cmd.velocity[:, 0]) > 1e-9)
    duration = (moving[-1] - moving[0] + 1) * cmd.period
    assert duration == pytest.approx(L / (F / 60.0) + TAU, abs=2 * cmd.period)
    # linear ramp to 100 mm/s over tau: acceleration F/tau = 2000 mm/s^2, twice the axis
    # limit the planner would have used (book eq. 4.11)
    peak_acc = np.max(np.abs(np.diff(cmd.velocity[:, 0]))) / cmd.period
    assert peak_acc == pytest.approx((F / 60.0) / TAU, rel=0.05)
    assert cmd.position[-1, 0] == pytest.approx(L, abs=1e-9)


def test_before_interpolation_the_planner_trapezoid_uses_the_axis_acceleration() -> None:
    cmd = commanded("before")
    peak_acc = np.max(np.abs(np.diff(cmd.velocity[:, 0]))) / cmd.period
    assert peak_acc == pytest.approx(1000.0, rel=0.05)
    moving = np.flatnonzero(np.abs(cmd.velocity[:, 0]) > 1e-9)
    duration = (moving[-1] - moving[0] + 1) * cmd.period
    v = F / 60.0
    assert duration == pytest.approx(L / v + v / 1000.0, abs=2 * cmd.period)
