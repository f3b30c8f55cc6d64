"""``cnc plan`` in bounded memory: the program planned and measured window by window
(issue 19), with the numbers of the whole-program pipeline (kernel.simulation).

The IR is read as a stream, a batch of commands at a time (kernel.path.builder's batches);
each batch's rows of the segment table are made, blended, planned, sampled and reduced, and
forgotten. What is kept between windows is a few numbers per quantity:

* **Rows** (kernel.path.builder ``take``): the rows of one batch of commands. ``G64 P``
  corner blending (kernel.path.blend) reads the two rows of a corner only and trims a line
  by the corners at its two ends, so a window's rows are blended with the row before them
  and the row after them at hand (the last row waits for the next batch).
* **Look-ahead** (the backward pass of :func:`kernel.plan.planner.lookahead`): the end
  speed of row ``i`` is ``min(x_{i+1} .. x_{i+N-1}, G_{i+N}) - G_{i+1}`` with
  ``x_k = c_k^2 + G_k``, ``c_k`` the junction caps and ``G`` the running sum of ``2 A L``
  (``N``: the planner's look-ahead, ``[controller] lookahead`` for the book, Grbl's 15
  blocks). A row's end speed is final, and the row is planned and handed on, as soon as
  either

  - the ``N - 1`` junctions after it are known (a bounded look-ahead: the whole-program
    planner reads no further), or
  - the smallest ``x`` known after it is at most ``G`` at the last known junction (the
    stopping-distance rule: every later ``x_k`` is at least ``G_k``, which only grows, so no
    later junction can lower the minimum; a stop, ``c = 0``, makes every row before it final
    at once);

  the program's end is a stop. Memory holds the rows within the look-ahead of the last final
  one: ``N`` rows, or fewer where a stop or the stopping distance comes first.
* **Forward pass, times, path positions**: running sums and minima carried from window to
  window in the order the whole-program planner adds them (``numpy.cumsum`` adds in
  sequence), so junction speeds, profiles, ``t_start`` and ``s_start`` are bit for bit
  those of planning the whole program.
* **Samples** (kernel.interp.interpolate): every sample ``t_k = k T`` belongs to the last
  piece starting at or before it, so the samples before the next window's first start time
  are this window's; they are made in windows of ``WINDOW`` samples and reduced
  (kernel.report.measure ``SampleReductions``), and the time per tool and operation is
  summed row by row (kernel.report.breakdown ``StretchSums``).

The report is the whole-program report bit for bit, except the cycle-time parts (cutting,
rapid, dwell, tool change, other) and the feed and rapid lengths: numpy sums a whole array
pairwise, here the windows' sums are added, so these can differ in the last bits (about
1e-15 relative; never in the printed digits of the text report). The cycle total, time per
tool and operation, peaks, chord error and limit hits are identical.

Which errors a program with several gets is the whole-program order too: an error of the
IR stream or the builder's walk first, then ``PLAN-AXIS``, ``PLAN-FEED``, ``PLAN-LIMIT``,
``PLAN-TRAVEL`` (each at its first row) and ``LIMIT-COUNT`` (at the move with the most
samples): after a first error, windows are still built and planned (not sampled) as far
as a later error could still come first.

Planned this way: the ``book`` model with trapezoidal acc/dec and the ``grbl`` model; the
``linuxcnc`` model (blend arcs and merged runs across joins, kernel.plan.models) from stop
to stop (:func:`_lcnc_windows`: holds, exact stops, traverse-feed changes) and, inside a
long run of joins, window by window with rows before and after each planned again (its
planner is local: a look-ahead of ``OPT_DEPTH`` segments, joins and blends of two rows).
The book's S-curve (its smoothing reach is set by the fastest move anywhere in the
program) is planned by kernel.stream_scurve, in two passes (:func:`streams` says which
models are planned here).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, replace
from itertools import islice

import numpy as np

import kernel.ir.canon as canon
from kernel.axes.accdec import planning_machine
from kernel.diagnostics import Diagnostic
from kernel.interp.interpolate import (
    check_steps,
    check_travel,
    move_steps,
    sample_span,
    sample_windows,
)
from kernel.interp.samples import Samples
from kernel.machine import AXIS_NAMES, Machine, with_controller
from kernel.path.blend import blend_rows
from kernel.path.builder import PathBuilder
from kernel.path.segments import FEED, HOLD, PROBE, RAPID, SEGMENT_DTYPE, Path
from kernel.plan.models import grbl, linuxcnc
from kernel.plan.planner import Plan, junction_caps, range_min, segment_limits, trapezoids
from kernel.plan.strategy import no_blend, plan_program
from kernel.report.breakdown import PARTS, Mark, StretchSums
from kernel.report.measure import CycleTime, Report, SampleReductions, measure_windows

#: commands read per window: about 10 MB of segment table and plan, a few hundred ms of
#: motion of a CAM program (its samples are made WINDOW at a time)
BATCH = 1 << 14


def streams(machine: Machine) -> bool:
    """Whether :func:`plan_windows` plans ``machine``'s model (else plan it whole)."""
    model = machine.controller.model
    if model in ("grbl", "linuxcnc"):
        return True
    if model != "book":
        return False
    planning = planning_machine(machine)
    return machine.controller.accdec != "scurve" and planning.controller.accdec != "scurve"


