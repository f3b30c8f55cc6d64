"""What the interpreter asks of a cutter compensator (G40/G41/G42), as a Protocol.

The interpreter and its sibling modules hold the compensator as :class:`CutterComp` so
they need not know which one is in use (:class:`gcode.ngc.comp.cutter_comp.CutterCompensator`
compensates the path; :class:`gcode.ngc.comp.keep.KeptCompensation` keeps G41/G42 as commands).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from gcode.ngc.comp.rules import ToolLookup
from kernel.diagnostics import Location
from kernel.ir import canon


class CutterComp(Protocol):
    """The cutter-compensation filter between the interpreter and its output."""

    #: set by G40 after a compensated move: the next motion must be straight
    arc_not_allowed: bool

    @property
    def on(self) -> bool:
        """G41/G42/G41.1/G42.1 in force (even with radius 0)."""
        ...

    @property
    def engaged(self) -> bool:
        """Motions must go through :meth:`straight` / :meth:`arc`."""
        ...

    @property
    def holding(self) -> bool:
        """A move is held: every other command must go through :meth:`passthrough`."""
        ...

    def require_off(self, action: str, source: Location | None) -> None:
        """Refuse ``action`` while compensation is on."""
        ...

    def check_arc_allowed(self, source: Location | None) -> None:
        """Refuse an arc as the first move after G40."""
        ...

    def start(
        self,
        code: str,
        plane: canon.Plane,
        *,
        d: float | None,
        l: float | None,  # noqa: E741 - the L word
        tool: ToolLookup,
        source: Location | None,
    ) -> list[canon.Command]:
        """G41 / G42 / G41.1 / G42.1."""
        ...

    def stop_offset(self) -> tuple[float, float, float] | None:
        """Before G40: the tool's point less the programmed one in X Y Z, or None."""
        ...

    def stop(self, *, source: Location | None) -> list[canon.Command]:
        """G40."""
        ...

    def flush(self, source: Location | None = None) -> list[canon.Command]:
        """Release everything held (program stops)."""
        ...

    def release(self) -> list[canon.Command]:
        """Release the held commands as they are (after M61)."""
        ...

    def end_program(self) -> None:
        """M2/M30 after :meth:`flush`."""
        ...

    def set_units(self, inches: bool) -> None:
        """G20/G21."""
        ...

    def passthrough(self, cmd: canon.Command) -> list[canon.Command]:
        """A non-motion command while a move is held."""
        ...

    def straight(
        self,
        start: Sequence[float],
        end: Sequence[float],
        *,
        rapid: bool,
        source: Location | None,
        g33: bool = False,
    ) -> list[canon.Command]:
        """A compensated G0/G1 (or G33)."""
        ...

    def arc(
        self,
        start: Sequence[float],
        end: Sequence[float],
        centre: tuple[float, float],
        turn: int,
        *,
        source: Location | None,
    ) -> list[canon.Command]:
        """A compensated G2/G3."""
        ...
