"""Reader of the Sandia generic CNC language (seed 003; research/seed-sandia-full.md §5.3-5.4).

The seed names the commands (Figure 3) and specifies one method fully
(``point_to_point_positioning``, Appendix A); the text syntax is the proposal of
research/seed-sandia-full.md §5.3, the one :mod:`gcode.write.sandia` writes: one command
per line, the seed's name (exact, case-sensitive), then positional or ``NAME=value``
arguments; ``#`` starts a comment. Mapping to the IR (§5.4):

* ``SetUnits linear=mm|inch|cm [angular=deg]`` -> ``USE_LENGTH_UNITS`` (the current position
  is re-expressed in the new units, as G20/G21 do);
* ``point_to_point_positioning X= Y= Z= A= B= C= [attributes=ABSOLUTE|CS_CURRENT]`` ->
  ``STRAIGHT_TRAVERSE`` (never a speed: App. A §1.2); ``RELATIVE`` adds to the current
  position; omitted axes keep their value;
* ``SetSpeed v`` -> ``SET_FEED_RATE`` (units per minute); ``MoveTo X= Y= Z=`` ->
  ``STRAIGHT_FEED`` at that speed (an error without one); world space, so no A/B/C;
* ``MoveReact X= Y= Z=`` -> ``STRAIGHT_PROBE``; ``GetTool n`` -> ``SELECT_TOOL`` +
  ``CHANGE_TOOL``; ``PutTool n`` -> ``CHANGE_TOOL(0)`` (spindle empty);
  ``SetToolLength L`` -> ``USE_TOOL_LENGTH_OFFSET`` (a length by value: with register
  marks, G43.1, or G49 for 0); ``StopMotion`` -> ``STOP``;
  ``Deactivate`` -> ``PROGRAM_END`` (the device goes inactive: nothing after it runs);
* session commands with no machining meaning (``Lock``, ``Release``, ``Activate``,
  ``Configure``, ``ReportState``, ``ClearPath``, ``InitRecordFile``, ``CloseRecordFile``)
  give no command;
* the rest of Figure 3 has no IR meaning or no argument format in the seed (``MovebyJoint``,
  ``MoveComply``, ``ManualControl``, ``LoadPath``, ``MoveAlongPath``, ``SetAcceleration``,
  ``OpenGripper``, ``CloseGripper``): refused with ``SANDIA-UNSUPPORTED``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator
from typing import TextIO

import kernel.limits as limits
from gcode.core.register_marks import ToolLengthRegister
from gcode.ngc.interpreter import InterpreterOptions
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon

#: attribute names (research/seed-sandia-full.md §5.3): bit 0 mode, bits 1-4 coordinate system
MODES = {"ABSOLUTE": 0, "RELATIVE": 1}
SYSTEMS = {
    "CS_CURRENT": 0,
    "CS_MACHINE": 1,
    **{f"CS_G{54 + i}": 2 + i for i in range(6)},
    "CS_LOCAL": 8,
    "CS_G92": 9,
}
UNITS = {"mm": canon.Units.MM, "inch": canon.Units.INCHES, "cm": canon.Units.CM}
SESSION = frozenset(
    {
        "Lock",
        "Release",
        "Activate",
        "Configure",
        "ReportState",
        "ClearPath",
        "InitRecordFile",
        "CloseRecordFile",
    }
)
UNSUPPORTED = {
    "MovebyJoint": "joint-space motion has no speed rule or axis mapping in the seed",
    "MoveComply": "compliant motion has no canonical command",
    "ManualControl": "teleoperation is not a program",
    "LoadPath": "the seed gives no format for path segments",
    "MoveAlongPath": "the seed gives no format for path segments",
    "SetAcceleration": "acceleration is a machine-profile property (cnc machine), not the IR's",
    "OpenGripper": "grippers have no canonical command",
    "CloseGripper": "grippers have no canonical command",
}
COMMANDS = frozenset(
    {
        "SetUnits",
        "point_to_point_positioning",
        "SetSpeed",
        "MoveTo",
        "MoveReact",
        "GetTool",
        "PutTool",
        "SetToolLength",
        "StopMotion",
        "Deactivate",
        *SESSION,
        *UNSUPPORTED,
    }
)
#: a plain decimal (the writer's and the seed's ``25.0``); at most 20 integer digits: finite
_NUMBER = re.compile(r"[-+]?(?:[0-9]{1,20}(?:\.[0-9]*)?|\.[0-9]+)\Z")
_AXES = "XYZABC"
#: programs from this size on are read back through the compiled lane (interpret_chunks)
LANE_MIN_BYTES = 1 << 17


def interpret(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of the generic-language program at ``path`` (streaming)."""
    name = os.fspath(path)
    try:
        fh = open(name, encoding="utf-8", errors="replace")  # noqa: SIM115 - closed below
    except OSError as exc:
        raise Diagnostic(
            "IO-OPEN", f"cannot open program: {exc.strerror or exc}", Location(name)
        ) from None
    return _closing(fh, Reader(name, options or InterpreterOptions()).run(fh))


