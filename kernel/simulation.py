"""The kernel's pipeline for one program: canonical commands -> path -> plan -> samples
(-> measurements) (-> servo), as ``cnc plan``, ``cnc trace`` and ``cnc run`` use it.

The path is built for the machine (kernel.path.build), planned on the limits the planner should
use where the profile puts acc/dec (:func:`kernel.axes.accdec.planning_machine`) and sampled
every interpolation period (kernel.interp.interpolate). Measuring (kernel.report.measure) and
the servo
stage (acc/dec after interpolation, fine interpolation, position loops: kernel.report.trace) are
asked of the result: ``cnc trace`` does not measure, and the servo stage runs chunk by chunk
as its :class:`~kernel.report.trace.Trace` is iterated, its setup errors (``SERVO-*``) coming
after the measurements are known. Exported as :func:`kernel.simulate`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import kernel.ir.canon as canon
from kernel.axes.accdec import planning_machine
from kernel.interp.interpolate import sample, sample_windows
from kernel.interp.samples import Samples
from kernel.machine import Machine
from kernel.path.segments import Path
from kernel.plan.planner import Plan
from kernel.plan.strategy import plan_program
from kernel.report.measure import Report, measure, measure_windows
from kernel.report.trace import CHUNK, Trace, setup


@dataclass(frozen=True, slots=True)
class SimulationResult:
    """Path, plan and samples of one program; :meth:`measure` and :meth:`servo` on request."""

    machine: Machine  # the profile as given (the servo stage's limits and settings)
    path: Path
    plan: Plan
    samples: Samples

    def measure(self) -> Report:
        """Cycle time, lengths, peaks, chord error and limit hits (kernel.report.measure)."""
        return measure(self.plan, self.samples)

    def servo(self, chunk: int = CHUNK) -> Trace:
        """The servo stage over the samples, ``chunk`` rows at a time (``SERVO-*`` on a bad
        ``[servo]`` table)."""
        return Trace(
            self.samples, setup(self.machine, self.samples.period), self.path.segments, chunk
        )


def simulate(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
) -> SimulationResult:
    """Build, plan and sample ``commands`` on ``machine`` (``file``: the program's name in
    diagnostics). Problems of the program raise ``PLAN-*`` diagnostics. The planner is the
    strategy ``[controller] model`` names (kernel.plan.strategy)."""
    path, pl = plan_program(commands, machine, planning_machine(machine), file)
    return SimulationResult(machine, path, pl, sample(pl))


def measure_program(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
) -> Report:
    """What ``simulate(...).measure()`` reports, with the samples made and reduced window by
    window (:func:`kernel.report.measure.measure_windows`): memory holds the path and plan
    and one window of samples, however long the program runs."""
    return plan_and_measure(commands, machine, file)[1]


def plan_and_measure(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
) -> tuple[Plan, Report]:
    """The plan and :func:`measure_program`'s report: the plan is what the time per tool
    and per operation is summed over (kernel.report.breakdown)."""
    _path, pl = plan_program(commands, machine, planning_machine(machine), file)
    return pl, measure_windows(pl, sample_windows(pl))


__all__ = ["SimulationResult", "measure_program", "plan_and_measure", "simulate"]
