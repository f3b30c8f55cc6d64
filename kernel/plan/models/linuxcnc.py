"""LinuxCNC 2.9's trajectory planner as a planner strategy (``[controller] model = "linuxcnc"``).

Re-derived from the behaviour of LinuxCNC 2.9's ``src/emc/tp`` and ``src/emc/task/emccanon.cc``
(read, not copied; GPL-2.0 sources), and checked against LinuxCNC itself
(tests/data/lcnc_tp). What is reproduced, and where it comes from:

* **Segment limits** (emccanon.cc ``getStraightVelocity``/``getStraightAcceleration``,
  ``ARC_FEED``): a line's speed and acceleration are the largest whose every axis share stays
  within its limit; an arc's are bounded by the plane's slowest axis, with the centripetal
  share ``sqrt(3)/2`` of the plane's acceleration (``v = sqrt(0.866 a r_eff)``).
* **Circle acceleration split** (blendmath.c ``pmCircleActualMaxVel``, tc.c
  ``tcUpdateCircleAccRatio``): the normal acceleration at the segment's top speed takes what
  it needs of the segment's acceleration, the tangential share is the rest (at most 1/2).
  The split is made when the segment is finalised (tc.c ``tcFinalizeLength``), once the
  next move is queued: a circle the queue runs dry after (the program's last move, a move
  before a task command's wait) keeps its top speed and the initial split of 1/2.
* **Short-segment cap** (tc.c ``tcClampVelocityByLength``, tp.c
  ``tpComputeOptimalVelocity``): a segment never runs faster than its length per servo
  period (per 1.02 periods after a tangent join).
* **Tangent joins and kinks** (tp.c ``tpSetupTangent``): a join whose direction change needs
  less than ``ARC_BLEND_KINK_RATIO`` (0.1) of the axis accelerations in one period is run
  through at speed; the two segments then lose that share of their acceleration. A kinked
  join that is not blended (G61, exact path) keeps the 0.1 loss on both segments: the "ramps
  peak near 0.9 of the acceleration" of multi-move G61 programs. Reversals within 2 degrees
  and G61.1 (exact stop) stop.
* **Blend arcs** (tp.c ``tpCreateLineLineBlend``, blendmath.c ``blendInit3FromLineLine``,
  ``blendParamKinematics``, ``blendComputeParameters``, tc.c ``tcFindBlendTolerance``):
  the G64 tolerance, or a quarter of the shorter segment when ``P`` is 0 (and never more than
  a quarter of either), bounds the arc; the arc also takes at most half of either line; its
  speed is ``sqrt(0.866 a_plane R)``; its radius is no larger than an equivalent parabolic
  blend needs. Blend arcs run at half their plane acceleration tangentially.
* **Blend arcs between a line and a circle** (blendmath.c ``blendLineArcPostProcess``,
  ``blendArcLinePostProcess``): the circle tangent to both at the blend radius, built
  wherever the line as already trimmed keeps some length (posemath ``pmCartLineStretch``),
  not only within half of it. The arc is judged by the length it is built with, between its
  tangent points (tc.c ``tcClampVelocityByLength``: its speed at most that length per
  period), not ``R * phi``: next to a nearly tangent circle it is a few micrometres and the
  kink wins.
* **Consumed lines** (blendmath.c ``blendCheckConsume``, tp.c ``tpCreateLineLineBlend``):
  what is left of a line before a blend arc, if run in fewer than ``ARC_BLEND_GAP_CYCLES``
  periods, is popped and run as part of the arc, at the arc's speed and requested feed
  (the faster of the two moves it joins).
* **Blend arcs between two circles** (blendmath.c ``blendArcArcPostProcess``, tp.c
  ``tpCreateArcArcBlend``): the exact blend circle tangent to both must stay within the
  tolerance of the corner and take no more of either circle than ``phi_max``, or there is no
  arc; the arc built runs between its two tangent points, and its speed is capped at that
  length per servo period (tc.c ``tcClampVelocityByLength``). Between nearly tangent circles
  (an arc-built spiral) that length is a few micrometres, far below the estimate
  ``R * phi``, so LinuxCNC passes such joins slowly with a small G64 P.
* **Blend choice** (tp.c ``tpChooseBestBlend``): the arc, the approximate tangent (kink
  speed) or a parabolic blend, whichever is fastest (the parabolic estimate halved). The
  parabolic blend's speed (``tpComputeBlendVelocity``) uses the angle between the directions
  of acceleration, not the tangents: a circle's start direction leans toward its centre by
  its centripetal share (tc.c ``tcCircleStartAccelUnitVector``).
* **Parabolic blends and the half acceleration** (tc.c ``tcGetOverallMaxAccel``, tp.c
  ``tpComputeBlendVelocity``, ``tpUpdateBlend``): a segment that ends in a parabolic blend,
  or that starts with one, runs at half its acceleration, and so does a G64 segment with no
  blend after it (the program's last move, a move before a stop). A parabolic blend overlaps
  the end of one segment with the start of the next (tc.c ``tcIsBlending``, tp.c
  ``tpDoParabolicBlending``): each runs to a stop, and the next starts once the first is on
  its final deceleration below the blend speed; the plan's ``overlap`` says for how long,
  and the sampler adds the two motions there (kernel.interp.interpolate), as LinuxCNC's
  axis positions are the sum of both. That sum can take an axis past its speed or
  acceleration limit (LinuxCNC checks nothing there; own_helix_small.native reaches 563
  mm/s^2 against 500): the model does the same, or with ``axis_limits = "strict"`` starts
  the overlap later, at the speed that keeps every axis within them.
* **Where LinuxCNC passes an axis limit** (``axis_limits``): also a steep helix's
  tangential share (:func:`_helix_tangential_cap`); LinuxCNC's acceleration violations are
  known upstream (github.com/LinuxCNC/linuxcnc issues 546, 1738, 3773).
* **Look-ahead** (tp.c ``tpRunOptimization``): backwards over ``ARC_BLEND_OPTIMIZATION_DEPTH``
  (50) tangent segments; non-tangent joins stop it. A move not finalised yet (the queue runs
  dry after it) is entered no faster than the peak of a triangle over it, ``sqrt(a L)``
  (``tpCalculateOptimizationInitialVel``): the program's last move is entered slower than
  a full deceleration over it would allow.
* **Ramped short segments** (tp.c ``tpActivateSegment``, ``tpCalculateRampAccel``): a
  tangent feed segment that lasts less than ``1/ARC_BLEND_RAMP_FREQ`` (10 ms) goes straight
  from its start speed to its end speed.
* **Stops at task commands** (emctask.cc: spindle and coolant commands wait for motion to
  finish): the queue runs dry there, so the move before stops (at half acceleration in G64).
* **Per-period discretisation** (tp.c ``tpCalculateTrapezoidalAccel``,
  ``tcUpdateDistFromAccel``, ``tpCheckEndCondition``): the planner steps once per servo period,
  and a stop costs it about 0.8 period more than the continuous profile, a program about 1.5
  (measured on the goldens); the plan adds them as stand-stills.
* **Naive-CAM merging** (emccanon.cc ``see_segment``/``linkable``/``flush_segments``): with
  ``G64 Q`` (``P`` alone sets ``Q = P``), runs of up to 101 feed lines whose points all lie
  within ``Q`` of the line from the run's start to its end become that one line. In G17
  an arc whose middle lies within ``Q`` of its chord (emccanon.cc ``chord_deviation``)
  joins them as two lines through its middle point (arc-fitted CAM output in G64 P).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

import kernel.ir.canon as canon
from kernel.interp.bulk import bulk_array
from kernel.machine import Machine
from kernel.path.blend import corner_trims, insert_blend_arcs, kept_after_blending
from kernel.path.segments import ARC, HOLD, LINE, RAPID, Path
from kernel.plan.models import lcnc_joins
from kernel.plan.models.lcnc_joins import (
    ACC_RATIO_NORMAL,
    ACC_RATIO_TAN,
    COMPILED_JOINS,
    EXACT,
    KINK_RATIO,
    PARABOLIC,
    STOP,
    TANGENT,
)
from kernel.plan.models.lcnc_joins import ARC_JOIN as _ARC_JOIN
from kernel.plan.models.lcnc_joins import SHARP as _SHARP
from kernel.plan.models.lcnc_joins import TINY as _TINY
from kernel.plan.models.lcnc_joins import VIRTUAL as _VIRTUAL
from kernel.plan.planner import (
    Plan,
    Profiles,
    commanded_feed,
    lookahead,
    ratio_min,
    resumed_lookahead,
    trapezoids,
)

OPT_DEPTH = 50  # [TRAJ] ARC_BLEND_OPTIMIZATION_DEPTH
RAMP_FREQ = 100.0  # [TRAJ] ARC_BLEND_RAMP_FREQ, Hz
GAP_CYCLES = 4  # [TRAJ] ARC_BLEND_GAP_CYCLES
MIN_SEGMENT_CYCLES = 1.02  # tp_types.h TP_MIN_SEGMENT_CYCLES
# discretisation of the per-period planner, in servo periods: measured on the goldens
# (tests/data/lcnc_tp: ~0.8 period per stop over 1-200 stops, ~1.5 per program)
STOP_CYCLES = 0.8
START_CYCLES = 1.5
_GONE = 1e-9  # mm: a line blending leaves shorter than this is dropped


def _rowsum(x: np.ndarray) -> np.ndarray:
    """``np.sum(x, axis=1)`` for a few columns, as column additions (the same order, the
    same numbers; a reduction over a short inner axis is an order of magnitude slower)."""
    if x.shape[1] > 7:
        return np.sum(x, axis=1)
    total = x[:, 0].copy()
    for col in range(1, x.shape[1]):
        total += x[:, col]
    return total


def _rownorm(x: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(x, axis=1)`` by :func:`_rowsum`."""
    return np.sqrt(_rowsum(x * x))


# ----------------------------------------------------------------------------- the IR pass
@dataclass(frozen=True, slots=True)
class Prepared:
    """The program as LinuxCNC's canon layer hands it to the planner.

    ``commands``: the IR with naive-CAM runs merged and every motion-mode change replaced by
    an exact-path one (so the path builder blends nothing: the planner decides);
    ``term`` and ``tolerance`` (mm): the path mode and G64 P in force at each command.
    """

    commands: list[canon.Command]
    term: np.ndarray
    tolerance: np.ndarray
    first: int = 0  # ``term[k]`` is command ``first + k``'s (a window of a streamed program)


@dataclass(slots=True)
class Carry:
    """What planning a program window by window (kernel.stream) carries from one window to
    the next: the look-ahead's running sum ``G`` of ``2 A L`` and its forward pass's running
    minimum ``m`` at the window's first kept junction, the start time and path position;
    whether the window holds the program's last move (which takes the program's
    ``START_CYCLES``) and whether its last row ends at a stop join the next window's first
    row makes (a traverse next to a feed move, tp.c handleModeChange).

    A window that does not start at a stop starts with ``skip`` rows already planned (their
    joins decide the first kept row's start); one that does not end at a stop has rows after
    the kept ones (``own``: at most the rows before are kept; set to the rows kept, cut at a
    join where a window may start, :func:`_window_end`), planned only so that the kept rows
    see what follows them; ``reach`` is set to how many junctions after the kept rows were
    planned as the program plans them (the rest feel the window's end; -1: no cut)."""

    g: float = 0.0
    t: float = 0.0
    s: float = 0.0
    last: bool = True
    stop_at_end: bool = False  # the window ends at a stop join: the next row is a stop
    m: float = 0.0
    skip: int = 0
    own: int | None = None
    reach: int = 0


_MODE_TERM = {
    canon.MotionMode.EXACT_STOP: STOP,
    canon.MotionMode.EXACT_PATH: EXACT,
    canon.MotionMode.CONTINUOUS: PARABOLIC,
}


