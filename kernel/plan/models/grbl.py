"""Grbl 1.1's planner as a planner strategy (``[controller] model = "grbl"``).

Re-derived from the behaviour of Grbl 1.1h (github.com/gnea/grbl, GPL-3.0; read, not
copied) and checked against grbl-sim built from it (tests/data/grbl_sim):

* **Arcs as lines** (motion_control.c ``mc_arc``): an arc of radius ``r`` and sweep ``phi``
  becomes ``floor(|phi r / 2| / sqrt(tol (2 r - tol)))`` equal chords (``$12`` arc
  tolerance, ``[controller] arc_tolerance``), a helix' axial travel shared evenly; fewer
  than one chord is one line.
* **Steps** (planner.c ``plan_buffer_line``): each block's target is rounded to whole steps
  of each axis (``[axes.*] steps_per_mm``, ``$100..$102``; 0: no grid), and its length and
  direction come from the step counts, so the chords of a small arc meet at corners a little
  sharper than the arc's.
* **Block limits** (planner.c ``plan_buffer_line``, ``limit_value_by_axis_maximum``): a
  block's acceleration and rapid rate are the largest whose every axis share stays within
  its ``$12x`` / ``$11x`` limit; its nominal speed is the feed, never above the rapid rate.
* **Junction deviation** (planner.c ``plan_buffer_line``): the junction speed is
  ``v^2 = a_j delta sin(theta/2) / (1 - sin(theta/2))`` with ``theta`` the angle between
  the moves' directions (``cos theta = -u1.u2``), ``delta`` the junction deviation (``$11``,
  ``[controller] junction_deviation``) and ``a_j`` the acceleration along the difference of
  the two directions; a straight continuation runs through at speed, a reversal stops; never
  above either block's nominal speed.
* **Stepper timing** (stepper.c): with a step grid each step takes a few 16 MHz timer ticks
  more than planned (:func:`stepper_speed`), some 0.05-0.1 % at usual rates.
* **Forward and reverse passes** (planner.c ``planner_recalculate``) over the 16-block
  buffer (``BLOCK_BUFFER_SIZE``, one kept free): the last block in the buffer ends at rest.
* **Stops** at every buffer synchronisation (gcode.c ``protocol_buffer_synchronize``): a
  dwell, a program stop or end (the path's holds), and, made holds by :func:`synchronised`,
  a change of the spindle's state (``M3``/``M4``/``M5``), of the coolant (``M7``/``M8``/``M9``)
  and of ``S`` while the spindle turns (``spindle_sync``, ``coolant_sync``); on a
  ``kind = "laser"`` machine Grbl's laser mode (``$32=1``), where an ``S`` on a block that
  moves does not stop.
* **Restarts** (stepper.c ``st_go_idle``, ``st_wake_up``): with a step grid, each run of
  holds costs the time the steppers take to go idle and start again, a fraction of a
  millisecond fitted on grbl-sim (:func:`restart_times`), counted with the hold.
* **Late last steps** (stepper.c ``st_prep_buffer``): a block that ends at rest on a 10 ms
  segment boundary can, by Grbl's float32 rounding, leave its last step for a segment of
  20-33 ms; a pause after the block (:func:`late_stops`, kernel.plan.models.grbl_segments).
* **Inverse time arcs** (``mc_arc`` in G93): Grbl multiplies ``F`` by the chord count and
  then runs the chords at that many mm/min (:func:`synchronised`).

The program is taken as streamed by an ideal sender, so Grbl starts each cycle with its
planner full (the goldens' lockstep harness, tests/data/grbl_sim/README.md). A real sender on
a 115200-baud link makes Grbl start moving with one block in view, which slows the first
moves of a program of tiny segments.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator

import numpy as np

import kernel.ir.canon as canon
import kernel.limits as limits
from kernel.diagnostics import Location
from kernel.ir.arcsweep import arc_sweep
from kernel.machine import Machine
from kernel.path.geometry import evaluate
from kernel.path.segments import ARC, HOLD, LINE, Path
from kernel.plan.models.grbl_segments import stop_tails
from kernel.plan.planner import Plan, commanded_feed, lookahead, ratio_min, trapezoids

BLOCK_BUFFER = 16  # config.h BLOCK_BUFFER_SIZE on the AVR
_F_CPU = 16e6  # the AVR's clock, Hz: stepper timer ticks
_DT_SEGMENT = 0.01  # stepper.c: the segments' time, s (ACCELERATION_TICKS_PER_SECOND 100)
# a stop and restart cost _RESTART_SCALE * T^0.75 s, T the interrupt period next to the stop
# (fitted on grbl-sim: 0.15 ms at T = 0.1 ms to 1.4 ms at T = 2 ms)
_RESTART_SCALE = 0.151
_RESTART_POWER = 0.75
_TINY = 1e-12
_COS_STRAIGHT = 0.999999  # planner.c: straight continuation / reversal thresholds


_SPINDLE = {
    canon.StartSpindleClockwise: 1,
    canon.StartSpindleCounterclockwise: 2,
    canon.StopSpindleTurning: 0,
}
_COOLANT = {
    canon.FloodOn: (1, 1),
    canon.FloodOff: (1, 0),
    canon.MistOn: (2, 2),
    canon.MistOff: (2, 0),
}
_MOVES = (canon.StraightFeed, canon.StraightTraverse, canon.StraightProbe)
_MOTIONS = frozenset({*_MOVES, canon.ArcFeed})
# the commands synchronised() acts on besides the straight moves
_WATCHED = frozenset(
    {
        canon.ArcFeed,
        canon.SetFeedRate,
        canon.SetFeedMode,
        canon.SelectPlane,
        canon.UseLengthUnits,
        canon.SetSpindleSpeed,
        *_SPINDLE,
        *_COOLANT,
    }
)
# commands after which the tool's position in program coordinates is not known here
_REFRAME = frozenset({"SET_ORIGIN_OFFSETS", "SET_G5X_OFFSET", "SET_G92_OFFSET", "SET_XY_ROTATION"})
# ARC_FEED's (first, second, normal) axes -> x, y, z indices, per plane
_PLANE_AXES = {
    canon.Plane.XY: (0, 1, 2),
    canon.Plane.XZ: (2, 0, 1),
    canon.Plane.YZ: (1, 2, 0),
}


def _inverse_time_rate(
    arc: canon.ArcFeed,
    start: list[float],
    axes: tuple[int, int, int],
    rate: float,
    mm: float,
    tolerance: float,
) -> float | None:
    """motion_control.c ``mc_arc`` in G93: the per-minute rate (program units) Grbl runs an
    arc's chords at, or None where it keeps the inverse time (no whole chord). Grbl multiplies
    the inverse-time ``F`` by the chord count and then reads it as mm/min; the IR's ``rate``
    is the arc's length times ``F`` (the interpreter's conversion)."""
    i, j, k = axes
    d1, d2 = start[i] - arc.first_axis, start[j] - arc.second_axis
    radius = math.hypot(d1, d2)
    theta0 = math.atan2(d2, d1)
    theta1 = math.atan2(arc.second_end - arc.second_axis, arc.first_end - arc.first_axis)
    sweep = arc_sweep(theta0, theta1, arc.rotation)
    length = math.hypot(sweep * radius, arc.axis_end_point - start[k])
    count = int(arc_chords(np.array([radius * mm]), np.array([sweep]), tolerance)[0])
    if length <= _TINY or radius * mm <= 0.5 * tolerance or count < 1:
        return None
    return rate / length * count / mm


def _tool_length(cmd: canon.Command) -> float:
    """The Z tool length offset of a ``USE_TOOL_LENGTH_OFFSET`` (NIST's ``length``, or
    LinuxCNC's nine values, known by name only)."""
    if hasattr(cmd, "offset"):
        return float(canon.named_field(cmd, "offset")[2])
    return float(canon.named_field(cmd, "length"))


def _at(last: canon.Command | None, pos: list[float] | None, move: canon.Command) -> bool:
    """Whether straight ``move`` ends where the tool is (``last``: the straight move before
    it, else ``pos``; neither: not known, False)."""
    assert isinstance(move, _MOVES)
    if last is not None:
        assert isinstance(last, _MOVES)
        return last.x == move.x and last.y == move.y and last.z == move.z
    return pos is not None and pos == [move.x, move.y, move.z]


def _same_block(a: canon.Command, b: canon.Command) -> bool:
    """Whether two commands come from one source block (known lines only)."""
    return a.source is not None and b.source is not None and a.source.line == b.source.line > 0


def synchronised(
    commands: Iterable[canon.Command], arc_tolerance: float, laser: bool = False
) -> Iterator[canon.Command]:
    """The IR as Grbl runs it. A zero-second dwell (a stop) before every command at which Grbl
    empties its planner buffer: a spindle state change, a coolant change, a new ``S`` while
    the spindle turns (gcode.c steps 4, 7 and 8; repeating the state in force does not
    stop); in laser mode (``$32=1``, ``laser``) a new ``S`` on a block that moves does not
    stop, and with ``M3`` a block without axis words that switches the motion mode between
    G1/G2/G3 and G0 stops (gcode.c ``GC_PARSER_LASER_FORCE_SYNC``; the IR shows such a block
    as a move to where the tool is, as it shows a block whose axis words name the point the
    tool is at, which Grbl does not stop for). Grbl also empties its buffer where the work
    frame changes (system.c ``system_flag_wco_change``: a new G54..G59 system, G92 and
    G92.1, a new G43.1/G49 tool length offset; settings.c ``settings_write_coord_data``: G10
    L2/L20, G28.1, G30.1, which the grbl reader marks ``OFFSETS_STORED``): a stop there too,
    once the tool has moved (before the first move a stop costs nothing). An arc in inverse
    time (G93) at the rate Grbl gives its chords (``mc_arc``)."""
    spindle, coolant, speed = 0, 0, 0.0
    inverse, rate, mm = False, 0.0, 1.0
    axes = _PLANE_AXES[canon.Plane.XY]
    last: canon.Command | None = None  # the last straight move: the tool is at its end
    pos: list[float] | None = None  # else where the tool is (None: not known here)
    pending: canon.Command | None = None  # laser mode: a new S, stopping unless its block moves
    moved = False  # a move came: a stop from now on costs time
    tlo = 0.0  # the tool length offset in force (G43.1, G49)
    feeding = False  # laser mode: the motion mode is G1/G2/G3 (Grbl starts in G0)
    for cmd in commands:
        kind = type(cmd)
        # laser mode: a move to where the tool is, rs274's reading of a line with a motion
        # mode and no axis words, which Grbl does not count as motion
        still = laser and kind in _MOVES and _at(last, pos, cmd)
        if pending is not None:
            if still or not (kind in _MOTIONS and _same_block(pending, cmd)):
                yield canon.Dwell(0.0, source=pending.source)
            yield pending
            pending = None
        if kind in _MOVES:  # the common case first, and cheaply
            if laser:
                mode = kind is not canon.StraightTraverse
                if still and mode != feeding and spindle == 1:
                    yield canon.Dwell(0.0, source=cmd.source)  # GC_PARSER_LASER_FORCE_SYNC
                feeding = mode
            last, moved = cmd, True
            yield cmd
            continue
        if kind not in _WATCHED:
            name = cmd.NAME
            if name in _REFRAME:
                last, pos = None, None
                if moved and name != "SET_XY_ROTATION":
                    yield canon.Dwell(0.0, source=cmd.source)
            elif name == "OFFSETS_STORED" and moved:
                yield canon.Dwell(0.0, source=cmd.source)
            elif name == "USE_TOOL_LENGTH_OFFSET":
                new_tlo = _tool_length(cmd)
                if new_tlo != tlo and moved:
                    yield canon.Dwell(0.0, source=cmd.source)
                tlo = new_tlo
            yield cmd
            continue
        if last is not None:
            assert isinstance(last, _MOVES)
            pos = [last.x, last.y, last.z]
            last = None
        if kind is canon.ArcFeed:
            assert isinstance(cmd, canon.ArcFeed)
            moved, feeding = True, True
            grbl_rate = None
            if inverse and pos is not None:
                grbl_rate = _inverse_time_rate(cmd, pos, axes, rate, mm, arc_tolerance)
            i, j, k = axes
            pos = pos or [0.0, 0.0, 0.0]
            pos[i], pos[j], pos[k] = cmd.first_end, cmd.second_end, cmd.axis_end_point
            if grbl_rate is not None:
                yield canon.SetFeedRate(grbl_rate, source=cmd.source)
                yield cmd
                yield canon.SetFeedRate(rate, source=cmd.source)
                continue
        elif kind is canon.SetFeedRate:
            assert isinstance(cmd, canon.SetFeedRate)
            rate = cmd.rate
        elif kind is canon.SetFeedMode:
            assert isinstance(cmd, canon.SetFeedMode)
            inverse = cmd.mode is canon.FeedMode.INVERSE_TIME
        elif kind is canon.SelectPlane:
            assert isinstance(cmd, canon.SelectPlane)
            axes = _PLANE_AXES[cmd.plane]
        elif kind is canon.UseLengthUnits:
            assert isinstance(cmd, canon.UseLengthUnits)
            new = cmd.units.mm_per_unit
            pos = None if pos is None else [p * mm / new for p in pos]
            mm = new
        elif kind is canon.SetSpindleSpeed:
            assert isinstance(cmd, canon.SetSpindleSpeed)
            changed = cmd.speed != speed and spindle
            speed = cmd.speed
            if changed and laser:
                pending = cmd
                continue
            if changed:
                yield canon.Dwell(0.0, source=cmd.source)
        elif kind in _SPINDLE:
            state = _SPINDLE[kind]
            if state != spindle:
                yield canon.Dwell(0.0, source=cmd.source)
            spindle = state
        else:
            bit, on = _COOLANT[kind]
            state = (coolant & ~bit) | on
            if state != coolant:
                yield canon.Dwell(0.0, source=cmd.source)
            coolant = state
        yield cmd
    if pending is not None:
        yield canon.Dwell(0.0, source=pending.source)
        yield pending


def arc_chords(radius: np.ndarray, sweep: np.ndarray, tolerance: float) -> np.ndarray:
    """motion_control.c ``mc_arc``: how many chords an arc becomes (at least one)."""
    r = np.asarray(radius, float)
    q = tolerance * (2.0 * r - tolerance)
    den = np.sqrt(np.where(q > 0, q, 1.0))
    count = np.floor(np.abs(0.5 * np.asarray(sweep, float) * r) / den)
    return np.where(q > 0, np.maximum(count, 1), 1).astype(np.int64)


def _check_chords(path: Path, arc: np.ndarray, radius: np.ndarray, tolerance: float) -> None:
    """``LIMIT-COUNT`` at the first arc that would become more than ``kernel.limits``'
    ``arc_chords`` chords (an arc of a million turns, or of radius 1e99: each chord is a row
    of the segment table, 367 bytes)."""
    seg = path.segments
    q = tolerance * (2.0 * radius - tolerance)
    with np.errstate(all="ignore"):
        chords = np.abs(0.5 * seg["sweep"][arc] * radius) / np.sqrt(np.where(q > 0, q, 1.0))
    limit = limits.current().arc_chords
    over = ~(np.floor(chords) <= limit)  # NaN and inf are over
    if over.any():
        i = int(np.argmax(over))
        raise limits.count_error(
            "chords of one arc (Grbl's arc segments)",
            float(chords[i]),
            limit,
            "arc_chords",
            Location(path.file, int(seg["line"][arc[i]])),
        )


def segment_arcs(path: Path, tolerance: float) -> Path:
    """``path`` with every arc replaced by its Grbl chords (lines)."""
    seg = path.segments
    arc = np.flatnonzero(seg["kind"] == ARC)
    if not arc.size:
        return path
    r = np.minimum(seg["radius"][arc], seg["radius_end"][arc])
    _check_chords(path, arc, r, tolerance)
    count = arc_chords(r, seg["sweep"][arc], tolerance)
    reps = np.ones(len(seg), dtype=np.int64)
    reps[arc] = count
    out = np.repeat(seg, reps)
    first = np.concatenate([[0], np.cumsum(reps)[:-1]])
    # local chord index k within each arc, and the arc rows' positions in ``out``
    owner = np.repeat(np.arange(len(seg)), reps)
    k = np.arange(len(out)) - first[owner]
    is_arc = seg["kind"][owner] == ARC
    rows = np.flatnonzero(is_arc)
    n_of = reps[owner[rows]]
    length = seg["length"][owner[rows]]
    s0 = length * k[rows] / n_of
    s1 = length * (k[rows] + 1) / n_of
    p0, *_ = evaluate(seg, owner[rows], s0)
    p1, *_ = evaluate(seg, owner[rows], s1)
    last = k[rows] == n_of - 1
    p1[last] = seg["end"][owner[rows][last]]
    first_chord = k[rows] == 0
    p0[first_chord] = seg["start"][owner[rows][first_chord]]
    d = p1 - p0
    lin = np.linalg.norm(d[:, :3], axis=1)
    rot = np.linalg.norm(d[:, 3:], axis=1)
    ln = np.where(lin > _TINY, lin, rot)
    u = d / np.maximum(ln, _TINY)[:, None]
    sub = out[rows]
    sub["kind"] = LINE
    sub["start"], sub["end"] = p0, p1
    sub["length"] = ln
    sub["u_start"] = sub["u_end"] = u
    sub["radius"] = sub["radius_end"] = sub["sweep"] = sub["axial"] = 0.0
    out[rows] = sub
    keep = ~((out["kind"] == LINE) & (out["length"] <= 1e-12))
    return Path(out[keep], path.file)


def on_steps(path: Path, steps_per_mm: np.ndarray, copy: bool = True) -> Path:
    """``path`` (lines and holds) with every line's ends on the axes' step grids, as Grbl's
    planner takes them (planner.c ``plan_buffer_line``: the target rounded to whole steps,
    the block's length and direction from the step counts; a block of no step is dropped).
    Axes with no step size (0) are left as they are; ``copy=False`` rounds ``path``'s own
    rows (a table made for it)."""
    if not np.any(steps_per_mm > 0):
        return path
    seg = path.segments.copy() if copy else path.segments
    grid = np.flatnonzero(steps_per_mm > 0)
    scale = steps_per_mm[grid]
    start, end = seg["start"], seg["end"]  # views: rounded in place (a hold stays put)
    start[:, grid] = np.round(start[:, grid] * scale) / scale
    end[:, grid] = np.round(end[:, grid] * scale) / scale
    line = seg["kind"] == LINE
    d = end - start
    lin = np.linalg.norm(d[:, :3], axis=1)
    rot = np.linalg.norm(d[:, 3:], axis=1)
    ln = np.where(lin > _TINY, lin, rot)
    seg["length"] = np.where(line, ln, seg["length"])
    u = d / np.maximum(ln, _TINY)[:, None]
    seg["u_start"][line] = u[line]
    seg["u_end"][line] = u[line]
    empty = line & (ln <= 1e-12)
    return Path(seg[~empty] if empty.any() else seg, path.file)


def blocks(
    path: Path, machine: Machine, before: np.ndarray | None = None, after: np.ndarray | None = None
) -> Path:
    """The blocks Grbl's planner receives for ``path``: its stops' restart time added
    (:func:`restart_times`; ``before``, ``after``: the rows next to ``path``, where there),
    arcs as chords (``$12``), ends on the step grids (``steps_per_mm``, ``$100..$102``)."""
    steps = np.array(machine.limit_vector("steps_per_mm"))
    if np.any(steps > 0) and np.any(path.segments["kind"] == HOLD):
        seg = path.segments.copy()
        seg["duration"] += restart_times(seg, machine, before, after)
        path = Path(seg, path.file)
    chords = segment_arcs(path, machine.controller.arc_tolerance)
    return on_steps(chords, steps, copy=chords is path)


def _isr_period(u: np.ndarray, machine: Machine) -> np.ndarray:
    """The stepper interrupt's period in the first 10 ms segment (DT_SEGMENT) of a block
    along ``u`` (rows) from rest: ``1 / (2^L r)`` at its step rate ``r`` (AMASS level L)."""
    amax = np.array(machine.limit_vector("acceleration"))
    steps = np.array(machine.limit_vector("steps_per_mm"))
    per_mm = np.max(np.abs(u) * steps, axis=1)
    rate = ratio_min(amax, u) * per_mm * (0.5 * _DT_SEGMENT)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(rate > 0, _F_CPU / rate, np.inf)
    level = np.select([c < _F_CPU / 8000, c < _F_CPU / 4000, c < _F_CPU / 2000], [0, 1, 2], 3)
    return np.where(rate > 0, 1.0 / (np.exp2(level) * np.maximum(rate, _TINY)), 0.0)


def _restart(period: np.ndarray) -> np.ndarray:
    """Seconds a stop and restart cost next to moves of interrupt period ``period`` (s)."""
    return _RESTART_SCALE * np.power(period, _RESTART_POWER)


def restart_times(
    seg: np.ndarray, machine: Machine, before: np.ndarray | None, after: np.ndarray | None
) -> np.ndarray:
    """Seconds each hold of ``seg`` adds where Grbl's steppers go idle and wake up again
    (a dwell, a program stop, a sync point): the interrupt's phase at wake-up and its first
    call, which steps nothing, cost of the order of the interrupt period ``T`` of the slow
    segments next to the stop; measured on grbl-sim, ``0.151 T^0.75`` s (0.15 ms a stop at
    1000 mm/s^2, 1.4 ms at 50 mm/s^2, 250 steps/mm). Half comes from the move before a run
    of holds (on its first hold), half from the move after it (on its last)."""
    n = len(seg)
    out = np.zeros(n)
    kind = seg["kind"]
    h = np.flatnonzero(kind == HOLD)
    if not h.size:
        return out
    for side, edge, key in ((-1, before, "u_end"), (1, after, "u_start")):
        j = h + side  # the neighbour on this side, where inside ``seg``
        inside = (j >= 0) & (j < n)
        jj = np.clip(j, 0, n - 1)
        moving = np.where(inside, kind[jj] != HOLD, edge is not None and edge["kind"] != HOLD)
        if not moving.any():
            continue
        u = seg[key][jj]
        if edge is not None:
            u[~inside] = edge[key]
        out[h[moving]] += 0.5 * _restart(_isr_period(u[moving], machine))
    return out


def junction_speed(
    u1: np.ndarray, u2: np.ndarray, accel: np.ndarray, deviation: float
) -> np.ndarray:
    """planner.c: the junction-deviation speed between directions ``u1`` and ``u2`` (rows)."""
    cos = -np.sum(u1 * u2, axis=1)
    diff = u2 - u1
    norm = np.linalg.norm(diff, axis=1)
    unit = diff / np.maximum(norm, _TINY)[:, None]
    a_j = ratio_min(accel, unit)
    sin_half = np.sqrt(np.clip(0.5 * (1.0 - cos), 0.0, 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        v2 = a_j * deviation * sin_half / np.maximum(1.0 - sin_half, _TINY)
    v = np.sqrt(np.maximum(v2, 0.0))
    v = np.where(cos > _COS_STRAIGHT, 0.0, v)
    return np.where(cos < -_COS_STRAIGHT, np.inf, v)


def block_limits(path: Path, machine: Machine) -> tuple[np.ndarray, np.ndarray]:
    """planner.c ``plan_buffer_line``: every block's nominal speed (0 for holds) and
    acceleration, each from its own row (the path already in chords)."""
    seg = path.segments
    vmax = np.array(machine.limit_vector("velocity"))
    amax = np.array(machine.limit_vector("acceleration"))
    moving = seg["kind"] != HOLD
    u = seg["u_start"]
    rapid_rate = ratio_min(vmax, u)
    acc = ratio_min(amax, u)
    feed = commanded_feed(path, machine.controller)
    nominal = np.minimum(feed, rapid_rate)
    steps = np.array(machine.limit_vector("steps_per_mm"))
    if np.any(steps > 0):
        nominal = stepper_speed(nominal, u, steps)
    return np.where(moving, nominal, 0.0), acc


def stepper_speed(speed: np.ndarray, u: np.ndarray, steps_per_mm: np.ndarray) -> np.ndarray:
    """The speed Grbl's stepper interrupt really runs at when asked for ``speed`` along ``u``
    (rows): stepper.c times each step event as ``ceil(c)`` timer ticks at 16 MHz, ``c`` the
    exact count, and the interrupt at ``2^L`` times the step rate (AMASS level ``L``: 0 above
    8 kHz, 1 above 4 kHz, 2 above 2 kHz, else 3) in CTC mode, a period of the compare value
    plus one tick: each step takes ``1 + 2^(L - 1)`` ticks more than ``c`` on average."""
    per_mm = np.max(np.abs(u) * steps_per_mm, axis=1)  # step events per mm of the block
    rate = speed * per_mm
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(rate > 0, _F_CPU / rate, np.inf)
    level = np.select([c < _F_CPU / 8000, c < _F_CPU / 4000, c < _F_CPU / 2000], [0, 1, 2], 3)
    extra = 1.0 + np.exp2(level - 1.0)
    return np.where(rate > 0, speed / (1.0 + extra / c), speed)


def junction_caps(seg: np.ndarray, nominal: np.ndarray, machine: Machine) -> np.ndarray:
    """The speed allowed at each junction between consecutive rows of ``seg`` (n - 1):
    junction deviation, never above either block's nominal speed, 0 next to a hold."""
    amax = np.array(machine.limit_vector("acceleration"))
    moving = seg["kind"] != HOLD
    v_j = junction_speed(
        seg["u_end"][:-1], seg["u_start"][1:], amax, machine.controller.junction_deviation
    )
    inner = np.minimum.reduce([v_j, nominal[:-1], nominal[1:]])
    ok = moving[:-1] & moving[1:]
    return np.where(ok, inner, 0.0)


def plan(path: Path, machine: Machine) -> Plan:
    """Plan ``path`` as Grbl 1.1 does (its arcs become chords first)."""
    path = blocks(path, machine)
    seg = path.segments
    n = len(seg)
    moving = seg["kind"] != HOLD
    nominal, acc = block_limits(path, machine)
    jcap = np.zeros(n + 1)
    if n > 1:
        jcap[1:-1] = junction_caps(seg, nominal, machine)
    acc_plan = np.where(moving, acc, 0.0)
    window = None if n <= BLOCK_BUFFER - 1 else BLOCK_BUFFER - 1
    length = seg["length"]
    v = lookahead(length, jcap, acc_plan, None, window)
    prof = trapezoids(length, v[:-1], v[1:], nominal, acc_plan)
    pause = late_stops(seg, v, nominal, machine)
    duration = np.where(moving, prof.duration, seg["duration"]) + pause
    t_start = np.concatenate([[0.0], np.cumsum(duration)[:-1]]) if n else np.zeros(0)
    s = np.concatenate([[0.0], np.cumsum(length)])
    return Plan(path, machine, v, nominal, prof, pause, duration, t_start, s[:-1], 0.0)


def late_stops(
    seg: np.ndarray,
    v: np.ndarray,
    nominal: np.ndarray,
    machine: Machine,
    after: np.ndarray | None = None,
) -> np.ndarray:
    """Seconds Grbl's last step comes late at the end of each block of ``seg`` (rows on
    the step grids, ``v`` the junction speeds, ``nominal`` the blocks' speeds as
    :func:`block_limits` gives them; ``after``: the row after ``seg``, None at the program's
    end) that
    ends at rest: float32 rounding in its 10 ms segments (stepper.c ``st_prep_buffer``,
    kernel.plan.models.grbl_segments), and before a hold (the steppers go idle) the longer
    interrupt period too; a pause after the block. Zero without step grids on X, Y, Z."""
    out = np.zeros(len(seg))
    steps = np.array(machine.limit_vector("steps_per_mm"))[:3]
    if not len(seg) or not np.all(steps > 0):
        return out
    k = np.flatnonzero((seg["kind"] != HOLD) & (v[1:] <= 0.0))
    if k.size:
        rows = seg[k]
        dsteps = np.rint((rows["end"][:, :3] - rows["start"][:, :3]) * steps)
        feed = commanded_feed(Path(rows), machine.controller)
        cruise = v[k] >= nominal[k] * (1.0 - 1e-12)
        late, idle = stop_tails(dsteps, feed, v[k], cruise, machine)
        nxt = np.append(seg["kind"][1:], LINE if after is None else after["kind"])[k]
        out[k] = late + np.where(nxt == HOLD, idle, 0.0)
    return out


__all__ = [
    "BLOCK_BUFFER",
    "arc_chords",
    "block_limits",
    "blocks",
    "junction_caps",
    "junction_speed",
    "late_stops",
    "on_steps",
    "plan",
    "restart_times",
    "segment_arcs",
    "stepper_speed",
    "synchronised",
]
