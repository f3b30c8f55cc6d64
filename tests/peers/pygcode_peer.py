"""pygcode 0.2.1 as a peer reader of our writers' output.

pygcode has its own block parser (``pygcode.Line``: words, parenthesised and ``;``
comments, ``%``) and a ``Machine`` with modal groups (motion, plane, units, feed, distance
mode) and a position in the current work system. Its ``Machine`` moves to the end point
of G0/G1/G2/G3/G33/G38.x blocks (G91 incremental, G90 absolute); it does not change
numbers on G20/G21 (a block's numbers stay in the units it was written in), applies no
offsets (G10, G92, G43 only set modes) and draws no arc (the end point only). So after
the blocks of each IR motion, pygcode's position (converted to mm with its own G20/G21
mode) must be the IR's end point; its parsed centre words I/J/K, taken from its own start
position, must be the IR's arc centre; its G2/G3 the IR's turning sense; its plane the
IR's plane; its modal F the IR's feed.

What pygcode cannot read (:data:`RULES`) is excluded by name, with the reason, and
counted; a motion whose blocks were excluded is not compared, and pygcode's position is
set to the IR's end point so that the next motion is compared again.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

from pygcode import GCodeArcMove, GCodeArcMoveCW, Line, Machine
from pygcode.gcodes import GCodeUseInches

from tests.peers.ir_motion import AXES, PLANE_LETTERS, Motion, group_lines

#: the (dialect, arc format) outputs pygcode reads: its dialects, each arc form it parses
RUNS = [
    ("grbl", "ijk"),
    ("grbl", "r"),
    ("fanuc", "ijk"),
    ("fanuc", "r"),
    ("haas", "ijk"),
    ("nist_v3", "ijk"),
]

TOLERANCE = 1e-4  # mm

Words = list[tuple[str, float]]
_COMMENT = re.compile(r"\([^)]*\)")
WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def _has(words: Words, letter: str, *values: float) -> bool:
    return any(w == letter and (not values or v in values) for w, v in words)


@dataclass(frozen=True)
class Rule:
    """A construct pygcode 0.2.1 cannot read, or reads with another meaning."""

    name: str
    reason: str
    matches: Callable[[Words], bool]


RULES: tuple[Rule, ...] = (
    Rule(
        "G06.2 NURBS",
        "Fanuc NURBS (G06.2 P K X Y R and its K continuation blocks): pygcode knows "
        "LinuxCNC's G5.2 only and rejects the block",
        lambda ws: _has(ws, "G", 6.2),
    ),
    Rule(
        "G31 skip",
        "Fanuc/Haas skip function (probing move): pygcode knows G38.2-G38.5 only",
        lambda ws: _has(ws, "G", 31),
    ),
    Rule(
        "G52 local offset",
        "local coordinate system: not in pygcode 0.2.1 (unsupported gcode)",
        lambda ws: _has(ws, "G", 52),
    ),
    Rule(
        "G68/G69 rotation",
        "coordinate system rotation: not in pygcode 0.2.1 (unsupported gcode)",
        lambda ws: _has(ws, "G", 68, 69),
    ),
    Rule(
        "G09 exact stop",
        "one-block exact stop (Haas G09): not in pygcode 0.2.1",
        lambda ws: _has(ws, "G", 9),
    ),
    Rule(
        "G04 X dwell",
        "Fanuc dwell in seconds by X: pygcode's G4 takes P only and would read X as a "
        "move in the current motion mode",
        lambda ws: _has(ws, "G", 4) and _has(ws, "X"),
    ),
    Rule(
        "M19 angle",
        "spindle orientation with an angle word (Haas M19 P, LinuxCNC M19 R): pygcode's M19 "
        "takes no parameter and rejects the block",
        lambda ws: _has(ws, "M", 19) and any(w in "PRQ" for w, _ in ws),
    ),
    Rule(
        "G43.1 Z",
        "dynamic tool length (Grbl/LinuxCNC G43.1 Z): pygcode's G43.1 takes no parameter "
        "and would read Z as a move in the current motion mode",
        lambda ws: _has(ws, "G", 43.1) and _has(ws, "Z"),
    ),
)
NURBS = RULES[0]  # its continuation blocks (K first) are excluded with it
#: pygcode splits a line at the first ';' even inside a parenthesised comment
SEMICOLON_IN_COMMENT = (
    "';' inside a (...) comment: pygcode ends the block there (RS274/NGC, Grbl and Fanuc "
    "keep it in the comment); the comment is removed before pygcode reads the block"
)


class PeerMachine(Machine):
    """pygcode's machine with the rotary axes our writers may address."""

    axes = set(AXES)


@dataclass
class PeerResult:
    """What pygcode did with one written program."""

    blocks: int = 0  # lines pygcode parsed and ran
    motions: int = 0  # IR motions whose end point was compared
    arcs: int = 0  # arc blocks whose centre words were compared
    feeds: int = 0  # motions whose modal F was compared
    deviation: float = 0.0  # largest end-point or centre difference, mm
    excluded: Counter[str] = field(default_factory=Counter)  # rule name -> blocks not read
    comments_cut: int = 0  # blocks read without a comment holding ';'
    problems: list[str] = field(default_factory=list)