_TASK_WAITS = frozenset(
    {
        "START_SPINDLE_CLOCKWISE",
        "START_SPINDLE_COUNTERCLOCKWISE",
        "STOP_SPINDLE_TURNING",
        "FLOOD_ON",
        "FLOOD_OFF",
        "MIST_ON",
        "MIST_OFF",
    }
)


def _arc_end(cmd: canon.ArcFeed, plane: canon.Plane) -> tuple[float, float, float]:
    if plane is canon.Plane.XZ:
        return (cmd.second_end, cmd.axis_end_point, cmd.first_end)
    if plane is canon.Plane.YZ:
        return (cmd.axis_end_point, cmd.first_end, cmd.second_end)
    return (cmd.first_end, cmd.second_end, cmd.axis_end_point)


def _linkable(
    chain: list[canon.StraightFeed], start: tuple[float, ...], cmd: canon.StraightFeed, tol: float
) -> bool:
    """emccanon.cc ``linkable``: every chained point within ``tol`` of start..new point."""
    if len(chain) > 100:
        return False
    last = chain[-1]
    if (cmd.a, cmd.b, cmd.c) != (last.a, last.b, last.c):
        return False
    b = np.array(start[:3])
    m = np.array((cmd.x, cmd.y, cmd.z)) - b
    mm = float(m @ m)
    if mm == 0.0:
        return False
    for p in chain:
        d = np.array((p.x, p.y, p.z)) - b
        t = min(max(float(m @ d) / mm, 0.0), 1.0)
        if float(np.linalg.norm(d - t * m)) > tol:
            return False
    return True


def _chord_deviation(
    start: tuple[float, float], cmd: canon.ArcFeed
) -> tuple[float, tuple[float, float]]:
    """emccanon.cc ``chord_deviation``: how far an XY arc's middle lies from its chord, and
    that middle point (the sweep taken as LinuxCNC takes it, full turns left out)."""
    cx, cy = cmd.first_axis, cmd.second_axis
    th1 = math.atan2(start[1] - cy, start[0] - cx)
    th2 = math.atan2(cmd.second_end - cy, cmd.first_end - cx)
    r = math.hypot(start[1] - cy, start[0] - cx)
    for _ in range(2):
        if cmd.rotation < 0 and th2 - th1 >= -1e-5:
            th2 -= 2.0 * math.pi
        elif cmd.rotation >= 0 and th2 - th1 <= 1e-5:
            th2 += 2.0 * math.pi
    mid = (th1 + th2) / 2.0
    dev = r * (1.0 - math.cos(abs(th2 - th1) / 2.0))
    return dev, (cx + r * math.cos(mid), cy + r * math.sin(mid))


_RESETS = frozenset({"USE_LENGTH_UNITS", "SET_G5X_OFFSET", "SET_G92_OFFSET", "SET_XY_ROTATION"})


def _end_of(move: canon.Command) -> tuple[float, ...]:
    """Where a straight move or an XY arc ends: x y z a b c (program units)."""
    if isinstance(move, canon.ArcFeed):
        return (move.first_end, move.second_end, move.axis_end_point, move.a, move.b, move.c)
    assert isinstance(move, (canon.StraightFeed, canon.StraightTraverse))
    return (move.x, move.y, move.z, move.a, move.b, move.c)


def _flat_arcs_as_lines(commands: Iterable[canon.Command]) -> Iterator[canon.Command]:
    """emccanon.cc ``ARC_FEED``: in G17 with G64, an arc whose middle lies closer to its
    chord than the naive-CAM tolerance ``Q`` goes to the planner as two lines, through its
    middle point, that the naive-CAM merging then takes as any other lines. (Type tests by
    identity: this runs once per command of every program.)"""
    xy, continuous, naive = True, True, 0.0
    last: canon.Command | None = None  # the last move: its end is the current point
    for cmd in commands:
        kind = type(cmd)
        if kind is canon.StraightFeed or kind is canon.StraightTraverse:
            last = cmd
        elif kind is canon.ArcFeed:
            assert isinstance(cmd, canon.ArcFeed)
            if naive > 0 and xy and continuous and last is not None:
                at = _end_of(last)
                dev, (mx, my) = _chord_deviation((at[0], at[1]), cmd)
                if dev < naive:
                    end = _end_of(cmd)
                    half = [(p + q) / 2.0 for p, q in zip(at[2:], end[2:], strict=True)]
                    yield canon.StraightFeed(mx, my, *half, source=cmd.source)
                    last = canon.StraightFeed(*end, source=cmd.source)
                    yield last
                    continue
            last = cmd if xy else None
        elif kind is canon.SelectPlane:
            assert isinstance(cmd, canon.SelectPlane)
            xy = cmd.plane is canon.Plane.XY
        elif kind is canon.SetMotionControlMode:
            assert isinstance(cmd, canon.SetMotionControlMode)
            continuous = cmd.mode is canon.MotionMode.CONTINUOUS
        elif kind is canon.SetNaivecamTolerance:
            assert isinstance(cmd, canon.SetNaivecamTolerance)
            naive = cmd.tolerance
        elif (
            cmd.NAME in _RESETS
            or cmd.NAME.endswith("_FEED")  # NURBS, ellipses: moves not followed here
            or cmd.NAME.startswith(("STRAIGHT_PROBE", "RIGID_TAP"))
        ):
            last = None
        yield cmd


def prepared_commands(
    commands: Iterable[canon.Command],
) -> Iterator[tuple[canon.Command, int, float]]:
    """The commands of :func:`prepare` as they come, each with its path mode and G64 P
    (mm): a streamed program's canon layer (kernel.stream), a naive-CAM run held until it
    ends."""
    yield canon.SetMotionControlMode(canon.MotionMode.EXACT_PATH), PARABOLIC, 0.0
    term, tol, mm = PARABOLIC, 0.0, 1.0
    naive = 0.0
    plane = canon.Plane.XY
    pos: tuple[float, ...] | None = None  # where the chain starts (program units)
    chain: list[canon.StraightFeed] = []

    for cmd in _flat_arcs_as_lines(commands):
        if isinstance(cmd, canon.StraightFeed):
            if chain and not (
                term == PARABOLIC
                and naive > 0
                and pos is not None
                and _linkable(chain, pos, cmd, naive)
            ):
                last = chain[-1]
                yield last, term, tol
                pos = (last.x, last.y, last.z)
                chain.clear()
            chain.append(cmd)
            if naive <= 0 or term != PARABOLIC:
                last = chain[-1]
                yield last, term, tol
                pos = (last.x, last.y, last.z)
                chain.clear()
            continue
        if chain:
            last = chain[-1]
            yield last, term, tol
            pos = (last.x, last.y, last.z)
            chain.clear()
        match cmd:
            case canon.SetMotionControlMode():
                term = _MODE_TERM[cmd.mode]
                tol = cmd.tolerance * mm if term == PARABOLIC else 0.0
                mode = canon.SetMotionControlMode(canon.MotionMode.EXACT_PATH, source=cmd.source)
                yield mode, term, tol
                continue
            case canon.SetNaivecamTolerance():
                naive = cmd.tolerance
            case canon.UseLengthUnits():
                mm = 25.4 if cmd.units is canon.Units.INCHES else 1.0
                pos = None
            case canon.SelectPlane():
                plane = cmd.plane
            case canon.StraightTraverse():
                pos = (cmd.x, cmd.y, cmd.z)
            case canon.ArcFeed():
                pos = _arc_end(cmd, plane)
            case _ if cmd.NAME in _TASK_WAITS:
                # issued by task once motion has stopped (emctask.cc preconditions):
                # the planner's queue runs dry there, a stop
                yield cmd, term, tol
                yield canon.Dwell(0.0, source=cmd.source), term, tol
                continue
            case _:
                moved = cmd.NAME.startswith(("STRAIGHT_PROBE", "RIGID_TAP"))
                if moved or cmd.NAME in ("SET_G5X_OFFSET", "SET_G92_OFFSET", "SET_XY_ROTATION"):
                    pos = None
        yield cmd, term, tol
    if chain:
        yield chain[-1], term, tol


def prepare(commands: Iterable[canon.Command]) -> Prepared:
    """Merge naive-CAM runs and record the path mode of every command (emccanon.cc)."""
    out: list[canon.Command] = []
    terms: list[int] = []
    tols: list[float] = []
    for cmd, term, tol in prepared_commands(commands):
        out.append(cmd)
        terms.append(term)
        tols.append(tol)
    return Prepared(out, np.array(terms, dtype=np.int8), np.array(tols, dtype=float))


# ----------------------------------------------------------------------------- segment limits
def _helix_tangential_cap(arcs: np.ndarray, machine: Machine, speed: np.ndarray) -> np.ndarray:
    """The largest path acceleration along each arc (rows of the segment table) that keeps
    its in-plane acceleration within the plane's slowest axis at ``speed``.

    LinuxCNC's effective radius (blendmath.c ``pmCircleEffectiveMinRadius``) adds the whole
    helix rise squared over the radius, so on a steep short helix it overstates the radius
    and the tangential share it leaves can push an axis past its limit. Here the normal
    acceleration is taken with the helix's true curvature r / (r^2 + c^2) (c the rise per
    radian), and the tangential share is what the plane has left, seen along the path (a
    helix's tangent leaves the plane by the angle whose cosine is arc length / path length).
    On flat arcs this never binds below LinuxCNC's own split. Applied with
    ``axis_limits = "strict"`` only: by default the model splits as LinuxCNC does and
    its report shows the axis over its limit where the machine's would be (LinuxCNC's
    acceleration violations: github.com/LinuxCNC/linuxcnc issues 546, 1738, 3773)."""
    amax = np.array(machine.limit_vector("acceleration"))[:3]
    plane = np.abs(arcs["normal"]) < 0.5
    a_pl = np.where(plane, amax[None, :], np.inf).min(axis=1)
    r = np.maximum(np.minimum(arcs["radius"], arcs["radius_end"]), _TINY)
    sweep = np.maximum(np.abs(arcs["sweep"]), _TINY)
    rise = arcs["axial"] / sweep
    kappa = r / (r * r + rise * rise)
    cos_tilt = np.clip(r * sweep / np.maximum(arcs["length"], _TINY), _TINY, 1.0)
    a_n = speed * speed * kappa
    return np.sqrt(np.maximum(a_pl * a_pl - a_n * a_n, 0.0)) / cos_tilt


