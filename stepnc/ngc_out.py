"""Canonical commands -> RS274/NGC text (LinuxCNC dialect), so a STEP-NC program can run on
a conventional controller (book §11 "Type 1" STEP-CNC: STEP-NC converted to G-code).

Each canonical command becomes the block LinuxCNC's interpreter maps back to it (seed
NISTIR 5970 App. B; LinuxCNC G-code reference): ARC_FEED in the XY plane is G2/G3 with
I J relative to the start and P for extra turns; NURBS_FEED is G5.2/G5.3; a tool length
offset is G43.1 Z; SPINDLE_RETRACT is a machine-coordinate move to Z0 (G53 G0 Z0).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from kernel import canon


def _n(v: float) -> str:
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def to_ngc(commands: Iterable[canon.Command], title: str = "") -> Iterator[str]:
    """Yield NGC lines (with newline)."""
    if title:
        yield f"({title.replace('(', '[').replace(')', ']')})\n"
    x = y = 0.0
    pockets: dict[str, int] = {}
    for cmd in commands:
        line = _block(cmd, x, y, pockets)
        if isinstance(cmd, (canon.StraightFeed, canon.StraightTraverse)):
            x, y = cmd.x, cmd.y
        elif isinstance(cmd, canon.ArcFeed):
            x, y = cmd.first_end, cmd.second_end
        elif isinstance(cmd, canon.NurbsFeed) and cmd.points:
            x, y = cmd.points[-1][0], cmd.points[-1][1]
        if line is not None:
            yield line + "\n"


def _block(cmd: canon.Command, x: float, y: float, pockets: dict[str, int]) -> str | None:
    if isinstance(cmd, canon.UseLengthUnits):
        return {canon.Units.MM: "G21", canon.Units.INCHES: "G20"}.get(cmd.units, "G21")
    if isinstance(cmd, canon.SetOriginOffsets):
        return f"G10 L2 P1 X{_n(cmd.x)} Y{_n(cmd.y)} Z{_n(cmd.z)}\nG54"
    if isinstance(cmd, canon.SetFeedReference):
        return None
    if isinstance(cmd, canon.StraightTraverse):
        return f"G0 X{_n(cmd.x)} Y{_n(cmd.y)} Z{_n(cmd.z)}"
    if isinstance(cmd, canon.StraightFeed):
        return f"G1 X{_n(cmd.x)} Y{_n(cmd.y)} Z{_n(cmd.z)}"
    if isinstance(cmd, canon.ArcFeed):
        g = "G3" if cmd.rotation > 0 else "G2"
        turns = abs(cmd.rotation)
        p = f" P{turns}" if turns > 1 else ""
        return (
            f"{g} X{_n(cmd.first_end)} Y{_n(cmd.second_end)} Z{_n(cmd.axis_end_point)} "
            f"I{_n(cmd.first_axis - x)} J{_n(cmd.second_axis - y)}{p}"
        )
    if isinstance(cmd, canon.NurbsFeed):
        lines = []
        for i, (px, py, w) in enumerate(cmd.points):
            lines.append(
                f"G5.2 X{_n(px)} Y{_n(py)} P{_n(w)}" + (f" L{cmd.order}" if i == 0 else "")
            )
        lines.append("G5.3")
        return "\n".join(lines)
    if isinstance(cmd, canon.SetFeedRate):
        return f"F{_n(cmd.rate)}"
    if isinstance(cmd, canon.SetSpindleSpeed):
        return f"S{_n(cmd.speed)}"
    if isinstance(cmd, canon.StartSpindleClockwise):
        return "M3"
    if isinstance(cmd, canon.StartSpindleCounterclockwise):
        return "M4"
    if isinstance(cmd, canon.StopSpindleTurning):
        return "M5"
    if isinstance(cmd, canon.FloodOn):
        return "M8"
    if isinstance(cmd, canon.MistOn):
        return "M7"
    if isinstance(cmd, (canon.FloodOff, canon.MistOff)):
        return "M9"
    if isinstance(cmd, canon.SpindleRetract):
        return "G53 G0 Z0"
    if isinstance(cmd, canon.UseToolLengthOffset):
        return "G49" if cmd.length == 0 else f"G43.1 Z{_n(cmd.length)}"
    if isinstance(cmd, canon.ChangeTool):
        slot = cmd.slot or pockets.setdefault(cmd.name, len(pockets) + 1)
        comment = f" ({cmd.name})" if cmd.name else ""
        return f"T{slot} M6{comment}"
    if isinstance(cmd, canon.Dwell):
        return f"G4 P{_n(cmd.seconds)}"
    if isinstance(cmd, canon.Message):
        return f"(MSG,{cmd.text})"
    if isinstance(cmd, canon.Comment):
        return f"({cmd.text})"
    if isinstance(cmd, canon.ProgramStop):
        return "M0"
    if isinstance(cmd, canon.OptionalProgramStop):
        return "M1"
    if isinstance(cmd, canon.ProgramEnd):
        return "M2"
    if isinstance(cmd, canon.PalletShuttle):
        return "M60"
    return f"({cmd.to_text()})"
