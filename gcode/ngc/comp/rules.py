"""Rules of the G41/G42 mode (LinuxCNC ``convert_cutter_compensation_on`` and friends).

Which radius and side a G41/G42/G41.1/G42.1 block selects, which canonical commands wait
behind a held compensated move, and what LinuxCNC refuses while compensation is on. Used by
:mod:`gcode.ngc.comp.cutter_comp`; the interpreter uses :data:`FORBIDDEN` through
:meth:`gcode.ngc.comp.cutter_comp.CutterCompensator.require_off`.
"""

from __future__ import annotations

from collections.abc import Callable

from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

LEFT, RIGHT = 1, -1
#: ``tool(number)`` -> (diameter in program units, lathe orientation) or None if unknown;
#: ``number`` None means the tool in the spindle.
ToolLookup = Callable[[int | None], "tuple[float, int] | None"]

#: Canonical commands LinuxCNC holds in the queue behind a compensated move (enqueue_*).
QUEUED_NAMES = frozenset(
    {
        "SET_FEED_RATE",
        "DWELL",
        "SET_FEED_MODE",
        "MIST_ON",
        "MIST_OFF",
        "FLOOD_ON",
        "FLOOD_OFF",
        "START_SPINDLE_CLOCKWISE",
        "START_SPINDLE_COUNTERCLOCKWISE",
        "STOP_SPINDLE_TURNING",
        "SET_SPINDLE_MODE",
        "SET_SPINDLE_SPEED",
        "COMMENT",
        "ORIENT_SPINDLE",
        "WAIT_ORIENT_SPINDLE_COMPLETE",
        "START_CHANGE",
    }
)

#: What LinuxCNC refuses while compensation is on (G41/G42 in force), with its messages.
FORBIDDEN = {
    "G53": "Cannot use g53 with cutter radius comp",  # any motion with G53
    "G28/G30": "Cannot use g28 or g30 with cutter radius comp",
    # G52 and G92 with axis words only: rs274 allows G92.1, G92.2 and G92.3 while compensated
    "axis offsets": "Cannot change axis offsets with cutter radius comp",
    "coordinate system": "Cannot change coordinate systems with cutter radius compensation on",
    "active coordinate system": "Cannot change the active coordinate system with cutter radius "
    "compensation on",  # G10 L2/L20 of the system in use
    "tool offset": "Cannot change tool offset with cutter radius compensation on",  # G43 G49
    "tool change": "Cannot change tools with cutter radius compensation on",  # M6
    "plane": "Cannot change planes with cutter radius compensation on",  # to another plane
    "control mode": "Cannot change control mode with cutter radius compensation on",  # G61 G64
    "enable overrides": "Cannot enable overrides with cutter radius compensation on",  # M48
    "disable overrides": "Cannot disable overrides with cutter radius compensation on",  # M49-53
    "canned cycle": "Cannot use canned cycles with cutter compensation on",
    "probe": "Cannot probe with cutter radius comp on",  # G38.x
    "G76": "Cannot use G76 threading cycle with cutter radius compensation on",
    "spline": "Cannot convert spline with cutter radius compensation",  # G5 G5.1
    "M62/M63": "Cannot set motion output with cutter radius compensation on",
    "M64/M65": "Cannot set auxiliary digital output with cutter radius compensation on",
    "M66": "Cannot wait for digital input with cutter radius compensation on",
    "M67": "Cannot set motion analog output with cutter radius compensation on",
    "M68": "Cannot set auxiliary analog output with cutter radius compensation on",
}


def comp_setting(
    code: str,
    plane: canon.Plane,
    d: float | None,
    l: float | None,  # noqa: E741 - the L word
    tool: ToolLookup,
    source: Location | None,
) -> tuple[int, float, int]:
    """(side, radius, lathe orientation) selected by a G41/G42/G41.1/G42.1 block.

    G41/G42 use the diameter of tool D (D0 or no D: the tool in the spindle); G41.1/G42.1
    use D as the diameter and L as the lathe orientation (G18 only). A negative radius
    swaps the side, so the radius returned is never negative.
    """
    side = LEFT if code.startswith("G41") else RIGHT
    if code.endswith(".1"):
        if d is None:
            raise Diagnostic("NGC-COMP-D-MISSING", f"{code[:3]}.1 with no D word", source)
        radius = d / 2.0
        orientation = 0
        if l is not None:
            if plane != canon.Plane.XZ:
                raise Diagnostic(
                    "NGC-COMP-L-PLANE",
                    f"{code[:3]}.1 with L word, but plane is not G18",
                    source,
                )
            orientation = int(l)
    else:
        number: int | None = None
        if d is not None:
            number = int(d + 0.5)
            if abs(number - d) >= 0.0001:
                raise Diagnostic(
                    "NGC-COMP-D-INTEGER", f"{code} requires D word to be a whole number", source
                )
        found = tool(number or None)  # D0 is the tool in the spindle, as no D
        if found is None:
            raise Diagnostic(
                "NGC-COMP-D-UNKNOWN-TOOL",
                f"Requested tool {number} not found in the tool table",
                source,
            )
        diameter, orientation = found
        radius = diameter / 2.0
        if plane != canon.Plane.XZ and orientation not in (0, 9):
            raise Diagnostic(
                "NGC-COMP-LATHE-TOOL", f"{code} with lathe tool, but plane is not G18", source
            )
    if radius < 0.0:
        return -side, -radius, orientation
    return side, radius, orientation