@dataclass(frozen=True, slots=True)
class _Model:
    """What the windowed pipeline needs of a planner strategy (kernel.plan.strategy)."""

    name: str
    build: Machine  # the machine the path is built for
    planning: Machine  # the machine the planner plans on (the plan's machine)
    window: int  # look-ahead N

    @classmethod
    def of(cls, machine: Machine) -> _Model:
        planning = planning_machine(machine)
        if machine.controller.model == "linuxcnc":
            flat = with_controller(machine, accdec="trapezoid")
            return cls("linuxcnc", flat, with_controller(planning, accdec="trapezoid"), 0)
        if machine.controller.model == "grbl":
            flat = with_controller(machine, accdec="trapezoid", blend_tolerance=0.0)
            plan_on = with_controller(planning, accdec="trapezoid")
            return cls("grbl", flat, plan_on, grbl.BLOCK_BUFFER - 1)
        return cls("book", machine, planning, planning.controller.lookahead)

    def commands(self, commands: Iterable[canon.Command]) -> Iterable[canon.Command]:
        return (
            grbl.synchronised(
                no_blend(commands),
                self.planning.controller.arc_tolerance,
                self.build.kind == "laser",
            )
            if self.name == "grbl"
            else commands
        )

    def rows(self, raw: np.ndarray, a: int, b: int, file: str | None) -> np.ndarray:
        """Raw rows ``a .. b - 1`` as the planner plans them (``raw[a - 1]`` and
        ``raw[b]``, where there, are their neighbours: the corners blended on either side)."""
        if self.name == "grbl":
            before = raw[a - 1] if a > 0 else None
            after = raw[b] if b < len(raw) else None
            return grbl.blocks(Path(raw[a:b], file), self.planning, before, after).segments
        return blend_rows(raw, a, b)

    def limits(self, path: Path) -> tuple[np.ndarray, np.ndarray]:
        """Every row's speed cap and (raw) path acceleration."""
        if self.name == "grbl":
            return grbl.block_limits(path, self.planning)
        return segment_limits(path, self.planning)

    def late(
        self, rows: np.ndarray, v: np.ndarray, cap: np.ndarray, after: np.ndarray | None
    ) -> np.ndarray | None:
        """The pause after each of the final ``rows`` (junction speeds ``v``, caps ``cap``;
        ``after``: the row after them, where there): Grbl's late last step at a stop
        (kernel.plan.models.grbl ``late_stops``); None for the other models."""
        if self.name == "grbl":
            return grbl.late_stops(rows, v, cap, self.planning, after)
        return None

    def junctions(self, seg: np.ndarray, cap: np.ndarray, acc: np.ndarray) -> np.ndarray:
        """The caps at the junctions between consecutive rows of ``seg`` (n - 1)."""
        if self.name == "grbl":
            return grbl.junction_caps(seg, cap, self.planning)
        return junction_caps(Path(seg), self.planning, cap, acc)[1:-1]