def _inscribed(binormal: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """blendmath.c ``calculateInscribedDiameter``: the smallest axis bound seen in the plane
    of ``binormal`` (rows), each axis' bound divided by the length of its projection."""
    eye = np.eye(3)
    out = np.full(binormal.shape[0], np.inf)
    for i in range(3):
        proj = np.abs(eye[i][None, :] - binormal * binormal[:, i : i + 1])
        proj[:, i] = np.maximum(proj[:, i], _TINY)
        scale = _rownorm(proj)
        if bounds[i] > 0:
            out = np.minimum(out, bounds[i] / scale)
    return out


@dataclass(frozen=True, slots=True)
class _Limits:
    reqvel: np.ndarray  # requested speed (feed, capped by the axes)
    maxvel: np.ndarray  # the segment's own top speed
    maxacc: np.ndarray  # path acceleration the axes allow
    r_eff: np.ndarray  # arcs: effective radius (inf for lines)


def _limits(path: Path, machine: Machine) -> _Limits:
    seg = path.segments
    ctl = machine.controller
    vmax = np.array(machine.limit_vector("velocity"))
    amax = np.array(machine.limit_vector("acceleration"))
    feed = commanded_feed(path, ctl)
    u = np.ascontiguousarray(seg["u_start"])  # read twice: one pass over the packed table
    maxvel = ratio_min(vmax, u)
    maxacc = ratio_min(amax, u)
    r_eff = np.full(len(seg), np.inf)
    arc = np.flatnonzero(seg["kind"] == ARC)
    if arc.size:
        sa = seg[arc]
        nrm = np.abs(sa["normal"])
        plane = nrm < 0.5  # the two in-plane axes
        v_pl = np.where(plane, vmax[None, :3], np.inf).min(axis=1)
        a_pl = np.where(plane, amax[None, :3], np.inf).min(axis=1)
        sweep = np.maximum(np.abs(sa["sweep"]), _TINY)
        spiral = sa["radius_end"] - sa["radius"]
        rmin = np.minimum(sa["radius"], sa["radius_end"])
        dr = spiral / sweep
        reff_canon = np.sqrt(dr * dr + rmin * rmin)
        v_planar = np.minimum(np.sqrt(a_pl * math.sqrt(3.0) / 2.0 * reff_canon), v_pl)
        spiral_len = np.hypot(rmin * sweep, spiral)
        total = sa["length"]
        chord = np.abs(sa["end"] - sa["start"])
        with np.errstate(divide="ignore", invalid="ignore"):
            t_motion = np.where(chord > _TINY, chord / vmax, 0.0).max(axis=1)
            tt_motion = np.where(chord > _TINY, chord / amax, 0.0).max(axis=1)
        t_max = np.maximum(t_motion, spiral_len / v_planar)
        tt_max = np.maximum(tt_motion, spiral_len / a_pl)
        maxvel[arc] = total / np.maximum(t_max, _TINY)
        maxacc[arc] = total / np.maximum(tt_max, _TINY)
        # tp's effective radius (blendmath.c pmCircleEffectiveMinRadius)
        h2 = sa["axial"] ** 2
        n_inner = dr * dr + sa["radius"] ** 2
        r_spiral = np.sqrt(n_inner**3) / np.maximum(n_inner + dr * dr, _TINY)
        r_eff[arc] = h2 / np.maximum(r_spiral, _TINY) + r_spiral
    reqvel = np.minimum(feed, maxvel)
    return _Limits(reqvel, maxvel, maxacc, r_eff)


# ----------------------------------------------------------------------------- joins
@dataclass(frozen=True, slots=True)
class _Joins:
    kind: np.ndarray  # STOP / TANGENT / PARABOLIC / ARC blend (3 = TANGENT, 4 = arc)
    kink_vel: np.ndarray
    kink_red: np.ndarray
    radius: np.ndarray  # blend arc radius (arc joins)
    arc_vel: np.ndarray  # blend arc top speed
    arc_acc: np.ndarray  # blend arc (plane) acceleration
    arc_req: np.ndarray  # blend arc requested speed
    trim: np.ndarray  # blend arc tangent length on the lines (d_plan)


def _axis_limits(machine: Machine) -> tuple[float, np.ndarray, np.ndarray]:
    """The servo period and the X Y Z velocity and acceleration limits."""
    period = machine.controller.interpolation_period
    vmax = np.array(machine.limit_vector("velocity"))[:3]
    amax = np.array(machine.limit_vector("acceleration"))[:3]
    return period, vmax, amax


def _stops(m: int) -> tuple[np.ndarray, ...]:
    """The arrays of :class:`_Joins` for ``m`` joins, each a stop until decided: kind,
    kink speed (-1: none), kink reduction, blend radius, speed, acceleration, requested
    speed and trim."""
    return (np.full(m, STOP, dtype=np.int8), np.full(m, -1.0), *(np.zeros(m) for _ in range(6)))


def _tri_vel(acc: np.ndarray, length: np.ndarray) -> np.ndarray:
    """blendmath.h ``findVPeak``: top of a triangle over ``length``."""
    return np.sqrt(np.maximum(acc * length, 0.0))


def _blend_velocity(
    acc1: np.ndarray,
    acc2: np.ndarray,
    len1: np.ndarray,
    len2: np.ndarray,
    vt1: np.ndarray,
    vt2: np.ndarray,
    cos_half: np.ndarray,
    tol: np.ndarray,
    unfinal2: np.ndarray | bool = False,
    unfinal1: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """tp.c ``tpComputeBlendVelocity``: the parabolic blend's speed on each side. The peak
    of the triangle over a move not finalised yet (``unfinal1``, ``unfinal2``: the queue
    runs dry after it, or the blend is estimated as the next move is queued) is taken over
    half its length (tp.c ``tpCalculateTriangleVel``: blending may take up to half of it);
    its time still over the whole (``tc->target``)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = np.minimum(_tri_vel(acc1, len1 / 2 if unfinal1 else len1), vt1)
        r2 = np.minimum(_tri_vel(acc2, np.where(unfinal2, len2 / 2, len2)), vt2)
        t_reach = np.minimum(len1 / r1, len2 / r2)
        t_blend = np.minimum(t_reach, np.maximum(r1 / acc1, r2 / acc2))
        b1 = np.minimum(r1, t_blend * acc1)
        b2 = np.minimum(r2, t_blend * acc2)
        ok = (tol > 0) & (cos_half > math.cos(math.pi / 2 - 1e-3))
        tv = 2.0 * np.sqrt(acc1 * tol / np.where(ok, cos_half, 1.0))
    b1 = np.where(ok, np.minimum(b1, tv), b1)
    b2 = np.where(ok, np.minimum(b2, tv), b2)
    return np.nan_to_num(b1), np.nan_to_num(b2)


def _accel_half_angle(
    u1: np.ndarray,
    u2: np.ndarray,
    arc2: np.ndarray,
    inward2: np.ndarray,
    radius2: np.ndarray,
    acc2: np.ndarray,
    reqvel2: np.ndarray,
) -> np.ndarray:
    """Half the angle between the directions of acceleration at a join (tp.c
    ``tpComputeBlendVelocity``, tc.c ``tcCircleStartAccelUnitVector``): the end tangent of the
    first move and, for a circle after it, its start tangent leaned toward the centre by the
    centripetal share ``(v/2)^2 / r`` against the overall acceleration ``acc2``. The parabolic
    blend's speed follows from it, not from the tangents' angle."""
    v2 = u2.copy()
    if arc2.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            inward = inward2 / np.maximum(_rownorm(inward2), _TINY)[:, None]
            lean = np.where(radius2 > _TINY, (0.5 * reqvel2) ** 2 / radius2, 0.0)
            tilted = u2 * acc2[:, None] + inward * lean[:, None]
            tilted /= np.maximum(_rownorm(tilted), _TINY)[:, None]
        v2 = np.where(arc2[:, None], tilted, u2)
    dot = np.clip(_rowsum(u1 * v2), -1.0, 1.0)
    return np.arccos(-dot) / 2.0


def _circle_tangent(
    table: np.ndarray, rows: np.ndarray, arc: np.ndarray, at_end: bool
) -> np.ndarray:
    """The direction tp.c's blend speed takes for each row's end (or start): a line's own,
    a circle's the plane's normal crossed with its radius there (tc.c
    ``tcCircleEndAccelUnitVector``, ``tcCircleStartAccelUnitVector``), which leaves out a
    helix's rise and a spiral's radial drift."""
    u = table["u_end" if at_end else "u_start"][rows, :3]
    if not arc.any():
        return u
    point = table["end" if at_end else "start"][rows, :3]
    normal = table["normal"][rows]
    t = np.cross(normal, point - table["centre"][rows])
    t /= np.maximum(_rownorm(t), _TINY)[:, None]
    t *= np.where(_rowsum(t * u) < 0, -1.0, 1.0)[:, None]
    return np.where(arc[:, None] & (_rownorm(t) > 0.5)[:, None], t, u)


def _spiral_circle(
    seg: np.ndarray, idx: np.ndarray, p: np.ndarray, u_tan: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """blendmath.c ``findSpiralApproximation``: the circle through ``p`` that approximates a
    spiral there (the centre moved along the tangent by the radius change per radian)."""
    sweep = np.abs(seg["sweep"][idx])
    with np.errstate(divide="ignore", invalid="ignore"):
        dr = np.where(sweep > 0, (seg["radius_end"][idx] - seg["radius"][idx]) / sweep, 0.0)
    centre = seg["centre"][idx] + u_tan * dr[:, None]
    return centre, _rownorm(p - centre)


def _arc_arc_blend(
    seg: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    binormal: np.ndarray,
    r_plan: np.ndarray,
    tolerance: np.ndarray,
    theta_tan: np.ndarray,
    which: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """blendmath.c ``blendArcArcPostProcess``: the blend circle of radius ``r_plan`` tangent
    to both circles (inside a convex one, outside a concave one) must stay within the
    tolerance of the corner, and take no more of either circle than the blend may
    (``phi_max``); where it does not, LinuxCNC builds no arc between the two circles
    (``fails``). Also the length of the arc it builds, between the two tangent points
    (tp.c ``tpInitBlendArcFromPrev``: its speed is capped at that length per period; where
    the circles are nearly tangent it is far shorter than the estimate ``R_plan * phi``)."""
    fails = np.zeros(len(a), dtype=bool)
    length = np.zeros(len(a))
    ia, ib = a[which], b[which]
    rp = r_plan[which]
    geo = _arc_arc_geometry(seg, ia, ib, u1[which], u2[which], binormal[which], rp)
    p, c1, r1, c2, r2, convex1, convex2, centre, good = geo
    t_final = _rownorm(centre - p) - rp
    tt = theta_tan[which]
    phi1_max = np.minimum(np.abs(seg["sweep"][ia]) * 2.0 / 3.0, np.where(convex1, tt, np.pi / 2))
    phi2_max = np.minimum(np.abs(seg["sweep"][ib]) / 3.0, np.where(convex2, tt, np.pi / 2))
    fails[which] = (
        ~good
        | ~(t_final <= tolerance[which])
        | (_trim_angle(p, c1, centre) > phi1_max)
        | (_trim_angle(p, c2, centre) > phi2_max)
    )
    length[which] = _blend_arc_length(centre, rp, c1, r1, c2, r2)
    return fails, length


def _circle_blends(
    seg: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    binormal: np.ndarray,
    r_plan: np.ndarray,
    tolerance: np.ndarray,
    theta_tan: np.ndarray,
    ok: np.ndarray,
    s_arc: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The blend arcs ``ok`` so far at the joins next to a circle, as LinuxCNC post-processes
    them (:func:`_arc_arc_blend` between two circles, :func:`_line_arc_blend` between a line
    and a circle): those it cannot build are no longer ``ok``, and those it builds take the
    length of the arc built instead of the estimate ``s_arc``."""
    m = len(ok)
    arc_a = seg["kind"][:m] == ARC
    arc_b = seg["kind"][1 : m + 1] == ARC
    both = ok & arc_a & arc_b
    if both.any():
        rows = np.arange(m)
        fails, s_exact = _arc_arc_blend(
            seg, rows, rows + 1, u1, u2, binormal, r_plan, tolerance, theta_tan, both
        )
        ok = ok & ~fails
        s_arc = np.where(both, s_exact, s_arc)
    one = ok & (arc_a != arc_b)
    if one.any():
        fails, s_exact = _line_arc_blend(seg, u1, u2, binormal, r_plan, tolerance, theta_tan, one)
        ok = ok & ~fails
        s_arc = np.where(one, s_exact, s_arc)
    return ok, s_arc


def _line_arc_blend(
    seg: np.ndarray,
    u1: np.ndarray,
    u2: np.ndarray,
    binormal: np.ndarray,
    r_plan: np.ndarray,
    tolerance: np.ndarray,
    theta_tan: np.ndarray,
    which: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """blendmath.c ``blendLineArcPostProcess`` and ``blendArcLinePostProcess`` at the joins
    ``which`` between a line and a circle (either order): the blend circle of radius
    ``r_plan`` tangent to the line and to the circle (inside a convex one, outside a concave
    one), its centre found along the line by the quadratic's smaller root in magnitude. No arc
    (``fails``) where there is no root, where it leaves the tolerance or takes more of the
    circle than ``phi_max`` (tp.c ``tpCreateLineArcBlend``, ``tpCreateArcLineBlend``). Also
    the length of the arc built, between its tangent points: tc.c
    ``tcClampVelocityByLength`` caps its speed at that length per period (tp.c
    ``tpInitBlendArcFromPrev``), and next to a nearly tangent circle it is far shorter than
    the estimate ``R_plan * phi`` (real_fusion_1028_rough: 8 um after an r 0.8 mm corner,
    so LinuxCNC takes the kink there)."""
    m = len(which)
    fails = np.zeros(m, dtype=bool)
    length = np.zeros(m)
    idx = np.flatnonzero(which)
    if not idx.size:
        return fails, length
    arc_first = seg["kind"][idx] == ARC  # the circle before the join, the line after
    ic = np.where(arc_first, idx, idx + 1)
    t1, t2 = u1[idx], u2[idx]
    p = seg["end"][idx, :3]
    u_tan = np.where(arc_first[:, None], t1, t2)
    c, r = _spiral_circle(seg, ic, p, u_tan)
    u_line = np.where(arc_first[:, None], t2, t1)
    convex = np.where(arc_first, _rowsum((p - c) * t2) < 0, _rowsum((p - c) * t1) >= 0)
    sweep = np.abs(seg["sweep"][ic])
    tt = theta_tan[idx]
    phi_max = np.minimum(
        np.where(arc_first, sweep * 2.0 / 3.0, sweep / 3.0), np.where(convex, tt, np.pi / 2)
    )
    rp = r_plan[idx]
    n = np.cross(binormal[idx], u_line)
    n /= np.maximum(_rownorm(n), _TINY)[:, None]
    d = np.where(convex, -rp, rp) + r
    cu = _rowsum((c - p) * u_line)
    cn = _rowsum((c - p) * n)
    disc = 4.0 * cu * cu - 4.0 * (cu * cu - d * d + (rp - cn) ** 2)
    root = np.sqrt(np.maximum(disc, 0.0))
    d_l = np.minimum(np.abs(-cu + root / 2.0), np.abs(-cu - root / 2.0))
    along = np.where(arc_first, d_l, -d_l)
    foot = p + u_line * along[:, None]
    centre = foot + n * rp[:, None]
    t_final = _rownorm(centre - p) - rp
    fails[idx] = (disc < 0) | ~(t_final <= tolerance[idx]) | (_trim_angle(p, c, centre) > phi_max)
    to_c = centre - c
    touch = c + to_c * (r / np.maximum(_rownorm(to_c), _TINY))[:, None] - centre
    touch /= np.maximum(_rownorm(touch), _TINY)[:, None]
    to_foot = foot - centre
    to_foot /= np.maximum(_rownorm(to_foot), _TINY)[:, None]
    length[idx] = rp * np.arccos(np.clip(_rowsum(touch * to_foot), -1.0, 1.0))
    return fails, length


def _blend_arc_length(
    centre: np.ndarray,
    rp: np.ndarray,
    c1: np.ndarray,
    r1: np.ndarray,
    c2: np.ndarray,
    r2: np.ndarray,
) -> np.ndarray:
    """The length of the blend arc (centre ``centre``, radius ``rp``) between the points
    where it touches the circles of centres ``c1`` and ``c2`` (rows)."""

    def touch(c: np.ndarray, r: np.ndarray) -> np.ndarray:
        """Where the blend circle touches the circle of centre ``c``: along the centres'
        line, from the blend's centre (unit vector)."""
        d = centre - c
        t = c + d * (r / np.maximum(_rownorm(d), _TINY))[:, None] - centre
        return t / np.maximum(_rownorm(t), _TINY)[:, None]

    cos_arc = np.clip(_rowsum(touch(c1, r1) * touch(c2, r2)), -1.0, 1.0)
    return rp * np.arccos(cos_arc)


def _trim_angle(p: np.ndarray, c: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """blendmath.c ``findTrimAngle``: the angle a blend centred at ``centre`` takes off the
    circle of centre ``c`` that ends (or starts) at ``p`` (rows)."""
    up = (p - c) / np.maximum(_rownorm(p - c), _TINY)[:, None]
    uq = (centre - c) / np.maximum(_rownorm(centre - c), _TINY)[:, None]
    return np.arccos(np.clip(_rowsum(up * uq), -1.0, 1.0))


def _arc_arc_geometry(
    seg: np.ndarray,
    ia: np.ndarray,
    ib: np.ndarray,
    t1: np.ndarray,
    t2: np.ndarray,
    binormal: np.ndarray,
    rp: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """The blend circle of radius ``rp`` between circle rows ``ia`` and ``ib`` (blendmath.c
    ``blendArcArcPostProcess``): the corner, each circle as the spiral approximation there
    (centre, radius), whether each is convex, the blend's centre and where it exists."""
    p = seg["end"][ia, :3]
    c1, r1 = _spiral_circle(seg, ia, p, t1)
    c2, r2 = _spiral_circle(seg, ib, p, t2)
    convex1 = _rowsum((p - c1) * t2) < 0
    convex2 = _rowsum((p - c2) * t1) >= 0
    d1 = np.where(convex1, -rp, rp) + r1
    d2 = np.where(convex2, -rp, rp) + r2
    c12 = c2 - c1
    cx_len = _rownorm(c12)
    good = cx_len > _TINY
    with np.errstate(divide="ignore", invalid="ignore"):
        uc = c12 / np.where(good, cx_len, 1.0)[:, None]
        cx = (-(d1**2) + d2**2 - cx_len**2) / (-2.0 * np.where(good, cx_len, 1.0))
        cy = np.sqrt(np.maximum(d1**2 - cx**2, 0.0))
    normal = t2 - t1
    normal /= np.maximum(_rownorm(normal), _TINY)[:, None]
    nc = np.cross(binormal, uc)
    nc = np.where((_rowsum(normal * nc) < 0)[:, None], -nc, nc)
    nc /= np.maximum(_rownorm(nc), _TINY)[:, None]
    base = c1 - p + uc * cx[:, None]
    plus = _rownorm(base + nc * cy[:, None])
    minus = _rownorm(base - nc * cy[:, None])
    cy = np.where(minus < plus, -cy, cy)
    centre = c1 + uc * cx[:, None] + nc * cy[:, None]
    return p, c1, r1, c2, r2, convex1, convex2, centre, good


def _joins(
    seg: np.ndarray,
    lim: _Limits,
    term: np.ndarray,
    tol: np.ndarray,
    machine: Machine,
    compiled: bool | None = None,
) -> _Joins:
    """Decide every join as tp.c ``tpHandleBlendArc`` does when the next move is queued;
    from :data:`COMPILED_JOINS` joins on (or as ``compiled`` says) in compiled loops
    (:func:`_joins_compiled`, the same numbers)."""
    n = len(seg)
    m = max(n - 1, 0)
    if m and (compiled if compiled is not None else m >= COMPILED_JOINS):
        return _joins_compiled(seg, lim, term, tol, machine)
    period, vmax, amax = _axis_limits(machine)
    kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim = _stops(m)
    if m == 0:
        return _Joins(kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim)
    moving = seg["kind"] != HOLD
    # the rows before and after each join (slices: views, not gathers)
    a, b = slice(0, m), slice(1, n)
    valid = moving[a] & moving[b]
    rot = (np.abs(seg["u_end"][:, 3:]).max(axis=1) > 0) | (
        np.abs(seg["u_start"][:, 3:]).max(axis=1) > 0
    )
    rot_j = rot[a] | rot[b]
    mode = term[a]
    u1 = seg["u_end"][a, :3]
    u2 = seg["u_start"][b, :3]
    u1 = u1 / np.maximum(_rownorm(u1), _TINY)[:, None]
    u2 = u2 / np.maximum(_rownorm(u2), _TINY)[:, None]
    length = seg["length"]
    # speeds when the join is decided: the add-time short-segment cap only
    maxvel = np.minimum(lim.maxvel, length / period)
    vt = np.minimum(lim.reqvel, maxvel)
    v_max = np.minimum(vt[a], vt[b])
    circ = (seg["kind"][a] == ARC) | (seg["kind"][b] == ARC)
    # tpSetupTangent
    anti = _rowsum((u1 + u2) ** 2) < _SHARP
    a_inst = v_max / period + lim.maxacc[b]
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(
            amax > 0, np.abs(a_inst[:, None] * (u2 - u1)) / np.where(amax > 0, amax, 1.0), 0.0
        ).max(axis=1)
    scale = np.where(circ, scale / ACC_RATIO_TAN, scale)
    tangent = scale < KINK_RATIO
    considered = valid & ~rot_j & (mode != STOP) & ~anti
    is_tan = considered & tangent
    kind[is_tan] = TANGENT
    kink_vel[is_tan] = v_max[is_tan]
    kink_red[is_tan] = scale[is_tan]
    kinked = considered & ~tangent
    with np.errstate(divide="ignore", invalid="ignore"):
        kv = v_max * KINK_RATIO / np.maximum(scale, _TINY)
    kink_vel[kinked] = kv[kinked]
    kink_red[kinked] = KINK_RATIO
    # rotary joins in G64: parabolic (no tangent check, no arc)
    kind[valid & rot_j & (mode == PARABOLIC)] = PARABOLIC
    blend = kinked & (mode == PARABOLIC)
    if not blend.any():
        return _Joins(kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim)
    # --- blend arc (blendmath.c), line-line geometry at every blended corner
    dot = np.clip(_rowsum(u1 * u2), -1.0, 1.0)
    theta = np.arccos(-dot) / 2.0
    ok = blend & (math.pi / 2 - theta >= 1e-6) & (theta >= 1e-6)
    phi = math.pi - 2.0 * theta
    nominal = length
    t1 = np.where(tol[a] > 0, tol[a], nominal[a] * 0.25)
    t2 = np.where(tol[b] > 0, tol[b], nominal[b] * 0.25)
    tolerance = np.minimum.reduce([t1, t2, nominal[a] * 0.25, nominal[b] * 0.25])
    l1 = nominal[a] * 0.5
    l2 = nominal[b] * 0.5
    # next to a circle (blendmath.c blendInit3FromLineArc / ArcLine / ArcArc, spherical_arc.c
    # arcConvexTest): the blend may take a third of the circle's angle (two thirds of a
    # circle before the corner), less on a convex side, where the corner angle also shrinks
    theta_tan = theta
    arc_b = seg["kind"][b] == ARC
    arc_a = seg["kind"][a] == ARC
    if arc_b.any():
        r2 = seg["radius"][b]
        dot2 = _rowsum((seg["start"][b, :3] - seg["centre"][b]) * u1)
        convex2 = dot2 >= 0
        phi2 = np.minimum(np.abs(seg["sweep"][b]) / 3.0, np.where(convex2, theta_tan, np.pi / 2))
        l2 = np.where(arc_b, np.where(convex2, np.sin(phi2 / 4.0) * r2, phi2 * r2), l2)
        theta = np.where(arc_b & convex2, np.minimum(theta, theta_tan - phi2 / 4.0), theta)
    if arc_a.any():
        r1 = seg["radius_end"][a]
        dot1 = _rowsum((seg["end"][a, :3] - seg["centre"][a]) * u2)
        convex1 = dot1 < 0
        phi1 = np.minimum(
            np.abs(seg["sweep"][a]) * 2.0 / 3.0, np.where(convex1, theta_tan, np.pi / 2)
        )
        l1 = np.where(arc_a, np.where(convex1, np.sin(phi1 / 4.0) * r1, phi1 * r1), l1)
        theta = np.where(arc_a & convex1, np.minimum(theta, theta_tan - phi1 / 4.0), theta)
    theta = np.maximum(theta, 1e-6)
    phi = math.pi - 2.0 * theta
    binormal = np.cross(u1, u2)
    binormal /= np.maximum(_rownorm(binormal), _TINY)[:, None]
    a_max = _inscribed(binormal, amax)
    a_n = a_max * ACC_RATIO_NORMAL
    v_req = np.maximum(vt[a], vt[b])
    v_planar = _inscribed(binormal, vmax)
    phi_eff = np.minimum(phi, math.pi * 0.49)
    vm1 = np.minimum(maxvel[a], maxvel[b] / np.cos(phi_eff))
    vm2 = np.minimum(maxvel[b], maxvel[a] / np.cos(phi_eff))
    area = vm1 * vm2 / 2.0 * np.sin(phi)
    base = _rownorm(u2 * vm2[:, None] - u1 * vm1[:, None])
    with np.errstate(divide="ignore", invalid="ignore"):
        v_alt = np.where(circ | (base <= _TINY), 0.0, 2.0 * area / np.maximum(base, _TINY))
        v_goal = np.minimum(v_req, np.maximum(v_alt, v_planar))
        h_tol = tolerance / (1.0 - np.sin(theta))
        d_tol = np.cos(theta) * h_tol
        d_geom = np.minimum.reduce([l1, l2, d_tol])
        r_geom = np.tan(theta) * d_geom
        v_plan = np.minimum(np.sqrt(a_n * r_geom), v_goal)
        a_par = 0.5 * a_max
        v_tri = np.sqrt(2.0 * a_par * d_geom)
        t_b = np.minimum(v_tri, v_plan) / a_par
        r_blend = np.minimum(t_b * v_plan / phi, r_geom)
        r_plan = np.maximum(v_plan**2 / a_n, r_blend)
        s_arc = r_plan * phi
    ok &= np.isfinite(r_plan) & (r_plan >= _TINY) & (s_arc >= 1e-6)
    # a blend next to a circle must lie in the circle's plane (tp.c tpCreateLineArcBlend and
    # friends: pmUnitCartsColinear of the binormal and the circle's normal, to 1e-6 rad):
    # a helix never blends with an arc
    eps2 = 1e-12
    for idx, is_arc in ((a, seg["kind"][a] == ARC), (b, seg["kind"][b] == ARC)):
        nrm = seg["normal"][idx]
        same = _rowsum((binormal - nrm) ** 2) < eps2
        opposite = _rowsum((binormal + nrm) ** 2) < eps2
        ok &= ~is_arc | same | opposite
    ok, s_arc = _circle_blends(seg, u1, u2, binormal, r_plan, tolerance, theta_tan, ok, s_arc)
    perf_arc = np.where(ok, np.minimum(v_plan, s_arc / period), 0.0)
    # parabolic estimate (segments not finalized yet: half their lengths, kink loss 0.1)
    acc1 = lim.maxacc[a] * (1.0 - KINK_RATIO) * 0.5
    acc2 = lim.maxacc[b] * (1.0 - KINK_RATIO) * 0.5
    acc1 = np.where(seg["kind"][a] == ARC, acc1 * ACC_RATIO_TAN, acc1)
    acc2 = np.where(seg["kind"][b] == ARC, acc2 * ACC_RATIO_TAN, acc2)
    theta_acc = _accel_half_angle(
        u1,
        u2,
        seg["kind"][b] == ARC,
        seg["centre"][b] - seg["start"][b, :3],
        seg["radius"][b],
        lim.maxacc[b] * (1.0 - KINK_RATIO) * 0.5,
        lim.reqvel[b],
    )
    # both moves are unfinalised when the next is queued (tp.c tpAddLine: tpHandleBlendArc
    # before tcFinalizeLength)
    b1, b2 = _blend_velocity(
        acc1, acc2, length[a], length[b], vt[a], vt[b], np.cos(theta_acc), tol[a], True, True
    )
    perf_par = np.sin(theta_acc) * (b1 + b2) / 2.0 / 2.0
    perf = np.stack([perf_par, kink_vel, perf_arc], axis=1)
    best = np.argmax(perf, axis=1)
    use_par = blend & (best == 0)
    use_tan = blend & (best == 1)
    use_arc = blend & (best == 2)
    kind[use_par] = PARABOLIC
    kink_vel[use_par | use_arc] = -1.0
    kink_red[use_par | use_arc] = 0.0
    kind[use_tan] = TANGENT
    kind[use_arc] = _ARC_JOIN
    # a blend arc next to a circle (blendmath.c blendInit3FromLineArc and friends) is not
    # built: its length is run at its speed on the line beside it (on the programmed
    # corner); between two circles the join is passed at the blend arc's speed
    virtual = use_arc & circ
    line_side = (seg["kind"][a] == LINE) | (seg["kind"][b] == LINE)
    kind[virtual & line_side] = _VIRTUAL
    kind[virtual & ~line_side] = TANGENT
    kink_vel[virtual] = perf_arc[virtual]
    radius[use_arc] = r_plan[use_arc]
    with np.errstate(divide="ignore", invalid="ignore"):
        trim[use_arc] = (r_plan / np.tan(theta))[use_arc]
    arc_vel[use_arc] = perf_arc[use_arc]
    arc_acc[use_arc] = a_max[use_arc]
    arc_req[use_arc] = v_req[use_arc]
    return _Joins(kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim)


def _joins_compiled(
    seg: np.ndarray,
    lim: _Limits,
    term: np.ndarray,
    tol: np.ndarray,
    machine: Machine,
) -> _Joins:
    """:func:`_joins` by the loops of :mod:`kernel.plan.models.lcnc_joins`, with numpy's
    inverse cosines and tangents between them (the same numbers, bit for bit)."""
    n = len(seg)
    m = n - 1
    period, vmax, amax = _axis_limits(machine)
    kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim = _stops(m)
    u1, u2 = np.zeros((m, 3)), np.zeros((m, 3))
    dot = np.zeros(m)
    blend = np.zeros(m, dtype=bool)
    vt, maxvel = np.zeros(n), np.zeros(n)
    skind = np.ascontiguousarray(seg["kind"])
    length = np.ascontiguousarray(seg["length"])
    lcnc_joins.tangent_joins(
        skind,
        np.ascontiguousarray(seg["u_end"]),
        np.ascontiguousarray(seg["u_start"]),
        length,
        np.ascontiguousarray(lim.maxvel, dtype=float),
        np.ascontiguousarray(lim.reqvel, dtype=float),
        np.ascontiguousarray(lim.maxacc, dtype=float),
        np.ascontiguousarray(term, dtype=np.int8),
        vmax,
        amax,
        period,
        kind,
        kink_vel,
        kink_red,
        u1,
        u2,
        dot,
        blend,
        vt,
        maxvel,
    )
    if not blend.any():
        return _Joins(kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim)
    theta0 = np.arccos(-dot) / 2.0
    theta, l1, l2, tolerance = np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m)
    ok = np.zeros(m, dtype=bool)
    arcs = np.flatnonzero(skind == ARC)
    # the arc fields of the arc rows only (zero elsewhere)
    fields = {}
    for f in ("radius", "radius_end", "sweep", "centre", "normal", "start", "end"):
        col = seg[f] if f in ("radius", "radius_end", "sweep") else seg[f][:, :3]
        arr = np.zeros((n, *col.shape[1:]))
        arr[arcs] = col[arcs]
        fields[f] = arr
    tolv = np.ascontiguousarray(tol, dtype=float)
    lcnc_joins.blend_angles(
        blend,
        theta0,
        skind,
        length,
        tolv,
        fields["radius"],
        fields["radius_end"],
        fields["sweep"],
        fields["start"],
        fields["end"],
        fields["centre"],
        u1,
        u2,
        theta,
        l1,
        l2,
        tolerance,
        ok,
    )
    tan_theta = np.tan(theta)
    binormal = np.zeros((m, 3))
    a_max, v_req, v_plan, r_plan, s_arc = (np.zeros(m) for _ in range(5))
    lcnc_joins.blend_arcs(
        blend,
        ok,
        theta,
        tan_theta,
        u1,
        u2,
        skind,
        maxvel,
        vt,
        l1,
        l2,
        tolerance,
        fields["normal"],
        vmax,
        amax,
        binormal,
        a_max,
        v_req,
        v_plan,
        r_plan,
        s_arc,
    )
    ok, s_arc = _circle_blends(seg, u1, u2, binormal, r_plan, tolerance, theta0, ok, s_arc)
    # the parabolic estimate's angle between the directions of acceleration (blended joins)
    theta_acc = np.zeros(m)
    jb = np.flatnonzero(blend)
    nb = jb + 1
    theta_acc[jb] = _accel_half_angle(
        u1[jb],
        u2[jb],
        skind[nb] == ARC,
        fields["centre"][nb] - fields["start"][nb],
        fields["radius"][nb],
        lim.maxacc[nb] * (1.0 - KINK_RATIO) * 0.5,
        lim.reqvel[nb],
    )
    lcnc_joins.blend_choice(
        blend,
        ok,
        v_plan,
        s_arc,
        period,
        skind,
        length,
        np.ascontiguousarray(lim.maxacc, dtype=float),
        vt,
        tolv,
        theta_acc,
        r_plan,
        tan_theta,
        a_max,
        v_req,
        kind,
        kink_vel,
        kink_red,
        radius,
        trim,
        arc_vel,
        arc_acc,
        arc_req,
    )
    return _Joins(kind, kink_vel, kink_red, radius, arc_vel, arc_acc, arc_req, trim)


# ----------------------------------------------------------------------------- the plan
def _fillet(
    line_p: np.ndarray, u: np.ndarray, arc: np.void, at_start: bool, radius: float
) -> tuple[np.ndarray, float, float, np.ndarray] | None:
    """A circle of ``radius`` tangent to a line and to a planar circle meeting it at the
    circle's start (``at_start``) or end: the point on the line (``line_p`` is the corner,
    ``u`` the line's direction away from the corner), the distance back along the line, the
    angle taken off the circle, and the fillet's centre; None when there is none. A planar
    spiral (start and end radius differ) is taken as the circle that approximates it at the
    corner (blendmath.c ``findSpiralApproximation``)."""
    n = arc["normal"]
    sweep = float(arc["sweep"])
    e1, e2 = arc["e1"], arc["e2"]
    psi = 0.0 if at_start else sweep
    tangent = math.copysign(1.0, sweep) * (-math.sin(psi) * e1 + math.cos(psi) * e2)
    dr = float(arc["radius_end"] - arc["radius"]) / max(abs(sweep), _TINY)
    c = arc["centre"] + dr * tangent
    to_p = (arc["start"][:3] if at_start else arc["end"][:3]) - c
    r = float(np.linalg.norm(to_p))
    radial = to_p / max(r, _TINY)
    t_away = tangent if at_start else -tangent  # the circle's direction away from the corner
    side = t_away - float(t_away @ u) * u
    norm = float(np.linalg.norm(side))
    if norm < 1e-9 or abs(float(u @ n)) > 1e-9:
        return None
    side /= norm
    inside = float(radial @ u) < 0.0  # the line lies inside the circle near the corner
    rho = r - radius if inside else r + radius
    if rho <= 0:
        return None
    w = line_p + radius * side - c
    b = float(w @ u)
    disc = b * b - float(w @ w) + rho * rho
    if disc < 0:
        return None
    roots = [b - math.sqrt(disc), b + math.sqrt(disc)]
    back = min((-x for x in roots if -x > 1e-12), default=None)
    if back is None:
        return None
    q = line_p + back * u + radius * side
    to_q = (q - c) / np.linalg.norm(q - c)
    delta = math.acos(max(-1.0, min(1.0, float(to_q @ radial))))
    if delta >= abs(sweep) / 2:
        return None
    return line_p + back * u, back, delta, q


def _arc_row(
    proto: np.void, centre: np.ndarray, start: np.ndarray, end: np.ndarray, u_in: np.ndarray
) -> np.void:
    """A planar arc row from ``start`` (leaving along ``u_in``) to ``end`` about ``centre``."""
    row = proto.copy()
    r = float(np.linalg.norm(start - centre))
    e1 = (start - centre) / r
    normal = np.cross(e1, u_in)
    normal /= np.linalg.norm(normal)
    e2 = np.cross(normal, e1)
    to_end = (end - centre) / r
    sweep = math.atan2(float(to_end @ e2), float(to_end @ e1)) % (2 * math.pi)
    row["kind"] = ARC
    row["start"][:3], row["end"][:3] = start, end
    row["centre"], row["normal"], row["e1"], row["e2"] = centre, normal, e1, e2
    row["radius"] = row["radius_end"] = r
    row["sweep"] = sweep
    row["axial"] = 0.0
    row["length"] = r * sweep
    row["u_start"][:3] = u_in
    row["u_end"][:3] = -math.sin(sweep) * e1 + math.cos(sweep) * e2
    return row


def _trim_circle(row: np.void, delta: float, at_start: bool) -> None:
    """Take ``delta`` (rad) off a planar circle or spiral row at its start or end, in place
    (a spiral's radius changing in proportion to the angle, posemath ``pmCircleStretch``)."""
    sweep = float(row["sweep"])
    sign = math.copysign(1.0, sweep)
    e1, e2 = row["e1"].copy(), row["e2"].copy()
    r0, r1 = float(row["radius"]), float(row["radius_end"])
    c = row["centre"]
    cut = delta / max(abs(sweep), _TINY)
    if at_start:
        d = sign * delta
        row["e1"] = math.cos(d) * e1 + math.sin(d) * e2
        row["e2"] = -math.sin(d) * e1 + math.cos(d) * e2
        r0 += (r1 - r0) * cut
        row["radius"] = r0
        row["start"][:3] = c + r0 * row["e1"]
        row["u_start"][:3] = sign * row["e2"]
    else:
        psi = sweep - sign * delta
        r1 -= (r1 - r0) * cut
        row["radius_end"] = r1
        row["end"][:3] = c + r1 * (math.cos(psi) * e1 + math.sin(psi) * e2)
        row["u_end"][:3] = sign * (-math.sin(psi) * e1 + math.cos(psi) * e2)
    row["sweep"] = sweep - sign * delta
    row["length"] = 0.5 * (r0 + r1) * abs(float(row["sweep"]))


def _arc_arc_fillets(
    seg: np.ndarray, joins: np.ndarray, radius: np.ndarray, shortest: np.ndarray
) -> list[tuple[float, float, np.ndarray] | None]:
    """The blend arcs LinuxCNC builds between two planar circles (tp.c
    ``tpCreateArcArcBlend``, blendmath.c ``blendArcArcPostProcess``) at ``joins`` (the row
    before each), of the radius the join was decided with: the angle taken off the end of
    the first circle and the start of the second, and the blend's centre; None where there
    is none to build (a helix, or a blend that would take a whole circle) or where the arc
    is no longer than ``shortest`` (it is run within one servo period: LinuxCNC passes it
    in a split cycle, the join at the arc's speed)."""
    a, b = joins, joins + 1
    u1 = seg["u_end"][a, :3]
    u2 = seg["u_start"][b, :3]
    u1 = u1 / np.maximum(_rownorm(u1), _TINY)[:, None]
    u2 = u2 / np.maximum(_rownorm(u2), _TINY)[:, None]
    binormal = np.cross(u1, u2)
    binormal /= np.maximum(_rownorm(binormal), _TINY)[:, None]
    rp = radius[joins]
    p, c1, r1, c2, r2, _, _, centre, good = _arc_arc_geometry(seg, a, b, u1, u2, binormal, rp)
    d1, d2 = _trim_angle(p, c1, centre), _trim_angle(p, c2, centre)
    flat = (np.abs(seg["axial"][a]) < 1e-9) & (np.abs(seg["axial"][b]) < 1e-9)
    fits = (d1 < np.abs(seg["sweep"][a])) & (d2 < np.abs(seg["sweep"][b]))
    long = _blend_arc_length(centre, rp, c1, r1, c2, r2) > shortest
    made = good & flat & fits & long & np.isfinite(centre).all(axis=1)
    return [
        (float(d1[k]), float(d2[k]), centre[k].copy()) if made[k] else None
        for k in range(joins.size)
    ]


def _split_lines(
    table: np.ndarray,
    pos: np.ndarray,
    trim: np.ndarray,
    tail: np.ndarray,
    radius: np.ndarray,
    circles: list[tuple[float, float, np.ndarray] | None],
) -> tuple[np.ndarray, np.ndarray]:
    """The blend of a line and a circle at each join after row ``pos``: where the circle is
    planar, a fillet of ``radius`` tangent to both (the line and the circle shortened);
    otherwise ``trim`` cut off the line (its end, where ``tail``, else the next row's start)
    as a row of its own, on the programmed corner. Between two circles (``circles[k]``: the
    angles taken off each and the blend's centre, :func:`_arc_arc_fillets`) the blend arc
    itself. Returns the table and the new rows."""
    table = table.copy()
    pieces = []
    for k in range(pos.size):
        p = int(pos[k])
        both = circles[k]
        if both is not None:
            _trim_circle(table[p : p + 1][0], both[0], False)
            _trim_circle(table[p + 1 : p + 2][0], both[1], True)
            first = table[p]
            start, end = first["end"][:3].copy(), table["start"][p + 1, :3].copy()
            pieces.append(_arc_row(first, both[2], start, end, first["u_end"][:3].copy()))
            continue
        line_i, arc_i = (p, p + 1) if tail[k] else (p + 1, p)
        line, arc = table[line_i], table[arc_i]
        u = line["u_start"][:3]
        corner = line["end"][:3] if tail[k] else line["start"][:3]
        away = -u if tail[k] else u
        flat = abs(arc["axial"]) < 1e-9
        got = _fillet(corner, away, arc, tail[k], float(radius[k])) if flat else None
        if got is not None and got[1] < float(line["length"]) - _GONE:
            a_pt, back, delta, q = got
            _trim_circle(table[arc_i : arc_i + 1][0], delta, tail[k])
            arc = table[arc_i]
            if tail[k]:
                table["end"][line_i, :3] = a_pt
                piece = _arc_row(line, q, a_pt, arc["start"][:3], u)
            else:
                table["start"][line_i, :3] = a_pt
                piece = _arc_row(line, q, arc["end"][:3], a_pt, arc["u_end"][:3])
            table["length"][line_i] -= back
            pieces.append(piece)
            continue
        d = min(float(trim[k]), 0.5 * float(line["length"]))
        piece = line.copy()
        if tail[k]:
            piece["start"][:3] = corner - d * u
            table["end"][line_i, :3] = corner - d * u
        else:
            piece["end"][:3] = corner + d * u
            table["start"][line_i, :3] = corner + d * u
        piece["length"] = d
        table["length"][line_i] -= d
        pieces.append(piece)
    out = np.insert(table, pos + 1, np.array(pieces, dtype=table.dtype))
    return out, pos + 1 + np.arange(pos.size)


def _kept_rows(table: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """``table[keep]``, the rows copied as bytes (a structured copy goes field by field)
    into a bulk array (a fresh large array's first touch is slow: kernel.interp.bulk)."""
    n, k = len(table), int(np.count_nonzero(keep))
    out = bulk_array(k, table.dtype)
    rows = np.ascontiguousarray(table).view(np.uint8).reshape(n, -1)
    np.compress(keep, rows, axis=0, out=out.view(np.uint8).reshape(k, -1))
    return out


def _window_end(kind: np.ndarray, overlaps: np.ndarray, skip: int, own: int) -> int:
    """The last row after ``skip`` and up to ``own`` that a later window may start at (0:
    none): the join before it is no parabolic blend (``overlaps``: the two moves' motions
    add, and are sampled together), and one of the two joins before it is no blend next to
    a circle. Those trim the rows on both sides one after the other (:func:`_split_lines`),
    each reading what the one before left, so a run of them carries a trim's last bits on;
    a window's two first rows (its context) see the joins before them, so a window may
    start two rows after such a run is broken."""
    plain = np.concatenate([[True], kind != _VIRTUAL])  # the join before each row
    free = np.concatenate([[True], ~overlaps])
    r = np.arange(skip + 1, own + 1)
    ok = np.flatnonzero((plain[r - 1] | plain[r]) & free[r])
    return int(r[ok[-1]]) if ok.size else 0


def plan(path: Path, machine: Machine, prepared: Prepared, carry: Carry | None = None) -> Plan:
    """Plan ``path`` (built from ``prepared.commands``) as LinuxCNC 2.9's planner runs it.
    ``carry``: ``path`` is one window of a program, starting and ending at a stop (a hold
    row, a G61.1 join or a traverse next to a feed move), planned as the whole program
    plans those rows (or, with ``carry.skip`` and ``carry.own``, any rows of it: only the
    kept ones are returned); updated for the next window."""
    seg = path.segments
    n = len(seg)
    period = machine.controller.interpolation_period
    src = np.clip(seg["source"] - prepared.first, 0, max(len(prepared.term) - 1, 0))
    term = prepared.term[src] if n else np.zeros(0, dtype=np.int8)
    if n and carry is not None and carry.stop_at_end:
        term[-1] = STOP  # the join after the window stops (its mode change, below)
    tol = prepared.tolerance[src] if n else np.zeros(0)
    lim = _limits(path, machine)
    if n > 1:
        # tp.c handleModeChange: no blending between a traverse and a feed move
        rapid = seg["category"] == RAPID
        mv = seg["kind"] != HOLD
        change = np.concatenate([(rapid[:-1] != rapid[1:]) & mv[:-1] & mv[1:], [False]])
        term = np.where(change, STOP, term).astype(np.int8)
    j = _joins(seg, lim, term, tol, machine)
    # a blend arc between two circles is built (as between a line and a circle), where
    # its geometry allows; else the join is passed at the blend arc's speed
    pairs = np.flatnonzero((j.kind == TANGENT) & (j.radius > 0))
    circles: dict[int, tuple[float, float, np.ndarray]] = {}
    if pairs.size:
        shortest = j.arc_vel[pairs] * period * MIN_SEGMENT_CYCLES
        made = _arc_arc_fillets(seg, pairs, j.radius, shortest)
        for k, got in zip(pairs.tolist(), made, strict=True):
            if got is not None:
                circles[k] = got
                j.kind[k] = _VIRTUAL
    moving = seg["kind"] != HOLD
    # per-segment state after the joins: how each segment ends and starts
    out_kind = np.concatenate([j.kind, [STOP]])
    in_kind = np.concatenate([[STOP], j.kind])
    seg_term = np.where(out_kind == STOP, np.where(term == PARABOLIC, PARABOLIC, term), out_kind)
    seg_term = np.where((out_kind == _ARC_JOIN) | (out_kind == _VIRTUAL), TANGENT, seg_term)
    # a G64 segment whose join stopped for a reversal is STOP (full acceleration)
    if n > 1:
        u1 = seg["u_end"][:-1, :3]
        u2 = seg["u_start"][1:, :3]
        anti = _rowsum((u1 + u2) ** 2) < _SHARP
        stop_rev = (j.kind == STOP) & anti & moving[:-1] & moving[1:] & (term[:-1] != STOP)
        seg_term[:-1] = np.where(stop_rev, STOP, seg_term[:-1])
    if carry is not None and carry.own is not None:
        overlaps = (seg_term[:-1] == PARABOLIC) & moving[:-1] & moving[1:]
        carry.own = _window_end(j.kind, overlaps, carry.skip, carry.own)
    blend_prev = in_kind == PARABOLIC
    kred = np.maximum(np.concatenate([j.kink_red, [0.0]]), np.concatenate([[0.0], j.kink_red]))
    half = (seg_term == PARABOLIC) | blend_prev
    acc_all = lim.maxacc * (1.0 - kred) * np.where(half, 0.5, 1.0)
    maxvel = lim.maxvel.copy()
    kink_vel = np.concatenate([j.kink_vel, [-1.0]])
    reqvel = lim.reqvel.copy()
    # insert the blend arcs
    corners = np.flatnonzero(j.kind == _ARC_JOIN)
    virt = np.flatnonzero(j.kind == _VIRTUAL)
    table = seg
    kept = None  # without blends next to circles: the lines blending empties left out now
    if corners.size:
        big = n - 1 >= COMPILED_JOINS  # compiled as the joins were (numba loaded)
        radius = j.radius[corners]
        trims = corner_trims(seg, corners, radius, big)
        if not virt.size:
            kept = kept_after_blending(seg, corners, radius, _GONE, big, trims)
        # the blend arc is asked the faster of its two moves' speeds (tp.c
        # tpCreateLineLineBlend: v_req)
        arc_feed = np.maximum(seg["feed"][corners], seg["feed"][corners + 1])
        table = insert_blend_arcs(seg, corners, radius, kept, big, trims, arc_feed)
        at = corners + 1
        arc_len = radius * trims[3]  # the arcs' length in the table
        arc_max = np.minimum(j.arc_vel[corners], arc_len / period)
        # np.insert(x, at, values) for every per-row array, the places found once
        arc_at = at + np.arange(corners.size)
        old_at = np.ones(n + corners.size, dtype=bool)
        old_at[arc_at] = False

        def ins(x: np.ndarray, values: np.ndarray | float | bool) -> np.ndarray:
            out = np.empty(old_at.size, dtype=x.dtype)
            out[old_at] = x
            out[arc_at] = values
            return out

        seg_term = ins(seg_term, TANGENT)
        acc_all = ins(acc_all, j.arc_acc[corners])
        maxvel = ins(maxvel, arc_max)
        reqvel = ins(reqvel, j.arc_req[corners])
        kink_vel = ins(kink_vel, -1.0)
        moving = ins(moving, True)
        r_eff = ins(lim.r_eff, np.inf)
        is_blend_arc = ins(np.zeros(n, bool), True)
        bprev = ins(blend_prev, False)
        in_prev_tan = ins(np.concatenate([[False], j.kind == _ARC_JOIN]), True)
    else:
        r_eff = lim.r_eff
        is_blend_arc = np.zeros(n, bool)
        in_prev_tan = np.zeros(n, bool)
        bprev = blend_prev
    if virt.size:
        # where the original rows are now (after the blend arcs)
        pos = virt + np.searchsorted(corners, virt, "left")
        table, rows = _split_lines(
            table,
            pos,
            j.trim[virt],
            seg["kind"][virt] == LINE,
            j.radius[virt],
            [circles.get(k) for k in virt.tolist()],
        )
        # the blend is asked the faster of its two moves' speeds, as a blend arc is
        table["feed"][rows] = np.maximum(seg["feed"][virt], seg["feed"][virt + 1])
        at = pos + 1
        vmax = np.minimum(j.arc_vel[virt], table["length"][rows] / period)

        def ins_v(x: np.ndarray, values: np.ndarray | float | bool) -> np.ndarray:
            return np.insert(x, at, values)

        seg_term = ins_v(seg_term, TANGENT)
        acc_all = ins_v(acc_all, j.arc_acc[virt])
        maxvel = ins_v(maxvel, vmax)
        reqvel = ins_v(reqvel, j.arc_req[virt])
        kink_vel = ins_v(kink_vel, -1.0)
        moving = ins_v(moving, True)
        r_eff = ins_v(r_eff, np.inf)
        is_blend_arc = ins_v(is_blend_arc, True)
        bprev = ins_v(bprev, False)
        in_prev_tan = ins_v(in_prev_tan, True)
        nxt = rows + 1
        in_prev_tan[nxt[nxt < in_prev_tan.size]] = True
    inserted = is_blend_arc  # the rows a blend made, before empty lines go
    # a line both blends shortened to nothing is gone
    if kept is not None:
        keep = kept
    else:
        keep = ~((table["kind"] == LINE) & (table["length"] <= _GONE))
        if not keep.all():
            table = _kept_rows(table, keep)
    if not keep.all():
        seg_term, acc_all = seg_term[keep], acc_all[keep]
        maxvel, reqvel = maxvel[keep], reqvel[keep]
        kink_vel, moving, r_eff = kink_vel[keep], moving[keep], r_eff[keep]
        is_blend_arc, in_prev_tan, bprev = is_blend_arc[keep], in_prev_tan[keep], bprev[keep]
    kinds = table["kind"]
    length = table["length"]
    nn = len(table)
    k0, k1 = 0, nn  # the rows kept (a window with rows before or after them: kernel.stream)
    if carry is not None:
        origin = np.cumsum(~inserted) - 1  # the row of ``seg`` each comes from (a blend: before)
        origin = origin if keep.all() else origin[keep]
        k0 = int(np.searchsorted(origin, carry.skip))
        if carry.own is not None:
            k1 = max(int(np.searchsorted(origin, carry.own)), k0)
            carry.reach = int(np.searchsorted(origin, n - 1)) - k1 if carry.own else -1
    prev_tan = np.concatenate([[False], seg_term[:-1] == TANGENT]) | in_prev_tan
    # short-segment caps at finalisation and in the optimiser
    capped = np.minimum(maxvel, length / period)
    capped = np.where(prev_tan, np.minimum(capped, length / (period * MIN_SEGMENT_CYCLES)), capped)
    # blendmath.c blendCheckConsume: what is left of a line before a blend arc, if shorter
    # than GAP_CYCLES periods at the arc's speed, becomes part of the arc (its speed)
    arc_next = np.concatenate([is_blend_arc[1:], [False]])
    v_next = np.concatenate([maxvel[1:], [0.0]])
    consumed = (kinds == LINE) & arc_next & ~bprev & (length < GAP_CYCLES * period * v_next)
    maxvel = np.where(consumed, np.minimum(maxvel, v_next), capped)
    # tp.c tpCreateLineLineBlend: the consumed line is popped and its length run as part of
    # the blend arc, at the arc's requested speed (the faster of the two moves it joins)
    if consumed.any():
        reqvel = np.where(consumed, np.concatenate([reqvel[1:], [0.0]]), reqvel)
        table = table.copy() if table is seg else table
        table["feed"][consumed] = table["feed"][1:][consumed[:-1]]
    # circles: normal acceleration at the top speed, tangential share of the rest

    def target_of(rows: np.ndarray) -> np.ndarray:
        return np.minimum(reqvel[rows], maxvel[rows])

    acc_t = acc_all.copy()
    circle = (kinds == ARC) & ~is_blend_arc
    # the rows the queue runs dry after: never finalised (the program's last move, a move
    # before a task command's wait)
    dry = np.concatenate([kinds[1:] == HOLD, [carry is None or carry.last]]) & moving
    if circle.any():
        a_c = acc_all[circle]
        r = np.maximum(r_eff[circle], 1e-300)
        v = maxvel[circle]
        a_n_vmax = v * v / r
        cut = ACC_RATIO_NORMAL * a_c
        over = a_n_vmax > cut
        ratio = np.where(over, ACC_RATIO_TAN, np.sqrt(np.clip(1 - (a_n_vmax / a_c) ** 2, 0, 1)))
        # tc.c tcFinalizeLength: a segment is finalised (its split computed) only when the
        # next one is queued; a circle the queue runs dry after (the program's last move, a
        # move before a task command's wait) keeps its top speed and the initial 1/2 split
        unfinal = dry[circle]
        ratio = np.where(unfinal, ACC_RATIO_TAN, ratio)
        over &= ~unfinal
        maxvel[circle] = np.where(over, np.sqrt(cut * r), v)
        acc_t[circle] = a_c * ratio
        if machine.controller.axis_limits == "strict":
            acc_t[circle] = np.minimum(
                acc_t[circle], _helix_tangential_cap(table[circle], machine, target_of(circle))
            )
    acc_t = np.where(is_blend_arc, acc_all * ACC_RATIO_TAN, acc_t)
    acc_t = np.where(consumed, np.concatenate([acc_t[1:], [0.0]]), acc_t)
    target = np.minimum(reqvel, maxvel)
    # junction speeds
    jcap = np.zeros(nn + 1)
    par_at = np.zeros(0, dtype=np.intp)
    blend_vel = np.zeros(nn)  # parabolic blends: the speed below which the next move starts
    if nn > 1:
        tan = (seg_term[:-1] == TANGENT) & moving[:-1] & moving[1:]
        cap_t = np.minimum(target[:-1], target[1:])
        kv = kink_vel[:-1]
        cap_t = np.where(kv >= 0, np.minimum(cap_t, kv), cap_t)
        par = (seg_term[:-1] == PARABOLIC) & moving[:-1] & moving[1:]
        par_at = np.flatnonzero(par)
        par_at = par_at[par_at >= k0] if k0 else par_at
        if par_at.size:
            p, q = par_at, par_at + 1
            u1 = _circle_tangent(table, p, circle[p], at_end=True)
            u2 = _circle_tangent(table, q, circle[q], at_end=False)
            cos_half = np.cos(
                _accel_half_angle(
                    u1,
                    u2,
                    circle[q],
                    table["centre"][q] - table["start"][q, :3],
                    table["radius"][q],
                    acc_all[q] * 0.5,
                    reqvel[q],
                )
            )
            src_t = np.clip(
                table["source"][p] - prepared.first, 0, max(len(prepared.tolerance) - 1, 0)
            )
            b1, b2 = _blend_velocity(
                acc_t[p],
                acc_t[q],
                length[p],
                length[q],
                target[p],
                target[q],
                cos_half,
                prepared.tolerance[src_t],
                dry[q],
            )
            blend_vel[par_at] = b1
        # a parabolic blend: each move runs to a stop, the next starts during the end of
        # its deceleration (below)
        jcap[1:-1] = np.where(tan, cap_t, 0.0)
    acc_plan = np.where(moving, acc_t, 0.0)
    # tp.c tpRunOptimization: the move before an unfinalised one may end no faster than
    # the peak of a triangle over it (tpCalculateOptimizationInitialVel, findVPeak)
    last_in = np.flatnonzero(dry[1:]) + 1
    jcap[last_in] = np.minimum(jcap[last_in], np.sqrt(acc_plan[last_in] * length[last_in]))
    window = None if nn <= OPT_DEPTH else OPT_DEPTH
    if carry is None:
        v = lookahead(length, jcap, acc_plan, None, window, n - 1 >= COMPILED_JOINS)
    else:
        v = np.zeros(nn + 1)
        v[k0:], g_run, m_run = resumed_lookahead(
            length[k0:], jcap[k0:], acc_plan[k0:], OPT_DEPTH, carry.g, carry.m
        )
        carry.g, carry.m = float(g_run[k1 - k0]), float(m_run[k1 - k0])
    # ramped short tangent segments: straight from the start speed to the end speed
    cap = target.copy()
    with np.errstate(divide="ignore", invalid="ignore"):
        t_est = 2.0 * length / (v[:-1] + np.minimum(v[1:], target))
    ramp = (
        (seg_term == TANGENT)
        & (table["category"] != RAPID)
        & moving
        & (t_est < 1.0 / RAMP_FREQ)
        & (kinds == LINE)
    )
    cap = np.where(ramp, np.maximum(v[:-1], v[1:]), cap)
    cap = np.where(moving, cap, 0.0)
    prof = trapezoids(length, v[:-1], v[1:], np.where(moving, cap, 0.0), acc_plan)
    limits = (
        np.array(machine.limit_vector("velocity"), dtype=float),
        np.array(machine.limit_vector("acceleration"), dtype=float),
    )
    strict = machine.controller.axis_limits == "strict"
    overlap = _blend_overlap(prof, par_at, blend_vel, table, limits, strict)
    duration = np.where(moving, prof.duration, table["duration"]) - overlap
    # the planner runs once per servo period: every stop costs about STOP_CYCLES periods
    # more than the continuous profile, and a program START_CYCLES (tp.c
    # tcUpdateDistFromAccel's half-period undershoot, the split cycle at a segment's end)
    pause = np.where(moving & (v[1:] <= 0.0) & (overlap <= 0.0), STOP_CYCLES * period, 0.0)
    last = np.flatnonzero(moving)
    if last.size and (carry is None or carry.last):
        pause[last[-1]] += START_CYCLES * period
    duration = duration + pause
    if carry is None:
        t_start = np.concatenate([[0.0], np.cumsum(duration)[:-1]]) if nn else np.zeros(0)
        s = np.concatenate([[0.0], np.cumsum(length)])
    else:  # the kept rows, with the running sums from the program's start in the same order
        if (k0, k1) != (0, nn):
            table, v, cap, pause = table[k0:k1], v[k0 : k1 + 1], cap[k0:k1], pause[k0:k1]
            duration, overlap, length = duration[k0:k1], overlap[k0:k1], length[k0:k1]
            prof = Profiles(*(getattr(prof, f)[k0:k1] for f in Profiles.__slots__))
        t_all = np.cumsum(np.concatenate([[carry.t], duration]))
        s = np.cumsum(np.concatenate([[carry.s], length]))
        t_start, carry.t, carry.s = t_all[:-1], float(t_all[-1]), float(s[-1])
    out_path = Path(table, path.file)
    return Plan(out_path, machine, v, cap, prof, pause, duration, t_start, s[:-1], 0.0, overlap)


def _tangents(table: np.ndarray, rows: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """d position / ds and d2 position / ds2 (6 axes) of ``rows`` at path positions ``s``
    (one row of positions per row): on lines the unit direction and zero, on arcs as
    kernel.path.geometry computes them (XYZ, rotary zero), each arc's fields gathered once
    for all its positions."""
    out = np.repeat(table["u_start"][rows][:, None, :], s.shape[1], axis=1)
    out2 = np.zeros_like(out)
    arc = np.flatnonzero(table["kind"][rows] == ARC)
    if arc.size:
        g = table[rows[arc]]
        length = g["length"][:, None]
        lam = np.clip(s[arc] / np.maximum(length, _TINY), 0.0, 1.0)
        sweep = g["sweep"][:, None]
        dr = (g["radius_end"] - g["radius"])[:, None]
        psi = sweep * lam
        c, sn = np.cos(psi)[..., None], np.sin(psi)[..., None]
        e1, e2, n = g["e1"][:, None, :], g["e2"][:, None, :], g["normal"][:, None, :]
        w = c * e1 + sn * e2
        wp = -sn * e1 + c * e2
        rho = g["radius"][:, None] + dr * lam
        ax = g["axial"][:, None, None]
        d1 = (dr[..., None] * w + (rho * sweep)[..., None] * wp + ax * n) / length[..., None]
        d2 = (2 * (dr * sweep)[..., None] * wp - (rho * sweep**2)[..., None] * w) / (length**2)[
            ..., None
        ]
        out[arc, :, :3] = d1
        out[arc, :, 3:] = 0.0
        out2[arc, :, :3] = d2
    return out, out2


def _overlap_ratio(
    table: np.ndarray,
    p: np.ndarray,
    move: tuple[np.ndarray, ...],
    limits: tuple[np.ndarray, np.ndarray],
    tau: np.ndarray,
) -> np.ndarray:
    """The axis speeds and accelerations over their limits (``limits``: speeds,
    accelerations) at times ``tau`` (a row of times per row, from the start of the overlap)
    while move ``p`` (from ``v_on`` down to a stop at ``a_p``) and ``p + 1`` (from rest at
    ``a_q`` up to ``vq``; ``move = (v_on, a_p, a_q, vq)``) run together: the largest over
    the axes where ``p`` adds to the speed ``p + 1`` has alone, or where the two add to more
    acceleration than either has alone (each alone keeps its own limits: only the overlap's
    sum is the blend's to cap)."""
    v_on, a_p, a_q, vq = (x[:, None] for x in move)
    v1 = np.maximum(v_on - a_p * tau, 0.0)
    left = v1 * v1 / (2.0 * a_p)  # what p has still to go
    t_up = vq / a_q
    v2 = np.minimum(a_q * tau, vq)
    ramp = 0.5 * a_q * tau * tau
    gone = np.where(tau < t_up, ramp, 0.5 * vq * t_up + vq * (tau - t_up))
    u1, k1 = _tangents(table, p, table["length"][p][:, None] - left)
    u2, k2 = _tangents(table, p + 1, gone)
    alone = u2 * v2[..., None]
    w = np.abs(u1 * v1[..., None] + alone)
    w = np.where(w > np.abs(alone), w, 0.0)
    # the accelerations: along the path (p slowing while it moves, p + 1 speeding up to vq)
    # and toward the centre on arcs; the sum counts where it is more than either alone
    # (at the overlap's end and where p + 1 reaches vq a sample may still see the piece
    # before: both accelerations count there)
    acc1 = u1 * (-a_p)[..., None] + k1 * (v1 * v1)[..., None]
    acc2 = u2 * np.where(tau <= t_up, a_q, 0.0)[..., None] + k2 * (v2 * v2)[..., None]
    total = np.abs(acc1 + acc2)
    total = np.where(total > np.maximum(np.abs(acc1), np.abs(acc2)), total, 0.0)
    vmax, amax = limits
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(vmax > 0, w / np.where(vmax > 0, vmax, 1.0), 0.0)
        ratio_a = np.where(amax > 0, total / np.where(amax > 0, amax, 1.0), 0.0)
    return np.maximum(ratio.max(axis=2), ratio_a.max(axis=2))


_GRID = 32  # overlap grid intervals (at least)
_GRID_ANGLE = 0.05  # rad: the most an arc turns between two grid nodes
_NEAR = 1e-2  # grid maxima this close to the limit are refined
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
_GOLDEN_STEPS = 48  # brackets shrink to 0.618^48 ~ 1e-10 of two grid intervals


def _axis_speed_ratio(
    table: np.ndarray,
    p: np.ndarray,
    v_on: np.ndarray,
    a_p: np.ndarray,
    a_q: np.ndarray,
    vq: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """The largest axis speed or acceleration over its limit that the overlap of moves ``p``
    and ``p + 1`` makes (:func:`_overlap_ratio`; ``limits``: speeds, accelerations): on a
    grid over the overlap, fine enough that an arc turns at most ``_GRID_ANGLE`` between
    two nodes, with the time ``p + 1`` reaches ``vq`` as a node (between two lines the
    peaks are at the nodes); every grid maximum near the limit is refined by golden-section
    search between its neighbours (on arcs the peak lies between nodes, and a grid alone
    missed it by 2e-5 of the limit)."""
    t_end = v_on / a_p
    t_up = vq / a_q
    went = np.where(t_end < t_up, 0.5 * a_q * t_end * t_end, 0.5 * vq * t_up + vq * (t_end - t_up))
    # how far the arcs turn over the overlap: p over what it has left, p + 1 over what it goes
    turn = np.zeros(p.size)
    curved = np.zeros(p.size, dtype=bool)
    for rows, dist in ((p, 0.5 * v_on * t_end), (p + 1, went)):
        arc = table["kind"][rows] == ARC
        if arc.any():
            r = np.minimum(table["radius"][rows], table["radius_end"][rows])
            turn = np.where(arc, turn + dist / np.maximum(r, _TINY), turn)
            curved |= arc
    # between two lines the speeds are linear between the start, t_up and the end: those
    # nodes hold the peak exactly
    steps = np.maximum(np.ceil(turn / _GRID_ANGLE), np.where(curved, _GRID, 2))
    steps = np.minimum(2.0 ** np.ceil(np.log2(steps)), 1 << 14).astype(np.int64)
    out = np.zeros(p.size)
    for m in np.unique(steps).tolist():
        rows = np.flatnonzero(steps == m)
        move = (v_on[rows], a_p[rows], a_q[rows], vq[rows])
        te = t_end[rows][:, None]
        nodes = te * np.linspace(0.0, 1.0, m + 1)[None, :]
        tau = np.sort(np.concatenate([nodes, np.minimum(t_up[rows][:, None], te)], axis=1))
        ratio = _overlap_ratio(table, p[rows], move, limits, tau)
        out[rows] = ratio.max(axis=1)
        # the grid's local maxima near the limit: search between their neighbours
        pad = np.pad(ratio, ((0, 0), (1, 1)), constant_values=-1.0)
        peak = (ratio >= pad[:, :-2]) & (ratio >= pad[:, 2:]) & (ratio > 1.0 - _NEAR)
        ri, ci = np.nonzero(peak)
        if not ri.size:
            continue
        lo = tau[ri, np.maximum(ci - 1, 0)]
        hi = tau[ri, np.minimum(ci + 1, tau.shape[1] - 1)]
        g = rows[ri]
        one = (v_on[g], a_p[g], a_q[g], vq[g])

        def at(x: np.ndarray, g: np.ndarray = g, one: tuple[np.ndarray, ...] = one) -> np.ndarray:
            return _overlap_ratio(table, p[g], one, limits, x[:, None])[:, 0]

        x1, x2 = hi - _GOLDEN * (hi - lo), lo + _GOLDEN * (hi - lo)
        f1, f2 = at(x1), at(x2)
        best = np.maximum(f1, f2)
        for _ in range(_GOLDEN_STEPS):
            left = f1 >= f2  # the maximum lies in [lo, x2]
            hi = np.where(left, x2, hi)
            lo = np.where(left, lo, x1)
            x1, x2 = (
                np.where(left, hi - _GOLDEN * (hi - lo), x2),
                np.where(left, x1, lo + _GOLDEN * (hi - lo)),
            )
            f = at(np.where(left, x1, x2))
            f1, f2 = np.where(left, f, f2), np.where(left, f1, f)
            best = np.maximum(best, f)
        np.maximum.at(out, g, best)
    return out


def _blend_overlap(
    prof: Profiles,
    par_at: np.ndarray,
    blend_vel: np.ndarray,
    table: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray],
    strict: bool,
) -> np.ndarray:
    """How long each move that ends in a parabolic blend runs on into the next one's slot
    (tc.c ``tcIsBlending``, tp.c ``tpUpdateBlend``, ``tpDoParabolicBlending``): once the move
    is on its final deceleration (to a stop) and slower than its blend speed, the next move
    starts and runs at the same time; their axis motions add. The overlap is the rest of the
    deceleration, from the blend speed (or the move's peak, if lower) to the stop.

    The next move accelerates at its own rate from its start (the target speed
    tpUpdateBlend gives it is used by position-synchronised moves only, tp.c
    ``tpGetRealTargetVel``), so where it speeds up faster than this one slows, an axis both
    move along in the same sense could pass its velocity limit (LinuxCNC checks nothing
    there), and on arcs their accelerations toward the centre add to the two moves' own;
    with ``strict`` (``axis_limits = "strict"``) the model then starts that blend at the
    lower speed that keeps every axis within its speed and acceleration limits, else it
    blends as LinuxCNC does. A move is shared with at most one neighbour at a time
    (the next move blends on only once this one has ended)."""
    overlap = np.zeros(len(prof.v_peak))
    if not par_at.size:
        return overlap
    p, q = par_at, par_at + 1
    a_p = np.maximum(prof.decel[p], _TINY)
    a_q = np.maximum(prof.accel[q], _TINY)
    v_on = np.minimum(blend_vel[p], prof.v_peak[p])
    # the axis speeds u1 v1 + u2 v2 over the overlap, checked on a grid; where one passes
    # its limit the blend starts at a lower speed (bisection)
    vq = prof.v_peak[q]
    over = np.zeros(p.size, dtype=bool)
    if strict:
        over = _axis_speed_ratio(table, p, v_on, a_p, a_q, vq, limits) > 1.0 + 1e-9
    if over.any():
        k = np.flatnonzero(over)
        lo, hi = np.zeros(k.size), v_on[k].copy()
        for _ in range(12):
            mid = 0.5 * (lo + hi)
            bad = _axis_speed_ratio(table, p[k], mid, a_p[k], a_q[k], vq[k], limits) > 1.0 + 1e-9
            hi = np.where(bad, mid, hi)
            lo = np.where(bad, lo, mid)
        v_on[k] = lo
    overlap[p] = np.minimum(v_on / a_p, prof.t_dec[p])
    own = prof.duration
    tight = p[overlap[p] + overlap[q] > own[q]]
    for row in tight.tolist():  # rare: a short move between two blends
        overlap[row] = min(overlap[row], own[row + 1])
        overlap[row + 1] = min(overlap[row + 1], max(own[row + 1] - overlap[row], 0.0))
    return overlap
