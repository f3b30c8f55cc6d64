"""The state of one Fanuc run around the RS274/NGC machine model, and the flow's actions.

:class:`ExecutorState` is what :class:`gcode.fanuc.executor.Executor` keeps between
blocks (transforms, modal motion, offset tables, the G06.2 curve being read, the macro
call depth). The modules that act on it (:mod:`gcode.fanuc.cycles`,
:mod:`gcode.fanuc.moves`, :mod:`gcode.fanuc.offsets`, :mod:`gcode.fanuc.sysvars`) receive
it typed, so they never import the executor back; the executor imports them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

from gcode.core.corners import CornerRequest
from gcode.fanuc.options import Flavour
from gcode.fanuc.transforms import Transforms
from gcode.ngc.interpreter import Interpreter
from kernel.diagnostics import Location


@dataclass
class Action:
    """What the flow does after the block: call, return, end."""

    kind: str  # "m98" "g65" "m97" "m99" "end" "g66"
    number: int = 0
    repeats: int = 1
    args: dict[int, float] = field(default_factory=dict)
    seq: int | None = None


@dataclass
class ModalCall:
    """G66 P L arguments: the macro called after each move."""

    number: int
    repeats: int
    args: dict[int, float]
    depth: int


@dataclass
class NurbsCollector:
    """The blocks of one G06.2 curve: control points, weights and knots."""

    order: int
    points: list[tuple[float, float, float]] = field(default_factory=list)
    knots: list[float] = field(default_factory=list)
    end_knots: int = 0
    loc: Location | None = None


class LatheMode(Protocol):
    """Lathe-mode handling of a block (:class:`gcode.fanuc.lathe.Lathe`)."""

    @property
    def codes(self) -> frozenset[int]:
        """The G codes (round(G*10)) read in lathe mode."""
        ...

    def start(self) -> None:
        """The power-on state of a lathe (ZX plane, feed per revolution)."""
        ...

    def block(
        self,
        gs: list[int],
        ms: list[int],
        v: dict[str, float],
        cols: dict[str, int],
        raw: dict[str, int | float],
        loc: Location,
    ) -> list[Action]:
        """Execute one block's evaluated words; the flow actions it asks for."""
        ...


class ExecutorState:
    """Per-run Fanuc state around the RS274/NGC machine model ``ip``."""

    def __init__(self, ip: Interpreter, flavour: Flavour) -> None:
        self.ip = ip
        self.fl = flavour
        self.tf = Transforms()
        #: what an axis word alone runs: the group 01 mode, or the canned cycle (group 09)
        self.motion: int | None = 0
        self.group01: int | None = 0  # Fanuc modal group 01 (power-on G00)
        self.nurbs: NurbsCollector | None = None
        self.lengths: dict[int, list[float]] = {}  # G10 L10/L11: [geometry, wear]
        self.radii: dict[int, list[float]] = {}  # G10 L12/L13
        self.modal_call: ModalCall | None = None
        self.extended: dict[int, list[float]] = {}  # G10 L20 / G54.1 P offsets
        self.extended_selected: int | None = None
        self.control = 640  # G61 / G64 for G05.1 Q0 and G09
        self.comp_d: float | None = None  # D word of the G41/G42 in force
        self.modal_h: float | None = None  # H word of the last G43 (#4111)
        self.lathe: LatheMode | None = None  # set by the flow when the flavour is a lathe
        self.depth = 0  # macro call depth (set by the flow)
        self.last_comment: str | None = None
        #: the ,C / ,R corner the block just run asks for (the flow cuts it)
        self.corner: CornerRequest | None = None
        ip.s.retract_r = False  # Fanuc mills power on in G98 (initial level)
        ip.s.motion_mode = 0