class _Lookahead:
    """The rows not yet final: their caps, planning accelerations, the squared cap at the
    junction each starts at, ``G`` at those junctions (and at the last one's end), and the
    forward pass's running minimum and speed at the first of them."""

    def __init__(self, window: int) -> None:
        self.window = window
        self.rows = np.zeros(0, SEGMENT_DTYPE)
        self.cap = np.zeros(0)
        self.acc = np.zeros(0)  # planning acceleration (0 for holds)
        self.c2 = np.zeros(0)
        self.g = np.zeros(1)
        self.fmin = 0.0  # min of (v^2 - G) over the final junctions, as the forward pass
        self.v0 = 0.0  # speed at the first pending junction

    def push(self, rows: np.ndarray, cap: np.ndarray, acc: np.ndarray, c2: np.ndarray) -> None:
        terms = 2.0 * acc * rows["length"]
        g = np.cumsum(np.concatenate([self.g[-1:], terms]))[1:]
        self.rows = np.concatenate([self.rows, rows])
        self.cap = np.concatenate([self.cap, cap])
        self.acc = np.concatenate([self.acc, acc])
        self.c2 = np.concatenate([self.c2, c2])
        self.g = np.concatenate([self.g, g])

    def pop(self, end: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """The rows now final (all at the program's ``end``): rows, caps, planning
        accelerations and junction speeds (one more than rows); ``None`` if none is."""
        p = len(self.rows)
        if not p:
            return None
        n_win, g = self.window, self.g
        x = self.c2 + g[:p]
        if end:
            x = np.concatenate([x, 0.0 + g[p:]])
            f = p
        else:
            suffix = np.minimum.accumulate(x[::-1])[::-1]
            by_distance = int(np.count_nonzero(suffix[1:] <= g[p]))
            f = max(p - n_win + 1, by_distance)
            if f <= 0:
                return None
        i = np.arange(f)
        inner = range_min(x, i + 1, np.minimum(i + n_win - 1, len(x) - 1))
        end2 = np.minimum(inner, g[np.minimum(i + n_win, p)]) - g[1 : f + 1]
        run = np.minimum.accumulate(np.concatenate([[self.fmin], end2 - g[1 : f + 1]]))
        w = run[1:] + g[1 : f + 1]
        v = np.concatenate([[self.v0], np.sqrt(np.clip(w, 0.0, None))])
        self.fmin, self.v0 = float(run[-1]), float(v[-1])
        out = (self.rows[:f], self.cap[:f], self.acc[:f], v)
        self.rows, self.cap, self.acc = self.rows[f:], self.cap[f:], self.acc[f:]
        self.c2, self.g = self.c2[f:], g[f:]
        return out


#: the order in which a whole-program run reports errors (kernel.simulation): the builder's
#: table (PLAN-AXIS over all rows before PLAN-FEED), the planner, the checks before sampling
_RANK = {"PLAN-AXIS": 2, "PLAN-FEED": 3, "PLAN-LIMIT": 4, "PLAN-TRAVEL": 5, "LIMIT-COUNT": 6}


@dataclass(slots=True)
class _Errors:
    """The error a whole-program run would raise, among those found so far."""

    rank: int = 99
    error: Diagnostic | None = None
    steps: float = -math.inf  # LIMIT-COUNT: the most samples of one move so far

    def note(self, error: Diagnostic, rank: int) -> None:
        if rank < self.rank:
            self.rank, self.error = rank, error

    def checked(self, plan: Plan) -> bool:
        """Check a window's final rows as the whole program's are checked before sampling
        (``PLAN-TRAVEL``, ``LIMIT-COUNT``): whether no error is known so far."""
        try:
            check_travel(plan)
        except Diagnostic as diag:
            self.note(diag, 5)
        steps, row = move_steps(plan, plan.machine.controller.interpolation_period)
        key = math.inf if math.isnan(steps) else steps
        if key > self.steps:
            self.steps = key
            try:
                check_steps(plan, steps, row)
            except Diagnostic as diag:
                if self.rank == 6:  # a move with more samples than the last one's
                    self.error = diag
                self.note(diag, 6)
        return self.error is None


@dataclass(slots=True)
class _Clock:
    """Running sums over the planned rows: start time, path position."""

    t: float = 0.0
    s: float = 0.0
    rows: int = 0


def _window_plan(
    planning: Machine,
    file: str | None,
    rows: np.ndarray,
    cap: np.ndarray,
    acc: np.ndarray,
    v: np.ndarray,
    clock: _Clock,
    tf: float = 0.0,
    late: np.ndarray | None = None,
) -> Plan:
    """The plan of final rows, as the whole-program planner computes them (``tf``: the
    S-curve filter time, a pause at every stop; kernel.stream_scurve; ``late``: a model's
    own pause after each row, as :meth:`_Model.late`)."""
    length = rows["length"]
    moving = rows["kind"] != HOLD
    prof = trapezoids(length, v[:-1], v[1:], cap, acc)
    duration = np.where(moving, prof.duration, rows["duration"])
    pause = np.zeros(len(rows))
    if late is not None:
        pause = late
        duration = duration + pause
    if tf > 0:
        pause = np.where((v[1:] <= 0.0) & moving, tf, 0.0)
        duration = duration + pause
    t = np.cumsum(np.concatenate([[clock.t], duration]))
    s = np.cumsum(np.concatenate([[clock.s], length]))
    clock.t, clock.s = float(t[-1]), float(s[-1])
    clock.rows += len(rows)
    return Plan(Path(rows, file), planning, v, cap, prof, pause, duration, t[:-1], s[:-1], tf)


def _batches(
    builder: PathBuilder, commands: Iterator[canon.Command], batch: int, errors: _Errors
) -> Iterator[tuple[np.ndarray, bool, int]]:
    """The segment-table rows of ``commands``, ``batch`` commands at a time, as (rows,
    whether the program has ended, commands read so far). A command that fails to read
    still gets the ones before it built; a row-building error is noted in ``errors`` (the
    whole-program order), after which no rows are given."""
    idx, end = 0, False
    while not end:
        cmds: list[canon.Command] = []
        try:
            cmds.extend(islice(commands, batch))
        except Exception:
            builder.feed_commands(cmds, idx)
            raise
        end = not cmds
        if cmds:
            builder.feed_commands(cmds, idx)
            idx += len(cmds)
        try:
            raw = builder.take()
        except Diagnostic as diag:
            errors.note(diag, 2 if diag.code != "PLAN-FEED" else 3)
            continue
        if errors.rank <= 3:
            continue
        yield raw, end, idx


def plan_windows(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
    batch: int = BATCH,
) -> Iterator[Plan]:
    """The plan of ``commands`` on ``machine`` (a model :func:`streams` plans) as
    consecutive windows of rows, each with its start times and path positions from the
    program's start. Raises the error planning the whole program would raise, once the
    windows before it have been given. ``batch``: commands read at a time (the window)."""
    model = _Model.of(machine)
    if model.name == "linuxcnc":
        yield from _lcnc_windows(commands, model, file, batch)
        return
    builder = PathBuilder(model.build, file)
    look = _Lookahead(model.window)
    errors = _Errors()
    clock = _Clock()
    # raw rows not planned yet (the last one waits for the corner after it), after the
    # last one planned (``held_context``: the corner before the first waiting one)
    held = np.zeros(0, SEGMENT_DTYPE)
    held_context = False
    last: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # row, cap, acc
    for raw, end, _ in _batches(builder, iter(model.commands(commands)), batch, errors):
        raw = np.concatenate([held, raw]) if len(held) else raw
        first = 1 if len(held) and held_context else 0
        cut = len(raw) if end else max(len(raw) - 1, first)
        rows = model.rows(raw, first, cut, file)
        held, held_context = raw[max(cut - 1, 0) :], cut > 0
        if len(rows):
            try:
                cap, acc = model.limits(Path(rows, file))
            except Diagnostic as diag:
                errors.note(diag, _RANK.get(diag.code, 4))
                continue
        if errors.rank <= 5:
            continue
        if len(rows):
            c2 = np.zeros(len(rows))
            if last is not None:
                seg = np.concatenate([last[0], rows])
                caps = model.junctions(
                    seg, np.concatenate([last[1], cap]), np.concatenate([last[2], acc])
                )
                c2 = np.square(caps)
            else:
                c2[1:] = np.square(model.junctions(rows, cap, acc))
            last = (rows[-1:], cap[-1:], acc[-1:])
            look.push(rows, cap, np.where(rows["kind"] != HOLD, acc, 0.0), c2)
        final = look.pop(end)
        if final is not None:
            after = look.rows[0] if len(look.rows) else None
            late = model.late(final[0], final[3], final[1], after)
            plan = _window_plan(model.planning, file, *final, clock, late=late)
            if errors.checked(plan):
                yield plan
    if errors.error is not None:
        raise errors.error


class _Pending:
    """Raw rows not planned yet (in chunks, joined only when cut), the last hold row among
    them and the last stop join (``G61.1`` exact stop, or a traverse next to a feed move:
    kernel.plan.models.linuxcnc stops there, deciding it from the two rows alone)."""

    def __init__(self) -> None:
        self.chunks: list[np.ndarray] = []
        self.count = 0
        self.last_hold = -1
        self.last_stop = -1  # a stop join after this row
        self.tail: tuple[int, bool, int] | None = None  # the last row: kind, rapid, term

    def add(self, raw: np.ndarray, term: np.ndarray, end: bool) -> tuple[int, bool]:
        """Add ``raw`` (``term``: each row's path mode); the number of rows to plan now
        (all at the ``end``; else up to the last hold row with a move after it or the last
        stop join; 0: none) and whether the cut is at a stop join."""
        base = self.count
        if not len(raw):
            return (self.count, False) if end else (0, False)
        self.chunks.append(raw)
        self.count += len(raw)
        kind, rapid = raw["kind"], raw["category"] == RAPID
        if self.tail is not None:
            k0, r0, t0 = self.tail
            kinds = np.concatenate([[k0], kind])
            rapids = np.concatenate([[r0], rapid])
            terms = np.concatenate([[t0], term])
            offset = base - 1
        else:
            kinds, rapids, terms, offset = kind, rapid, term, base
        self.tail = (int(kind[-1]), bool(rapid[-1]), int(term[-1]))
        if end:
            return self.count, False
        mv = kinds != HOLD
        stops = np.flatnonzero(
            mv[:-1] & mv[1:] & ((rapids[:-1] != rapids[1:]) | (terms[:-1] == linuxcnc.STOP))
        )
        if stops.size:
            self.last_stop = offset + int(stops[-1])
        moving = np.flatnonzero(kind != HOLD)
        cut = 0
        if moving.size:
            before = np.flatnonzero(kind[: moving[-1]] == HOLD)
            cut = base + int(before[-1]) + 1 if before.size else self.last_hold + 1
        holds = np.flatnonzero(kind == HOLD)
        if holds.size:
            self.last_hold = base + int(holds[-1])
        stop_cut = self.last_stop + 1
        return (stop_cut, True) if stop_cut > cut else (cut, False)

    def rows(self) -> np.ndarray:
        """The rows, joined."""
        if len(self.chunks) > 1:
            self.chunks = [np.concatenate(self.chunks)]
        return self.chunks[0] if self.chunks else np.zeros(0, SEGMENT_DTYPE)

    def take(self, cut: int, keep: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The first ``cut`` rows, and the rows kept after dropping the first ``keep``
        (``cut``: none of them kept; fewer: the last ones, planned again with the next)."""
        rows = self.rows()
        window, rest = rows[:cut], rows[cut if keep is None else keep :]
        self.chunks = [rest] if len(rest) else []
        self.count = len(rest)
        holds = np.flatnonzero(rest["kind"] == HOLD)
        self.last_hold = int(holds[-1]) if holds.size else -1
        self.last_stop = -1  # none after the cut: the cut is at the last one or later
        return window, rest


#: the linuxcnc model inside a run of joins: rows planned again before a window's first
#: kept row (the joins at its start: blend arcs, trims, kinks touch two rows; the cut is at
#: a join kernel.plan.models.linuxcnc ``_window_end`` allows for two), rows planned after
#: its last kept one at first (the look-ahead's OPT_DEPTH), and how many junctions after the
#: kept rows must be planned as the whole program plans them (the rest feel the window's
#: end): a window with fewer (lines blending empties) is planned again with twice the rows
_CONTEXT = 2
_MARGIN = linuxcnc.OPT_DEPTH + 8
_REACH = linuxcnc.OPT_DEPTH + 6


def _lcnc_windows(
    commands: Iterable[canon.Command], model: _Model, file: str | None, batch: int
) -> Iterator[Plan]:
    """:func:`plan_windows` for the ``linuxcnc`` model: its blend arcs, merged runs, kink
    losses and look-ahead reach across joins, but not across a stop: a hold row (a dwell,
    a tool change, a task command's wait: the queue runs dry there), a G61.1 exact-stop
    join, or a traverse next to a feed move (never blended). The rows are cut after the
    last such stop with a move after it (the program's last move takes the program's own
    start-up cost, kernel.plan.models.linuxcnc ``START_CYCLES``), and each window is
    planned by the whole-program planner with the running sums carried
    (:class:`~kernel.plan.models.linuxcnc.Carry`). A run of ``batch`` rows or more with no
    stop (a CAM program in one G64 run) is cut at joins too: each window's ``batch`` rows
    (up to the last join after which a window may start: no parabolic blend, whose two
    moves run at once, and not two blends next to circles in a row) are planned with the
    ``_CONTEXT`` rows before them and at least ``_MARGIN`` after them, the look-ahead's
    sums and the forward pass's running minimum carried: LinuxCNC's planner is local (its
    look-ahead reads ``OPT_DEPTH`` segments back, its joins and blends two rows, naive-CAM
    runs are one row by then), so the kept rows plan as in the whole program. A window
    with no such join is planned again with twice the rows."""
    builder = PathBuilder(model.build, file)
    errors = _Errors()
    carry = linuxcnc.Carry()
    prepared = linuxcnc.prepared_commands(commands)
    terms: list[int] = []  # path mode and G64 P of commands ``first`` on
    tols: list[float] = []
    first = 0
    pending = _Pending()
    ctx = 0  # the first rows of ``pending``, planned already: context of the next window
    margin = _MARGIN
    span = max(batch, 1)  # rows kept per window inside a run

    def noted() -> Iterator[canon.Command]:  # each command's path mode and G64 P kept
        for cmd, term, tol in prepared:
            terms.append(term)
            tols.append(tol)
            yield cmd

    def prepared_for(window: np.ndarray) -> linuxcnc.Prepared:
        """The path modes of ``window``'s commands."""
        upto = int(window["source"].max()) + 1 - first
        return linuxcnc.Prepared(
            [], np.array(terms[:upto], dtype=np.int8), np.array(tols[:upto]), first
        )

    def forget(rest: np.ndarray, idx: int) -> None:
        """Forget the path modes of the commands before ``rest``'s (``idx``: read so far)."""
        nonlocal first
        keep = int(rest["source"].min()) if len(rest) else idx
        del terms[: keep - first], tols[: keep - first]
        first = keep

    for raw, end, idx in _batches(builder, noted(), batch, errors):
        src = raw["source"] - first
        term = (
            np.asarray(terms[int(src.min()) :], dtype=np.int8)[src - src.min()] if len(raw) else src
        )
        cut, at_stop = pending.add(raw, term, end)
        plans: list[Plan] = []
        if cut > ctx:
            window, rows = pending.take(cut)
            prep = prepared_for(window)
            forget(rows, idx)
            carry.last, carry.stop_at_end, carry.skip, carry.own = end, at_stop, ctx, None
            ctx, margin, span = 0, _MARGIN, max(batch, 1)
            try:
                plans.append(linuxcnc.plan(Path(window, file), model.planning, prep, carry))
            except Diagnostic as diag:
                errors.note(diag, _RANK.get(diag.code, 4))
        while not end and pending.count >= ctx + span + margin:
            rows = pending.rows()
            if not (rows["kind"][ctx + span :] != HOLD).any():
                break  # the program's last move may be among them: wait for a stop
            window = rows[: ctx + span + margin]
            saved = replace(carry)
            carry.last, carry.stop_at_end, carry.skip, carry.own = False, False, ctx, ctx + span
            try:
                prep = prepared_for(window)
                plan = linuxcnc.plan(Path(window, file), model.planning, prep, carry)
            except Diagnostic as diag:
                errors.note(diag, _RANK.get(diag.code, 4))
                plan = None
            if plan is not None and carry.reach < 0:  # a run of blends next to circles
                carry, span = saved, 2 * span
                continue
            if plan is not None and carry.reach < _REACH:
                carry, margin = saved, 2 * margin  # lines blending emptied: more rows after
                continue
            cut = ctx + span if plan is None or carry.own is None else carry.own
            done = max(cut - _CONTEXT, 0)  # rows no later window plans again
            _, rows = pending.take(len(window), done)
            forget(rows, idx)
            ctx, span = cut - done, max(batch, 1)
            if plan is not None:
                plans.append(plan)
        for plan in plans:
            if errors.rank > 5 and errors.checked(plan):
                yield plan
    if errors.error is not None:
        raise errors.error


@dataclass(slots=True)
class StreamedPlan:
    """What ``cnc plan`` reports of a program planned window by window: the report, the
    cycle time, and the time per tool and per operation (``tools``, ``operations``: sums
    over the marks of the stream's :class:`~kernel.report.breakdown.Stretches`)."""

    report: Report
    total_time: float
    tools: StretchSums | None = None
    operations: StretchSums | None = None


class _Sampling:
    """Samples of the windows, reduced one sample late: the last sample made so far is held
    back, for it may be the program's last (the end point, at rest) even when it lies in an
    earlier window than the last (every later window lasting no time)."""

    def __init__(self, red: SampleReductions) -> None:
        self.red = red
        self.held: tuple[np.ndarray, Samples, bool] | None = None

    def add(self, plan: Plan, lo: int, hi: int, last: bool) -> None:
        """Sample and reduce samples ``lo .. hi - 1`` of ``plan``'s window (the first of
        them is not joined to the sample before: that one lies on other rows)."""
        seg = plan.path.segments
        for k, w in enumerate(sample_span(plan, lo, hi, last)):
            if self.held is not None:
                self.red.add(*self.held)
            n = len(w)
            if n > 1:
                self.red.add(seg, _rows(w, 0, n - 1), k > 0)
            self.held = (seg, _rows(w, n - 1, n), n > 1 or k > 0)

    def finish(self, end: np.ndarray, columns: list[int]) -> None:
        """Reduce the held sample as the program's last: at ``end`` (the last row's end
        point, the machine's axes ``columns``), at rest."""
        if self.held is None:
            return
        seg, w, joined = self.held
        _at_rest(w, end, columns)
        self.red.add(seg, w, joined)
        self.held = None


def _at_rest(w: Samples, end: np.ndarray, columns: list[int]) -> None:
    """Make ``w``'s last sample the program's last: at ``end`` (the last row's end point,
    the machine's axes ``columns``), at rest, as the whole-program sampler ends."""
    w.position[-1] = end[columns]
    w.velocity[-1] = w.acceleration[-1] = 0.0
    if w.jerk[-1].any():
        w.jerk[-1] = 0.0


def _rows(w: Samples, a: int, b: int) -> Samples:
    """Rows ``a .. b - 1`` of ``w`` (views)."""
    return Samples(
        w.period,
        w.t[a:b],
        w.position[a:b],
        w.velocity[a:b],
        w.acceleration[a:b],
        w.jerk[a:b],
        w.segment[a:b],
        w.source_line[a:b],
        w.axes,
    )


def _samples_before(t_end: float, period: float) -> int:
    """The number of samples ``k`` with ``float(k) * period < t_end``."""
    k = max(int(math.ceil(t_end / period)), 0)
    while k > 0 and float(k - 1) * period >= t_end:
        k -= 1
    while float(k) * period < t_end:
        k += 1
    return k


class _Totals:
    """What a streamed plan's report sums over its windows (added in the order the
    whole-program report adds them): the cycle-time parts, feed and rapid lengths, rows,
    the tool and operation stretches, and the cycle time so far; ``watch`` sees each
    window's plan."""

    def __init__(
        self,
        tools: list[Mark] | None,
        operations: list[Mark] | None,
        watch: Callable[[Plan], None] | None,
    ) -> None:
        self.tool_sums = StretchSums(tools) if tools is not None else None
        self.op_sums = StretchSums(operations) if operations is not None else None
        self.parts = [0.0] * len(PARTS)
        self.feed_length = self.rapid_length = 0.0
        self.rows = 0
        self.total = 0.0
        self.watch = watch

    def add(self, plan: Plan) -> None:
        seg = plan.path.segments
        cat, d, length = seg["category"], plan.duration, seg["length"]
        for j, kinds in enumerate(PARTS):
            self.parts[j] += float(d[np.isin(cat, kinds)].sum())
        self.feed_length += float(length[(cat == FEED) | (cat == PROBE)].sum())
        self.rapid_length += float(length[cat == RAPID].sum())
        self.rows += len(seg)
        for sums in (self.tool_sums, self.op_sums):
            if sums is not None:
                sums.add(plan)
        if self.watch is not None:
            self.watch(plan)
        self.total = plan.total_time

    def result(self, report: Report, total: float | None = None) -> StreamedPlan:
        """The streamed plan of ``report`` (``total``: the cycle time, if not the sum)."""
        t = self.total if total is None else total
        return StreamedPlan(report, t, self.tool_sums, self.op_sums)

    def report(self, red: SampleReductions) -> Report:
        """The report of the sampled windows (``red``) with these sums."""
        return red.report(
            CycleTime(self.total, *self.parts), self.feed_length, self.rapid_length, self.rows
        )


def measure_streamed(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
    tools: list[Mark] | None = None,
    operations: list[Mark] | None = None,
    batch: int = BATCH,
    watch: Callable[[Plan], None] | None = None,
) -> StreamedPlan:
    """:func:`kernel.simulation.plan_and_measure`'s report and cycle time, planned and
    sampled window by window (:func:`plan_windows`; ``machine`` a model :func:`streams`
    plans). ``tools`` and ``operations``: mark lists a
    :class:`~kernel.report.breakdown.Stretches` fills as ``commands`` pass it, summed.
    ``watch``: called with each window's plan (``cnc plan --compare``'s time per line)."""
    model = _Model.of(machine)
    red = SampleReductions(model.planning)
    period = model.planning.controller.interpolation_period
    sums = _Totals(tools, operations, watch)
    next_k = 0
    pending: Plan | None = None
    sampling = _Sampling(red)
    for plan in plan_windows(commands, machine, file, batch):
        if pending is not None:
            k = _samples_before(pending.total_time, period)
            sampling.add(pending, next_k, k, False)
            next_k = max(next_k, k)
        sums.add(plan)
        pending = plan
    if pending is None:  # no rows: the whole-program pipeline's empty plan
        _path, pl = plan_program([], machine, planning_machine(machine), file)
        return sums.result(measure_windows(pl, sample_windows(pl)), pl.total_time)
    count = int(math.ceil(sums.total / period - 1e-9)) + 1
    sampling.add(pending, next_k, count, True)
    last_row = pending.path.segments[-1]
    sampling.finish(last_row["end"], [AXIS_NAMES.index(a) for a in pending.machine.axis_names])
    return sums.result(sums.report(red))


__all__ = ["StreamedPlan", "measure_streamed", "plan_windows", "streams"]
