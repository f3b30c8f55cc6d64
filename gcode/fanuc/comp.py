"""Cutter compensation with Fanuc's change of offset in offset mode.

The RS274/NGC compensator (:class:`gcode.ngc.comp.cutter_comp.CutterCompensator`) follows
LinuxCNC, which refuses G41/G42 while compensation is on. A Fanuc (0i-MF operator's manual,
"Tool radius compensation", change of the compensation value in offset mode) and a Haas
take a new D there: the vector at the start of that block keeps the old value, the vector
at its end is computed for the new one, so the tool slants from the old offset path to the
new one along that block and follows the new one after it. :class:`FanucCompensator` adds
that one operation; everything else is the RS274/NGC compensator's.
"""

from __future__ import annotations

from gcode.ngc.comp.cutter_comp import CutterCompensator
from gcode.ngc.comp.queue import HeldMove
from kernel.diagnostics import Diagnostic, Location


class FanucCompensator(CutterCompensator):
    """The RS274/NGC compensator plus Fanuc's new D in offset mode."""

    def change_radius(self, radius: float, source: Location | None) -> None:
        """After the block at ``source`` that gave the new D: its held end moves
        from the old offset path to the new one (``radius``), and the radius changes."""
        if self.first_move or self.radius <= 0.0:
            self.radius = radius  # no compensated move yet: the start-up uses the new value
            return
        items = self._queue.items
        last = next((i for i in reversed(range(len(items))) if isinstance(items[i], HeldMove)), -1)
        held = items[last] if last >= 0 else None
        if (
            not isinstance(held, HeldMove)
            or held.is_arc
            or held.direction == (0.0, 0.0)
            or held.source is None
            or source is None
            or (held.source.file, held.source.line) != (source.file, source.line)
        ):
            raise Diagnostic(
                "FANUC-COMP-CHANGE",
                "a new D in offset mode is read on a straight move in the plane only",
                source,
            )
        p1, p2, _ = self._programmed
        k = radius / self.radius
        end = (p1 + (held.end[0] - p1) * k, p2 + (held.end[1] - p2) * k)
        items[last] = HeldMove(
            held.kind, end, held.normal, held.abc, held.source, direction=held.direction
        )
        self._current = (end[0], end[1], self._current[2])
        self.radius = radius