def interpret_chunks(
    path: str | os.PathLike[str], options: InterpreterOptions | None = None, *, arcs: bool = False
) -> Iterator[object]:
    """Like :func:`interpret`, with the runs of plain lines of a large program (``MoveTo``,
    ``SetSpeed``, absolute rapids) as :class:`gcode.ngc.lane.fastlane.Run` arrays scanned
    by the compiled lane (:mod:`gcode.sandia.lane`); ``arcs`` changes nothing (the language
    has none). A small program, one with CR line ends, or one read where no kernel loads
    goes through the general reader alone."""
    name = os.fspath(path)
    try:
        with open(name, "rb") as fh:
            data = fh.read()
    except OSError:
        return interpret(path, options)  # the general reader's located IO-OPEN
    opts = options or InterpreterOptions()
    if not opts.fast_lane or len(data) < LANE_MIN_BYTES or b"\r" in data:
        return interpret(path, options)
    # imported here: numpy and the kernel load only for a large program
    from gcode.sandia import lane

    try:
        lane.kernels()
    except ImportError:
        return interpret(path, options)
    limits.check_lines(data, name)
    return lane.chunks(Reader(name, opts), data)


def _closing(fh: TextIO, commands: Iterator[canon.Command]) -> Iterator[canon.Command]:
    """The commands, with the file closed once they end (or the generator is closed)."""
    with fh:
        yield from commands


def interpret_text(
    text: str, name: str = "<input>", options: InterpreterOptions | None = None
) -> Iterator[canon.Command]:
    """Canonical commands of a generic-language program given as text."""
    return Reader(name, options or InterpreterOptions()).run(text.splitlines())


