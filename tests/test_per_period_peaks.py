"""With ``model = "linuxcnc"`` the report's peak axis speed and acceleration are those of
the joint positions commanded every servo period (kernel.report.measure.per_period_peaks), as a
recording of LinuxCNC's commanded positions shows them: checked against such recordings
(tests/data/lcnc_tp goldens' largest first and second differences), against closed forms,
and window by window against the whole program."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from gcode.readers import read, read_text
from kernel.interp.interpolate import sample, sample_windows
from kernel.machine import parse_machine
from kernel.plan.strategy import plan_program
from kernel.report.measure import measure, measure_windows
from kernel.simulation import measure_program

LCNC = Path(__file__).parent / "data" / "lcnc_tp"
GOLDENS = json.loads((LCNC / "goldens.json").read_text())["goldens"]
MACHINE = parse_machine((LCNC / "machine.toml").read_text())


# variants where the planned profile's peaks are 2-15 % off LinuxCNC's recorded maxima
# (a kink's velocity step, Z's share of a helix, ramps cut short by 10-50 um moves) and the
# commanded positions' differences are not
@pytest.mark.parametrize(
    "name",
    [
        "own_helix_r5.G64P",
        "own_pocket_rings.G61",
        "own_tiny_segments.G64P",
        "own_g64pq_noise.G64P",
        "lcnc_helix_slowdown.G64P",
    ],
)
def test_linuxcnc_report_peaks_are_the_recorded_maxima(name: str) -> None:
    prog = LCNC / "ngc" / f"{name}.ngc"
    report = measure_program(read(prog, "rs274ngc"), MACHINE, str(prog))
    golden = GOLDENS[name]
    # the recording prints positions to 1e-6 mm: up to 1e-3 mm/s on a first difference and
    # 2 mm/s^2 on a second difference over the 1 ms period
    for i, axis in enumerate("xyz"):
        for ours, theirs, floor, rounding in (
            (report.peak_velocity[axis], golden["peak_velocity"][i], 0.5, 1e-3),
            (report.peak_acceleration[axis], golden["peak_acceleration"][i], 5.0, 2.0),
        ):
            if max(ours, theirs) >= floor:
                assert abs(ours - theirs) <= 0.01 * theirs + rounding, (axis, ours, theirs)


def test_a_single_move_peaks_at_the_feed_and_the_axis_acceleration() -> None:
    """Closed form: inside a constant-acceleration ramp the second difference of the
    positions is the acceleration itself; the cruise's first difference is the feed."""
    text = "G21 G90 G61\nG0 X0 Y0 Z0\nG1 X100 F2400\nM2\n"
    report = measure_program(read_text(text, "rs274ngc", "line.ngc"), MACHINE, "line.ngc")
    assert report.peak_velocity["x"] == pytest.approx(40.0, rel=1e-9)
    assert report.peak_acceleration["x"] == pytest.approx(500.0, rel=1e-6)
    assert report.peak_acceleration["y"] == report.peak_velocity["y"] == 0.0


def test_a_kink_passed_at_speed_is_one_period_of_acceleration() -> None:
    """A near-tangent join (3.4 arc minutes) LinuxCNC passes at speed (tp.c's tangent kink):
    the Y speed steps by at most F sin(theta) = 0.02 mm/s within one servo period, 20 mm/s^2
    of commanded acceleration (LinuxCNC's output interpolator spreads it over three periods,
    two thirds of it in one), where the planned profile shows only the ramps' share."""
    text = "G21 G90 G64\nG0 X0 Y0 Z0\nG1 X50 Y0 F1200\nG1 X100 Y0.05\nM2\n"
    _, plan = plan_program(list(read_text(text, "rs274ngc", "kink.ngc")), MACHINE)
    samples = sample(plan)
    report = measure(plan, samples)
    planned = float(abs(samples.acceleration[:, 1]).max())
    step = 20.0 * 0.05 / math.hypot(50.0, 0.05) / samples.period
    assert 0.5 * step < report.peak_acceleration["y"] <= step * (1 + 1e-6)
    assert report.peak_acceleration["y"] > 20 * planned


def test_window_by_window_peaks_are_the_whole_programs() -> None:
    """The per-period peaks carried across window boundaries (the last two samples of one
    window difference with the first of the next) equal those of the whole program."""
    prog = LCNC / "ngc" / "own_tiny_segments.G64P.ngc"
    _, plan = plan_program(list(read(prog, "rs274ngc")), MACHINE, file=str(prog))
    whole = measure(plan, sample(plan))
    windowed = measure_windows(plan, sample_windows(plan, window=1))
    assert windowed.peak_velocity == pytest.approx(whole.peak_velocity, rel=1e-12)
    assert windowed.peak_acceleration == pytest.approx(whole.peak_acceleration, rel=1e-12)
