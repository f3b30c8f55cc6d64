"""Cutter radius compensation kept for the target control (``cnc convert --cutter-comp keep``).

By default the interpreter compensates the path itself, as LinuxCNC's does
(:mod:`gcode.ngc.comp.cutter_comp`), so the IR holds the tool-centre path. A program converted for
another control should instead keep ``G41``/``G42`` with the *programmed* (part contour)
path, so the operator can still adjust the radius or wear at the machine. With this class
in place of :class:`~gcode.ngc.comp.cutter_comp.CutterCompensator` the interpreter emits the
NISTIR 5970 commands (App. A.8: ``SET_CUTTER_RADIUS_COMPENSATION``,
``START_CUTTER_RADIUS_COMPENSATION``, ``STOP_CUTTER_RADIUS_COMPENSATION``) and the moves as
programmed. A shadow compensator runs beside it on the same moves and its output is
dropped: a program the control would refuse (entry move too short, arc after G40, tool
too big for a concave corner) is refused here at the same block. Compensation outside
the XY plane or with a lathe orientation (G41.1 L) is applied as before: no writer states
it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

from gcode.ngc.comp.cutter_comp import CutterCompensator
from gcode.ngc.comp.rules import LEFT, ToolLookup, comp_setting
from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.record import record


@record
class CompRegister(canon.Command):
    """Where a kept G41/G42 takes its radius: the tool-table entry / offset register
    ``register`` (G41 D n, or the tool in the spindle without D), or None for a radius
    given by value (G41.1 D diameter). Emitted just before SET_CUTTER_RADIUS_COMPENSATION
    so a writer can keep ``D n`` instead of stating the value."""

    NAME: ClassVar[str] = "CUTTER_COMP_REGISTER"
    register: int | None


class KeptCompensation(CutterCompensator):
    """G40/G41/G42 as canonical commands around the programmed path (see module doc)."""

    def __init__(self, *, comments: bool = True) -> None:
        self.shadow = CutterCompensator(comments=False)  # checks; its output is dropped
        super().__init__(comments=comments)
        self.applying = False  # this G41/G42 is compensated here after all (XZ, lathe)

    @property
    def arc_not_allowed(self) -> bool:
        return self.shadow.arc_not_allowed

    @arc_not_allowed.setter
    def arc_not_allowed(self, value: bool) -> None:
        self.shadow.arc_not_allowed = value

    @property
    def holding(self) -> bool:
        return self.applying and super().holding

    def set_units(self, inches: bool) -> None:
        self.shadow.set_units(inches)
        super().set_units(inches)

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
        side, radius, orientation = comp_setting(code, plane, d, l, tool, source)
        if plane != canon.Plane.XY or orientation:
            self.applying = True
            return super().start(code, plane, d=d, l=l, tool=tool, source=source)
        self.shadow.start(code, plane, d=d, l=l, tool=tool, source=source)
        self.side, self.radius, self.plane, self.orientation = side, radius, plane, 0
        which = canon.CompSide.LEFT if side == LEFT else canon.CompSide.RIGHT
        return [
            canon.SetCutterRadiusCompensation(radius, source=source),
            canon.StartCutterRadiusCompensation(which, source=source),
        ]

    def stop_offset(self) -> tuple[float, float, float] | None:
        """Compensation kept as commands leaves the tool on the programmed path."""
        return super().stop_offset() if self.applying else None

    def stop(self, *, source: Location | None) -> list[canon.Command]:
        if self.applying:
            self.applying = False
            return super().stop(source=source)
        self.shadow.stop(source=source)
        was_on = self.side != 0
        self.side = 0
        self.first_move = True
        return [canon.StopCutterRadiusCompensation(source=source)] if was_on else []

    def flush(self, source: Location | None = None) -> list[canon.Command]:
        if self.applying:
            return super().flush(source)
        self.shadow.flush(source)
        return []

    def release(self) -> list[canon.Command]:
        if self.applying:
            return super().release()
        self.shadow.release()
        return []

    def end_program(self) -> None:
        self.shadow.end_program()
        super().end_program()

    def straight(
        self,
        start: Sequence[float],
        end: Sequence[float],
        *,
        rapid: bool,
        source: Location | None,
        g33: bool = False,
    ) -> list[canon.Command]:
        if self.applying:
            return super().straight(start, end, rapid=rapid, source=source, g33=g33)
        self.shadow.straight(start, end, rapid=rapid, source=source, g33=g33)
        kind = canon.StraightTraverse if rapid else canon.StraightFeed
        return [kind(*end[:6], source=source)]

    def arc(
        self,
        start: Sequence[float],
        end: Sequence[float],
        centre: tuple[float, float],
        turn: int,
        *,
        source: Location | None,
    ) -> list[canon.Command]:
        if self.applying:
            return super().arc(start, end, centre, turn, source=source)
        self.shadow.arc(start, end, centre, turn, source=source)
        x, y, z, a, b, c = end[:6]
        return [canon.ArcFeed(x, y, centre[0], centre[1], turn, z, a, b, c, source=source)]
