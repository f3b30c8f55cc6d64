"""Equivalence of two canonical-command texts, as defined in ``tests/data/README.md``.

Two outputs are *equivalent* when, after dropping the LinuxCNC-only commands
(:data:`kernel.ir.canon.LINUXCNC_ONLY`), they give the same ordered sequence of motions
(``STRAIGHT_TRAVERSE``, ``STRAIGHT_FEED``, ``ARC_FEED``, ``NURBS_FEED``, ``STRAIGHT_PROBE``,
``DWELL``) with the same end points and arc data within 1e-4 program units, each motion
seeing the same feed rate, spindle speed and direction, tool, coolant state, length units
and plane; and tool changes, stops, messages and program end appear in the same order.

Offsets (``SET_ORIGIN_OFFSETS`` on our side, ``SET_G5X_OFFSET``/``SET_G92_OFFSET`` on
LinuxCNC's) are not compared: motions are in program coordinates on both sides. Commands
outside the rule (comments, tool length offsets, overrides, ...) are ignored.

The machine state a motion "sees" starts from the canonical machine's initial state
(NISTIR 5970 §3.2 ``INIT_CANON``: XY plane, spindle stopped at speed 0, feed 0, no tool,
coolant off); the length units have no default and must be set by the stream.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, fields, replace

from kernel.diagnostics import Diagnostic
from kernel.ir import canon

TOLERANCE = 1e-4 + 1e-9  # 1e-4 in program units; the 1e-9 absorbs float noise of printed values
MAX_DIFFERENCES = 8

MOTION_NAMES = frozenset(c.NAME for c in canon.MOTIONS)
EVENT_NAMES = frozenset(
    {"CHANGE_TOOL", "PROGRAM_STOP", "OPTIONAL_PROGRAM_STOP", "PROGRAM_END", "MESSAGE"}
)
STATE_NAMES = frozenset(
    {
        "SET_FEED_RATE",
        "SET_SPINDLE_SPEED",
        "START_SPINDLE_CLOCKWISE",
        "START_SPINDLE_COUNTERCLOCKWISE",
        "STOP_SPINDLE_TURNING",
        "MIST_ON",
        "MIST_OFF",
        "FLOOD_ON",
        "FLOOD_OFF",
        "USE_LENGTH_UNITS",
        "SELECT_PLANE",
    }
)
RELEVANT = MOTION_NAMES | EVENT_NAMES | STATE_NAMES


@dataclass(frozen=True, slots=True)
class MachineState:
    """What a motion sees (the README's list)."""

    feed: float = 0.0
    speed: float = 0.0
    direction: canon.Direction = canon.Direction.STOPPED
    tool: int | str = 0
    mist: bool = False
    flood: bool = False
    units: canon.Units | None = None
    plane: canon.Plane = canon.Plane.XY


@dataclass(frozen=True, slots=True)
class Item:
    """A motion (with the state it sees) or an ordered event, with its text line number."""

    command: canon.Command
    line: int
    state: MachineState | None = None  # None for events


def _apply(state: MachineState, cmd: canon.Command) -> MachineState:
    """The state after a state-setting command."""
    if isinstance(cmd, canon.SetFeedRate):
        return replace(state, feed=cmd.rate)
    if isinstance(cmd, canon.SetSpindleSpeed):
        return replace(state, speed=cmd.speed)
    if isinstance(cmd, canon.StartSpindleClockwise):
        return replace(state, direction=canon.Direction.CLOCKWISE)
    if isinstance(cmd, canon.StartSpindleCounterclockwise):
        return replace(state, direction=canon.Direction.COUNTERCLOCKWISE)
    if isinstance(cmd, canon.StopSpindleTurning):
        return replace(state, direction=canon.Direction.STOPPED)
    if isinstance(cmd, canon.MistOn | canon.MistOff):
        return replace(state, mist=isinstance(cmd, canon.MistOn))
    if isinstance(cmd, canon.FloodOn | canon.FloodOff):
        return replace(state, flood=isinstance(cmd, canon.FloodOn))
    if isinstance(cmd, canon.UseLengthUnits):
        return replace(state, units=cmd.units)
    if isinstance(cmd, canon.SelectPlane):
        return replace(state, plane=cmd.plane)
    if isinstance(cmd, canon.ChangeTool):
        return replace(state, tool=cmd.name or cmd.slot)
    return state


def items(lines: Iterable[str]) -> Iterator[Item | str]:
    """The motions and events of a canonical text, in order.

    Yields a string (a difference description) for a relevant command that cannot be read.
    """
    state = MachineState()
    for tc in canon.read_text(lines):
        if tc.name not in RELEVANT:
            continue
        try:
            cmd = canon.parse_command(tc)
        except Diagnostic as exc:
            yield f"line {tc.line}: {exc.message}"
            continue
        state = _apply(state, cmd)
        if tc.name in MOTION_NAMES:
            yield Item(cmd, tc.line, state)
        elif tc.name in EVENT_NAMES:
            yield Item(cmd, tc.line)


def _close(a: object, b: object) -> bool:
    if isinstance(a, float | int) and isinstance(b, float | int) and not isinstance(a, bool):
        return abs(float(a) - float(b)) <= TOLERANCE
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, str) and isinstance(b, str):
        return a.strip() == b.strip()
    return a == b


