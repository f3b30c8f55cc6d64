"""The planner strategy a machine profile asks for (``[controller] model``).

``book`` is kernel.plan.planner (the ADCBI look-ahead); ``linuxcnc`` and ``grbl`` are the
controller models of kernel.plan.models, which reproduce a real control's planner. Every
strategy turns the same IR into a :class:`~kernel.plan.planner.Plan`, so sampling, measuring
and the servo stage do not know which one ran. The controller models have no jerk limit
(LinuxCNC 2.9's planner and Grbl 1.1's are trapezoidal): they plan with ``accdec =
"trapezoid"`` whatever the profile says.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import kernel.ir.canon as canon
from kernel.machine import Machine, with_controller
from kernel.path.build import build_path
from kernel.path.segments import Path
from kernel.plan.models import grbl, linuxcnc
from kernel.plan.planner import Plan, plan


@dataclass(frozen=True, slots=True)
class Built:
    """A program's path as its model needs it (``prepared``: LinuxCNC's canon-layer view)."""

    model: str
    path: Path
    prepared: linuxcnc.Prepared | None = None


def build(commands: Iterable[canon.Command], machine: Machine, file: str | None = None) -> Built:
    """IR -> path for ``machine.controller.model`` (the models see the program unblended)."""
    model = machine.controller.model
    if model == "linuxcnc":
        prepared = linuxcnc.prepare(commands)
        flat = with_controller(machine, accdec="trapezoid")
        return Built(model, build_path(prepared.commands, flat, file), prepared)
    if model == "grbl":
        flat = with_controller(machine, accdec="trapezoid", blend_tolerance=0.0)
        laser = machine.kind == "laser"  # Grbl's laser mode, $32=1
        ir = grbl.synchronised(no_blend(commands), machine.controller.arc_tolerance, laser)
        return Built(model, build_path(ir, flat, file))
    return Built(model, build_path(commands, machine, file))


def plan_built(built: Built, planning: Machine) -> Plan:
    """Plan a :func:`build` result on ``planning`` with the model it was built for."""
    if built.model == "linuxcnc" and built.prepared is not None:
        return linuxcnc.plan(
            built.path, with_controller(planning, accdec="trapezoid"), built.prepared
        )
    if built.model == "grbl":
        return grbl.plan(built.path, with_controller(planning, accdec="trapezoid"))
    return plan(built.path, planning)


def plan_program(
    commands: Iterable[canon.Command],
    machine: Machine,
    planning: Machine | None = None,
    file: str | None = None,
) -> tuple[Path, Plan]:
    """Build the path of ``commands`` on ``machine`` and plan it on ``planning`` (default:
    ``machine``) with the strategy ``machine.controller.model`` names. The path returned is
    the one planned (a model may add blend arcs or split arcs into chords)."""
    built = build(commands, machine, file)
    pl = plan_built(built, machine if planning is None else planning)
    return (built.path, pl) if built.model == "book" else (pl.path, pl)


def no_blend(commands: Iterable[canon.Command]) -> Iterator[canon.Command]:
    """The IR with G64 P tolerances dropped: Grbl has no blending, only junction speeds."""
    for cmd in commands:
        if isinstance(cmd, canon.SetMotionControlMode) and cmd.tolerance:
            yield canon.SetMotionControlMode(cmd.mode, 0.0, source=cmd.source)
        else:
            yield cmd


__all__ = ["Built", "build", "no_blend", "plan_built", "plan_program"]
