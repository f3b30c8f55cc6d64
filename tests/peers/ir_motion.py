"""What a peer reader must find: each IR motion's end point, centre, plane and feed, in mm.

The writer (:func:`gcode.write.writer.write`) is a generator that pulls one canonical command,
handles it and yields its blocks before pulling the next one, so every written line can be
tagged with the index of the command that produced it (:func:`tagged_lines`). A peer then
runs the blocks of command ``i`` and must stand where the IR's command ``i`` ends.

Coordinates: the IR holds program coordinates in its current length units
(``USE_LENGTH_UNITS``); here everything is converted to mm (rotary axes stay in degrees).
The plane axes follow NISTIR 5970 §3.6.1 (in the XZ plane the first axis is Z), written out
here rather than taken from the writer so that the check does not share its tables.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from gcode.write.report import ConversionReport
from gcode.write.writer import WriterOptions, write
from kernel.diagnostics import Diagnostic
from kernel.ir import canon
from tests.convert_support import programs, read_ir

#: plane -> (first, second, normal) axis letters, NISTIR 5970 §3.6.1
PLANE_LETTERS: dict[canon.Plane, tuple[str, str, str]] = {
    canon.Plane.XY: ("X", "Y", "Z"),
    canon.Plane.YZ: ("Y", "Z", "X"),
    canon.Plane.XZ: ("Z", "X", "Y"),
}
AXES = "XYZABC"
HEADER = -1  # command index of the program header's lines
#: the peers read our output with 6 decimals (the comparison tolerances assume it)
SIX = WriterOptions(decimals=6)


@dataclass(frozen=True)
class Motion:
    """One IR motion as a reader must see it (lengths in mm, angles in degrees)."""

    index: int  # position of the command in the IR
    name: str  # NISTIR name (STRAIGHT_FEED, ARC_FEED, ...)
    start: dict[str, float]
    end: dict[str, float]
    plane: canon.Plane
    centre: dict[str, float] | None = None  # ARC_FEED: the two in-plane centre coordinates
    rotation: int = 0  # ARC_FEED: signed turns (> 0 counter-clockwise)
    feed: float | None = None  # mm/min (or mm/rev) a reader must hold; None: not comparable
    checkable: bool = True  # False: the reader's end point is not the IR's (rigid tap)


def tagged_lines(
    ir: list[canon.Command],
    dialect: str,
    options: WriterOptions,
    report: ConversionReport | None = None,
) -> list[tuple[int, str]]:
    """The written program, each line with the index of the IR command that produced it.

    Header lines carry :data:`HEADER`, footer lines ``len(ir)``.
    """
    current = [HEADER]

    def commands() -> Iterator[canon.Command]:
        for i, cmd in enumerate(ir):
            current[0] = i
            yield cmd
        current[0] = len(ir)

    return [(current[0], line) for line in write(commands(), dialect, options, report)]


def motions(ir: Iterable[canon.Command]) -> Iterator[Motion]:
    """The IR's motions with the state a reader needs to check them."""
    scale = 1.0  # mm per IR length unit
    plane = canon.Plane.XY
    pos = dict.fromkeys(AXES, 0.0)
    feed = 0.0
    mode = canon.FeedMode.UNITS_PER_MINUTE
    synced = False
    for i, c in enumerate(ir):
        if isinstance(c, canon.UseLengthUnits):
            scale = c.units.mm_per_unit
        elif isinstance(c, canon.SelectPlane):
            plane = c.plane
        elif isinstance(c, canon.SetFeedRate):
            feed = c.rate
        elif isinstance(c, canon.SetFeedMode):
            mode = c.mode
        elif isinstance(c, canon.StartSpeedFeedSynch):
            synced = True
        elif isinstance(c, canon.StopSpeedFeedSynch):
            synced = False
        end = _end_point(c, plane, pos, scale)
        if end is None:
            continue
        centre = None
        rotation = 0
        if isinstance(c, canon.ArcFeed):
            first, second, _ = PLANE_LETTERS[plane]
            centre = {first: c.first_axis * scale, second: c.second_axis * scale}
            rotation = c.rotation
        comparable = (
            isinstance(c, canon.StraightFeed | canon.ArcFeed)
            and mode != canon.FeedMode.INVERSE_TIME
            and not synced
        )
        yield Motion(
            index=i,
            name=c.NAME,
            start=dict(pos),
            end=end,
            plane=plane,
            centre=centre,
            rotation=rotation,
            feed=feed * scale if comparable else None,
            checkable=not isinstance(c, canon.RigidTap),
        )
        pos = end


def _end_point(
    c: canon.Command, plane: canon.Plane, pos: dict[str, float], scale: float
) -> dict[str, float] | None:
    """Where a motion command leaves the tool (mm, degrees); None for a non-motion."""
    if isinstance(c, canon.StraightTraverse | canon.StraightFeed | canon.StraightProbe):
        return {
            "X": c.x * scale,
            "Y": c.y * scale,
            "Z": c.z * scale,
            "A": c.a,
            "B": c.b,
            "C": c.c,
        }
    if isinstance(c, canon.ArcFeed | canon.EllipseFeed):
        first, second, normal = PLANE_LETTERS[plane]
        end = {"A": c.a, "B": c.b, "C": c.c}
        end[first], end[second] = c.first_end * scale, c.second_end * scale
        end[normal] = c.axis_end_point * scale
        return end
    if isinstance(c, canon.NurbsFeed):
        if c.elided or not c.points:
            return None
        first, second, _ = PLANE_LETTERS[plane]
        end = dict(pos)
        end[first], end[second] = c.points[-1][0] * scale, c.points[-1][1] * scale
        return end
    if isinstance(c, canon.RigidTap):  # to (x, y, z) and back: it ends where it began
        return dict(pos)
    return None


def by_index(ms: Iterable[Motion]) -> dict[int, Motion]:
    return {m.index: m for m in ms}


def group_lines(tagged: list[tuple[int, str]]) -> list[tuple[int, list[tuple[int, str]]]]:
    """Consecutive lines per command index: [(index, [(line number, text), ...]), ...]."""
    groups: list[tuple[int, list[tuple[int, str]]]] = []
    for number, (index, text) in enumerate(tagged, start=1):
        if not groups or groups[-1][0] != index:
            groups.append((index, []))
        groups[-1][1].append((number, text))
    return groups


@dataclass(frozen=True)
class Written:
    """One corpus program written in a dialect: its IR and tagged lines (None: refused)."""

    program: Path
    ir: list[canon.Command]
    tagged: list[tuple[int, str]] | None
    refusal: str = ""


def corpus(dialect: str, options: WriterOptions) -> Iterator[Written]:
    """Every golden and corpus program our interpreter reads, written in ``dialect``."""
    for program in programs():
        ir = _read(program)
        if ir is None:
            continue
        try:
            yield Written(program, list(ir), tagged_lines(list(ir), dialect, options))
        except Diagnostic as exc:
            yield Written(program, ir, None, f"{exc.code}: {exc}")


@cache
def _read(program: Path) -> tuple[canon.Command, ...] | None:
    ir = read_ir(program)
    return None if ir is None else tuple(ir)
