"""The planner strategy a machine profile asks for (``[controller] model``).

``book`` is kernel.plan.planner (the ADCBI look-ahead); ``linuxcnc`` and ``grbl`` are the
controller models of kernel.plan.models, which reproduce a real control's planner. Every
strategy turns the same IR into a :class:`~kernel.plan.planner.Plan`, so sampling, measuring
and the servo stage do not know which one ran. The controller models have no jerk limit
(LinuxCNC 2.9's planner and Grbl 1.1's are trapezoidal): they plan with ``accdec =
"trapezoid"`` whatever the profile says.
"""

from __future__ import annotations

from collections.abc import Iterable

import kernel.ir.canon as canon
from kernel.machine import Machine, with_controller
from kernel.path.build import build_path
from kernel.path.segments import Path
from kernel.plan.models import grbl, linuxcnc
from kernel.plan.planner import Plan, plan


def plan_program(
    commands: Iterable[canon.Command],
    machine: Machine,
    planning: Machine | None = None,
    file: str | None = None,
) -> tuple[Path, Plan]:
    """Build the path of ``commands`` on ``machine`` and plan it on ``planning`` (default:
    ``machine``) with the strategy ``machine.controller.model`` names."""
    planning = machine if planning is None else planning
    model = machine.controller.model
    if model == "linuxcnc":
        prepared = linuxcnc.prepare(commands)
        flat = with_controller(machine, accdec="trapezoid")
        path = build_path(prepared.commands, flat, file)
        pl = linuxcnc.plan(path, with_controller(planning, accdec="trapezoid"), prepared)
        return pl.path, pl
    if model == "grbl":
        flat = with_controller(machine, accdec="trapezoid", blend_tolerance=0.0)
        path = build_path(_no_blend(commands), flat, file)
        pl = grbl.plan(path, with_controller(planning, accdec="trapezoid"))
        return pl.path, pl
    path = build_path(commands, machine, file)
    return path, plan(path, planning)


def _no_blend(commands: Iterable[canon.Command]) -> Iterable[canon.Command]:
    """The IR with G64 P tolerances dropped: Grbl has no blending, only junction speeds."""
    for cmd in commands:
        if isinstance(cmd, canon.SetMotionControlMode) and cmd.tolerance:
            yield canon.SetMotionControlMode(cmd.mode, 0.0, source=cmd.source)
        else:
            yield cmd


__all__ = ["plan_program"]
