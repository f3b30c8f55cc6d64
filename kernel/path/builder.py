"""The IR walk behind :func:`kernel.path.build.build_path`: modal state and one light row per
motion or hold, vectorised into the segment table at the end (see kernel.path.build for the
rules: units, offsets, feed modes, arcs, NURBS tessellation, LinuxCNC additions).

Runs of consecutive ``STRAIGHT_FEED`` / ``STRAIGHT_TRAVERSE`` commands (the bulk of CAM
output) change no modal state: the walk records each run with its state, and
:func:`kernel.path.columns.segment_table` converts all runs as whole columns (units, G92, XY
rotation and G5x offset with the same floating-point operations as the command-by-command
walk, so the table is bit-for-bit the same; tests/test_kernel_path_speedpath.py).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from itertools import islice

import numpy as np

import kernel.ir.canon as canon
from kernel.diagnostics import Diagnostic
from kernel.interp.nurbs import NurbsCurve, tessellate
from kernel.ir.arcsweep import arc_sweep
from kernel.machine import Machine
from kernel.path.blend import blend_corners
from kernel.path.columns import ArcRecord, Row, StraightRun, segment_table
from kernel.path.curvature import cut_for_machine
from kernel.path.ellipse import ellipse_chords
from kernel.path.segments import (
    ARC,
    DWELL,
    FEED,
    HOLD,
    LINE,
    MACHINE_FUNCTION,
    MIN_LENGTH,
    ORIENT,
    PROBE,
    RAPID,
    STOP,
    TOOL_CHANGE,
    Path,
)

_PLANE_AXES = {
    canon.Plane.XY: (0, 1, 2),
    canon.Plane.YZ: (1, 2, 0),
    canon.Plane.XZ: (2, 0, 1),
}

_MODE = {
    canon.FeedMode.UNITS_PER_MINUTE: 0,
    canon.FeedMode.INVERSE_TIME: 1,
    canon.FeedMode.UNITS_PER_REVOLUTION: 2,
}


@dataclass
class _State:
    mm: float = 1.0
    # the offset applied after the rotation, mm: the work offset (G54..) plus the tool's
    g5x: tuple[float, ...] = (0.0,) * 6
    work: tuple[float, ...] = (0.0,) * 6  # the work offset (G54.., SET_ORIGIN_OFFSETS), mm
    tlo: tuple[float, ...] = (0.0,) * 6  # the tool length offset (USE_TOOL_LENGTH_OFFSET), mm
    g92: tuple[float, ...] = (0.0,) * 6  # G92 offset, mm, applied before rotation
    rot: float = 0.0  # SET_XY_ROTATION, rad about Z
    position: tuple[float, ...] = (0.0,) * 6
    feed: float = 0.0
    feed_mode: int = 0  # _MODE
    spindle: float = 0.0
    synch: float = 0.0  # feed per revolution of START_SPEED_FEED_SYNCH (program units)
    traverse: float = math.inf
    plane: canon.Plane = canon.Plane.XY
    exact_stop: bool = False
    blend: float = 0.0
    override: float = 1.0  # the factor in force (1 while overrides are disabled)


#: runs of straight moves at least this long take the columnar path (shorter: one by one)
MIN_RUN = 8
_BATCH = 1 << 16  # commands drawn at a time from a streamed program
_STRAIGHT = frozenset((canon.StraightFeed, canon.StraightTraverse))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` of two 3-vectors, same operations (and signed zeros), without its
    per-call overhead."""
    (a0, a1, a2), (b0, b1, b2) = a.tolist(), b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _loc_line(cmd: canon.Command) -> int:
    return cmd.source.line if cmd.source is not None else 0


def _tool_offset(cmd: canon.Command, mm: float) -> tuple[float, ...]:
    """The tool length offset of a ``USE_TOOL_LENGTH_OFFSET`` (NIST's Z ``length``, or
    LinuxCNC's nine values x y z, a b c, u v w) as x y z in mm and a b c."""
    if hasattr(cmd, "offset"):
        o = [float(v) for v in canon.named_field(cmd, "offset")]
        return (o[0] * mm, o[1] * mm, o[2] * mm, o[3], o[4], o[5])
    return (0.0, 0.0, canon.named_field(cmd, "length") * mm, 0.0, 0.0, 0.0)


