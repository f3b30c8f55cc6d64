"""cncjs's ``gcode-toolpath`` (npm) as a peer reader of our Grbl output.

``tests/peers/toolpath.js`` runs the parser and interpreter cncjs uses to preview what it
streams to Grbl, and prints every motion callback (start, end, arc centre, in mm). Here the
callbacks are matched with the IR through the writer's line tagging
(:func:`tests.peers.ir_motion.tagged_lines`): after the blocks of each IR motion the peer's
last end point must be the IR's end point; every arc's centre (from I/J/K or from R, by the
peer's own arithmetic) the IR's centre; G2/G3 the IR's turning sense; G17/G18/G19 its
plane; G0/G1 its traverse or feed.

``gcode-toolpath`` does not move on G38.2-G38.5 (it only sets the motion mode): such a
probing move is not compared, and the peer's start point is unknown for the next motion,
whose arc centre (relative to that start) is then not compared either.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from collections import defaultdict
from dataclasses import dataclass, field, replace
from pathlib import Path

from gcode.write.writer import WriterOptions
from kernel.ir import canon
from tests.peers.ir_motion import PLANE_LETTERS, SIX, Motion, group_lines

SCRIPT = Path(__file__).with_name("toolpath.js")
DEFAULT_NODE_PATH = "/tmp/peers/node_modules"
TOLERANCE = 1e-4  # mm (programs written with six decimals)
#: the Grbl outputs the peer reads: name -> (writer options, tolerance in mm); the default
#: format has 3 decimals in mm, 4 in inches (2 units of 0.0001 in = 5.08e-3 mm)
VARIANTS = {
    "ijk-6": (SIX, TOLERANCE),
    "r-6": (replace(SIX, arc_format="r"), TOLERANCE),
    "ijk-default": (WriterOptions(), 5.1e-3),
    "r-default": (WriterOptions(arc_format="r"), 5.1e-3),
}
PLANES = {canon.Plane.XY: "G17", canon.Plane.XZ: "G18", canon.Plane.YZ: "G19"}
KINDS = {"STRAIGHT_TRAVERSE": "G0", "STRAIGHT_FEED": "G1"}  # arcs: G2/G3 checked below
XYZ = "XYZ"


def node_path() -> str:
    return os.environ.get("CNC_PEERS_NODE_PATH", DEFAULT_NODE_PATH)


def available() -> str | None:
    """Why the peer cannot run here, or None when node and the modules are found."""
    if shutil.which("node") is None:
        return "needs node"
    if not (Path(node_path()) / "gcode-toolpath").is_dir():
        return f"needs gcode-toolpath in {node_path()} (CNC_PEERS_NODE_PATH)"
    return None


def run_node(files: list[Path]) -> tuple[dict[int, list[dict]], dict[int, int]]:
    """Callbacks and rejections per file index, and each file's number of blocks."""
    env = {**os.environ, "NODE_PATH": node_path()}
    proc = subprocess.run(
        ["node", str(SCRIPT), *map(str, files)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    if proc.returncode != 0:
        raise AssertionError(f"toolpath.js failed: {proc.stderr}")
    records: dict[int, list[dict]] = defaultdict(list)
    blocks: dict[int, int] = {}
    for line in proc.stdout.splitlines():
        rec = json.loads(line)
        if "blocks" in rec:
            blocks[rec["file"]] = rec["blocks"]
        else:
            records[rec["file"]].append(rec)
    return records, blocks


@dataclass
class ToolpathResult:
    blocks: int = 0
    tolerance: float = TOLERANCE
    motions: int = 0  # IR motions whose end point was compared
    arcs: int = 0  # arc callbacks whose centre was compared
    deviation: float = 0.0  # mm
    excluded: int = 0  # probing moves not compared
    problems: list[str] = field(default_factory=list)


def compare(
    tagged: list[tuple[int, str]],
    motions: dict[int, Motion],
    records: list[dict],
    blocks: int,
    tolerance: float = TOLERANCE,
) -> ToolpathResult:
    """The peer's callbacks against the IR, command by command (``tolerance`` in mm)."""
    result = ToolpathResult(blocks=blocks, tolerance=tolerance)
    by_line: dict[int, list[dict]] = defaultdict(list)
    for rec in records:
        if "reject" in rec:
            result.problems.append(f"block {rec['line']}: gcode-parser: {rec['reject']}")
        else:
            by_line[rec["line"]].append(rec)
    start_known = True
    for index, lines in group_lines(tagged):
        got = [rec for number, _ in lines for rec in by_line.get(number, [])]
        motion = motions.get(index)
        where = f"IR command {index}, blocks {lines[0][0]}-{lines[-1][0]}"
        if motion is None:
            if got:
                result.problems.append(f"{where}: the peer moves where the IR does not")
            continue
        if motion.name == "STRAIGHT_PROBE" or not motion.checkable:
            result.excluded += 1
            start_known = False
            continue
        where = f"{motion.name} ({where}: {lines[-1][1]!r})"
        if not got:
            result.problems.append(f"{where}: no motion callback")
            continue
        _check_motion(result, motion, got, where, start_known)
        start_known = True
    return result


def _check_motion(
    result: ToolpathResult, motion: Motion, got: list[dict], where: str, start_known: bool
) -> None:
    result.motions += 1
    end = got[-1]["end"]
    for axis, value in zip(XYZ, end, strict=True):
        d = abs(value - motion.end[axis])
        result.deviation = max(result.deviation, d)
        if d > result.tolerance:
            result.problems.append(f"{where}: peer {axis}={value:.6f}, IR {motion.end[axis]:.6f}")
    expected = KINDS.get(motion.name)
    if motion.name == "ARC_FEED" and motion.rotation == 0:
        expected = "G1"  # no turn: a move along the helix axis
    for rec in got:
        if expected and rec["motion"] != expected:
            result.problems.append(f"{where}: peer {rec['motion']}, IR {motion.name}")
    if motion.centre is None or motion.rotation == 0:
        return
    first, second, _ = PLANE_LETTERS[motion.plane]
    i, j = XYZ.index(first), XYZ.index(second)
    for n, rec in enumerate(got):
        if rec["kind"] != "arc" or rec["plane"] != PLANES[motion.plane]:
            result.problems.append(f"{where}: peer {rec['kind']} in {rec['plane']}")
            continue
        if (rec["motion"] == "G3") != (motion.rotation > 0):
            result.problems.append(f"{where}: peer {rec['motion']}, IR turns {motion.rotation}")
        if n == 0 and not start_known:
            continue
        c = rec["centre"]
        if None in c:  # JSON null: NaN from the square root of 4R^2 - chord^2 < 0
            result.problems.append(f"{where}: the peer finds no centre (4R^2 < chord^2)")
            continue
        d = math.dist((c[i], c[j]), (motion.centre[first], motion.centre[second]))
        result.arcs += 1
        result.deviation = max(result.deviation, d)
        if d > result.tolerance:
            result.problems.append(
                f"{where}: peer centre {first}={c[i]:.6f} {second}={c[j]:.6f}, IR {motion.centre}"
            )
