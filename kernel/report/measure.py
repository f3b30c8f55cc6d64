"""Measurements of a planned and sampled program (DESIGN.md, kernel.report.measure).

Cycle time split into cutting (feed and probe moves), rapid, dwell, tool change and other
stand-stills (spindle orientation, program stops); path lengths; peak axis velocity,
acceleration and jerk; the chord error of arcs between consecutive samples (book eq. 3.38,
``EH = R - |chord midpoint|``); and every place a sample exceeds an axis limit (velocity,
acceleration, jerk when the profile is jerk-limited, travel), with the program line.
Following and contour error of the servo are measured by the servo stage (issue 4).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import asdict, dataclass, field

import numpy as np

from kernel.interp.samples import Samples
from kernel.machine import Machine
from kernel.path.segments import (
    ARC,
    DWELL,
    FEED,
    MACHINE_FUNCTION,
    ORIENT,
    PROBE,
    RAPID,
    STOP,
    TOOL_CHANGE,
)
from kernel.plan.planner import Plan

#: relative and absolute slack before a sample counts as over a limit (rounding)
RTOL, ATOL = 1e-6, 1e-9


@dataclass(frozen=True, slots=True)
class CycleTime:
    """Seconds per kind of activity; ``total`` is their sum."""

    total: float
    cutting: float
    rapid: float
    dwell: float
    tool_change: float
    other: float


@dataclass(frozen=True, slots=True)
class LimitHit:
    """A run of consecutive samples over one axis limit."""

    axis: str
    kind: str  # velocity, acceleration, jerk, travel
    value: float  # the worst value in the run
    limit: float
    time: float  # first sample of the run, s
    samples: int  # length of the run
    line: int  # program line of the first sample (0: unknown)


@dataclass(frozen=True, slots=True)
class Report:
    """Everything :func:`measure` finds; plain data (``to_dict`` for JSON)."""

    cycle: CycleTime
    feed_length: float
    rapid_length: float
    segments: int
    samples: int
    peak_velocity: dict[str, float]
    peak_acceleration: dict[str, float]
    peak_jerk: dict[str, float]
    chord_error: float
    hits: list[LimitHit] = field(default_factory=list)
    hits_total: int = 0

    def to_dict(self) -> dict[str, object]:
        return asdict(self)


def cycle_time(plan: Plan) -> CycleTime:
    """Time per category from the plan (S-curve pauses count with their segment)."""
    cat = plan.path.segments["category"]
    d = plan.duration

    def part(mask: np.ndarray) -> float:
        return float(d[mask].sum())

    cutting = part((cat == FEED) | (cat == PROBE))
    rapid = part(cat == RAPID)
    dwell = part(cat == DWELL)
    tool = part(cat == TOOL_CHANGE)
    total = plan.total_time
    other = part((cat == ORIENT) | (cat == STOP) | (cat == MACHINE_FUNCTION))
    return CycleTime(total, cutting, rapid, dwell, tool, other)


def chord_error(plan: Plan, samples: Samples) -> float:
    """Largest ``|R - |midpoint - centre||`` over consecutive samples on the same arc."""
    return segment_chord_error(plan.path.segments, samples)


def segment_chord_error(seg: np.ndarray, samples: Samples) -> float:
    """:func:`chord_error` with the segment table the samples' ``segment`` indexes."""
    k = samples.segment
    if len(k) < 2 or "x" not in samples.axes:
        return 0.0
    on_arc = np.ascontiguousarray(seg["kind"]) == ARC
    same = k[1:] == k[:-1]
    same &= k[:-1] >= 0
    same &= on_arc.take(k[:-1], mode="wrap")  # -1 (holds) wraps, and is masked above
    idx = np.flatnonzero(same)
    if not idx.size:
        return 0.0
    cols = [samples.axes.index(a) for a in ("x", "y", "z") if a in samples.axes]
    mid = 0.5 * (samples.position[idx] + samples.position[idx + 1])[:, cols]
    rows = k[idx]
    centre = seg["centre"][rows][:, : len(cols)]
    normal = seg["normal"][rows][:, : len(cols)]
    rel = mid - centre
    rel = rel - np.sum(rel * normal, axis=1)[:, None] * normal
    r_mid = np.linalg.norm(rel, axis=1)
    r_ref = 0.5 * (seg["radius"][rows] + seg["radius_end"][rows])
    tol = np.abs(seg["radius_end"][rows] - seg["radius"][rows])
    return float(np.max(np.clip(np.abs(r_ref - r_mid) - tol, 0.0, None)))


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of runs of True."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(m)
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1)
    return starts, ends - starts


