"""Canonical calls LinuxCNC's ``rs274`` prints that NISTIR 5970 does not have.

They carry no IR meaning (``kernel.ir.canon.LINUXCNC_ONLY`` and ``../shared/corpus/README.md``:
equivalence drops them) but make ``cnc canon`` output read like rs274's. They live here, not
in :mod:`kernel.ir.canon`, because the kernel never consumes them; each prints exactly as
rs274's stand-alone canon (``saicanon.cc``) does.
"""

from __future__ import annotations

from typing import ClassVar

from kernel.ir.canon import (  # noqa: F401 - re-exported: the interpreter emits them as lc.*
    ChangeToolNumber,
    Command,
    Finish,
    OnReset,
    RigidTap,
    SetG5xOffset,
    SetG92Offset,
    SetToolTableEntry,
    SetXYRotation,
    StartChange,
    format_arg,
)
from kernel.record import record


@record
class ToolLengthOffsets(Command):
    """LinuxCNC's nine-value ``USE_TOOL_LENGTH_OFFSET`` (x y z, a b c, u v w)."""

    NAME: ClassVar[str] = "USE_TOOL_LENGTH_OFFSET"
    offset: tuple[float, ...]

    def to_text(self) -> str:
        o = [format_arg(v) for v in self.offset]
        return f"{self.NAME}({' '.join(o[0:3])}, {' '.join(o[3:6])}, {' '.join(o[6:9])})"


@record
class DigitalOutput(Command):
    """M62-M65: ``SET_/CLEAR_`` ``MOTION_`` (synchronised) or ``AUX_`` output bit."""

    NAME: ClassVar[str] = "SET_MOTION_OUTPUT_BIT"
    index: int
    on: bool = True
    synchronised: bool = True

    def to_text(self) -> str:
        kind = "MOTION" if self.synchronised else "AUX"
        verb = "SET" if self.on else "CLEAR"
        return f"{verb}_{kind}_OUTPUT_BIT({self.index})"


@record
class AnalogOutput(Command):
    """M67 (synchronised) / M68 (immediate) analog output."""

    NAME: ClassVar[str] = "SET_MOTION_OUTPUT_VALUE"
    index: int
    value: float
    synchronised: bool = True

    def to_text(self) -> str:
        kind = "MOTION" if self.synchronised else "AUX"
        return f"SET_{kind}_OUTPUT_VALUE({self.index},{self.value:.6f})"


@record
class WaitOrientComplete(Command):
    """M19 wait for the spindle orientation (timeout seconds)."""

    NAME: ClassVar[str] = "SPINDLE.0.WAIT_ORIENT_COMPLETE"
    timeout: float

    def to_text(self) -> str:
        return f"{self.NAME}({format_arg(self.timeout)})"
