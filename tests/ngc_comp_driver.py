"""A small G-code driver for testing :mod:`gcode.ngc.comp.cutter_comp` without the full interpreter.

It understands only what the cutter-compensation goldens use (one block per line, no
expressions or parameters): G0-G3 (I J K or R, P), G4, G10 L1 P R, G17/G18, G20/G21,
G40-G42 and G41.1/G42.1 with D and L, G90/G91, F, S, T, M0/M1/M2/M30/M60, M3-M9, M6, ``(MSG,...)``.
Execution order within a line follows LinuxCNC's (messages, F, S, T, M6, spindle, coolant,
dwell, plane, units, compensation, distance mode, G10, motion, stop). It exists so the
compensator can be checked against rs274 goldens (tests/golden/ngc/125_*..., 136_...) and
against rs274 itself on generated programs; :func:`gcode.ngc.interpreter.interpret` is the
real front end.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from gcode.core import arcs
from gcode.ngc.comp.cutter_comp import CutterCompensator
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon
from kernel.tooltable import ToolTable

_WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
_PLANE_AXES = {canon.Plane.XY: (0, 1, 2), canon.Plane.XZ: (2, 0, 1)}


#: rs274's ``GET_EXTERNAL_LENGTH_UNITS()``: tool tables are in inches, given per mm thus.
EXTERNAL_UNITS = 0.03937007874016


def user_to_program(length: float, inches: bool) -> float:
    """LinuxCNC ``USER_TO_PROGRAM_LEN`` as rs274 computes it (units.h), to the last bit."""
    return length / EXTERNAL_UNITS / (25.4 if inches else 1.0)


def _lookup(
    tools: ToolTable, loaded: int, inches: bool, g10: dict[int, float]
) -> Callable[[int | None], tuple[float, int] | None]:
    def lookup(number: int | None) -> tuple[float, int] | None:
        n = loaded if number in (None, 0) else number
        tool = tools.get(n)
        if tool is None:
            return None
        return user_to_program(g10.get(n, tool.diameter), inches), tool.orientation

    return lookup


def run(text: str, tools: ToolTable, name: str = "prog.ngc") -> list[canon.Command]:
    """Canonical commands of ``text``; a :class:`Diagnostic` stops the run as in rs274."""
    comp = CutterCompensator(comments=False)
    out: list[canon.Command] = [canon.UseLengthUnits(canon.Units.MM)]
    pos = [0.0] * 6
    inches, absolute, plane = False, True, canon.Plane.XY
    loaded = selected = 0
    motion = 1.0
    g10: dict[int, float] = {}

    def emit(cmd: canon.Command) -> None:
        out.extend(comp.passthrough(cmd) if comp.holding else [cmd])

    for lineno, raw in enumerate(text.splitlines(), 1):
        loc = Location(name, lineno, 1)
        line = raw.strip().upper()
        if line.startswith("%"):
            continue
        for msg in re.findall(r"\(\s*MSG\s*,([^)]*)\)", raw, flags=re.IGNORECASE):
            emit(canon.Message(msg))
        line = re.sub(r"\([^)]*\)", "", line).split(";")[0]
        words: dict[str, float] = {}
        gs: list[float] = []
        ms: list[float] = []
        for letter, value in _WORD.findall(line):
            if letter == "G":
                gs.append(float(value))
            elif letter == "M":
                ms.append(float(value))
            else:
                words[letter] = float(value)
        if "F" in words:
            emit(canon.SetFeedRate(words["F"]))
        if "S" in words:
            emit(canon.SetSpindleSpeed(words["S"]))
        if "T" in words:
            selected = int(words["T"])
            out.append(canon.SelectTool(selected))
        if 6 in ms:
            comp.require_off("tool change", loc)
            out.append(canon.ChangeTool(selected))
            loaded = selected
        for m, cmd in (
            (3, canon.StartSpindleClockwise()),
            (4, canon.StartSpindleCounterclockwise()),
            (5, canon.StopSpindleTurning()),
            (7, canon.MistOn()),
            (8, canon.FloodOn()),
        ):
            if m in ms:
                emit(cmd)
        if 9 in ms:
            emit(canon.MistOff())
            emit(canon.FloodOff())
        if 4 in gs:
            emit(canon.Dwell(words.get("P", 0.0)))
        for g, pl in ((17, canon.Plane.XY), (18, canon.Plane.XZ)):
            if g in gs:
                if comp.on and pl != plane:
                    raise Diagnostic("NGC-COMP-ACTIVE", "Cannot change planes with comp on", loc)
                plane = pl
                out.append(canon.SelectPlane(pl))
        for g, units in ((20, True), (21, False)):
            if g in gs:
                out.append(canon.UseLengthUnits(canon.Units.INCHES if units else canon.Units.MM))
                if units != inches:
                    factor = 1 / 25.4 if units else 25.4
                    pos = [v * factor for v in pos[:3]] + pos[3:]
                comp.set_units(units)
                inches = units
        for g in (40, 41, 42, 41.1, 42.1):
            if g in gs:
                if g == 40:
                    out.extend(comp.stop(source=loc))
                else:
                    code = f"G{g:g}"
                    out.extend(
                        comp.start(
                            code,
                            plane,
                            d=words.get("D"),
                            l=words.get("L"),
                            tool=_lookup(tools, loaded, inches, g10),
                            source=loc,
                        )
                    )
        if 90 in gs:
            absolute = True
        if 91 in gs:
            absolute = False
        if 10 in gs and words.get("L") == 1:
            # PROGRAM_TO_USER_LEN
            g10[int(words["P"])] = 2 * words["R"] * (25.4 if inches else 1.0) * EXTERNAL_UNITS
            continue
        for g in (0, 1, 2, 3):
            if g in gs:
                motion = float(g)
        if any(a in words for a in "XYZABC"):
            end = list(pos)
            for i, a in enumerate("XYZABC"):
                if a in words:
                    end[i] = words[a] if absolute else pos[i] + words[a]
            if motion in (0.0, 1.0):
                comp.arc_not_allowed = False
                if comp.engaged:
                    out.extend(comp.straight(pos, end, rapid=motion == 0, source=loc))
                else:
                    cls = canon.StraightTraverse if motion == 0 else canon.StraightFeed
                    out.append(cls(*end, source=loc))
            else:
                comp.check_arc_allowed(loc)
                i1, i2, _ = _PLANE_AXES[plane]
                start2 = (pos[i1], pos[i2])
                end2 = (end[i1], end[i2])
                turn = arcs.turns_for(motion == 2, words.get("P"), loc)
                if "R" in words:
                    centre = arcs.radius_format(start2, end2, words["R"], motion == 2, loc)
                else:
                    off = {0: "I", 1: "J", 2: "K"}
                    centre = (
                        pos[i1] + words.get(off[i1], 0.0),
                        pos[i2] + words.get(off[i2], 0.0),
                    )
                    arcs.centre_format(start2, end2, centre, ("xyz"[i1], "xyz"[i2]), inches, loc)
                if comp.engaged:
                    out.extend(comp.arc(pos, end, centre, turn, source=loc))
                else:
                    n = _PLANE_AXES[plane][2]
                    out.append(canon.ArcFeed(*end2, *centre, turn, end[n], *end[3:], source=loc))
            pos = end
        if any(m in ms for m in (0, 1, 2, 30, 60)):
            out.extend(comp.flush(loc))
            if 0 in ms or 60 in ms:
                out.append(canon.ProgramStop())
                continue
            if 1 in ms:
                out.append(canon.OptionalProgramStop())
                continue
            comp.end_program()
            out.append(canon.ProgramEnd())
            break
    return out