def _mm(m: Machine) -> float:
    return 25.4 if isinstance(m.mode.units, GCodeUseInches) else 1.0


def _position(m: Machine) -> dict[str, float]:
    k = _mm(m)
    values = m.pos.values
    return {a: values.get(a, 0.0) * (k if a in "XYZ" else 1.0) for a in AXES}


def _set_position(m: Machine, mm: dict[str, float]) -> None:
    k = _mm(m)
    m.pos = m.Position(**{a: v / k if a in "XYZ" else v for a, v in mm.items()})


def run(tagged: list[tuple[int, str]], motions: dict[int, Motion]) -> PeerResult:
    """Parse and run every written block on pygcode's machine; compare with the IR."""
    result = PeerResult()
    machine = PeerMachine()
    in_nurbs = False
    for index, lines in group_lines(tagged):
        motion = motions.get(index)
        skipped = False
        for number, text in lines:
            where = f"block {number} {text!r}"
            code = _COMMENT.sub(" ", text.upper())
            words = [(w, float(v)) for w, v in WORD.findall(code)]
            body = [(w, v) for w, v in words if w != "N"]
            in_nurbs = in_nurbs and bool(body) and body[0][0] == "K"
            rule = next((r for r in RULES if r.matches(words)), None)
            if rule is None and in_nurbs:
                rule = NURBS
            if rule is not None:
                in_nurbs = rule is NURBS
                result.excluded[rule.name] += 1
                skipped = True
                continue
            if ";" in "".join(_COMMENT.findall(text)):
                result.comments_cut += 1
                text = _COMMENT.sub(" ", text)
            try:
                block = Line(text).block
                start = _position(machine)
                gcodes = machine.block_modal_gcodes(block)
                machine.process_block(block)
            except Exception as exc:  # noqa: BLE001 - any pygcode error is a rejection
                result.problems.append(f"{where}: pygcode: {type(exc).__name__}: {exc}")
                continue
            result.blocks += 1
            arcs = [g for g in gcodes if isinstance(g, GCodeArcMove)]
            if arcs and motion is not None and motion.centre is not None:
                _check_arc(result, machine, arcs[0], start, motion, where)
        if motion is None:
            continue
        if skipped or not motion.checkable:
            _set_position(machine, motion.end)
            continue
        _check_end(result, machine, motion, lines[-1])
    return result


def _check_end(result: PeerResult, m: Machine, motion: Motion, last: tuple[int, str]) -> None:
    where = f"{motion.name} (IR command {motion.index}), last block {last[0]} {last[1]!r}"
    got = _position(m)
    result.motions += 1
    for a in AXES:
        d = abs(got[a] - motion.end[a])
        result.deviation = max(result.deviation, d)
        if d > TOLERANCE:
            result.problems.append(f"{where}: pygcode {a}={got[a]:.6f}, IR {motion.end[a]:.6f}")
    if motion.feed is not None and m.mode.feed_rate is not None:
        result.feeds += 1
        f = m.mode.feed_rate.word.value * _mm(m)
        if abs(f - motion.feed) > TOLERANCE * max(1.0, motion.feed):
            result.problems.append(f"{where}: pygcode F={f:.6f} mm/min, IR feed {motion.feed:.6f}")


def _check_arc(
    result: PeerResult,
    m: Machine,
    arc: GCodeArcMove,
    start: dict[str, float],
    motion: Motion,
    where: str,
) -> None:
    """Centre words (incremental I/J/K from pygcode's start point), sense and plane."""
    first, second, normal = PLANE_LETTERS[motion.plane]
    plane = m.mode.plane_selection
    if plane is None or plane.normal_axis != normal:
        result.problems.append(f"{where}: pygcode plane {plane}, IR {motion.plane.name}")
        return
    if isinstance(arc, GCodeArcMoveCW) != (motion.rotation < 0):
        result.problems.append(f"{where}: pygcode {arc.word}, IR rotation {motion.rotation}")
    assert motion.centre is not None
    params = arc.get_param_dict()
    k = _mm(m)
    if "R" in params:
        radius = math.dist(
            (start[first], start[second]), (motion.centre[first], motion.centre[second])
        )
        d = abs(abs(params["R"]) * k - radius)
        what = f"R {params['R']}"
    else:
        letter = {"X": "I", "Y": "J", "Z": "K"}
        got = [start[a] + params.get(letter[a], 0.0) * k for a in (first, second)]
        d = math.dist(got, (motion.centre[first], motion.centre[second]))
        what = f"centre ({got[0]:.6f}, {got[1]:.6f})"
    result.arcs += 1
    result.deviation = max(result.deviation, d)
    if d > TOLERANCE:
        result.problems.append(f"{where}: pygcode {what}, IR centre {motion.centre}")
