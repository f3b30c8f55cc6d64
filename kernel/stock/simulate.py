"""Walk a canonical command stream over a :class:`HeightField` and report what it did.

Coordinates: each programmed point is taken in millimetres (``USE_LENGTH_UNITS``) plus the
program origin of ``SET_ORIGIN_OFFSETS`` (and the ``SET_G5X_OFFSET``/``SET_G92_OFFSET`` pair
LinuxCNC prints), as the planner does; the tool length offset is not applied, so the
programmed point is the tool's tip, again as the planner does. Arcs and helices are cut into
chords within ``chord_tol`` and swept as lines. A move of a rotary axis, a rotated work
system, or a NURBS/ellipse move is refused with a located ``SIM-NOT-3AXIS`` /
``SIM-UNSUPPORTED`` error rather than simulated wrongly.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweep
from kernel.stock.heightfield import (
    HeightField,
    ball_envelope,
    bull_envelope,
    cone_envelope,
    flat_envelope,
)
from kernel.stock.solids import Fixture
from kernel.stock.tools import DEFAULT_TOOL, ToolShape

#: height (mm) material must stand above a rapid's swept tool to count as a collision
RAPID_EPS = 1e-6
#: a feed move steeper than this (|dz| / XY length) that cuts is a plunge
PLUNGE_SLOPE = 1.0

#: the findings' codes and severities (docs/simulation.md)
RULES: dict[str, Severity] = {
    "SIM-RAPID-IN-STOCK": Severity.ERROR,
    "SIM-PLUNGE-NON-CENTRE": Severity.WARNING,
    "SIM-FLUTE-DEPTH": Severity.WARNING,
    "SIM-HOLDER": Severity.ERROR,
    "SIM-AIR-CUTTING": Severity.NOTE,
    "SIM-GOUGE": Severity.ERROR,
    "SIM-LEFTOVER": Severity.WARNING,
    "SIM-FIXTURE": Severity.ERROR,
}
#: a tool whose feed path cuts nothing over more than this share of its length gets a note
AIR_SHARE = 0.5


@dataclass(frozen=True, slots=True)
class SimFinding:
    code: str
    severity: Severity
    message: str
    location: Location
    #: the worst value (mm, or the air share) and where (machine X, Y; a lathe's X, Z),
    #: when it has one
    value: float | None = None
    x: float | None = None
    y: float | None = None
    z: float | None = None

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "file": self.location.file,
            "line": self.location.line,
        }
        if self.value is not None:
            out["value"] = self.value
        for key, where in (("x", self.x), ("y", self.y), ("z", self.z)):
            if where is not None:
                out[key] = where
        return out


@dataclass
class ToolUse:
    """What one tool did: material removed (mm³), feed path length and the part of it that
    removed nothing (mm)."""

    removed_volume: float = 0.0
    feed_length: float = 0.0
    air_length: float = 0.0

    @property
    def air_share(self) -> float:
        return self.air_length / self.feed_length if self.feed_length > 0 else 0.0

    def to_dict(self) -> dict[str, float]:
        return {
            "removed_volume": self.removed_volume,
            "feed_length": self.feed_length,
            "air_length": self.air_length,
            "air_share": self.air_share,
        }


@dataclass
class SimResult:
    removed_volume: float
    moves: int
    findings: list[SimFinding] = field(default_factory=list)
    #: per tool number
    tools: dict[int, ToolUse] = field(default_factory=dict)
    #: with ``track_moves``: per cell, the index into ``move_locations`` of the last move
    #: that cut it (-1: never cut)
    last_move: np.ndarray | None = None
    move_locations: list[Location] = field(default_factory=list)
    #: with ``track_volume``: material removed (mm³) by each motion command, by its index
    #: in the command stream (the IR index a path segment's ``source`` holds)
    move_volumes: dict[int, float] | None = None

    @property
    def errors(self) -> int:
        return sum(f.severity is Severity.ERROR for f in self.findings)


def _located(cmd: canon.Command) -> Location:
    return cmd.source or Location()


@dataclass(slots=True)
class _State:
    mm: float = 1.0
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    g92: tuple[float, float, float] = (0.0, 0.0, 0.0)
    pos: tuple[float, float, float] | None = None
    rot: tuple[float, float, float] = (0.0, 0.0, 0.0)
    plane: canon.Plane = canon.Plane.XY
    selected: int = 0
    tool: int = 0


def _machine(st: _State, x: float, y: float, z: float) -> tuple[float, float, float]:
    o, g = st.origin, st.g92
    return (x * st.mm + o[0] + g[0], y * st.mm + o[1] + g[1], z * st.mm + o[2] + g[2])


def arc_points(
    st: _State, cmd: canon.ArcFeed, start: tuple[float, float, float], chord_tol: float
) -> np.ndarray:
    """Points (n, 3) along an ARC_FEED from ``start`` (machine mm), chords within
    ``chord_tol`` of the arc, helical motion along the plane normal linear in the angle."""
    mm = st.mm
    # index of the plane's first, second and normal axes in (x, y, z)
    first, second, normal = {
        canon.Plane.XY: (0, 1, 2),
        canon.Plane.YZ: (1, 2, 0),
        canon.Plane.XZ: (2, 0, 1),
    }[st.plane]
    off = tuple(a + b for a, b in zip(st.origin, st.g92, strict=True))
    c1 = cmd.first_axis * mm + off[first]
    c2 = cmd.second_axis * mm + off[second]
    e1 = cmd.first_end * mm + off[first]
    e2 = cmd.second_end * mm + off[second]
    en = cmd.axis_end_point * mm + off[normal]
    s = np.asarray(start)
    r = math.hypot(s[first] - c1, s[second] - c2)
    th0 = math.atan2(s[second] - c2, s[first] - c1)
    sweep = arc_sweep(th0, math.atan2(e2 - c2, e1 - c1), cmd.rotation)
    if r > chord_tol:
        step = 2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r))
        n = max(1, math.ceil(abs(sweep) / step))
    else:
        n = 1
    t = np.linspace(0.0, 1.0, n + 1)[1:]
    rad = r + (math.hypot(e1 - c1, e2 - c2) - r) * t
    pts = np.empty((n, 3))
    pts[:, first] = c1 + rad * np.cos(th0 + sweep * t)
    pts[:, second] = c2 + rad * np.sin(th0 + sweep * t)
    pts[:, normal] = s[normal] + (en - s[normal]) * t
    pts[-1, first], pts[-1, second], pts[-1, normal] = e1, e2, en
    return pts


def machine_moves(
    commands: Iterable[canon.Command], chord_tol: float
) -> Iterator[tuple[canon.Command, bool, int, np.ndarray]]:
    """(command, is_rapid, tool number, points (n, 3)) for every motion, in machine mm; the
    first point is where the move starts."""
    st = _State()
    for cmd in commands:
        match cmd:
            case canon.UseLengthUnits():
                st.mm = cmd.units.mm_per_unit
            case canon.SetOriginOffsets():
                st.origin = (cmd.x * st.mm, cmd.y * st.mm, cmd.z * st.mm)
                st.g92 = (0.0, 0.0, 0.0)
                _rotary(cmd, (cmd.a, cmd.b, cmd.c), (0.0, 0.0, 0.0))
            case canon.SelectPlane():
                st.plane = cmd.plane
            case canon.SelectTool():
                st.selected = cmd.slot
            case canon.ChangeTool():
                st.tool = st.selected or cmd.slot
            case canon.ChangeToolNumber():
                st.tool = cmd.number
            case canon.StraightTraverse() | canon.StraightFeed() | canon.StraightProbe():
                end = _machine(st, cmd.x, cmd.y, cmd.z)
                rot = (cmd.a, cmd.b, cmd.c)
                if st.pos is None:
                    st.pos, st.rot = end, rot
                    continue
                _rotary(cmd, rot, st.rot)
                pts = np.array([st.pos, end])
                st.pos = end
                yield cmd, isinstance(cmd, canon.StraightTraverse), st.tool, pts
            case canon.ArcFeed():
                _rotary(cmd, (cmd.a, cmd.b, cmd.c), st.rot)
                if st.pos is None:
                    raise Diagnostic(
                        "SIM-UNSUPPORTED", "an arc before any straight move", _located(cmd)
                    )
                pts = arc_points(st, cmd, st.pos, chord_tol)
                pts = np.vstack([np.asarray(st.pos)[None, :], pts])
                st.pos = (float(pts[-1, 0]), float(pts[-1, 1]), float(pts[-1, 2]))
                yield cmd, False, st.tool, pts
            case canon.NurbsFeed() | canon.EllipseFeed() | canon.RigidTap():
                raise Diagnostic(
                    "SIM-UNSUPPORTED",
                    f"{cmd.NAME} is not simulated on the height field",
                    _located(cmd),
                )
            case canon.SetXYRotation() if cmd.angle != 0.0:
                raise Diagnostic(
                    "SIM-UNSUPPORTED", "a rotated work system is not simulated", _located(cmd)
                )
            case _:
                _linuxcnc_offsets(st, cmd)


def _linuxcnc_offsets(st: _State, cmd: canon.Command) -> None:
    """LinuxCNC's SET_G5X_OFFSET / SET_G92_OFFSET (when its interpreter prints no
    SET_ORIGIN_OFFSETS, they carry the origin)."""
    if isinstance(cmd, canon.SetG5xOffset):
        st.origin = (cmd.x * st.mm, cmd.y * st.mm, cmd.z * st.mm)
    elif isinstance(cmd, canon.SetG92Offset):
        st.g92 = (cmd.x * st.mm, cmd.y * st.mm, cmd.z * st.mm)


def _rotary(cmd: canon.Command, rot: tuple[float, ...], before: tuple[float, ...]) -> None:
    if any(abs(a - b) > 1e-9 for a, b in zip(rot, before, strict=True)):
        raise Diagnostic(
            "SIM-NOT-3AXIS",
            "a rotary axis moves: only 3-axis programs are simulated on the height field",
            _located(cmd),
        )


def tool_envelope(
    qx: np.ndarray,
    qy: np.ndarray,
    d: tuple[float, float, float],
    z0: float,
    tool: ToolShape,
    ceiling: np.ndarray | None = None,
) -> np.ndarray:
    """Lowest point of ``tool``'s cutting end swept by ``d`` from tip height ``z0`` over the
    cells at (qx, qy) relative to the start (+inf where untouched). Where the result is at
    or above ``ceiling`` (the material's top, when given) it may be any such height: the
    cell is not cut."""
    r = tool.radius
    if tool.kind == "ball" or (tool.kind == "bull" and tool.corner_radius >= r):
        return ball_envelope(qx, qy, d, z0, r)
    if tool.kind == "bull" and tool.corner_radius > 0:
        return bull_envelope(qx, qy, d, z0, r, tool.corner_radius, ceiling)
    if tool.kind in ("drill", "chamfer"):
        return cone_envelope(qx, qy, d, z0, r, tool.cone_slope, 0.5 * tool.tip_diameter)
    return flat_envelope(qx, qy, d, z0, r)


def sweep_line(
    hf: HeightField, tool: ToolShape, p0: np.ndarray, p1: np.ndarray
) -> tuple[tuple[slice, slice], np.ndarray] | None:
    """The window of cells a line move can touch and the lowest swept tool height over
    each (+inf where untouched; where it is not below the material's top it may be any
    height not below it), or None when the move misses the grid."""
    return _sweep(hf, p0, p1, tool.radius, 0.0, tool)


def _sweep(
    hf: HeightField,
    p0: np.ndarray,
    p1: np.ndarray,
    r: float,
    lift: float,
    tool: ToolShape | None,
) -> tuple[tuple[slice, slice], np.ndarray] | None:
    """Like :func:`sweep_line` for ``tool``, or (``tool`` None) for a flat-bottomed
    cylinder of radius ``r`` whose bottom is ``lift`` above the tip (a shank, a holder)."""
    if min(p0[2], p1[2]) + lift >= hf.box.z1:
        return None  # wholly above the stock (whose top never rises)
    win = hf.window(
        min(p0[0], p1[0]) - r, max(p0[0], p1[0]) + r, min(p0[1], p1[1]) - r, max(p0[1], p1[1]) + r
    )
    if win is None:
        return None
    qx = hf.xs[win[1]][None, :] - p0[0]
    qy = hf.ys[win[0]][:, None] - p0[1]
    d = (float(p1[0] - p0[0]), float(p1[1] - p0[1]), float(p1[2] - p0[2]))
    z = float(p0[2]) + lift
    if tool is None:
        return win, flat_envelope(qx, qy, d, z, r)
    return win, tool_envelope(qx, qy, d, z, tool, hf.h[win])


def _worst(
    hf: HeightField, win: tuple[slice, slice], depth: np.ndarray
) -> tuple[float, float, float]:
    """(largest depth, its cell's X, Y) of a window's depth array."""
    k = int(np.argmax(depth))
    j, i = divmod(k, depth.shape[1])
    return float(depth.flat[k]), float(hf.xs[win[1]][i]), float(hf.ys[win[0]][j])


def _guards(tool: ToolShape) -> list[tuple[str, float, float]]:
    """(name, radius, bottom above the tip) of the tool's shank and holder, when known."""
    parts = []
    if tool.shank_bottom is not None:
        parts.append(("shank", 0.5 * tool.shank_diameter, tool.shank_bottom))
    if tool.holder_bottom is not None:
        parts.append(("holder", 0.5 * tool.holder_diameter, tool.holder_bottom))
    return parts


#: records a finding: (code, command, (worst value, x, y), message)
Recorder = Callable[[str, canon.Command, tuple[float, float, float], str], None]


def _fixture_contact(
    fixture: Fixture,
    tool: ToolShape,
    bodies: list[tuple[str, float, float]],
    p0: np.ndarray,
    p1: np.ndarray,
    rapid: bool,
    cmd: canon.Command,
    find: Recorder,
) -> None:
    """Record ``SIM-FIXTURE`` when the tool's cutting end, shank or holder (``bodies``:
    name, radius, bottom above the tip) swept from ``p0`` to ``p1`` goes below the
    fixture's top: the worst depth over the bodies, naming the one that reaches deepest."""
    grid = fixture.grid
    worst: tuple[float, float, float] | None = None
    what = ""
    for name, radius, lift in bodies:
        touched = _sweep(grid, p0, p1, radius, lift, tool if name == "tool" else None)
        if touched is None:
            continue
        win, env = touched
        over = grid.h[win] - env
        if np.max(over) > RAPID_EPS:
            here = _worst(grid, win, over)
            if worst is None or here[0] > worst[0]:
                worst, what = here, name
    if worst is None:
        return
    move = "rapid move" if rapid else "move"
    part = "tool" if what == "tool" else f"tool's {what}"
    find(
        "SIM-FIXTURE",
        cmd,
        worst,
        f"{move}: the {part} enters fixture {fixture.name} {worst[0]:.3f} mm deep",
    )


def add_air_cutting(result: SimResult, first_use: dict[int, Location]) -> None:
    """A ``SIM-AIR-CUTTING`` note for each tool more than :data:`AIR_SHARE` of whose feed
    path removed nothing, located at its first use (milling and turning alike)."""
    for number, use in result.tools.items():
        if use.feed_length > 0 and use.air_share > AIR_SHARE:
            result.findings.append(
                SimFinding(
                    "SIM-AIR-CUTTING",
                    RULES["SIM-AIR-CUTTING"],
                    f"tool {number}: {100 * use.air_share:.0f} % of its feed path "
                    f"({use.air_length:.1f} of {use.feed_length:.1f} mm) removes nothing",
                    first_use[number],
                    use.air_share,
                )
            )


def simulate_removal(
    commands: Iterable[canon.Command],
    hf: HeightField,
    tools: dict[int, ToolShape],
    chord_tol: float = 0.005,
    track_moves: bool = False,
    fixtures: Sequence[Fixture] = (),
    track_volume: bool = False,
) -> SimResult:
    """Sweep every move of ``commands`` through ``hf`` (changed in place) with the tools by
    number (a tool not in ``tools`` is tool 0's shape, or the default 6 mm flat end mill)
    and report the removed volume, each tool's share and the findings (:data:`RULES`), one
    per rule and line with the worst value found on that line. ``track_moves`` keeps, per
    cell, the last move that cut it (``SimResult.last_move``). Any move whose swept tool,
    shank or holder goes below the top of one of ``fixtures`` is ``SIM-FIXTURE``.
    ``track_volume`` keeps the volume each motion command removed
    (``SimResult.move_volumes``, by IR index) for the removal-rate trace column."""
    start = hf.volume()
    z0 = hf.box.z0
    result = SimResult(0.0, 0)
    if track_moves:
        result.last_move = np.full(hf.h.shape, -1, dtype=np.int32)
    ir_index: dict[int, int] = {}
    if track_volume:
        commands = list(commands)
        ir_index = {id(c): i for i, c in enumerate(commands)}
        result.move_volumes = {}
    index: dict[tuple[str, int | None], int] = {}
    fallback = tools.get(0, DEFAULT_TOOL)
    first_use: dict[int, Location] = {}

    def find(
        code: str, cmd: canon.Command, worst: tuple[float, float, float], message: str
    ) -> None:
        loc = _located(cmd)
        value, x, y = worst
        f = SimFinding(code, RULES[code], f"{message} at X{x:.3f} Y{y:.3f}", loc, value, x, y)
        k = index.get((code, loc.line))
        if k is None:
            index[(code, loc.line)] = len(result.findings)
            result.findings.append(f)
        elif value > (result.findings[k].value or 0.0):
            result.findings[k] = f

    current, mark = -1, start  # the tool in use and the volume when it came in

    def settle() -> None:
        """Book the volume removed since ``mark`` to the tool in use."""
        nonlocal mark
        if current >= 0:
            now = hf.volume()
            result.tools[current].removed_volume += mark - now
            mark = now

    for cmd, rapid, number, pts in machine_moves(commands, chord_tol):
        tool = tools.get(number, fallback)
        if tool.kind == "insert":
            raise Diagnostic(
                "SIM-UNSUPPORTED",
                f"tool {number} is a lathe insert: turning is simulated on a bar stock "
                "(--stock bar:R,Z0,Z1)",
                _located(cmd),
            )
        if number != current:
            settle()
            current = number
        use = result.tools.setdefault(number, ToolUse())
        first_use.setdefault(number, _located(cmd))
        result.moves += 1
        move_id = len(result.move_locations)
        if track_moves:
            result.move_locations.append(_located(cmd))
        guards = _guards(tool)
        bodies = [("tool", tool.radius, 0.0), *guards]
        for k in range(len(pts) - 1):
            p0, p1 = pts[k], pts[k + 1]
            seg = float(np.linalg.norm(p1 - p0))
            if not rapid:
                use.feed_length += seg
            for fixture in fixtures:
                _fixture_contact(fixture, tool, bodies, p0, p1, rapid, cmd, find)
            for name, radius, lift in guards:
                touched = _sweep(hf, p0, p1, radius, lift, None)
                if touched is None:
                    continue
                gwin, genv = touched
                over = hf.h[gwin] - genv
                if np.max(over) > RAPID_EPS:
                    worst = _worst(hf, gwin, over)
                    find(
                        "SIM-HOLDER",
                        cmd,
                        worst,
                        f"the {name} touches material {worst[0]:.3f} mm deep",
                    )
            swept = _sweep(hf, p0, p1, tool.radius, 0.0, tool)
            if swept is None:
                use.air_length += 0.0 if rapid else seg
                continue
            win, env = swept
            h = hf.h[win]
            cut = (env < h - RAPID_EPS) & (h > z0 + RAPID_EPS)
            if not cut.any():
                use.air_length += 0.0 if rapid else seg
                continue
            depth = np.where(cut, h - env, 0.0)
            if rapid:
                worst = _worst(hf, win, depth)
                find(
                    "SIM-RAPID-IN-STOCK",
                    cmd,
                    worst,
                    f"rapid move into material {worst[0]:.3f} mm deep",
                )
            else:
                dz = float(p1[2] - p0[2])
                xy = math.hypot(float(p1[0] - p0[0]), float(p1[1] - p0[1]))
                if not tool.centre_cutting and dz < 0 and -dz > PLUNGE_SLOPE * xy:
                    find(
                        "SIM-PLUNGE-NON-CENTRE",
                        cmd,
                        (-dz, float(p1[0]), float(p1[1])),
                        f"plunge of {-dz:.3f} mm with a tool that does not cut at its centre",
                    )
                if tool.flute_length > 0:
                    worst = _worst(hf, win, depth)
                    if worst[0] > tool.flute_length + RAPID_EPS:
                        find(
                            "SIM-FLUTE-DEPTH",
                            cmd,
                            worst,
                            f"cut {worst[0]:.3f} mm deep with {tool.flute_length:g} mm of flutes",
                        )
            if result.last_move is not None or result.move_volumes is not None:
                new = np.minimum(h, np.maximum(env, z0))
                if result.last_move is not None:
                    lm = result.last_move[win]
                    lm[new < h] = move_id
                if result.move_volumes is not None:
                    k_ir = ir_index[id(cmd)]
                    removed = float(np.sum(h - new)) * hf.cell_area
                    result.move_volumes[k_ir] = result.move_volumes.get(k_ir, 0.0) + removed
                h[...] = new
            else:
                np.minimum(h, np.maximum(env, z0), out=h)
    settle()
    add_air_cutting(result, first_use)
    result.removed_volume = start - hf.volume()
    return result
