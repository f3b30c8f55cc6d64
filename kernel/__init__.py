"""The kernel: the canonical-command IR (kernel.ir.canon), machine profiles, path, planner,
interpolation, measurements, servo and checks; never imports a front end.

:func:`simulate` (defined in kernel.simulation; a module named ``simulate`` would be
shadowed by the function of that name) runs a program's commands through path, plan and
samples. It is loaded on first use: importing the IR alone, as the front ends do, must not
pull in scipy and the whole motion pipeline.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from kernel.simulation import SimulationResult, simulate

__all__ = ["SimulationResult", "simulate"]


def __getattr__(name: str) -> Any:
    """``kernel.simulate`` and ``kernel.SimulationResult``, imported when first asked for."""
    if name in __all__:
        import kernel.simulation as module

        value = getattr(module, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'kernel' has no attribute {name!r}")