def _column_extremes(arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-column maximum and minimum of an (n, k) array, column by column (a strided
    column reduces an order of magnitude faster than ``arr.max(axis=0)``)."""
    if not len(arr):
        return np.zeros(arr.shape[1]), np.zeros(arr.shape[1])
    cols = range(arr.shape[1])
    return np.array([arr[:, j].max() for j in cols]), np.array([arr[:, j].min() for j in cols])


def _peak(extremes: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """``max |x|`` per column from the extremes (exact; NaN propagates)."""
    hi, lo = extremes
    return np.maximum(hi, -lo)


@dataclass(frozen=True, slots=True)
class DifferencePeaks:
    """Peak axis values from the sampled positions alone, per axis (mm/s, mm/s^2)."""

    velocity: np.ndarray  # max |first difference| / T
    acceleration: np.ndarray  # max |second difference| / T^2
    acceleration_p999: np.ndarray  # 99.9th percentile of |second difference| / T^2


def differences(t: np.ndarray, pos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Axis speed and acceleration between consecutive samples (rows of ``pos`` at times
    ``t``): first differences over the time step, and second differences over the mean of
    the two steps. Every servo period a discrete-time control (LinuxCNC's motion module)
    commands a position; these are the speed and acceleration those positions ask of the
    axis, velocity steps at kinks included."""
    dt = np.diff(t)[:, None]
    step = np.diff(pos, axis=0)
    v = np.divide(step, dt, out=np.zeros_like(step), where=dt > 0)
    if len(v) < 2:
        return v, np.zeros((0, pos.shape[1]))
    mid = 0.5 * (dt[1:] + dt[:-1])
    dv = np.diff(v, axis=0)
    return v, np.divide(dv, mid, out=np.zeros_like(dv), where=mid > 0)


def per_period_peaks(machine: Machine) -> bool:
    """Whether the report's peak speed and acceleration are those of the commanded joint
    positions period by period (:func:`differences` of :func:`servo_waypoints`) rather than
    of the planned profile: so for the ``linuxcnc`` model, whose motion module commands a
    position every servo period and whose recorded motion (halsampler, halscope) shows a
    kink's velocity step spread over three periods by its interpolator
    (docs/machine-profile.md, "Controller models")."""
    return machine.controller.model == "linuxcnc"


def servo_waypoints(position: np.ndarray) -> np.ndarray:
    """The joint positions LinuxCNC's motion module commands from its planner's positions
    (rows, one per servo period): every joint goes through cubic.c's interpolator
    (control.c), which with the trajectory period equal to the servo period outputs the
    spline's way points, ``(x[k-1] + 4 x[k] + x[k+1]) / 6`` (cubic.c ``wayPoint``), one
    period late. A constant acceleration passes unchanged; a velocity step at a kink or a
    blend arc's entry is spread over three periods (its peak to two thirds), and a circle
    of ``d`` radians per period is run on a radius ``(2 + cos d) / 3`` of its own (a blend
    arc of 0.017 mm at 2.7 mm/s: 0.4 % smaller, as recorded). The first and last rows are
    held (the machine stands still before and after)."""
    if len(position) < 2:
        return position.copy()
    return spline_points(np.concatenate([position[:1], position, position[-1:]]))


def spline_points(rows: np.ndarray) -> np.ndarray:
    """cubic.c ``wayPoint`` of every row but the first and last, from its two neighbours:
    ``(x[k-1] + 4 x[k] + x[k+1]) / 6`` (:func:`servo_waypoints` without the held ends)."""
    return (rows[:-2] + 4.0 * rows[1:-1] + rows[2:]) / 6.0


def difference_peaks(
    samples: Samples, resolution: float = 0.0, waypoints: bool = False
) -> DifferencePeaks:
    """Peak axis speed and acceleration as a recording of commanded positions gives them:
    the first and second differences of the positions over the sampling period, with the
    positions rounded to ``resolution`` first (0: not rounded), over the stretch from the
    first to the last period in which an axis moved, and the 99.9th percentile of the
    acceleration (single-period spikes left out). This is how LinuxCNC's goldens are reduced
    (tests/data/lcnc_tp/make_goldens.py: a HAL sampler every 1 ms servo period, printed to
    1e-6 mm), so a model's samples compare with them like for like; the analytic peaks of
    :func:`measure` hold no rounding and no discretisation. ``waypoints``: the positions
    as LinuxCNC's motion module commands them from its planner's (:func:`servo_waypoints`),
    the way a recording of a LinuxCNC machine has them."""
    pos = servo_waypoints(samples.position) if waypoints else samples.position
    if resolution > 0:
        pos = np.round(pos / resolution) * resolution
    nax = pos.shape[1]
    zero = np.zeros(nax)
    if len(pos) < 2:
        return DifferencePeaks(zero, zero, zero)
    step = np.diff(pos, axis=0)
    moving = np.flatnonzero(np.any(np.abs(step) > 1e-9, axis=1))
    if not moving.size:
        return DifferencePeaks(zero, zero, zero)
    span = slice(moving[0], moving[-1] + 2)
    v, a = differences(samples.t[span], pos[span])
    a = np.abs(a)
    if not len(a):
        return DifferencePeaks(np.abs(v).max(axis=0), zero, zero)
    return DifferencePeaks(np.abs(v).max(axis=0), a.max(axis=0), np.percentile(a, 99.9, axis=0))


def limit_hits(
    plan: Plan,
    samples: Samples,
    max_hits: int = 50,
    extremes: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
) -> tuple[list[LimitHit], int]:
    """Runs of samples over an axis limit: the first ``max_hits`` and the total count.

    A column is scanned for runs only when its extreme value is over the limit (the usual
    case has no hit at all). ``extremes``: per array name (``position``, ``velocity``,
    ``acceleration``, ``jerk``) the per-axis maxima and minima, when already known."""
    machine = plan.machine
    checks = ["velocity", "acceleration"]
    if machine.controller.accdec == "scurve":
        checks.append("jerk")
    known = dict(extremes or {})
    for name in ("position", *checks):
        if name not in known:
            known[name] = _column_extremes(getattr(samples, name))
    hits: list[LimitHit] = []
    total = 0
    if not len(samples):
        return hits, total
    for j, name in enumerate(samples.axes):
        ax = machine.axis(name)
        for kind in checks:
            lim = float(getattr(ax, kind))
            threshold = lim * (1 + RTOL) + ATOL
            if not _peak(known[kind])[j] > threshold:
                continue
            col = np.abs(getattr(samples, kind)[:, j])
            starts, lens = _runs(col > threshold)
            total += len(starts)
            for s, n in zip(starts[:max_hits], lens[:max_hits], strict=False):
                worst = float(col[s : s + n].max())
                hits.append(
                    LimitHit(
                        name,
                        kind,
                        worst,
                        lim,
                        float(samples.t[s]),
                        int(n),
                        int(samples.source_line[s]),
                    )
                )
        hi, lo = known["position"][0][j], known["position"][1][j]
        pos = samples.position[:, j]
        for kind, over, lim in (
            ("travel", hi > ax.max + ATOL, ax.max),
            ("travel", lo < ax.min - ATOL, ax.min),
        ):
            if not over:
                continue
            mask = pos > ax.max + ATOL if lim == ax.max else pos < ax.min - ATOL
            starts, lens = _runs(mask)
            total += len(starts)
            for s, n in zip(starts[:max_hits], lens[:max_hits], strict=False):
                seg = pos[s : s + n]
                worst = float(seg.max() if lim == ax.max else seg.min())
                hits.append(
                    LimitHit(
                        name,
                        kind,
                        worst,
                        float(lim),
                        float(samples.t[s]),
                        int(n),
                        int(samples.source_line[s]),
                    )
                )
    hits.sort(key=lambda h: h.time)
    return hits[:max_hits], total


def measure(plan: Plan, samples: Samples) -> Report:
    """Cycle time, lengths, peaks, chord error and limit hits of a sampled plan."""
    seg = plan.path.segments
    cat = seg["category"]
    length = seg["length"]

    extremes = {
        name: _column_extremes(getattr(samples, name))
        for name in ("position", "velocity", "acceleration", "jerk")
    }

    def peaks(name: str) -> dict[str, float]:
        m = _peak(extremes[name])
        return {a: float(v) for a, v in zip(samples.axes, m, strict=True)}

    hits, total = limit_hits(plan, samples, extremes=extremes)
    velocity, acceleration = peaks("velocity"), peaks("acceleration")
    if per_period_peaks(plan.machine) and len(samples) > 1:
        v, a = differences(samples.t, servo_waypoints(samples.position))
        velocity = dict(zip(samples.axes, map(float, np.abs(v).max(axis=0)), strict=True))
        a_max = np.abs(a).max(axis=0) if len(a) else np.zeros(len(samples.axes))
        acceleration = dict(zip(samples.axes, map(float, a_max), strict=True))
    return Report(
        cycle=cycle_time(plan),
        feed_length=float(length[(cat == FEED) | (cat == PROBE)].sum()),
        rapid_length=float(length[cat == RAPID].sum()),
        segments=len(seg),
        samples=len(samples),
        peak_velocity=velocity,
        peak_acceleration=acceleration,
        peak_jerk=peaks("jerk"),
        chord_error=chord_error(plan, samples),
        hits=hits,
        hits_total=total,
    )


class _Runs:
    """Runs of samples over one limit of one axis, across windows: the first ``keep`` runs
    (merged where a run crosses a window boundary) and how many there are."""

    __slots__ = ("axis", "kind", "limit", "high", "keep", "found", "total", "open")

    def __init__(self, axis: str, kind: str, limit: float, high: bool, keep: int) -> None:
        self.axis, self.kind, self.limit, self.high, self.keep = axis, kind, limit, high, keep
        self.found: list[list[float]] = []  # [value, time, samples, line]
        self.total = 0
        self.open = False  # the last window ended inside a run

    def add(self, values: np.ndarray, mask: np.ndarray, samples: Samples) -> None:
        starts, lens = _runs(mask)
        if self.open and len(starts) and starts[0] == 0:
            n0 = int(lens[0])
            worst = values[:n0].max() if self.high else values[:n0].min()
            if self.found and self.total <= self.keep:
                last = self.found[-1]
                last[0] = max(last[0], worst) if self.high else min(last[0], worst)
                last[2] += n0
            starts, lens = starts[1:], lens[1:]
        self.open = bool(mask[-1]) if len(mask) else self.open
        for s, n in zip(starts, lens, strict=True):
            self.total += 1
            if len(self.found) < self.keep:
                run = values[s : s + n]
                worst = float(run.max() if self.high else run.min())
                t, line = float(samples.t[s]), int(samples.source_line[s])
                self.found.append([worst, t, int(n), line])

    def hits(self) -> list[LimitHit]:
        return [
            LimitHit(self.axis, self.kind, float(v), self.limit, t, int(n), int(line))
            for v, t, n, line in self.found
        ]


def measure_windows(plan: Plan, windows: Iterable[Samples], max_hits: int = 50) -> Report:
    """:func:`measure` over samples that come window by window
    (:func:`kernel.interp.interpolate.sample_windows`): only running reductions are kept
    (extremes, chord error, the first runs over each limit), so memory does not grow with
    the program's duration. Gives the report :func:`measure` gives for the same samples."""
    seg = plan.path.segments
    cat = seg["category"]
    length = seg["length"]
    acc = SampleReductions(plan.machine, max_hits)
    for w in windows:
        acc.add(seg, w, True)
    return acc.report(
        cycle_time(plan),
        float(length[(cat == FEED) | (cat == PROBE)].sum()),
        float(length[cat == RAPID].sum()),
        len(seg),
    )


class SampleReductions:
    """The running reductions of :func:`measure_windows` (extremes, chord error, the first
    runs over each limit, the sample count), fed one window of samples at a time."""

    def __init__(self, machine: Machine, max_hits: int = 50) -> None:
        self.machine, self.max_hits = machine, max_hits
        self.checks = ["velocity", "acceleration"]
        if machine.controller.accdec == "scurve":
            self.checks.append("jerk")
        self.extremes: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.runs: list[tuple[int, str, _Runs]] = []
        self.count, self.chord = 0, 0.0
        self.last: Samples | None = None
        self.axes: tuple[str, ...] = machine.axis_names
        # per-period peaks (per_period_peaks): the last two planned rows (times, positions),
        # whose way points wait for the next row, and the last two way points, to difference
        # across a window boundary; and the largest |speed| and |acceleration|
        self.per_period = per_period_peaks(machine)
        self.raw: tuple[np.ndarray, np.ndarray] | None = None
        self.tail: tuple[np.ndarray, np.ndarray] | None = None
        self.commanded: tuple[np.ndarray, np.ndarray] | None = None

    def add(self, seg: np.ndarray, w: Samples, joined: bool) -> None:
        """Reduce window ``w``, whose ``segment`` indexes ``seg``; ``joined``: the last
        window's samples index ``seg`` too (the pair across the boundary may lie on one
        arc), else they belong to other rows."""
        machine, checks = self.machine, self.checks
        axes = self.axes = w.axes
        if not self.runs:
            for j, name in enumerate(axes):
                ax = machine.axis(name)
                for kind in checks:
                    lim = float(getattr(ax, kind))
                    self.runs.append((j, kind, _Runs(name, kind, lim, True, self.max_hits)))
                self.runs.append(
                    (j, "max", _Runs(name, "travel", float(ax.max), True, self.max_hits))
                )
                self.runs.append(
                    (j, "min", _Runs(name, "travel", float(ax.min), False, self.max_hits))
                )
        if not len(w):
            return
        self.count += len(w)
        extremes = self.extremes
        for name in ("position", "velocity", "acceleration", "jerk"):
            hi, lo = _column_extremes(getattr(w, name))
            if name in extremes:
                hi, lo = np.maximum(extremes[name][0], hi), np.minimum(extremes[name][1], lo)
            extremes[name] = (hi, lo)
        if self.per_period:
            self._difference(w)
        chord = max(self.chord, segment_chord_error(seg, w))
        last = self.last
        if last is not None and joined:  # the pair of samples across the boundary
            pair = Samples(
                w.period,
                *(np.concatenate([getattr(last, f)[-1:], getattr(w, f)[:1]]) for f in _FIELDS),
                axes,
            )
            chord = max(chord, segment_chord_error(seg, pair))
        self.chord = chord
        for j, kind, acc in self.runs:
            if kind == "max":
                col = w.position[:, j]
                mask = col > acc.limit + ATOL
            elif kind == "min":
                col = w.position[:, j]
                mask = col < acc.limit - ATOL
            else:
                col = np.abs(getattr(w, kind)[:, j])
                mask = col > acc.limit * (1 + RTOL) + ATOL
            acc.add(col, mask, w)
        self.last = w

    def _difference(self, w: Samples) -> None:
        """Fold window ``w`` into the per-period peaks: its rows' way points
        (:func:`servo_waypoints`; a row's waits for the next row, the first row is held
        before the program), differenced with the last two way points before them."""
        t, pos = w.t, w.position
        if self.raw is None:
            t, pos = np.concatenate([t[:1], t]), np.concatenate([pos[:1], pos])
        else:
            t, pos = np.concatenate([self.raw[0], t]), np.concatenate([self.raw[1], pos])
        self.raw = (t[-2:], pos[-2:])
        if len(t) > 2:
            self._fold(t[1:-1], spline_points(pos))

    def _last_waypoint(self) -> None:
        """The program's last row's way point (the row after it held: the machine stops)."""
        if self.raw is not None:
            t, pos = self.raw
            self._fold(t[-1:], spline_points(np.concatenate([pos, pos[-1:]])))
            self.raw = None

    def _fold(self, t: np.ndarray, pos: np.ndarray) -> None:
        """Way points ``pos`` at times ``t`` into the peaks of their differences."""
        if self.tail is not None:
            t, pos = np.concatenate([self.tail[0], t]), np.concatenate([self.tail[1], pos])
        self.tail = (t[-2:], pos[-2:])
        if len(t) < 2:
            return
        v, a = differences(t, pos)
        v_max = np.abs(v).max(axis=0)
        a_max = np.abs(a).max(axis=0) if len(a) else np.zeros(pos.shape[1])
        if self.commanded is not None:
            v_max = np.maximum(v_max, self.commanded[0])
            a_max = np.maximum(a_max, self.commanded[1])
        self.commanded = (v_max, a_max)

    def report(
        self, cycle: CycleTime, feed_length: float, rapid_length: float, segments: int
    ) -> Report:
        """The :class:`Report` of the windows seen, with the plan's own figures."""
        axes, extremes = self.axes, self.extremes

        def peaks(name: str) -> dict[str, float]:
            if name not in extremes:
                return {a: 0.0 for a in axes}
            m = _peak(extremes[name])
            return {a: float(v) for a, v in zip(axes, m, strict=True)}

        hits = [h for _, _, acc in self.runs for h in acc.hits()]
        hits.sort(key=lambda h: h.time)
        velocity, acceleration = peaks("velocity"), peaks("acceleration")
        self._last_waypoint()
        if self.commanded is not None:
            velocity = dict(zip(axes, map(float, self.commanded[0]), strict=True))
            acceleration = dict(zip(axes, map(float, self.commanded[1]), strict=True))
        return Report(
            cycle=cycle,
            feed_length=feed_length,
            rapid_length=rapid_length,
            segments=segments,
            samples=self.count,
            peak_velocity=velocity,
            peak_acceleration=acceleration,
            peak_jerk=peaks("jerk"),
            chord_error=self.chord,
            hits=hits[: self.max_hits],
            hits_total=sum(acc.total for _, _, acc in self.runs),
        )


_FIELDS = ("t", "position", "velocity", "acceleration", "jerk", "segment", "source_line")
