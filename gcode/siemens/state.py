"""The modal state of a Siemens 840D channel as the reader tracks it.

Start-up state (840D sl programming manual, fundamentals, "List of G functions": the
default of each group): G0, G17, G90, G94, G710-like metric (G71), G60-free continuous path
off (G60 is the 840D default, exact stop), G54 as the RS274/NGC interpreter starts,
spindle stopped, no tool, programmable frame empty.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from gcode.siemens.frames import Frame
from kernel.ir import canon

#: plane name -> (IR plane, (first, second, normal) axis indexes, centre letters)
PLANES: dict[str, tuple[canon.Plane, tuple[int, int, int], tuple[str, str]]] = {
    "XY": (canon.Plane.XY, (0, 1, 2), ("I", "J")),
    "ZX": (canon.Plane.XZ, (2, 0, 1), ("K", "I")),
    "YZ": (canon.Plane.YZ, (1, 2, 0), ("J", "K")),
}


@dataclass
class State:
    units: canon.Units = canon.Units.MM
    units_code: int = 71  # 70/71 (lengths only) or 700/710 (lengths and feeds)
    absolute: bool = True
    plane: str = "XY"
    motion: int = 0  # 0 1 2 3 33
    feed_mode: int = 0  # 0 G94 per minute, 1 G93 inverse time, 2 G95 per revolution
    feed: float = 0.0  # IR feed (program units per minute / per revolution)
    speed: float = 0.0
    direction: canon.Direction = canon.Direction.STOPPED
    css: bool = False
    css_max: float = 0.0
    selected_tool: int | None = None
    tool: int = 0
    edge: int = 0  # active D number
    tool_length: float = 0.0
    work: int = 1  # settable frame: 0 = G500, 1 = G54, ...
    g5x: tuple[float, ...] = (0.0,) * 6
    frame: Frame = field(default_factory=Frame)
    pos: list[float] = field(default_factory=lambda: [0.0] * 6)  # IR coordinates
    lead: float | None = None  # G33 K
    control: int = 60  # 60 exact stop, 64 continuous, 641 with ADIS= rounding
    adis: float = 0.0  # G641 rounding distance
    #: modal call (MCALL CYCLE81(...), MCALL L10): the cycle or subprogram, its arguments
    #: (None: none written), and whether a program file is called (else a cycle expanded)
    mcall: tuple[str, tuple | None, bool] | None = None
    probing: bool = False
    diameter: int = 0  # 0 DIAMOF, 1 DIAMON, 90 DIAM90 (X as a diameter)
    rounding: float = 0.0  # RNDM= modal rounding radius (0: off)