class Reader:
    """One run over one program: the CNCMachine state of App. A §3.2 (units, position)."""

    def __init__(self, name: str, options: InterpreterOptions) -> None:
        self.name = name
        self.compat = options.linuxcnc_compat
        self.marks = options.register_marks  # gcode.core.register_marks, for a writer
        self.units = canon.Units.MM
        self.pos = [0.0] * 6
        self.speed: float | None = None
        self.line = 0
        self.text = ""
        self.ended = False

    # ------------------------------------------------------------------ errors
    def error(
        self, code: str, message: str, token: str | None = None, col: int = 0, last: bool = False
    ) -> Diagnostic:
        """A located error; ``token``: the word (or the value after a ``=``) it is about,
        its first occurrence (``last``: its last) as a whole word of the line."""
        if token is not None and not col:
            pattern = r"(?<![^\s=])" + re.escape(token) + r"(?![^\s#])"
            found = list(re.finditer(pattern, self.text.partition("#")[0]))
            if found:
                col = found[-1 if last else 0].start() + 1
        column = col or (len(self.text) - len(self.text.lstrip()) + 1)
        return Diagnostic(code, message, Location(self.name, self.line, column))

    def loc(self) -> Location:
        return Location(self.name, self.line, len(self.text) - len(self.text.lstrip()) + 1)

    # ------------------------------------------------------------------ run
    def run(self, lines: Iterable[str]) -> Iterator[canon.Command]:
        yield from self.preamble()
        yield from self.body(enumerate(lines, 1))

    def body(self, numbered: Iterable[tuple[int, str]]) -> Iterator[canon.Command]:
        """The commands of the (line number, text) lines; ``ended`` once ``Deactivate``
        is read (nothing after it runs)."""
        limit = limits.current().line_chars
        for self.line, raw in numbered:
            if len(raw) > limit:
                limits.check_line(len(raw.rstrip("\r\n")), self.name, self.line)
            self.text = raw
            body, hash_, comment = raw.partition("#")
            parts = body.split()
            if hash_:
                yield canon.Comment(comment.strip(), source=self.loc())
            if not parts:
                continue
            name = parts[0]
            if name == "MoveTo":
                yield self.move_to(parts)
                continue
            if name not in COMMANDS:
                raise self.unknown(name)
            if name == "Deactivate":
                self.no_args(parts)
                self.ended = True
                yield canon.ProgramEnd(source=self.loc())
                return
            yield from self.command(name, parts)

    def preamble(self) -> Iterator[canon.Command]:
        """The start-up commands of the RS274/NGC interpreter (mm, no offsets, position 0)."""
        src = Location(self.name, 0, 0)
        yield canon.UseLengthUnits(canon.Units.MM, source=src)
        if self.compat:
            yield canon.SetG5xOffset(1, 0.0, 0.0, 0.0, source=src)
            yield canon.SetG92Offset(0.0, 0.0, 0.0, source=src)
            yield canon.SetXYRotation(0.0, source=src)
        else:
            yield canon.SetOriginOffsets(0.0, 0.0, 0.0, source=src)
        yield canon.SetFeedReference(canon.FeedReference.XYZ, source=src)
        if self.compat:
            yield canon.OnReset(source=src)

    def unknown(self, name: str) -> Diagnostic:
        near = [c for c in COMMANDS if c.lower() == name.lower()]
        hint = f" (names are case-sensitive: {near[0]})" if near else ""
        return self.error("SANDIA-UNKNOWN-COMMAND", f"unknown command '{name}'{hint}", name)

    # ------------------------------------------------------------------ arguments
    def number(self, token: str, value: str) -> float:
        if not _NUMBER.match(value):
            raise self.error("SANDIA-NUMBER", f"'{token}': malformed number", token)
        return float(value)

    def named(self, parts: list[str], allowed: str | tuple[str, ...]) -> dict[str, str]:
        """``NAME=value`` arguments (order-free, each once) among ``allowed``."""
        out: dict[str, str] = {}
        for token in parts[1:]:
            key, eq, value = token.partition("=")
            if not eq or not key or not value:
                raise self.error("SANDIA-ARG", f"'{token}': expected NAME=value", token)
            if key not in allowed:
                raise self.error("SANDIA-ARG", f"{parts[0]} has no argument '{key}'", token)
            if key in out:
                raise self.error(
                    "SANDIA-ARG-REPEATED", f"argument '{key}' given twice", token, last=True
                )
            out[key] = value
        return out

    def single(self, parts: list[str], key: str) -> tuple[str, str]:
        """The one argument of ``SetSpeed 20.0`` (or ``SetSpeed speed=20.0``): (token, value)."""
        if len(parts) != 2:
            col = 0 if len(parts) < 2 else self.text.find(parts[2]) + 1
            raise self.error("SANDIA-ARG", f"{parts[0]} takes exactly one argument", col=col)
        token = parts[1]
        if token.startswith(key + "="):
            return token, token[len(key) + 1 :]
        return token, token

    def no_args(self, parts: list[str]) -> None:
        if len(parts) > 1:
            raise self.error("SANDIA-ARG", f"{parts[0]} takes no arguments", parts[1])

    def target(self, parts: list[str], axes: str, relative: bool = False) -> list[float]:
        """The destination: commanded axes replaced (or added to, when relative)."""
        pos = list(self.pos)
        for key, value in self.named(parts, tuple(axes)).items():
            i = _AXES.index(key)
            v = self.number(f"{key}={value}", value)
            pos[i] = pos[i] + v if relative else v
        return pos

    # ------------------------------------------------------------------ commands
    def move_to(self, parts: list[str]) -> canon.Command:
        """World-space feed move (research §5.3: MoveTo is a feed at the SetSpeed speed)."""
        pos = self.pos
        x, y, z = pos[0], pos[1], pos[2]
        seen = ""
        for token in parts[1:]:
            key, eq, value = token.partition("=")
            if not eq or key in seen or not _NUMBER.match(value):
                return self.move_to_slow(parts)
            if key == "X":
                x = float(value)
            elif key == "Y":
                y = float(value)
            elif key == "Z":
                z = float(value)
            else:
                return self.move_to_slow(parts)
            seen += key
        if not self.speed:
            raise self.no_speed("MoveTo")
        pos[0], pos[1], pos[2] = x, y, z
        return canon.StraightFeed(x, y, z, pos[3], pos[4], pos[5], source=self.loc())

    def move_to_slow(self, parts: list[str]) -> canon.Command:
        for token in parts[1:]:
            if token.partition("=")[0] in ("A", "B", "C"):
                raise self.error(
                    "SANDIA-WORLD-ROTARY",
                    "MoveTo is world space: rotary axes need a kinematic model "
                    "(research §5.4); use point_to_point_positioning",
                    token,
                )
        self.pos = self.target(parts, "XYZ")
        if not self.speed:
            raise self.no_speed("MoveTo")
        return canon.StraightFeed(*self.pos, source=self.loc())

    def no_speed(self, what: str) -> Diagnostic:
        return self.error(
            "SANDIA-NO-SPEED", f"{what} needs a speed above 0: give SetSpeed first", col=0
        )

    def command(self, name: str, parts: list[str]) -> Iterator[canon.Command]:  # noqa: C901
        src = self.loc()
        if name == "point_to_point_positioning":
            args = self.named(parts, (*_AXES, "attributes"))
            relative = self.attributes(args.pop("attributes", "ABSOLUTE|CS_CURRENT"))
            self.pos = self.target([name, *(f"{k}={v}" for k, v in args.items())], _AXES, relative)
            yield canon.StraightTraverse(*self.pos, source=src)
        elif name == "SetSpeed":
            token, value = self.single(parts, "speed")
            speed = self.number(token, value)
            if speed < 0:
                raise self.error("SANDIA-SPEED", "a speed cannot be negative", token)
            self.speed = speed
            yield canon.SetFeedRate(speed, source=src)
        elif name == "SetUnits":
            yield from self.set_units(parts)
        elif name == "MoveReact":
            if not self.speed:
                raise self.no_speed("MoveReact")
            self.pos = self.target(parts, "XYZ")
            yield canon.StraightProbe(*self.pos, source=src)
        elif name in ("GetTool", "PutTool"):
            token, value = self.single(parts, "tool")
            slot, label = (int(value), "") if value.isascii() and value.isdigit() else (0, value)
            if name == "PutTool":
                yield canon.ChangeTool(0, source=src)
                return
            yield canon.SelectTool(slot, source=src)
            if self.compat:
                yield canon.StartChange(source=src)
            yield canon.ChangeTool(slot, label, source=src)
        elif name == "SetToolLength":
            token, value = self.single(parts, "length")
            length = self.number(token, value)
            if self.marks:  # a length by value (G43.1), or none (G49): no register
                yield ToolLengthRegister("G43.1" if length else "G49", None, source=src)
            yield canon.UseToolLengthOffset(length, source=src)
        elif name == "StopMotion":
            self.no_args(parts)
            yield canon.Stop(source=src)
        elif name in UNSUPPORTED:
            raise self.error("SANDIA-UNSUPPORTED", f"{name}: {UNSUPPORTED[name]}", name)
        # SESSION: no machining meaning, no command

    def attributes(self, value: str) -> bool:
        """Decode the bit mask (names joined by ``|`` or an integer); True when relative."""
        mode: int | None
        system: int | None
        if value.isascii() and value.isdigit():
            bits = int(value)
            if bits >= 32 or (bits >> 1) > 9:
                raise self.error("SANDIA-ATTR-INVALID", f"unrecognizable bit pattern {bits}", value)
            mode, system = bits & 1, bits >> 1
        else:
            mode = system = None
            for word in value.split("|"):
                if word in MODES and mode is None:
                    mode = MODES[word]
                elif word in SYSTEMS and system is None:
                    system = SYSTEMS[word]
                else:
                    raise self.error(
                        "SANDIA-ATTR-INVALID", f"unrecognizable attribute '{word}'", value
                    )
            mode, system = mode or 0, system or 0
        if system:
            raise self.error(
                "SANDIA-ATTR-UNSUPPORTED",
                "only CS_CURRENT: the seed omits the commands that set up coordinate systems",
                value,
            )
        return mode == 1

    def set_units(self, parts: list[str]) -> Iterator[canon.Command]:
        args = self.named(parts, ("linear", "angular"))
        if not args:
            raise self.error("SANDIA-ARG", "SetUnits needs linear= and/or angular=", col=0)
        angular = args.get("angular", "deg")
        if angular != "deg":
            raise self.error(
                "SANDIA-UNITS", f"angular={angular}: the IR's angles are degrees", angular
            )
        if "linear" not in args:
            return
        units = UNITS.get(args["linear"])
        if units is None:
            raise self.error(
                "SANDIA-UNITS", f"linear={args['linear']}: use mm, inch or cm", args["linear"]
            )
        if units is not self.units:
            factor = self.units.mm_per_unit / units.mm_per_unit
            self.pos = [v * factor for v in self.pos[:3]] + self.pos[3:]
            self.units = units
        yield canon.UseLengthUnits(units, source=self.loc())
