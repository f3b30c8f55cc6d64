"""``cnc plan`` in bounded memory for the book model's S-curve acc/dec (issue 19), with the
numbers of the whole-program pipeline (kernel.simulation), as kernel.stream does for the
trapezoid.

What the S-curve planning needs of the whole program (kernel.plan.planner ``plan``) is one
number: ``d0``, the distance covered in ``T_f`` at the fastest speed cap of any moving row
(:func:`~kernel.plan.planner.smoothing_reach`). Everything else reaches a bounded distance
along the path. So the program is read twice: :func:`smoothing_reach_of` builds, blends
and caps it window by window and keeps the largest cap; then :func:`measure_scurve` plans
and samples it window by window with ``d0`` fixed:

* **Cuts** (kernel.path.curvature ``cut_for_machine``): a line is cut next to a capped
  curvature joint at either end, which reads the row before and the row after it; the
  last blended row waits for the next batch.
* **Erosion** (:func:`~kernel.plan.planner.smoothed_limits`): a row's eroded caps read the
  rows within ``d0`` of the rows within ``d0`` of it. The rows are held until the path
  known after a row's second-level reach is longer than ``d0``, and those rows are kept
  behind it as context (:class:`_Erosion`); the caps are computed over all the rows held,
  with the path positions ``s`` of the whole program (a running sum carried in order), so
  each final row's result is the whole program's bit for bit.
* **Look-ahead, profiles, times**: kernel.stream's look-ahead (the same junction speeds as
  the whole program's backward and forward passes), then trapezoids, the ``T_f`` pause at
  every stop and the running start times.
* **Samples**: the smoothed motion at ``t`` is the trapezoid's averaged over
  ``[t - T_f, t]`` (kernel.interp.interpolate), through the running integral ``I`` of the
  path position, and its segment is found by its smoothed position, which lags behind.
  A window's samples are made from a table of the window's rows, the earlier rows back to
  ``T_f`` before its start (and back along the path as far as the smoothed position can
  lag, with rounding), and the later rows known so far (their geometry only: the samples
  before the window's end never reach their pieces), with ``I`` carried to the table's
  first row. The pair of samples across two windows is checked for chord error in the
  later window's table (:class:`_Reducer`).

Memory holds the rows within two ``d0`` of the rows being planned, the look-ahead, the rows
of ``T_f`` of motion, and one window of samples; it does not grow with the program's
length (a program whose moves are far shorter than ``d0`` holds more rows: ``d0`` is
``T_f`` times the fastest cap, a few mm to a few tens of mm).

The report equals the whole-program report as kernel.stream's does: bit for bit but the
cycle-time parts and path lengths, summed window by window (about 1e-15 relative).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator

import numpy as np

import kernel.ir.canon as canon
from kernel.axes.accdec import planning_machine
from kernel.diagnostics import Diagnostic
from kernel.interp.interpolate import pieces, sample_span, sample_windows
from kernel.interp.samples import Samples
from kernel.machine import AXIS_NAMES, Machine, filter_time
from kernel.path.blend import blend_rows
from kernel.path.builder import PathBuilder
from kernel.path.curvature import cut_for_machine
from kernel.path.segments import HOLD, SEGMENT_DTYPE, Path
from kernel.plan.planner import (
    Plan,
    Profiles,
    junction_caps,
    segment_limits,
    smoothed_limits,
    smoothing_reach,
)
from kernel.plan.strategy import plan_program
from kernel.report.breakdown import Mark
from kernel.report.measure import (
    SampleReductions,
    measure_windows,
    segment_chord_error,
)
from kernel.stream import (
    _RANK,
    BATCH,
    StreamedPlan,
    _at_rest,
    _batches,
    _Clock,
    _Errors,
    _Lookahead,
    _rows,
    _samples_before,
    _Totals,
    _window_plan,
)

_EPS = float(np.finfo(float).eps)


def smoothed(machine: Machine) -> bool:
    """Whether ``machine`` is the book model with S-curve acc/dec (planned here, not by
    kernel.stream's :func:`~kernel.stream.plan_windows`)."""
    if machine.controller.model != "book":
        return False
    planning = planning_machine(machine)
    return "scurve" in (machine.controller.accdec, planning.controller.accdec)


def _blended(
    machine: Machine,
    commands: Iterable[canon.Command],
    file: str | None,
    batch: int,
    errors: _Errors,
) -> Iterator[tuple[np.ndarray, bool]]:
    """The blended rows of ``commands``, a batch at a time (kernel.stream's windows: the
    last raw row waits for the corner after it), and whether the program has ended."""
    builder = PathBuilder(machine, file)
    held = np.zeros(0, SEGMENT_DTYPE)
    held_context = False
    for raw, end, _ in _batches(builder, iter(commands), batch, errors):
        raw = np.concatenate([held, raw]) if len(held) else raw
        first = 1 if len(held) and held_context else 0
        cut = len(raw) if end else max(len(raw) - 1, first)
        rows = blend_rows(raw, first, cut)
        held, held_context = raw[max(cut - 1, 0) :], cut > 0
        yield rows, end


def smoothing_reach_of(
    commands: Iterable[canon.Command],
    machine: Machine,
    file: str | None = None,
    batch: int = BATCH,
) -> float:
    """``d0`` of the whole program (:func:`~kernel.plan.planner.smoothing_reach`), found
    window by window: a first pass over the program. A window with an error is skipped
    (the second pass raises that error, which comes before anything ``d0`` changes)."""
    planning = planning_machine(machine)
    tf = filter_time(planning) if planning.controller.accdec == "scurve" else 0.0
    reach = 0.0
    errors = _Errors()
    for rows, _end in _blended(machine, commands, file, batch, errors):
        if not len(rows) or tf <= 0:
            continue
        try:
            cap, _acc = segment_limits(Path(rows, file), planning)
        except Diagnostic:
            continue
        reach = max(reach, smoothing_reach(rows, cap, tf))
    return reach


class _Cutter:
    """Lines cut next to curvature joints (kernel.path.curvature ``cut_for_machine``), a
    batch of blended rows at a time: a row is cut once the row after it is known."""

    def __init__(self, machine: Machine, file: str | None) -> None:
        self.machine, self.file = machine, file
        self.on = machine.controller.accdec == "scurve"
        self.before: np.ndarray | None = None  # the last row cut (context)
        self.tail = np.zeros(0, SEGMENT_DTYPE)

    def cut(self, rows: np.ndarray, end: bool) -> np.ndarray:
        if not self.on:
            return rows
        rows = np.concatenate([self.tail, rows]) if len(self.tail) else rows
        upto = len(rows) if end else max(len(rows) - 1, 0)
        self.tail = rows[upto:]
        if not upto:
            return rows[:0]
        sub = rows[: upto + 1]
        first = 0
        if self.before is not None:
            sub, first = np.concatenate([self.before, sub]), 1
        self.before = rows[upto - 1 : upto]
        marked = sub.copy()
        marked["source"] = np.arange(len(sub))  # which row each piece comes from
        out = cut_for_machine(Path(marked, self.file), self.machine).segments
        which = out["source"]
        out = out[(which >= first) & (which < first + upto)]
        out["source"] = sub["source"][out["source"]]
        return out


class _Erosion:
    """Rows whose S-curve caps are not all final yet, after the rows kept as their context
    (``first``: the first not given yet): segments, caps and accelerations, the junction
    cap at each one's start, their path positions (and the last one's end)."""

    def __init__(self, planning: Machine, file: str | None, d0: float) -> None:
        self.planning, self.file, self.d0 = planning, file, d0
        self.tf = filter_time(planning) if planning.controller.accdec == "scurve" else 0.0
        self.rows = np.zeros(0, SEGMENT_DTYPE)
        self.cap = np.zeros(0)
        self.acc = np.zeros(0)
        self.jcap = np.zeros(0)
        self.s = np.zeros(1)
        self.first = 0
        self.given = 0  # rows given so far (the program's row index of ``first``)
        self.cap_before = 0.0  # final cap of the last row given

    def push(self, rows: np.ndarray, cap: np.ndarray, acc: np.ndarray) -> None:
        if not len(rows):
            return
        if len(self.rows):
            seg = np.concatenate([self.rows[-1:], rows])
            both = (np.concatenate([self.cap[-1:], cap]), np.concatenate([self.acc[-1:], acc]))
            jc = junction_caps(Path(seg, self.file), self.planning, *both)[1:-1]
        else:
            jc = np.concatenate([[0.0], junction_caps(Path(rows), self.planning, cap, acc)[1:-1]])
        s = np.cumsum(np.concatenate([self.s[-1:], rows["length"]]))
        self.rows = np.concatenate([self.rows, rows])
        self.cap = np.concatenate([self.cap, cap])
        self.acc = np.concatenate([self.acc, acc])
        self.jcap = np.concatenate([self.jcap, jc])
        self.s = np.concatenate([self.s, s[1:]])

    def pending(self) -> np.ndarray:
        """The rows not given yet."""
        return self.rows[self.first :]

    def pop(self, end: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """The rows now final (all at the program's ``end``): rows, caps, accelerations and
        the junction cap at each one's start; ``None`` if none is."""
        n, f0, s, d0 = len(self.rows), self.first, self.s, self.d0
        if n == f0:
            return None
        margin = 1e-9 * (abs(float(s[-1])) + d0 + 1.0)
        reach = d0 + margin
        if end:
            f = n
        elif not math.isfinite(reach):
            return None
        else:  # the last row within reach of each pending row, and the path past it
            far = np.searchsorted(s[:-1], s[f0 + 1 :] + reach, "right") - 1
            ok = s[-1] > s[far + 1] + reach
            f = f0 + (int(np.argmin(ok)) if not ok.all() else len(ok))
            if f == f0:
                return None
        cap, jcap, acc = self.cap, self.jcap, self.acc
        if self.tf > 0:
            jc = np.concatenate([self.jcap, [0.0]])
            cap, jcap, acc = smoothed_limits(self.rows, self.planning, s, cap, acc, jc, d0)
        cap, acc, jcap = cap[f0:f], acc[f0:f], jcap[f0:f].copy()
        if self.tf > 0:  # the junction caps lowered to their two rows' final caps
            before = np.concatenate([[self.cap_before], cap[:-1]])
            inner = np.minimum(jcap, np.minimum(before, cap))
            if self.given == 0:
                inner[0] = jcap[0]
            jcap = inner
        out = (self.rows[f0:f], cap, acc, jcap)
        self.cap_before = float(cap[-1])
        self.given += f - f0
        # keep the rows within reach of the rows within reach of the next one
        lo1 = int(np.searchsorted(s[1:], s[f] - reach, "left"))
        keep = min(int(np.searchsorted(s[1:], s[lo1] - reach, "left")), f, n - 1)
        self.rows, self.cap, self.acc = self.rows[keep:], self.cap[keep:], self.acc[keep:]
        self.jcap, self.s, self.first = self.jcap[keep:], s[keep:], f - keep
        return out


def scurve_windows(
    commands: Iterable[canon.Command],
    machine: Machine,
    d0: float,
    file: str | None = None,
    batch: int = BATCH,
) -> Iterator[tuple[Plan, np.ndarray]]:
    """The plan of ``commands`` on ``machine`` (:func:`smoothed`) as consecutive windows
    of rows, given ``d0`` (:func:`smoothing_reach_of`), each with the rows after it known
    so far (not final: their geometry only). Raises the error planning the whole program
    would raise, once the windows before it have been given."""
    planning = planning_machine(machine)
    tf = filter_time(planning) if planning.controller.accdec == "scurve" else 0.0
    cutter = _Cutter(machine, file)
    erosion = _Erosion(planning, file, d0)
    look = _Lookahead(planning.controller.lookahead)
    errors = _Errors()
    clock = _Clock()
    for blended, end in _blended(machine, commands, file, batch, errors):
        rows = cutter.cut(blended, end)
        if len(rows):
            try:
                cap, acc = segment_limits(Path(rows, file), planning)
            except Diagnostic as diag:
                errors.note(diag, _RANK.get(diag.code, 4))
                continue
        if errors.rank <= 5:
            continue
        if len(rows):
            erosion.push(rows, cap, acc)
        eroded = erosion.pop(end)
        if eroded is not None:
            rows, cap, acc, jcap = eroded
            moving = rows["kind"] != HOLD
            look.push(rows, cap, np.where(moving, acc, 0.0), np.square(jcap))
        final = look.pop(end and not len(erosion.pending()))
        if final is not None:
            plan = _window_plan(planning, file, *final, clock, tf)
            if errors.checked(plan):
                yield plan, np.concatenate([look.rows, erosion.pending()])
    if errors.error is not None:
        raise errors.error


def _joined(plans: list[Plan], later: np.ndarray, machine: Machine, file: str | None) -> Plan:
    """One plan of consecutive window plans, and the rows ``later`` after them (at rest
    at the last one's end: their pieces start when it ends, so no sample before reaches
    them)."""
    n = len(later)
    end_t = plans[-1].total_time
    s_end = plans[-1].s_start[-1] + plans[-1].path.segments["length"][-1]
    s_later = np.cumsum(np.concatenate([[s_end], later["length"]]))[:-1]  # in order
    zero = np.zeros(n)
    prof = Profiles(
        *(np.concatenate([getattr(p.profiles, f) for p in plans] + [zero]) for f in _PROFILE)
    )

    def cat(name: str, extra: np.ndarray | list[float]) -> np.ndarray:
        return np.concatenate([getattr(p, name) for p in plans] + [np.asarray(extra, float)])

    v = np.concatenate([p.v_junction[:-1] for p in plans] + [[plans[-1].v_junction[-1]], zero])
    return Plan(
        Path(np.concatenate([p.path.segments for p in plans] + [later]), file),
        machine,
        v,
        cat("cap", zero),
        prof,
        cat("pause", zero),
        cat("duration", zero),
        cat("t_start", np.full(n, end_t)),
        cat("s_start", s_later),
        plans[-1].filter_time,
    )


_PROFILE = ("v_start", "v_end", "v_peak", "accel", "decel", "t_acc", "t_cruise", "t_dec")


class _Reducer:
    """Samples reduced (kernel.report.measure ``SampleReductions``) from tables that
    change from window to window, one sample late: the last sample made is held back, for
    it may be the program's last (the end point, at rest). ``base``: the program's row
    index of a table's first row, by which a sample's segment is found in the next table
    (the pair across two windows is checked for chord error there)."""

    def __init__(self, red: SampleReductions) -> None:
        self.red = red
        self.held: tuple[np.ndarray, int, Samples] | None = None
        self.table: tuple[np.ndarray, int] | None = None
        self.last: Samples | None = None

    def add(self, seg: np.ndarray, base: int, w: Samples) -> None:
        n = len(w)
        if not n:
            return
        if self.held is not None:
            self._reduce(*self.held)
        if n > 1:
            self._reduce(seg, base, _rows(w, 0, n - 1))
        self.held = (seg, base, _rows(w, n - 1, n))

    def _reduce(self, seg: np.ndarray, base: int, w: Samples) -> None:
        joined = self.table is not None and self.table[0] is seg
        if not joined and self.table is not None and self.last is not None:
            k = int(self.last.segment[-1])
            row = k + self.table[1] - base
            if k >= 0 and 0 <= row < len(seg):  # else a row not in this table: not w's
                pair = _pair(self.last, w)
                pair.segment[0] = row
                self.red.chord = max(self.red.chord, segment_chord_error(seg, pair))
        self.red.add(seg, w, joined)
        self.table, self.last = (seg, base), w

    def finish(self, end: np.ndarray, columns: list[int]) -> None:
        """Reduce the held sample as the program's last: at ``end``, at rest."""
        if self.held is None:
            return
        seg, base, w = self.held
        _at_rest(w, end, columns)
        self._reduce(seg, base, w)
        self.held = None


def _pair(a: Samples, b: Samples) -> Samples:
    """The last sample of ``a`` and the first of ``b``, as one window (new arrays)."""

    def two(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.concatenate([x[-1:], y[:1]])

    return Samples(
        b.period,
        two(a.t, b.t),
        two(a.position, b.position),
        two(a.velocity, b.velocity),
        two(a.acceleration, b.acceleration),
        two(a.jerk, b.jerk),
        two(a.segment, b.segment),
        two(a.source_line, b.source_line),
        b.axes,
    )


class _Sampler:
    """The windows' samples: each window is sampled with the earlier windows it may reach
    (``T_f`` back in time, and back along the path as far as the smoothed position lags)
    and the rows after it, with the integral ``I`` carried."""

    def __init__(self, red: SampleReductions, machine: Machine, file: str | None) -> None:
        self.reducer = _Reducer(red)
        self.machine, self.file = machine, file
        self.period = machine.controller.interpolation_period
        self.context: list[tuple[Plan, int, float]] = []  # plan, first row, I at its start
        self.next_k = 0
        self.rows = 0
        self.i_next = 0.0  # I at the next window's start

    def add(self, plan: Plan, later: np.ndarray, last: bool) -> None:
        """Sample ``plan`` (the next window; ``later``: the rows after it known so far)
        up to the next window's start (all at the program's ``last`` window)."""
        self.context.append((plan, self.rows, self.i_next))
        self.rows += len(plan.path.segments)
        plans = [p for p, _, _ in self.context]
        base, i_start = self.context[0][1], self.context[0][2]
        table = _joined(plans, later if not last else later[:0], self.machine, self.file)
        tf = plan.filter_time
        end_t = plan.total_time
        if last:
            count = int(math.ceil(end_t / self.period - 1e-9)) + 1
        else:
            count = _samples_before(end_t, self.period)
        seg = table.path.segments
        for w in sample_span(table, self.next_k, count, last, i_start=i_start):
            self.reducer.add(seg, base, w)
        self.next_k = max(self.next_k, count)
        own = len(seg) - len(later if not last else later[:0])
        if tf <= 0:  # a trapezoid: no integral, no context
            self.context = []
            return
        pc = pieces(table, True, i_start)
        assert pc.i0 is not None
        self.i_next = pc.i_end if own == len(seg) else float(pc.i0[4 * own])
        firsts = np.cumsum([0] + [len(p.path.segments) for p in plans])
        self.context = [
            (p, b, float(pc.i0[4 * int(firsts[j])])) for j, (p, b, _) in enumerate(self.context)
        ]
        self._trim(table, own, end_t, tf)

    def _slack(self, s: float, rows: int, tf: float) -> float:
        """How far the smoothed position may stray, by rounding, from the trapezoid's at
        ``T_f`` before (path position ``s``; ``rows``: rows within ``T_f``): the integral's
        sums over the pieces between, at its magnitude."""
        count = 1e3 + 8.0 * rows
        return 1e-6 * (1.0 + abs(s)) + count * _EPS * abs(self.i_next) / tf

    def reaches(self, plan: Plan, after: np.ndarray) -> bool:
        """Whether the rows ``after`` ``plan`` reach past its end as far as its samples'
        smoothed positions may (a moving row ends beyond that)."""
        tf = plan.filter_time
        if tf <= 0:
            return True
        moving = np.flatnonzero(after["kind"] != HOLD)
        if not moving.size:
            return False
        seg = plan.path.segments
        rows = len(seg) + sum(len(p.path.segments) for p, _, _ in self.context)
        beyond = float(np.cumsum(after["length"])[moving[-1]])
        return beyond > 2.0 * self._slack(float(plan.s_start[-1] + seg["length"][-1]), rows, tf)

    def _trim(self, table: Plan, own: int, end_t: float, tf: float) -> None:
        """Forget the windows the next one cannot reach."""
        seg = table.path.segments[:own]
        t_end = table.t_start[:own] + table.duration[:own]
        s_end = table.s_start[:own] + seg["length"]
        slack = self._slack(float(s_end[-1]), len(seg), tf)
        first = int(np.searchsorted(t_end, end_t - tf * (1.0 + 1e-9) - 1e-9, "left"))
        first = min(first, own - 1)
        back = float(table.s_start[first]) - slack
        first = min(first, int(np.searchsorted(s_end, back, "left")))
        drop = 0
        rows = 0
        for p, _, _ in self.context:
            n = len(p.path.segments)
            if rows + n > first:
                break
            rows += n
            drop += 1
        del self.context[:drop]

    def finish(self, end: np.ndarray, columns: list[int]) -> None:
        self.reducer.finish(end, columns)


def measure_scurve(
    commands: Iterable[canon.Command],
    machine: Machine,
    d0: float,
    file: str | None = None,
    tools: list[Mark] | None = None,
    operations: list[Mark] | None = None,
    batch: int = BATCH,
    watch: Callable[[Plan], None] | None = None,
) -> StreamedPlan:
    """:func:`kernel.simulation.plan_and_measure`'s report and cycle time for a machine
    :func:`smoothed` says is planned here, window by window, ``d0`` being the program's
    :func:`smoothing_reach_of` (a first pass over it). ``tools`` and ``operations``: mark
    lists a :class:`~kernel.report.breakdown.Stretches` fills as ``commands`` pass it,
    summed. ``watch``: called with each window's plan."""
    planning = planning_machine(machine)
    red = SampleReductions(planning)
    sums = _Totals(tools, operations, watch)
    sampler = _Sampler(red, planning, file)
    queue: list[Plan] = []  # windows not sampled yet: at least the last one given
    later = np.zeros(0, SEGMENT_DTYPE)
    for plan, later in scurve_windows(commands, machine, d0, file, batch):
        sums.add(plan)
        queue.append(plan)
        while len(queue) > 1:
            after = np.concatenate([q.path.segments for q in queue[1:]] + [later])
            if not sampler.reaches(queue[0], after):
                break
            sampler.add(queue.pop(0), after, False)
    if not queue:  # no rows: the whole-program pipeline's empty plan
        _path, pl = plan_program([], machine, planning, file)
        return sums.result(measure_windows(pl, sample_windows(pl)), pl.total_time)
    while queue:
        plan = queue.pop(0)
        after = np.concatenate([q.path.segments for q in queue] + [later[:0]])
        sampler.add(plan, after, not queue)
    last_row = plan.path.segments[-1]
    sampler.finish(last_row["end"], [AXIS_NAMES.index(a) for a in planning.axis_names])
    return sums.result(sums.report(red))


__all__ = [
    "measure_scurve",
    "scurve_windows",
    "smoothed",
    "smoothing_reach_of",
]
