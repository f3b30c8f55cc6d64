"""The rules of ``cnc check`` judged over a run of straight moves at once (numpy).

A CAM program is mostly consecutive STRAIGHT_FEED and STRAIGHT_TRAVERSE commands, and between
two other commands only the position changes: units, offsets, tool, spindle, feed and the
rest of :class:`~kernel.check.state.CheckState` stay the same. :func:`offences` says, for
one rule and such a run (:class:`StraightRun`), which of its commands the rule finds fault
with, without calling the rule once per command:

* *state* rules depend only on the state and the command's type: the rule is asked once for
  the first command of each type and the answer holds for the others;
* *cutting* rules find fault only with a move that cuts (:func:`~kernel.check.rules.is_cutting`)
  and otherwise depend only on the state: asked once, for the first cutting move;
* the rules that judge the position (travel limits, missing axes, feed against the axis
  velocities, rapids against the stock and the safe height) are computed from the arrays of
  the run's start and end points, with the same floating-point operations, in the same order,
  as the per-command rule.

A rule not listed here, or a run its arrays cannot judge exactly (a non-finite coordinate),
is asked command by command, as :func:`kernel.check.check_stream` does without runs: the
findings are the same either way (tests/test_check_batch.py compares both on every program
of the check tests and the goldens).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Protocol, TypeVar, cast

import numpy as np
import numpy.typing as npt

import kernel.ir.canon as canon
from kernel.check.rules import EPS, FEEDS, CheckContext, Rule
from kernel.check.state import PLANE_AXES, CheckState, Vec6
from kernel.diagnostics import Location
from kernel.machine import AXIS_NAMES, Machine

Bools = npt.NDArray[np.bool_]
Floats = npt.NDArray[np.float64]


T_co = TypeVar("T_co", covariant=True)


class Indexed(Protocol[T_co]):
    """What a run needs of its commands and locations: a list, or built when asked for."""

    def __len__(self) -> int: ...

    def __getitem__(self, i: int, /) -> T_co: ...


@dataclass
class StraightRun:
    """Consecutive moves (straight moves and arcs) with the state before the first: their
    commands, source locations, start and end points (program coordinates, ``n x 6``),
    which are straight feeds and which are arcs (the rest are straight traverses). The arcs
    are judged command by command; they are in the run so that it is long."""

    commands: Indexed[canon.Command]
    locations: Indexed[Location]
    start: Floats
    end: Floats
    feed: Bools
    arc: Bools
    traverse: Bools

    @classmethod
    def of(
        cls,
        commands: list[canon.Command],
        ends: list[Vec6],
        locations: list[Location],
        position: Vec6,
    ) -> StraightRun:
        """The run of ``commands`` (their ``ends``) from ``position``."""
        end = np.array(ends, dtype=np.float64).reshape(len(ends), 6)
        start = np.empty_like(end)
        start[0] = position
        start[1:] = end[:-1]
        n = len(commands)
        feed = np.fromiter((type(c) is canon.StraightFeed for c in commands), np.bool_, n)
        arc = np.fromiter((type(c) is canon.ArcFeed for c in commands), np.bool_, n)
        return cls(commands, locations, start, end, feed, arc, ~(feed | arc))

    @classmethod
    def of_moves(
        cls, moves: Moves, a: int, b: int, position: Vec6, plane: canon.Plane
    ) -> StraightRun:
        """The run of events ``a .. b`` of ``moves`` (none of them SET_FEED) from
        ``position``, in ``plane`` (the arcs' axes)."""
        kind = moves.kind[a:b]
        end = np.array(moves.position[a:b], dtype=np.float64)
        arc = kind == ARC
        if arc.any():
            assert moves.arc is not None
            i1, i2, n = PLANE_AXES[plane]
            rows = np.asarray(moves.arc[a:b], dtype=np.float64)[arc]
            end[arc, i1], end[arc, i2], end[arc, n] = rows[:, 0], rows[:, 1], rows[:, 5]
        start = np.empty_like(end)
        start[0] = position
        start[1:] = end[:-1]
        feed = kind == FEED
        return cls(
            _Commands(moves, a, b), _Locations(moves, a, b), start, end, feed, arc, ~(feed | arc)
        )

    def __len__(self) -> int:
        return len(self.start)

    def finite(self) -> bool:
        return bool(np.isfinite(self.start).all() and np.isfinite(self.end).all())


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
    """The rule's own verdict on command ``i`` of the run (the state with its start point)."""
    assert rule.check is not None
    keep = st.position
    p = run.start[i].tolist()
    st.position = (p[0], p[1], p[2], p[3], p[4], p[5])
    try:
        return rule.check(run.commands[i], st, ctx)
    finally:
        st.position = keep


def straight_kinds(rule: Rule) -> tuple[bool, bool]:
    """Whether the rule is called for STRAIGHT_FEED and for STRAIGHT_TRAVERSE."""
    if not rule.kinds:
        return True, True
    return issubclass(canon.StraightFeed, rule.kinds), issubclass(
        canon.StraightTraverse, rule.kinds
    )


def arc_kind(rule: Rule) -> bool:
    """Whether the rule is called for ARC_FEED."""
    return not rule.kinds or issubclass(canon.ArcFeed, rule.kinds)


def kinds_mask(rule: Rule, run: StraightRun) -> Bools:
    """The commands of the run the rule is called for (its ``kinds``)."""
    feeds, traverses = straight_kinds(rule)
    out = run.arc.copy() if arc_kind(rule) else np.zeros(len(run), dtype=np.bool_)
    if feeds:
        out |= run.feed
    if traverses:
        out |= run.traverse
    return out


def cutting(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools:
    """:func:`~kernel.check.rules.is_cutting` of each move of the run."""
    s, e = run.start, run.end
    retract = (np.abs(e[:, 0] - s[:, 0]) <= EPS) & (np.abs(e[:, 1] - s[:, 1]) <= EPS)
    retract &= e[:, 2] > s[:, 2] + EPS
    out = run.feed & ~retract  # straight feeds only: arcs are asked command by command
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


def _soft_limit(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    a, b = _machine(run.start, st), _machine(run.end, st)
    out = np.zeros(len(run), dtype=np.bool_)
    for axis in ctx.machine.axes:
        i = AXIS_NAMES.index(axis.name)
        hi = np.where(b[:, i] > a[:, i], b[:, i], a[:, i])
        lo = np.where(b[:, i] < a[:, i], b[:, i], a[:, i])
        out |= (hi > axis.max + EPS) | (lo < axis.min - EPS)
    return out


def _axis_missing(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    have = set(ctx.machine.axis_names)
    out = np.zeros(len(run), dtype=np.bool_)
    for i, name in enumerate(AXIS_NAMES):
        if name not in have:
            out |= np.abs(run.end[:, i] - run.start[:, i]) > EPS
    return out


def _feed_too_fast(run: StraightRun, st: CheckState, ctx: CheckContext) -> Bools | None:
    if st.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or st.synch:
        return np.zeros(len(run), dtype=np.bool_)
    f = st.feed * st.mm_per_unit
    fixed = []
    if ctx.config.max_feed is not None:
        fixed.append(ctx.config.max_feed)
    if ctx.machine.controller.max_feed > 0:
        fixed.append(ctx.machine.controller.max_feed * 60.0)
    if any(f > cap * (1 + 1e-9) for cap in fixed):
        return run.feed.copy()
    vel = _velocity(ctx.machine)
    k = st.mm_per_unit
    with np.errstate(over="ignore", invalid="ignore"):
        d = (run.end[:, :3] - run.start[:, :3]) * k
        length = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])
    if np.isnan(length).any():
        return None
    cap = np.full(len(run), np.inf)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for i in range(3):
            ad = np.abs(d[:, i])
            c = vel[i] * length / ad
            used = ad > EPS
            if np.isnan(c[used]).any():
                return None  # min() over a NaN depends on the order: ask the rule
            cap = np.where(used & (c < cap), c, cap)  # min() of the caps in axis order
    valid = (length >= EPS) & np.isfinite(cap)
    return run.feed & valid & (f > cap * 60.0 * (1 + 1e-9))


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


#: rules judged from the run's arrays; None from one: ask it command by command
ARRAY_RULES: dict[str, Callable[[StraightRun, CheckState, CheckContext], Bools | None]] = {
    "CNC101": _soft_limit,
    "CNC102": _axis_missing,
    "CNC103": _feed_too_fast,
    "CNC401": _rapid_into_stock,
    "CNC402": _rapid_below_safe,
}
#: rules whose verdict on a straight move depends only on the state and the move's type
#: (st.moved is true inside a run)
STATE_RULES = frozenset({"CNC030", "CNC104", "CNC105", "CNC502", "CNC701"})
#: rules that find fault only with a cutting move, and then depend only on the state
CUTTING_RULES = frozenset({"CNC202", "CNC203", "CNC204", "CNC504", "CNC505", "CNC601"})


#: the state a state or cutting rule's verdict depends on: every field but the position
STATE_FIELDS = tuple(f.name for f in fields(CheckState) if f.name not in ("position", "extra"))


def state_key(st: CheckState) -> tuple[object, ...]:
    """What the verdicts of :data:`STATE_RULES` and :data:`CUTTING_RULES` depend on."""
    return tuple(getattr(st, f) for f in STATE_FIELDS)


class Judge:
    """The rules over the runs of one stream: the verdicts of the state and cutting rules
    are kept per state (a CAM program's runs share a few states), so a rule that cannot find
    fault with a run costs nothing."""

    #: states remembered (a bound for programs whose feed changes at every move)
    MAX_STATES = 256

    def __init__(self, st: CheckState, ctx: CheckContext) -> None:
        self.st, self.ctx = st, ctx
        self.verdicts: dict[tuple[object, ...], dict[tuple[object, ...], str | None]] = {}

    def start(self, run: StraightRun) -> None:
        """Begin judging ``run`` (the state is the one before its first move)."""
        self.run = run
        self._cuts: Bools | None = None
        self.has_feed = bool(run.feed.any())
        self.has_traverse = bool(run.traverse.any())
        self.arcs = np.flatnonzero(run.arc).tolist()
        self.arc_msgs: dict[str, dict[int, str | None]] = {}
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

    def _verdict(self, rule: Rule, is_feed: bool, pick: Bools) -> str | None:
        """The rule's verdict on the run's straight moves of one type (``pick``: where to
        ask it)."""
        k = (rule.id, is_feed)
        if k in self.known:
            return self.known[k]
        which = np.flatnonzero(pick & (self.run.feed if is_feed else self.run.traverse))
        if not len(which):
            return None  # no such move here: nothing learnt about the state
        v = self.known[k] = _ask(rule, self.run, self.st, self.ctx, int(which[0]))
        return v

    def _arcs(self, rule: Rule) -> dict[int, str | None]:
        """The rule's verdict on each arc of the run: a state rule's (and, without a stock
        box, where every arc cuts, a cutting rule's) once per turning direction (G2/G3 are
        different codes), the others' arc by arc."""
        msgs = self.arc_msgs.get(rule.id)
        if msgs is None:
            if not arc_kind(rule):
                msgs = {}
            elif rule.id in STATE_RULES or (
                rule.id in CUTTING_RULES and rule.kinds == FEEDS and self.ctx.config.stock is None
            ):
                msgs = {}
                for i in self.arcs:
                    arc = cast(canon.ArcFeed, self.run.commands[i])
                    k = (rule.id, "arc", arc.rotation > 0)
                    if k not in self.known:
                        self.known[k] = _ask(rule, self.run, self.st, self.ctx, i)
                    msgs[i] = self.known[k]
            else:
                msgs = {i: _ask(rule, self.run, self.st, self.ctx, i) for i in self.arcs}
            self.arc_msgs[rule.id] = msgs
        return msgs

    def quiet(self, rule: Rule) -> bool:
        """True when the rule certainly finds fault with none of the run's moves (a state or
        cutting rule whose verdicts for this state are known to be None, and no arc)."""
        if rule.id not in STATE_RULES and rule.id not in CUTTING_RULES:
            return False
        known = self.known
        if self.has_feed and known.get((rule.id, True), "?") is not None:
            return False
        if self.has_traverse and known.get((rule.id, False), "?") is not None:
            return False
        return all(m is None for m in self._arcs(rule).values())

    def offences(self, rule: Rule) -> tuple[Bools, Bools, Message]:
        """The commands of the run the rule is called for, which of them it finds fault
        with, and the message for one of them by index."""
        with np.errstate(all="ignore"):  # overflow to inf compares as the rule's floats do
            mask, off, message = self._straight(rule)
        arcs = self._arcs(rule)
        if not arcs:
            return mask, off, message
        for i, m in arcs.items():
            off[i] = m is not None
        return mask, off, lambda i: arcs[i] if i in arcs else message(i)

    def _straight(self, rule: Rule) -> tuple[Bools, Bools, Message]:
        """:meth:`offences` of the straight moves (the arcs: False)."""
        run, st, ctx = self.run, self.st, self.ctx
        n = len(run)
        mask = kinds_mask(rule, run)
        straight = mask & ~run.arc
        if not straight.any():
            return mask, np.zeros(n, dtype=np.bool_), lambda i: None
        if rule.id in STATE_RULES or (rule.id in CUTTING_RULES and rule.kinds == FEEDS):
            pick = straight if rule.id in STATE_RULES else straight & self.cuts()
            out = np.zeros(n, dtype=np.bool_)
            verdicts: dict[bool, str | None] = {}
            for is_feed in (True, False):
                v = verdicts[is_feed] = self._verdict(rule, is_feed, pick)
                if v is not None:
                    out |= pick & (run.feed if is_feed else run.traverse)
            return mask, out, lambda i: verdicts[bool(run.feed[i])]
        fn = ARRAY_RULES.get(rule.id)
        if fn is not None and run.finite():
            arr = fn(run, st, ctx)
            if arr is not None:
                return mask, arr & straight, lambda i: _ask(rule, run, st, ctx, i)
        # command by command
        msgs = [_ask(rule, run, st, ctx, i) if straight[i] else None for i in range(n)]
        out = np.fromiter((m is not None for m in msgs), dtype=np.bool_, count=n)
        return mask, out, lambda i: msgs[i]