def _motion_difference(ours: canon.Command, ref: canon.Command) -> str | None:
    # LinuxCNC prints ``NURBS_FEED(count, ...)`` without the data: compare what both have.
    nurbs = isinstance(ours, canon.NurbsFeed) and isinstance(ref, canon.NurbsFeed)
    if nurbs and (ours.elided or ref.elided):  # type: ignore[union-attr]
        n_ours, n_ref = len(ours.points), len(ref.points)  # type: ignore[union-attr]
        return None if n_ours == n_ref else f"NURBS control points {n_ours} != {n_ref}"
    for f in fields(ours):
        if f.name == "source":
            continue
        a, b = getattr(ours, f.name), getattr(ref, f.name)
        if not _close(a, b):
            return f"{f.name} {a} != {b}"
    return None


def _state_difference(ours: MachineState, ref: MachineState) -> str | None:
    for f in fields(MachineState):
        a, b = getattr(ours, f.name), getattr(ref, f.name)
        if not _close(a, b):
            show = [x.value if hasattr(x, "value") else x for x in (a, b)]
            return f"{f.name} {show[0]} != {show[1]}"
    return None


def _item_difference(ours: Item, ref: Item) -> tuple[str | None, bool]:
    """(difference or None, whether the two sequences are still aligned)."""
    o, r = ours.command, ref.command
    if o.NAME != r.NAME:
        return f"{o.NAME} vs {r.NAME}", False
    if ours.state is None or ref.state is None:  # events
        return (None if _close(o.args(), r.args()) else f"{o.to_text()} vs {r.to_text()}"), True
    diff = _motion_difference(o, r)
    if diff is not None:
        return f"{o.NAME}: {diff}", True
    sdiff = _state_difference(ours.state, ref.state)
    return (None if sdiff is None else f"{o.NAME} sees {sdiff}"), True


def compare(ours_lines: Iterable[str], ref_lines: Iterable[str]) -> list[str]:
    """Human-readable differences between two canonical texts; ``[]`` means equivalent.

    Each difference names the motion/event index and the line numbers on both sides.
    At most :data:`MAX_DIFFERENCES` are returned; comparison stops at the first point where
    the two sequences no longer line up (different command kinds).
    """
    ours_all = list(items(ours_lines))
    ref_all = list(items(ref_lines))
    out = [f"ours {e}" for e in ours_all if isinstance(e, str)]
    out += [f"ref {e}" for e in ref_all if isinstance(e, str)]
    ours_items = [e for e in ours_all if isinstance(e, Item)]
    ref_items = [e for e in ref_all if isinstance(e, Item)]
    for i, (o, r) in enumerate(zip(ours_items, ref_items, strict=False)):
        diff, aligned = _item_difference(o, r)
        if diff is not None:
            out.append(f"item {i + 1} (ours line {o.line}, ref line {r.line}): {diff}")
        if not aligned or len(out) >= MAX_DIFFERENCES:
            return out[:MAX_DIFFERENCES]
    if len(ours_items) != len(ref_items):
        n = min(len(ours_items), len(ref_items))
        extra, side = (ours_items, "ours") if len(ours_items) > n else (ref_items, "ref")
        first = extra[n]
        out.append(
            f"{side} has {len(extra) - n} more motions/events, first {first.command.NAME} "
            f"at {side} line {first.line} (ours {len(ours_items)}, ref {len(ref_items)})"
        )
    return out[:MAX_DIFFERENCES]
