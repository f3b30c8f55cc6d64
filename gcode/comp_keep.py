"""Cutter radius compensation kept for the target control (``cnc convert --cutter-comp keep``).

By default the interpreter compensates the path itself, as LinuxCNC's does
(:mod:`gcode.cutter_comp`), so the IR holds the tool-centre path. A program converted for
another control should instead keep ``G41``/``G42`` with the *programmed* (part contour)
path, so the operator can still adjust the radius or wear at the machine. With this class
in place of :class:`~gcode.cutter_comp.CutterCompensator` the interpreter emits the
NISTIR 5970 commands (App. A.8: ``SET_CUTTER_RADIUS_COMPENSATION``,
``START_CUTTER_RADIUS_COMPENSATION``, ``STOP_CUTTER_RADIUS_COMPENSATION``) and the moves as
programmed; the same block errors as with compensation applied (plane, already on, D
missing, forbidden operations) still stop the program. Compensation outside the XY plane
or with a lathe orientation (G41.1 L) is applied as before: no writer states it.
"""

from __future__ import annotations

from gcode.comp_rules import LEFT, ToolLookup, comp_setting
from gcode.cutter_comp import CutterCompensator
from kernel import canon
from kernel.diagnostics import Diagnostic, Location


class KeptCompensation(CutterCompensator):
    """G40/G41/G42 as canonical commands around the programmed path (see module doc)."""

    def __init__(self, *, comments: bool = True) -> None:
        super().__init__(comments=comments)
        self.applying = False  # this G41/G42 is compensated here after all (XZ, lathe)

    @property
    def engaged(self) -> bool:
        return self.applying and super().engaged

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
        if self.side:
            raise Diagnostic(
                "NGC-COMP-ALREADY-ON", "Cannot turn cutter radius comp on when on", source
            )
        side, radius, orientation = comp_setting(code, plane, d, l, tool, source)
        if plane != canon.Plane.XY or orientation:
            self.applying = True
            return super().start(code, plane, d=d, l=l, tool=tool, source=source)
        self.side, self.radius, self.plane = side, radius, plane
        self.orientation = 0
        which = canon.CompSide.LEFT if side == LEFT else canon.CompSide.RIGHT
        return [
            canon.SetCutterRadiusCompensation(radius, source=source),
            canon.StartCutterRadiusCompensation(which, source=source),
        ]

    def stop(self, *, source: Location | None) -> list[canon.Command]:
        if self.applying:
            self.applying = False
            return super().stop(source=source)
        was_on = self.side != 0
        self.side = 0
        self.first_move = True
        return [canon.StopCutterRadiusCompensation(source=source)] if was_on else []

    def flush(self, source: Location | None = None) -> list[canon.Command]:
        return super().flush(source) if self.applying else []
