"""Canonical calls LinuxCNC's ``rs274`` prints that NISTIR 5970 does not have.

They carry no IR meaning (``kernel.canon.LINUXCNC_ONLY`` and ``../shared/corpus/README.md``:
equivalence drops them) but make ``cnc canon`` output read like rs274's. They live here, not
in :mod:`kernel.canon`, because the kernel never consumes them; each prints exactly as
rs274's stand-alone canon (``saicanon.cc``) does.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from kernel.canon import Command


def _f4(v: float) -> str:
    s = f"{v:.4f}"
    return "0.0000" if s == "-0.0000" else s


@dataclass(frozen=True, slots=True)
class SetG5xOffset(Command):
    """Active work offset G54..G59.3 (``index`` 1..9) in program units."""

    NAME: ClassVar[str] = "SET_G5X_OFFSET"
    index: int
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0

    def to_text(self) -> str:
        vals = ", ".join(_f4(v) for v in (self.x, self.y, self.z, self.a, self.b, self.c))
        return f"{self.NAME}({self.index}, {vals})"


@dataclass(frozen=True, slots=True)
class SetG92Offset(Command):
    NAME: ClassVar[str] = "SET_G92_OFFSET"
    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@dataclass(frozen=True, slots=True)
class SetXYRotation(Command):
    NAME: ClassVar[str] = "SET_XY_ROTATION"
    angle: float


@dataclass(frozen=True, slots=True)
class OnReset(Command):
    NAME: ClassVar[str] = "ON_RESET"


@dataclass(frozen=True, slots=True)
class StartChange(Command):
    NAME: ClassVar[str] = "START_CHANGE"


@dataclass(frozen=True, slots=True)
class ChangeToolNumber(Command):
    """M61: the spindle holds tool ``number`` now (no motion, no change cycle)."""

    NAME: ClassVar[str] = "CHANGE_TOOL_NUMBER"
    number: int


@dataclass(frozen=True, slots=True)
class SetToolTableEntry(Command):
    """G10 L1/L10/L11: a tool-table row rewritten (offsets x y z a b c u v w)."""

    NAME: ClassVar[str] = "SET_TOOL_TABLE_ENTRY"
    pocket: int
    tool: int
    offset: tuple[float, ...]
    diameter: float
    front_angle: float
    back_angle: float
    orientation: int

    def to_text(self) -> str:
        off = " ".join(_f4(v) for v in self.offset)
        return (
            f"{self.NAME}({self.pocket}, {self.tool}, {off}, {_f4(self.diameter)}, "
            f"{_f4(self.front_angle)}, {_f4(self.back_angle)}, {self.orientation})"
        )


@dataclass(frozen=True, slots=True)
class ToolLengthOffsets(Command):
    """LinuxCNC's nine-value ``USE_TOOL_LENGTH_OFFSET`` (x y z, a b c, u v w)."""

    NAME: ClassVar[str] = "USE_TOOL_LENGTH_OFFSET"
    offset: tuple[float, ...]

    def to_text(self) -> str:
        o = [_f4(v) for v in self.offset]
        return f"{self.NAME}({' '.join(o[0:3])}, {' '.join(o[3:6])}, {' '.join(o[6:9])})"


@dataclass(frozen=True, slots=True)
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


@dataclass(frozen=True, slots=True)
class AnalogOutput(Command):
    """M67 (synchronised) / M68 (immediate) analog output."""

    NAME: ClassVar[str] = "SET_MOTION_OUTPUT_VALUE"
    index: int
    value: float
    synchronised: bool = True

    def to_text(self) -> str:
        kind = "MOTION" if self.synchronised else "AUX"
        return f"SET_{kind}_OUTPUT_VALUE({self.index},{self.value:.6f})"


@dataclass(frozen=True, slots=True)
class WaitOrientComplete(Command):
    """M19 wait for the spindle orientation (timeout seconds)."""

    NAME: ClassVar[str] = "SPINDLE.0.WAIT_ORIENT_COMPLETE"
    timeout: float

    def to_text(self) -> str:
        return f"{self.NAME}({_f4(self.timeout)})"


@dataclass(frozen=True, slots=True)
class Finish(Command):
    """End of a sequence of motions rs274 prints before a probe or an M66 wait."""

    NAME: ClassVar[str] = "FINISH"


@dataclass(frozen=True, slots=True)
class RigidTap(Command):
    """G33.1: spindle-synchronised tap in to the point and back (LinuxCNC ``RIGID_TAP``)."""

    NAME: ClassVar[str] = "RIGID_TAP"
    x: float
    y: float
    z: float
