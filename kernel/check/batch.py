"""The rules of ``cnc check`` judged over a run of moves at once (numpy).

A CAM program is mostly consecutive STRAIGHT_FEED, STRAIGHT_TRAVERSE and ARC_FEED commands
with a SET_FEED_RATE now and then, and between two other commands only the position and the
feed rate change: units, offsets, tool, spindle, plane and the rest of
:class:`~kernel.check.state.CheckState` stay the same. :class:`Judge` says, for one rule and
such a run (:class:`StraightRun`, which holds each row's start and end point and the feed
rate it is judged in), which of its commands the rule finds fault with, without calling the
rule once per command:

* *state* rules depend only on the state (the feed rate aside) and the command's type (and
  an arc's turning direction: G2 and G3 are different codes): asked once for the first
  command of each type, and the answer holds for the others;
* *cutting* rules find fault only with a move that cuts (:func:`~kernel.check.rules.is_cutting`)
  and otherwise depend only on the state: asked once, for the first cutting move;
* the rules that judge the position or the feed rate (travel limits, missing axes, feed
  against the axis velocities, zero feed, rapids against the stock and the safe height) are
  computed from the arrays of the run's points and feed rates (and the arcs' centres and
  turns), with the same floating-point operations, in the same order, as the per-command
  rule. Where an arc's verdict needs the rule's own trigonometry (the quadrant points of a
  travel limit, the radii of an arc tolerance), the arrays only screen: an arc whose answer
  is certain either way with a wide margin is decided from them, the few near the limit
  are asked.

A rule not listed here, or a run its arrays cannot judge exactly (a non-finite coordinate),
is asked command by command, as :func:`kernel.check.check_stream` does without runs: the
findings are the same either way (tests/test_check_batch.py compares both on every program
of the check tests and the goldens).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Protocol, TypeVar

import numpy as np
import numpy.typing as npt

import kernel.ir.canon as canon
from kernel.check.config import ARC_TOLERANCES
from kernel.check.rules import EPS, FEEDS, CheckContext, Rule
from kernel.check.state import PLANE_AXES, CheckState, Vec6
from kernel.diagnostics import Location
from kernel.machine import AXIS_NAMES, Machine

Bools = npt.NDArray[np.bool_]
Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]


T_co = TypeVar("T_co", covariant=True)


class Indexed(Protocol[T_co]):
    """What a run needs of its commands and locations: a list, or built when asked for."""

    def __len__(self) -> int: ...

    def __getitem__(self, i: int, /) -> T_co: ...


@dataclass
class StraightRun:
    """Consecutive moves (straight moves and arcs) and SET_FEED_RATEs with the state before
    the first: their commands, source locations, start and end points (program coordinates,
    ``n x 6``; a SET_FEED_RATE's end is its start), which rows are straight feeds,
    traverses, arcs and feed rates, the feed state each row is judged in (``rate``,
    ``rate_set``: the state's ``feed`` and ``feed_set`` before it) and the one after the
    run (``after``), and each arc's centre (first and second axis of the plane) and signed
    turns (0 on other rows)."""

    commands: Indexed[canon.Command]
    locations: Indexed[Location]
    start: Floats
    end: Floats
    feed: Bools
    arc: Bools
    traverse: Bools
    setfeed: Bools
    rate: Floats
    rate_set: Bools
    after: tuple[float, bool]
    centre: Floats
    turns: Floats

    @classmethod
    def of(
        cls,
        commands: list[canon.Command],
        ends: list[Vec6],
        locations: list[Location],
        st: CheckState,
    ) -> StraightRun:
        """The run of ``commands`` (their ``ends``) from the state ``st``."""
        n = len(commands)
        end = np.array(ends, dtype=np.float64).reshape(n, 6)
        start = _starts(end, st.position)
        types = [type(c) for c in commands]
        feed = np.fromiter((t is canon.StraightFeed for t in types), np.bool_, n)
        arc = np.fromiter((t is canon.ArcFeed for t in types), np.bool_, n)
        setfeed = np.fromiter((t is canon.SetFeedRate for t in types), np.bool_, n)
        traverse = np.fromiter((t is canon.StraightTraverse for t in types), np.bool_, n)
        centre = np.zeros((n, 2))
        turns = np.zeros(n)
        for i in np.flatnonzero(arc).tolist():
            a = commands[i]
            assert isinstance(a, canon.ArcFeed)
            centre[i] = (a.first_axis, a.second_axis)
            turns[i] = a.rotation
        after: tuple[float, bool] = (st.feed, st.feed_set)
        new = np.zeros(n)
        sets = np.flatnonzero(setfeed).tolist()
        for i in sets:
            s = commands[i]
            assert isinstance(s, canon.SetFeedRate)
            new[i] = s.rate
        if sets:
            last = commands[sets[-1]]
            assert isinstance(last, canon.SetFeedRate)
            after = (last.rate, True)
        rate, rate_set = _rates(setfeed, new, st)
        return cls(
            commands,
            locations,
            start,
            end,
            feed,
            arc,
            traverse,
            setfeed,
            rate,
            rate_set,
            after,
            centre,
            turns,
        )

    @classmethod
    def of_moves(cls, moves: Moves, a: int, b: int, st: CheckState) -> StraightRun:
        """The run of events ``a .. b`` of ``moves`` from the state ``st`` (its position,
        feed and plane: the arcs' axes)."""
        kind = moves.kind[a:b]
        n = b - a
        end = np.array(moves.position[a:b], dtype=np.float64)
        arc = kind == ARC
        centre = np.zeros((n, 2))
        turns = np.zeros(n)
        if arc.any():
            assert moves.arc is not None
            i1, i2, normal = PLANE_AXES[st.plane]
            rows = np.asarray(moves.arc[a:b], dtype=np.float64)[arc]
            end[arc, i1], end[arc, i2], end[arc, normal] = rows[:, 0], rows[:, 1], rows[:, 5]
            centre[arc] = rows[:, 2:4]
            turns[arc] = rows[:, 4]
        setfeed = kind == SET_FEED
        after: tuple[float, bool] = (st.feed, st.feed_set)
        new = moves.feed[a:b]
        if setfeed.any():
            # a SET_FEED_RATE leaves the point where the move before it did
            last = np.maximum.accumulate(np.where(setfeed, -1, np.arange(n)))
            rows = np.flatnonzero(setfeed)
            src = last[rows]
            end[rows[src >= 0]] = end[src[src >= 0]]
            end[rows[src < 0]] = st.position
            after = (float(new[np.flatnonzero(setfeed)[-1]]), True)
        rate, rate_set = _rates(setfeed, new, st)
        return cls(
            _Commands(moves, a, b),
            _Locations(moves, a, b),
            _starts(end, st.position),
            end,
            kind == FEED,
            arc,
            kind == TRAVERSE,
            setfeed,
            rate,
            rate_set,
            after,
            centre,
            turns,
        )

    def __len__(self) -> int:
        return len(self.start)

    @cached_property
    def finite(self) -> bool:
        """Whether every point of the run is finite (its arrays judge as the rules do)."""
        return bool(np.isfinite(self.start).all() and np.isfinite(self.end).all())

    def carry(self, st: CheckState) -> None:
        """Leave ``st`` as the run does: its last point and feed."""
        p = self.end[-1].tolist()
        st.position = (p[0], p[1], p[2], p[3], p[4], p[5])
        st.feed, st.feed_set = self.after


def _starts(end: Floats, position: Vec6) -> Floats:
    """Each row's start: the end of the row before, ``position`` for the first."""
    start = np.empty_like(end)
    start[0] = position
    start[1:] = end[:-1]
    return start


def _rates(setfeed: Bools, new: Floats, st: CheckState) -> tuple[Floats, Bools]:
    """The feed state each row is judged in: the rate of the last SET_FEED_RATE before it
    (``new`` at those rows), else the state's."""
    n = len(setfeed)
    if not setfeed.any():
        return np.full(n, st.feed, dtype=np.float64), np.full(n, st.feed_set, dtype=np.bool_)
    seen = np.maximum.accumulate(np.where(setfeed, np.arange(n), -1))
    before = np.empty(n, dtype=np.int64)
    before[0] = -1
    before[1:] = seen[:-1]
    rate = np.where(before >= 0, new[np.maximum(before, 0)], st.feed)
    return rate.astype(np.float64), (before >= 0) | st.feed_set


Message = Callable[[int], "str | None"]

#: the kinds of :attr:`Moves.kind`
TRAVERSE, FEED, SET_FEED, ARC = 0, 1, 2, 3


@dataclass(frozen=True)
class Moves:
    """Canonical commands of a block of plain moves as arrays, the bulk form a front end may
    hand :func:`kernel.check.check_stream` instead of command objects (the RS274/NGC fast
    lane's runs): ``kind[i]`` (:data:`TRAVERSE` STRAIGHT_TRAVERSE, :data:`FEED`
    STRAIGHT_FEED, :data:`SET_FEED` SET_FEED_RATE, :data:`ARC` ARC_FEED), ``position[i]``
    (x y z a b c after the event, program coordinates), ``feed[i]`` (the rate of a
    SET_FEED), ``line[i]`` (1-based source line in ``file``) and, for an arc, ``arc[i]``:
    first and second end, first and second centre, turns, end on the normal axis."""

    kind: npt.NDArray[np.int64]
    position: Floats
    feed: Floats
    line: npt.NDArray[np.int64]
    arc: Floats | None
    file: str | None

    def __len__(self) -> int:
        return int(self.kind.shape[0])

    def command(self, i: int) -> canon.Command:
        """Event ``i`` as its command object."""
        k = int(self.kind[i])
        src = Location(self.file, int(self.line[i]), 1)
        pos = self.position[i].tolist()
        if k == TRAVERSE:
            return canon.StraightTraverse(*pos, source=src)
        if k == FEED:
            return canon.StraightFeed(*pos, source=src)
        if k == ARC:
            assert self.arc is not None
            e1, e2, c1, c2, turns, normal = self.arc[i].tolist()
            return canon.ArcFeed(e1, e2, c1, c2, int(turns), normal, *pos[3:], source=src)
        return canon.SetFeedRate(float(self.feed[i]), source=src)


class _Commands:
    """Events ``a .. b`` of a :class:`Moves`, built when first asked for."""

    def __init__(self, moves: Moves, a: int, b: int) -> None:
        self.moves, self.a, self.b = moves, a, b
        self.built: dict[int, canon.Command] = {}

    def __len__(self) -> int:
        return self.b - self.a

    def __getitem__(self, i: int) -> canon.Command:
        cmd = self.built.get(i)
        if cmd is None:
            cmd = self.built[i] = self.moves.command(self.a + i)
        return cmd


class _Locations:
    """Source locations of events ``a .. b`` of a :class:`Moves`."""

    def __init__(self, moves: Moves, a: int, b: int) -> None:
        self.moves, self.a, self.b = moves, a, b

    def __len__(self) -> int:
        return self.b - self.a

    def __getitem__(self, i: int) -> Location:
        return Location(self.moves.file, int(self.moves.line[self.a + i]), 1)


def _ask(rule: Rule, run: StraightRun, st: CheckState, ctx: CheckContext, i: int) -> str | None:
    """The rule's own verdict on command ``i`` of the run (the state with its start point
    and feed)."""
    assert rule.check is not None
    keep = st.position, st.feed, st.feed_set
    p = run.start[i].tolist()
    st.position = (p[0], p[1], p[2], p[3], p[4], p[5])
    st.feed, st.feed_set = float(run.rate[i]), bool(run.rate_set[i])
    try:
        return rule.check(run.commands[i], st, ctx)
    finally:
        st.position, st.feed, st.feed_set = keep


def called(rule: Rule, kind: type[canon.Command]) -> bool:
    """Whether the rule is called for commands of type ``kind``."""
    return not rule.kinds or issubclass(kind, rule.kinds)


def straight_kinds(rule: Rule) -> tuple[bool, bool]:
    """Whether the rule is called for STRAIGHT_FEED and for STRAIGHT_TRAVERSE."""
    return called(rule, canon.StraightFeed), called(rule, canon.StraightTraverse)


def arc_kind(rule: Rule) -> bool:
    """Whether the rule is called for ARC_FEED."""
    return called(rule, canon.ArcFeed)


def kinds_mask(rule: Rule, run: StraightRun) -> Bools:
    """The commands of the run the rule is called for (its ``kinds``)."""
    feeds, traverses = straight_kinds(rule)
    out = run.arc.copy() if arc_kind(rule) else np.zeros(len(run), dtype=np.bool_)
    if feeds:
        out |= run.feed
    if traverses:
        out |= run.traverse
    if called(rule, canon.SetFeedRate):
        out |= run.setfeed
    return out


def cutting(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools:
    """:func:`~kernel.check.rules.is_cutting` of each straight feed of the run (False for
    the other rows)."""
    s, e = run.start, run.end
    retract = (np.abs(e[:, 0] - s[:, 0]) <= EPS) & (np.abs(e[:, 1] - s[:, 1]) <= EPS)
    retract &= e[:, 2] > s[:, 2] + EPS
    out = run.feed & ~retract  # straight feeds only: arcs are judged apart
    stock = ctx.config.stock
    if stock is None:
        return out
    k = st.mm_per_unit
    for axis in range(3):
        a, b = s[:, axis] * k, e[:, axis] * k
        hi = np.where(b > a, b, a)  # max(a, b) as Python's max
        lo = np.where(b < a, b, a)
        out &= ~((hi <= stock[0][axis] + EPS) | (lo >= stock[1][axis] - EPS))
    return out


def _machine(run_points: Floats, st: CheckState) -> Floats:
    """:meth:`CheckState.machine_point` of each row."""
    p = run_points
    k = st.mm_per_unit
    out = np.empty_like(p)
    if st.rotation:
        g92, g5x, o = st.g92_mm, st.g5x_mm, st.origin_mm
        x, y = p[:, 0] * k + g92[0], p[:, 1] * k + g92[1]
        c, s = math.cos(st.rotation), math.sin(st.rotation)
        out[:, 0] = c * x - s * y + g5x[0]
        out[:, 1] = s * x + c * y + g5x[1]
        out[:, 2] = p[:, 2] * k + g92[2] + g5x[2] + st.tlo_mm
    else:
        o = st.origin_mm
        out[:, 0] = p[:, 0] * k + o[0]
        out[:, 1] = p[:, 1] * k + o[1]
        out[:, 2] = p[:, 2] * k + o[2] + st.tlo_mm
    for i in range(3, 6):
        out[:, i] = p[:, i] + o[i]
    return out


def _beyond(a: Floats, b: Floats, ctx: CheckContext) -> Bools:
    """Rows whose machine points ``a`` or ``b`` leave an axis's travel (as CNC101 does for
    each point: ``max`` above the maximum or ``min`` below the minimum)."""
    out = np.zeros(len(a), dtype=np.bool_)
    for axis in ctx.machine.axes:
        i = AXIS_NAMES.index(axis.name)
        hi = np.where(b[:, i] > a[:, i], b[:, i], a[:, i])
        lo = np.where(b[:, i] < a[:, i], b[:, i], a[:, i])
        out |= (hi > axis.max + EPS) | (lo < axis.min - EPS)
    return out


def _soft_limit(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    return _beyond(_machine(run.start, st), _machine(run.end, st), ctx)


def _axis_missing(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    have = set(ctx.machine.axis_names)
    out = np.zeros(len(run), dtype=np.bool_)
    for i, name in enumerate(AXIS_NAMES):
        if name not in have:
            out |= np.abs(run.end[:, i] - run.start[:, i]) > EPS
    return out


def _fixed_caps(ctx: CheckContext) -> list[float]:
    """CNC103's caps (mm/min) that do not depend on the move, in the rule's order."""
    fixed = []
    if ctx.config.max_feed is not None:
        fixed.append(ctx.config.max_feed)
    if ctx.machine.controller.max_feed > 0:
        fixed.append(ctx.machine.controller.max_feed * 60.0)
    return fixed


def _feed_too_fast(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    if st.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or st.synch:
        return np.zeros(len(run), dtype=np.bool_)
    f = run.rate * st.mm_per_unit
    over = np.zeros(len(run), dtype=np.bool_)
    for fixed in _fixed_caps(ctx):
        over |= f > fixed * (1 + 1e-9)
    vel = _velocity(ctx.machine)
    k = st.mm_per_unit
    with np.errstate(over="ignore", invalid="ignore"):
        d = (run.end[:, :3] - run.start[:, :3]) * k
        length = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])
    if np.isnan(length[run.feed & ~over]).any():
        return None
    cap = np.full(len(run), np.inf)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i in range(3):
            ad = np.abs(d[:, i])
            c = vel[i] * length / ad
            used = ad > EPS
            if np.isnan(c[used & run.feed & ~over]).any():
                return None  # min() over a NaN depends on the order: ask the rule
            cap = np.where(used & (c < cap), c, cap)  # min() of the caps in axis order
    valid = (length >= EPS) & np.isfinite(cap)
    return run.feed & (over | (valid & (f > cap * 60.0 * (1 + 1e-9))))


_VELOCITY: dict[int, tuple[Machine, tuple[float, ...]]] = {}


def _velocity(machine: Machine) -> tuple[float, ...]:
    """``machine.limit_vector("velocity")``, kept for the machine (asked at every run)."""
    hit = _VELOCITY.get(id(machine))
    if hit is None or hit[0] is not machine:
        if len(_VELOCITY) > 16:
            _VELOCITY.clear()
        hit = _VELOCITY[id(machine)] = (machine, machine.limit_vector("velocity"))
    return hit[1]


def _rapid_into_stock(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    if ctx.config.stock is None:
        return np.zeros(len(run), dtype=np.bool_)
    return None


def _rapid_below_safe(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    if ctx.config.safe_z is None:
        return np.zeros(len(run), dtype=np.bool_)
    return None


def _feed_zero(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    if st.synch or st.feed_mode == canon.FeedMode.INVERSE_TIME:
        return np.zeros(len(run), dtype=np.bool_)
    return run.rate <= 0.0


#: rules judged on the straight moves from the run's arrays; None from one: ask it command
#: by command
ARRAY_RULES: dict[str, Callable[[StraightRun, CheckState, CheckContext], Bools | None]] = {
    "CNC101": _soft_limit,
    "CNC102": _axis_missing,
    "CNC103": _feed_too_fast,
    "CNC104": _feed_zero,
    "CNC401": _rapid_into_stock,
    "CNC402": _rapid_below_safe,
}

#: what an arc rule says of the arcs at some rows: (offend for certain, to be asked), or
#: None: ask them all
ArcVerdict = tuple[Bools, Bools] | None

#: relative margin of the arc screens: far above the few ulps by which numpy's hypot and
#: products may differ from the rule's math.hypot
SLACK = 1e-9


def _arc_radii(run: StraightRun, st: CheckState, rows: Ints) -> tuple[Floats, Floats]:
    """Radii (program units) of the arcs at ``rows`` at their start and end points."""
    i1, i2, _ = PLANE_AXES[st.plane]
    c = run.centre[rows]
    s, e = run.start[rows], run.end[rows]
    with np.errstate(over="ignore", invalid="ignore"):
        r0 = np.hypot(s[:, i1] - c[:, 0], s[:, i2] - c[:, 1])
        r1 = np.hypot(e[:, i1] - c[:, 0], e[:, i2] - c[:, 1])
    return r0, r1


def _soft_limit_arcs(run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints) -> ArcVerdict:
    """CNC101 of arcs: an end point beyond the travel decides (the rule's points include
    both ends, computed alike); otherwise only an arc whose whole circle, with a margin,
    reaches beyond is asked (the rule's quadrant points lie on that circle)."""
    s, e = run.start[rows], run.end[rows]
    certain = _beyond(_machine(s, st), _machine(e, st), ctx)
    if st.rotation:
        return certain, ~certain  # quadrant points of a turned frame: asked
    i1, i2, _ = PLANE_AXES[st.plane]
    r0, r1 = _arc_radii(run, st, rows)
    r = np.where(r1 > r0, r1, r0)
    c = run.centre[rows]
    lo, hi = s.copy(), s.copy()
    with np.errstate(over="ignore", invalid="ignore"):
        lo[:, i1], hi[:, i1] = c[:, 0] - r, c[:, 0] + r
        lo[:, i2], hi[:, i2] = c[:, 1] - r, c[:, 1] + r
        # without a rotation each machine axis grows with its program axis alone
        lo_m, hi_m = _machine(lo, st), _machine(hi, st)
    maybe = certain | ~np.isfinite(r)
    for axis in ctx.machine.axes:
        i = AXIS_NAMES.index(axis.name)
        if i not in (i1, i2):
            continue
        slack = SLACK * (np.abs(lo_m[:, i]) + np.abs(hi_m[:, i]) + 1.0)
        maybe |= (hi_m[:, i] + slack > axis.max + EPS) | (lo_m[:, i] - slack < axis.min - EPS)
    return certain, maybe & ~certain


def _axis_missing_arcs(
    run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints
) -> ArcVerdict:
    """CNC102 of arcs: the end point against the start, exactly as for a straight move."""
    out = _axis_missing(run, st, ctx)
    assert out is not None
    return out[rows], np.zeros(len(rows), dtype=np.bool_)


def _feed_too_fast_arcs(
    run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints
) -> ArcVerdict:
    """CNC103 of arcs: the feed against the fixed caps and the slower axis of the plane."""
    none = np.zeros(len(rows), dtype=np.bool_)
    if st.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or st.synch:
        return none, none
    i1, i2, _ = PLANE_AXES[st.plane]
    vel = _velocity(ctx.machine)
    f = run.rate[rows] * st.mm_per_unit
    over = none.copy()
    for cap in [*_fixed_caps(ctx), min(vel[i1], vel[i2]) * 60.0]:
        over |= f > cap * (1 + 1e-9)
    return over, none


def _feed_zero_arcs(run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints) -> ArcVerdict:
    """CNC104 of arcs: the feed rate each is judged in."""
    zero = _feed_zero(run, st, ctx)
    assert zero is not None
    return zero[rows], np.zeros(len(rows), dtype=np.bool_)


def _arc_radius_arcs(run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints) -> ArcVerdict:
    """CNC301: the radii at both ends against the tolerance, decided where the margin
    leaves no doubt."""
    turning = run.turns[rows] != 0
    r0, r1 = _arc_radii(run, st, rows)
    k = st.mm_per_unit
    absolute, relative, hard = ARC_TOLERANCES[ctx.config.arc_tolerance]
    with np.errstate(over="ignore", invalid="ignore"):
        r0, r1 = r0 * k, r1 * k
        diff = np.abs(r1 - r0)
        r = np.where(r1 > r0, r1, r0)
        slack = SLACK * r + 1e-300
        low, high = diff - slack, diff + slack
        certain = (low > hard + EPS) | ((low > absolute + 1e-9) & (low > relative * (r + slack)))
        maybe = (high > hard + EPS) | ((high > absolute + 1e-9) & (high > relative * (r - slack)))
    unsure = turning & ((maybe & ~certain) | ~np.isfinite(diff) | ~np.isfinite(r))
    return turning & certain & ~unsure, unsure


def _comp_gouge_arcs(run: StraightRun, st: CheckState, ctx: CheckContext, rows: Ints) -> ArcVerdict:
    """CNC801: only with compensation on, the concave arcs against the tool radius."""
    none = np.zeros(len(rows), dtype=np.bool_)
    if st.comp_side is None or st.comp_radius <= 0:
        return none, none
    turns = run.turns[rows]
    inside = (turns != 0) & ((st.comp_side == canon.CompSide.LEFT) == (turns > 0))
    _, r = _arc_radii(run, st, rows)
    with np.errstate(over="ignore", invalid="ignore"):
        slack = SLACK * r + 1e-300
        certain = st.comp_radius >= r + slack - EPS
        maybe = st.comp_radius >= r - slack - EPS
    unsure = inside & ((maybe & ~certain) | ~np.isfinite(r))
    return inside & certain & ~unsure, unsure


#: rules judged on the arcs from the run's arrays (arcs of a run whose coordinates are all
#: finite)
ARC_RULES: dict[str, Callable[[StraightRun, CheckState, CheckContext, Ints], ArcVerdict]] = {
    "CNC101": _soft_limit_arcs,
    "CNC102": _axis_missing_arcs,
    "CNC103": _feed_too_fast_arcs,
    "CNC104": _feed_zero_arcs,
    "CNC301": _arc_radius_arcs,
    "CNC801": _comp_gouge_arcs,
}
#: rules whose verdict on a move or SET_FEED_RATE depends only on the state and the
#: command's type (st.moved is true inside a run), never on the feed rate: the one part of
#: the state that changes inside a run
STATE_RULES = frozenset({"CNC030", "CNC105", "CNC502", "CNC701"})
#: rules that find fault only with a cutting move, and then depend only on the state (the
#: feed rate aside)
CUTTING_RULES = frozenset({"CNC202", "CNC203", "CNC204", "CNC504", "CNC505", "CNC601"})


#: the state a state or cutting rule's verdict depends on: every field but the position
#: and the feed rate
STATE_FIELDS = tuple(
    f.name for f in fields(CheckState) if f.name not in ("position", "extra", "feed", "feed_set")
)


def state_key(st: CheckState) -> tuple[object, ...]:
    """What the verdicts of :data:`STATE_RULES` and :data:`CUTTING_RULES` depend on."""
    return tuple(getattr(st, f) for f in STATE_FIELDS)


#: a verdict not known yet
_UNKNOWN = "?"
#: the kinds of rows a state rule answers for alike: straight feed, traverse, arc clockwise
#: or not (G2, G3), SET_FEED_RATE
Tag = bool | tuple[str, bool] | str
FEED_TAG, TRAVERSE_TAG, SET_TAG = True, False, "set"


class Judge:
    """The rules over the runs of one stream: the verdicts of the state and cutting rules
    are kept per state (a CAM program's runs share a few states), so a rule that cannot find
    fault with a run costs nothing."""

    #: states remembered (a bound for programs whose state changes all the time)
    MAX_STATES = 256

    def __init__(self, st: CheckState, ctx: CheckContext) -> None:
        self.st, self.ctx = st, ctx
        self.verdicts: dict[tuple[object, ...], dict[tuple[str, Tag], str | None]] = {}

    def start(self, run: StraightRun) -> None:
        """Begin judging ``run`` (the state is the one before its first row)."""
        self.run = run
        self._cuts: Bools | None = None
        self._present: dict[Tag, bool] = {}
        self._arc_finite: bool | None = None
        self._arc_verdicts: dict[str, tuple[Bools, Message]] = {}
        key = state_key(self.st)
        known = self.verdicts.get(key)
        if known is None:
            if len(self.verdicts) >= self.MAX_STATES:
                self.verdicts.clear()
            known = self.verdicts[key] = {}
        self.known = known

    def cuts(self) -> Bools:
        if self._cuts is None:
            self._cuts = cutting(self.run, self.st, self.ctx)
        return self._cuts

    def _rows(self, tag: Tag) -> Bools:
        """The rows of one kind (:data:`Tag`)."""
        run = self.run
        if tag is FEED_TAG:
            return run.feed
        if tag is TRAVERSE_TAG:
            return run.traverse
        if tag == SET_TAG:
            return run.setfeed
        assert isinstance(tag, tuple)
        return run.arc & ((run.turns < 0) == tag[1])

    def _tags(self, rule: Rule) -> list[Tag]:
        """The kinds of rows a state (or cutting) rule is called for."""
        feeds, traverses = straight_kinds(rule)
        tags: list[Tag] = []
        if feeds:
            tags.append(FEED_TAG)
        if traverses:
            tags.append(TRAVERSE_TAG)
        if arc_kind(rule) and self._arcs_by_state(rule):
            tags += [("arc", True), ("arc", False)]
        if called(rule, canon.SetFeedRate) and rule.id in STATE_RULES:
            tags.append(SET_TAG)
        return tags

    def _arcs_by_state(self, rule: Rule) -> bool:
        """Whether the rule's verdict on an arc depends only on the state and the arc's
        turning direction: a state rule's, and without a stock box, where every arc cuts,
        a cutting rule's."""
        return rule.id in STATE_RULES or (
            rule.id in CUTTING_RULES and rule.kinds == FEEDS and self.ctx.config.stock is None
        )

    def present(self, tag: Tag) -> bool:
        """Whether the run has rows of kind ``tag``."""
        got = self._present.get(tag)
        if got is None:
            got = self._present[tag] = bool(self._rows(tag).any())
        return got

    def _verdict(self, rule: Rule, tag: Tag, pick: Bools) -> str | None:
        """A state rule's verdict on the rows of kind ``tag`` among ``pick``, asked at the
        first of them if not known (None when there is none)."""
        key = (rule.id, tag)
        v = self.known.get(key, _UNKNOWN)
        if v is not _UNKNOWN:
            return v
        rows = pick & self._rows(tag)
        if not rows.any():
            return None  # no such row here: nothing learnt about the state
        v = self.known[key] = _ask(rule, self.run, self.st, self.ctx, int(rows.argmax()))
        return v

    def quiet(self, rule: Rule) -> bool:
        """True when the rule certainly finds fault with none of the run's rows (a state or
        cutting rule whose verdicts for this state are known to be None)."""
        if rule.id not in STATE_RULES and rule.id not in CUTTING_RULES:
            return False
        if arc_kind(rule) and not self._arcs_by_state(rule) and self.run.arc.any():
            return False
        for tag in self._tags(rule):
            if self.present(tag) and self.known.get((rule.id, tag), _UNKNOWN) is not None:
                return False
        return True

    def offences(self, rule: Rule) -> tuple[Bools, Bools, Message]:
        """The commands of the run the rule is called for, which of them it finds fault
        with, and the message for one of them by index."""
        with np.errstate(all="ignore"):  # overflow to inf compares as the rule's floats do
            return self._offences(rule)

    def _offences(self, rule: Rule) -> tuple[Bools, Bools, Message]:
        run = self.run
        mask = kinds_mask(rule, run)
        arcs = bool(run.arc.any()) and arc_kind(rule)
        if rule.id in STATE_RULES or (rule.id in CUTTING_RULES and rule.kinds == FEEDS):
            off, message = self._by_state(rule, mask)
            if not arcs or self._arcs_by_state(rule):
                return mask, off, message
            arc_off, arc_message = self._arc_offences(rule, mask)
            return mask, off | arc_off, _either(run.arc, arc_message, message)
        off, message = self._straight(rule, mask)
        if arcs:
            arc_off, arc_message = self._arc_offences(rule, mask)
            off |= arc_off
            message = _either(run.arc, arc_message, message)
        if run.setfeed.any() and called(rule, canon.SetFeedRate):
            set_off, set_message = self._asked(rule, mask & run.setfeed)
            off |= set_off
            message = _either(run.setfeed, set_message, message)
        return mask, off, message

    def _by_state(self, rule: Rule, mask: Bools) -> tuple[Bools, Message]:
        """A state or cutting rule's offences: its verdict per kind of row (for a cutting
        rule, on the straight feeds that cut)."""
        run = self.run
        out = np.zeros(len(run), dtype=np.bool_)
        verdicts: dict[Tag, str | None] = {}
        for tag in self._tags(rule):
            pick = mask
            if rule.id in CUTTING_RULES and tag is FEED_TAG:
                pick = mask & self.cuts()
            v = verdicts[tag] = self._verdict(rule, tag, pick)
            if v is not None:
                out |= pick & self._rows(tag)

        def message(i: int) -> str | None:
            if run.arc[i]:
                return verdicts[("arc", bool(run.turns[i] < 0))]
            if run.setfeed[i]:
                return verdicts[SET_TAG]
            return verdicts[bool(run.feed[i])]

        return out, message

    def _straight(self, rule: Rule, mask: Bools) -> tuple[Bools, Message]:
        """The offences of the straight moves of a rule judged by position or feed (False
        on the other rows)."""
        run, st, ctx = self.run, self.st, self.ctx
        straight = mask & (run.feed | run.traverse)
        if not straight.any():
            return np.zeros(len(run), dtype=np.bool_), _none
        fn = ARRAY_RULES.get(rule.id)
        if fn is not None and run.finite:
            arr = fn(run, st, ctx)
            if arr is not None:
                return arr & straight, lambda i: _ask(rule, run, st, ctx, i)
        return self._asked(rule, straight)

    def _asked(self, rule: Rule, rows: Bools) -> tuple[Bools, Message]:
        """The rule asked command by command at ``rows``."""
        run, st, ctx = self.run, self.st, self.ctx
        msgs = {i: _ask(rule, run, st, ctx, i) for i in np.flatnonzero(rows).tolist()}
        out = np.zeros(len(run), dtype=np.bool_)
        out[[i for i, m in msgs.items() if m is not None]] = True
        return out, lambda i: msgs.get(i)

    def _arc_offences(self, rule: Rule, mask: Bools) -> tuple[Bools, Message]:
        """The offences of the run's arcs of a rule judged arc by arc: from the arrays
        (:data:`ARC_RULES`) where they decide, else asked."""
        done = self._arc_verdicts.get(rule.id)
        if done is not None:
            return done
        run, st, ctx = self.run, self.st, self.ctx
        rows = np.flatnonzero(mask & run.arc)
        out = np.zeros(len(run), dtype=np.bool_)
        fn = ARC_RULES.get(rule.id)
        verdict = fn(run, st, ctx, rows) if fn is not None and self._arcs_finite() else None
        if verdict is None:
            ask = rows
        else:
            certain, unsure = verdict
            out[rows[certain]] = True
            ask = rows[unsure]
        msgs = {i: _ask(rule, run, st, ctx, i) for i in ask.tolist()}
        out[[i for i, m in msgs.items() if m is not None]] = True

        def message(i: int) -> str | None:
            return msgs[i] if i in msgs else _ask(rule, run, st, ctx, i)

        self._arc_verdicts[rule.id] = out, message
        return out, message

    def _arcs_finite(self) -> bool:
        """Whether every arc of the run has finite points and centre (its arrays judge)."""
        if self._arc_finite is None:
            a = self.run.arc
            self._arc_finite = bool(self.run.finite and np.isfinite(self.run.centre[a]).all())
        return self._arc_finite


def _either(rows: Bools, there: Message, elsewhere: Message) -> Message:
    """The message of ``there`` at ``rows``, of ``elsewhere`` at the others."""
    return lambda i: there(i) if rows[i] else elsewhere(i)


def _none(i: int) -> str | None:
    return None