class PathBuilder:
    """Turns canonical commands into light rows; :meth:`table` vectorises them."""

    def __init__(self, machine: Machine, file: str | None) -> None:
        self.machine = machine
        self.st = _State()
        self.st.position = tuple(machine.limit_vector("home"))
        self.st.override = machine.controller.feed_override
        self.st.blend = machine.controller.blend_tolerance  # G64 is the initial mode
        self.rows: list[Row] = []  # light rows not yet moved into ``chunks``
        self.chunks: list[list[Row] | StraightRun] = []  # light rows and runs, in program order
        self.file = file

    # ------------------------------------------------------------------ motions
    def _rot(self, v: np.ndarray, sign: float = 1.0) -> np.ndarray:
        """Rotate the XY part of 3-vectors (rows) by the XY rotation in force."""
        c, sn = math.cos(sign * self.st.rot), math.sin(sign * self.st.rot)
        out = np.array(v, dtype=float)
        out[..., 0] = c * v[..., 0] - sn * v[..., 1]
        out[..., 1] = sn * v[..., 0] + c * v[..., 1]
        return out

    def _to_machine(self, w: np.ndarray) -> tuple[float, ...]:
        """Work frame (program position in mm + G92) to machine: ``R w + g5x`` (rs274's
        order: G92, then the XY rotation, then the G5x offset)."""
        m = np.array(w, dtype=float)
        if self.st.rot:
            m[:3] = self._rot(m[:3])
        m += self.st.g5x
        return tuple(m.tolist())

    def _to_work(self, m: tuple[float, ...]) -> np.ndarray:
        w = np.array(m, dtype=float) - self.st.g5x
        if self.st.rot:
            w[:3] = self._rot(w[:3], -1.0)
        return w

    def _target(self, values: tuple[float, ...]) -> tuple[float, ...]:
        """Machine coordinates of a programmed end point."""
        mm, o = self.st.mm, self.st.g92
        w = (
            values[0] * mm + o[0],
            values[1] * mm + o[1],
            values[2] * mm + o[2],
            values[3] + o[3],
            values[4] + o[4],
            values[5] + o[5],
        )
        if not self.st.rot and not any(self.st.g5x):
            return w
        return self._to_machine(np.array(w))

    def line_to(self, cmd: canon.Command, end: tuple[float, ...], category: int, idx: int) -> None:
        st = self.st
        start = st.position
        st.position = end
        if end == start:
            return
        rate = st.traverse if category == RAPID else st.feed
        self._add_row(
            LINE, category, start, end, cmd, idx, rate, st.exact_stop or category == PROBE
        )

    def arc(self, cmd: canon.ArcFeed, idx: int) -> None:
        st = self.st
        f, s, ax = _PLANE_AXES[st.plane]
        start = self._to_work(st.position)
        off = np.array(st.g92)
        end = start.copy()
        end[f] = cmd.first_end * st.mm + off[f]
        end[s] = cmd.second_end * st.mm + off[s]
        end[ax] = cmd.axis_end_point * st.mm + off[ax]
        end[3:] = np.array([cmd.a, cmd.b, cmd.c]) + off[3:]
        cf = cmd.first_axis * st.mm + off[f]
        cs = cmd.second_axis * st.mm + off[s]
        r0 = math.hypot(start[f] - cf, start[s] - cs)
        r1 = math.hypot(end[f] - cf, end[s] - cs)
        if r0 <= MIN_LENGTH or r1 <= MIN_LENGTH:
            raise Diagnostic("PLAN-ARC", "arc with zero radius", cmd.source)
        if cmd.rotation == 0:
            raise Diagnostic("PLAN-ARC", "arc with rotation 0", cmd.source)
        t0 = math.atan2(start[s] - cs, start[f] - cf)
        t1 = math.atan2(end[s] - cs, end[f] - cf)
        sweep = arc_sweep(t0, t1, cmd.rotation)
        centre = np.zeros(3)
        centre[f], centre[s], centre[ax] = cf, cs, start[ax]
        normal = np.zeros(3)
        normal[ax] = 1.0
        e1 = np.zeros(3)
        e1[f], e1[s] = (start[f] - cf) / r0, (start[s] - cs) / r0
        axial = end[ax] - start[ax]
        length = math.hypot(0.5 * (r0 + r1) * abs(sweep), axial)
        rec = ArcRecord(
            centre=centre,
            normal=normal,
            e1=e1,
            e2=_cross(normal, e1),
            radius=r0,
            radius_end=r1,
            sweep=sweep,
            axial=axial,
            length=length,
        )
        if st.rot or any(st.g5x):
            rot = np.stack([centre, normal, e1, rec.e2])
            if st.rot:
                rot = self._rot(rot)
            centre, normal, e1, e2 = rot
            rec = rec._replace(centre=centre + np.array(st.g5x[:3]), normal=normal, e1=e1, e2=e2)
            start, end = np.array(self._to_machine(start)), np.array(self._to_machine(end))
        st.position = tuple(end.tolist())
        start_m = tuple(start.tolist())
        self._add_row(ARC, FEED, start_m, st.position, cmd, idx, st.feed, st.exact_stop, rec)

    def nurbs(self, cmd: canon.NurbsFeed, idx: int) -> None:
        st = self.st
        if not cmd.points or cmd.elided:
            raise Diagnostic(
                "PLAN-NURBS", "NURBS_FEED without its control points and knots", cmd.source
            )
        f, s, _ = _PLANE_AXES[st.plane]
        pts = np.array([[p[0], p[1]] for p in cmd.points], dtype=float) * st.mm
        pts[:, 0] += st.g92[f]
        pts[:, 1] += st.g92[s]
        weights = np.array([p[2] for p in cmd.points], dtype=float)
        curve = NurbsCurve.create(pts, weights, cmd.knots or None, cmd.order - 1, cmd.source)
        xy = tessellate(curve, self.machine.controller.chord_tolerance)
        base = self._to_work(st.position)
        for q in xy[1:]:
            w = base.copy()
            w[f], w[s] = float(q[0]), float(q[1])
            self.line_to(cmd, self._to_machine(w), FEED, idx)

    def ellipse(self, cmd: canon.EllipseFeed, idx: int) -> None:
        """ELLIPSE_FEED as chords within the chord tolerance (kernel.path.ellipse), every one a
        feed line mapped back to the command's index; the helix axis follows the swept
        polar angle (NIST rule 2), rotary axes move linearly along the path."""
        st = self.st
        f, s, ax = _PLANE_AXES[st.plane]
        mm, off = st.mm, st.g92
        start = self._to_work(st.position)
        end = start.copy()
        end[f] = cmd.first_end * mm + off[f]
        end[s] = cmd.second_end * mm + off[s]
        end[ax] = cmd.axis_end_point * mm + off[ax]
        end[3:] = np.array([cmd.a, cmd.b, cmd.c]) + off[3:]
        chords = ellipse_chords(
            (float(start[f]), float(start[s])),
            (float(end[f]), float(end[s])),
            (cmd.first_axis * mm + off[f], cmd.second_axis * mm + off[s]),
            cmd.major * mm,
            cmd.minor * mm,
            cmd.angle_to_first,
            cmd.rotation,
            float(end[ax] - start[ax]),
            self.machine.controller.chord_tolerance,
            cmd.source,
        )
        w = np.repeat(start[None], len(chords.first), axis=0)
        w[:, f], w[:, s] = chords.first, chords.second
        w[:, ax] += chords.axial_fraction * (end[ax] - start[ax])
        w[:, 3:] += chords.length_fraction[:, None] * (end[3:] - start[3:])
        w[-1] = end  # exactly the programmed end point
        if st.rot:
            w[:, :3] = self._rot(w[:, :3])
        w += np.array(st.g5x)
        for p in w.tolist():
            self.line_to(cmd, tuple(p), FEED, idx)

    def hold(self, cmd: canon.Command, seconds: float, category: int, idx: int) -> None:
        p = self.st.position
        self._add_row(HOLD, category, p, p, cmd, idx, 0.0, True, duration=max(0.0, seconds))

    def machine_function(self, cmd: canon.MachineFunction, idx: int) -> None:
        """An M code for the PLC: the machine stops and waits ``[m_codes]`` time (0 s for
        one the profile does not name); a forbidden one is a located ``PLAN-M-FORBIDDEN``."""
        spec = self.machine.m_codes.get(cmd.code)
        if spec is not None and spec.forbid:
            what = f" ({spec.name})" if spec.name else ""
            raise Diagnostic(
                "PLAN-M-FORBIDDEN",
                f"M{cmd.code}{what} is forbidden on this machine ([m_codes] forbid = true)",
                cmd.source,
            )
        self.hold(cmd, spec.time if spec is not None else 0.0, MACHINE_FUNCTION, idx)

    def _add_row(
        self,
        kind: int,
        category: int,
        start: tuple[float, ...],
        end: tuple[float, ...],
        cmd: canon.Command,
        idx: int,
        rate: float,
        exact_stop: bool,
        arc: ArcRecord | None = None,
        duration: float = 0.0,
    ) -> None:
        """The one place a light row is made: a motion carries the modal feed state in force,
        a hold the neutral one (per minute, unit scale, no spindle, override 1, no blend)."""
        st = self.st
        moving = kind != HOLD
        self.rows.append(
            Row(
                kind=kind,
                category=category,
                start=start,
                end=end,
                rate=rate,
                feed_mode=st.feed_mode if moving else 0,
                mm=st.mm if moving else 1.0,
                spindle=st.spindle if moving else 0.0,
                synch=st.synch if moving else 0.0,
                override=st.override if moving else 1.0,
                exact_stop=exact_stop,
                blend=st.blend if moving else 0.0,
                source=idx,
                line=_loc_line(cmd),
                duration=duration,
                arc=arc,
            )
        )

    # ------------------------------------------------------------------ dispatch
    def feed_all(self, commands: Iterable[canon.Command]) -> None:
        """Walk a whole program. A streamed one is drawn in batches; if the stream fails,
        the commands before the failure are walked first (their errors come first)."""
        if isinstance(commands, list):
            self._feed_batch(commands, 0)
            return
        it, idx = iter(commands), 0
        while True:
            batch: list[canon.Command] = []
            try:
                batch.extend(islice(it, _BATCH))  # keeps what came before a failure
            except Exception:
                self._feed_batch(batch, idx)
                raise
            if not batch:
                return
            self._feed_batch(batch, idx)
            idx += len(batch)

    def _feed_batch(self, cmds: list[canon.Command], idx0: int) -> None:
        n = len(cmds)
        types = list(map(type, cmds))
        flags = np.fromiter(map(_STRAIGHT.__contains__, types), bool, n)
        edges = np.flatnonzero(np.diff(flags, prepend=False, append=False)).tolist()
        pos, feed = 0, self.feed
        for a, b in zip(edges[0::2], edges[1::2], strict=True):
            if b - a < MIN_RUN:
                continue
            for i in range(pos, a):
                feed(idx0 + i, cmds[i])
            self.straight_run(cmds[a:b], idx0 + a)
            pos = b
        for i in range(pos, n):
            feed(idx0 + i, cmds[i])

    def straight_run(self, run: list[canon.Command], idx0: int) -> None:
        """Record consecutive STRAIGHT_FEED / STRAIGHT_TRAVERSE commands with the modal state
        they run under; :func:`kernel.path.columns.merged_columns` converts all runs at once."""
        st = self.st
        if self.rows:
            self.chunks.append(self.rows)
            self.rows = []
        start = st.position
        last = run[-1]
        st.position = self._target((last.x, last.y, last.z, last.a, last.b, last.c))
        self.chunks.append(
            StraightRun(
                run,
                idx0,
                start,
                (st.mm, *st.g92),
                (st.rot, math.cos(st.rot), math.sin(st.rot), *st.g5x),
                bool(st.rot or any(st.g5x)),
                (
                    float(st.feed),
                    float(st.traverse),
                    st.feed_mode,
                    st.mm,
                    st.spindle,
                    st.synch,
                    st.override,
                    st.blend,
                ),
                bool(st.exact_stop),
            )
        )

    def feed(self, idx: int, cmd: canon.Command) -> None:
        st = self.st
        cls = type(cmd)
        if cls is canon.StraightFeed:
            self.line_to(cmd, self._target((cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c)), FEED, idx)
            return
        c = self.machine.controller
        match cmd:
            case canon.StraightTraverse():
                self.line_to(
                    cmd, self._target((cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c)), RAPID, idx
                )
            case canon.StraightProbe():
                self.line_to(
                    cmd, self._target((cmd.x, cmd.y, cmd.z, cmd.a, cmd.b, cmd.c)), PROBE, idx
                )
            case canon.ArcFeed():
                self.arc(cmd, idx)
            case canon.NurbsFeed():
                self.nurbs(cmd, idx)
            case canon.Dwell():
                self.hold(cmd, cmd.seconds, DWELL, idx)
            case canon.ChangeTool():
                self.hold(cmd, c.tool_change_time, TOOL_CHANGE, idx)
            case canon.OrientSpindle():
                self.hold(cmd, c.spindle_orient_time, ORIENT, idx)
            case canon.ProgramStop() | canon.OptionalProgramStop() | canon.Stop():
                self.hold(cmd, c.program_stop_time, STOP, idx)
            case canon.ProgramEnd():
                self.hold(cmd, 0.0, STOP, idx)
            case canon.MachineFunction():
                self.machine_function(cmd, idx)
            case canon.UseLengthUnits():
                st.mm = cmd.units.mm_per_unit
            case canon.SetOriginOffsets():
                mm = st.mm
                self._offsets(work=(cmd.x * mm, cmd.y * mm, cmd.z * mm, cmd.a, cmd.b, cmd.c))
                st.g92 = (0.0,) * 6
            case canon.SetFeedRate():
                st.feed = cmd.rate
            case canon.SetFeedMode():
                st.feed_mode = _MODE[cmd.mode]
            case canon.SetTraverseRate():
                st.traverse = cmd.rate if cmd.rate > 0 else math.inf
            case canon.SelectPlane():
                st.plane = cmd.plane
            case canon.SetMotionControlMode():
                st.exact_stop = cmd.mode is canon.MotionMode.EXACT_STOP
                cont = cmd.mode is canon.MotionMode.CONTINUOUS
                tol = cmd.tolerance * st.mm if cmd.tolerance > 0 else c.blend_tolerance
                st.blend = tol if cont else 0.0
            case canon.SetSpindleSpeed():
                st.spindle = cmd.speed
            case canon.StartSpeedFeedSynch():
                st.synch = cmd.feed_per_revolution
            case canon.StopSpeedFeedSynch():
                st.synch = 0.0
            case canon.EnableFeedOverride():
                st.override = c.feed_override
            case canon.DisableFeedOverride():
                st.override = 1.0
            case canon.EllipseFeed():
                self.ellipse(cmd, idx)
            case _:
                self._linuxcnc(cmd, idx)

    def _offsets(
        self, work: tuple[float, ...] | None = None, tlo: tuple[float, ...] | None = None
    ) -> None:
        """A new work offset or tool length offset: the offset added after the rotation is
        their sum (LinuxCNC emccanon.cc and Grbl gcode.c both move the tool by the program
        position plus the work and the tool length offsets; the tool's is not rotated)."""
        st = self.st
        st.work = st.work if work is None else work
        st.tlo = st.tlo if tlo is None else tlo
        st.g5x = tuple(w + t for w, t in zip(st.work, st.tlo, strict=True))

    def _linuxcnc(self, cmd: canon.Command, idx: int) -> None:
        """LinuxCNC additions, known by NAME only (the kernel never imports a front end)."""
        st = self.st
        name = cmd.NAME
        if name in ("SET_G5X_OFFSET", "SET_G92_OFFSET"):
            v = [canon.named_field(cmd, k) for k in ("x", "y", "z", "a", "b", "c")]
            scaled = (v[0] * st.mm, v[1] * st.mm, v[2] * st.mm, v[3], v[4], v[5])
            if name == "SET_G5X_OFFSET":
                self._offsets(work=scaled)
            else:
                st.g92 = scaled
        elif name == "USE_TOOL_LENGTH_OFFSET":
            self._offsets(tlo=_tool_offset(cmd, st.mm))
        elif name == "SET_XY_ROTATION":
            st.rot = math.radians(canon.named_field(cmd, "angle"))
        elif name == "RIGID_TAP":  # G33.1: in synchronised, spindle reversal, back out
            start = st.position
            w = self._to_work(start)
            x, y, z = (canon.named_field(cmd, k) for k in ("x", "y", "z"))
            w[:3] = [x * st.mm + st.g92[0], y * st.mm + st.g92[1], z * st.mm + st.g92[2]]
            bottom = self._to_machine(w)
            saved = st.exact_stop
            st.exact_stop = True
            self.line_to(cmd, bottom, FEED, idx)
            self.line_to(cmd, start, FEED, idx)
            st.exact_stop = saved

    def feed_commands(self, cmds: list[canon.Command], idx0: int) -> None:
        """Walk one batch of a streamed program, ``cmds[0]`` being command ``idx0``: what
        :meth:`feed_all` does with each batch it draws (kernel.stream feeds batch by batch)."""
        self._feed_batch(cmds, idx0)

    def take(self) -> np.ndarray:
        """The rows made since the last call, vectorised, and forgotten here (a streamed
        table; not for S-curve machines, whose lines are cut next to their neighbours): the
        rows of :meth:`table` in order, in pieces, for a consumer that keeps none of them."""
        if self.rows:
            self.chunks.append(self.rows)
            self.rows = []
        chunks, self.chunks = self.chunks, []
        return segment_table(chunks, self.machine, self.file)

    # ------------------------------------------------------------------ vectorised finish
    def table(self) -> np.ndarray:
        """The segment table; for an S-curve machine with its corners blended (G64 P,
        kernel.path.blend, idempotent) and its lines cut next to curvature joints
        (kernel.path.curvature.cut_for_machine)."""
        if self.rows:
            self.chunks.append(self.rows)
            self.rows = []
        seg = segment_table(self.chunks, self.machine, self.file)
        if self.machine.controller.accdec != "scurve":
            return seg
        return cut_for_machine(blend_corners(Path(seg, self.file)), self.machine).segments
