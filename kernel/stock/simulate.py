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
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

import numpy as np

from kernel.diagnostics import Diagnostic, Location, Severity
from kernel.ir import canon
from kernel.ir.arcsweep import arc_sweep
from kernel.stock.heightfield import HeightField, ball_envelope, flat_envelope
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
}


@dataclass(frozen=True, slots=True)
class SimFinding:
    code: str
    severity: Severity
    message: str
    location: Location

    def to_dict(self) -> dict[str, object]:
        return {
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "file": self.location.file,
            "line": self.location.line,
        }


@dataclass
class SimResult:
    removed_volume: float
    moves: int
    findings: list[SimFinding] = field(default_factory=list)

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


def _moves(
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


def sweep_line(
    hf: HeightField, tool: ToolShape, p0: np.ndarray, p1: np.ndarray
) -> tuple[tuple[slice, slice], np.ndarray] | None:
    """The window of cells a line move can touch and the lowest swept tool height over
    each (+inf where untouched), or None when the move misses the grid."""
    r = tool.radius
    if min(p0[2], p1[2]) >= hf.box.z1:
        return None  # wholly above the stock (whose top never rises)
    win = hf.window(
        min(p0[0], p1[0]) - r, max(p0[0], p1[0]) + r, min(p0[1], p1[1]) - r, max(p0[1], p1[1]) + r
    )
    if win is None:
        return None
    qx = hf.xs[win[1]][None, :] - p0[0]
    qy = hf.ys[win[0]][:, None] - p0[1]
    d = (float(p1[0] - p0[0]), float(p1[1] - p0[1]), float(p1[2] - p0[2]))
    envelope = flat_envelope if tool.kind == "flat" else ball_envelope
    return win, envelope(qx, qy, d, float(p0[2]), r)


def simulate_removal(
    commands: Iterable[canon.Command],
    hf: HeightField,
    tools: dict[int, ToolShape],
    chord_tol: float = 0.005,
) -> SimResult:
    """Sweep every move of ``commands`` through ``hf`` (changed in place) with the tools by
    number (a tool not in ``tools`` is tool 0's shape, or the default 6 mm flat end mill)
    and report the removed volume and the findings (:data:`RULES`), one per rule and line."""
    start = hf.volume()
    z0 = hf.box.z0
    result = SimResult(0.0, 0)
    seen: set[tuple[str, int]] = set()
    fallback = tools.get(0, DEFAULT_TOOL)

    def find(code: str, message: str, cmd: canon.Command) -> None:
        loc = _located(cmd)
        if (code, loc.line) not in seen:
            seen.add((code, loc.line))
            result.findings.append(SimFinding(code, RULES[code], message, loc))

    for cmd, rapid, number, pts in _moves(commands, chord_tol):
        tool = tools.get(number, fallback)
        result.moves += 1
        for k in range(len(pts) - 1):
            p0, p1 = pts[k], pts[k + 1]
            swept = sweep_line(hf, tool, p0, p1)
            if swept is None:
                continue
            win, env = swept
            h = hf.h[win]
            cut = (env < h - RAPID_EPS) & (h > z0 + RAPID_EPS)
            if not cut.any():
                continue
            deepest = float(np.max(np.where(cut, h - env, 0.0)))
            if rapid:
                find(
                    "SIM-RAPID-IN-STOCK",
                    f"rapid move into material: {deepest:.3f} mm deep at "
                    f"X{p1[0]:.3f} Y{p1[1]:.3f} Z{p1[2]:.3f}",
                    cmd,
                )
            else:
                dz = float(p1[2] - p0[2])
                xy = math.hypot(float(p1[0] - p0[0]), float(p1[1] - p0[1]))
                if not tool.centre_cutting and dz < 0 and -dz > PLUNGE_SLOPE * xy:
                    find(
                        "SIM-PLUNGE-NON-CENTRE",
                        f"plunge of {-dz:.3f} mm with a tool that does not cut at its centre",
                        cmd,
                    )
                if tool.flute_length > 0 and deepest > tool.flute_length + RAPID_EPS:
                    find(
                        "SIM-FLUTE-DEPTH",
                        f"cut {deepest:.3f} mm deep with {tool.flute_length:g} mm of flutes",
                        cmd,
                    )
            np.minimum(h, np.maximum(env, z0), out=h)
    result.removed_volume = start - hf.volume()
    return result
