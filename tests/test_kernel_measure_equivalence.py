"""The faster measurements (kernel.measure) report exactly what the former code did.

Reference: :func:`kernel.measure.measure` as it was before the speed work, kept verbatim
below (peaks from ``abs(arr).max(axis=0)``, every column scanned for runs over each limit,
the chord error from all same-segment sample pairs). The new code takes per-column
extremes, scans a column only when its extreme is over a limit, and keeps only arc pairs
before gathering. Reports must be equal field for field, limit hits included: sampled
programs on their own machine (no hit), and the same samples judged against tighter
velocity, acceleration, jerk and travel limits (many hits, the cap of 50 reached).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from kernel import canon
from kernel.interpolate import sample
from kernel.machine import DEFAULT_MACHINE, Machine, with_controller
from kernel.measure import (
    ATOL,
    RTOL,
    LimitHit,
    Report,
    cycle_time,
    measure,
)
from kernel.path import ARC, FEED, PROBE, RAPID, build_path
from kernel.planner import Plan, plan
from kernel.samples import Samples


# ----------------------------------------------------------------------------- reference
def _reference_chord_error(plan: Plan, samples: Samples) -> float:
    """Largest ``|R - |midpoint - centre||`` over consecutive samples on the same arc."""
    seg = plan.path.segments
    k = samples.segment
    if len(k) < 2 or "x" not in samples.axes:
        return 0.0
    same = (k[1:] == k[:-1]) & (k[:-1] >= 0)
    idx = np.flatnonzero(same)
    idx = idx[seg["kind"][k[idx]] == ARC]
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


def _reference_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and lengths of runs of True."""
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(m)
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1)
    return starts, ends - starts


def _reference_limit_hits(
    plan: Plan, samples: Samples, max_hits: int = 50
) -> tuple[list[LimitHit], int]:
    """Runs of samples over an axis limit: the first ``max_hits`` and the total count."""
    machine = plan.machine
    checks = [("velocity", samples.velocity), ("acceleration", samples.acceleration)]
    if machine.controller.accdec == "scurve":
        checks.append(("jerk", samples.jerk))
    hits: list[LimitHit] = []
    total = 0
    for j, name in enumerate(samples.axes):
        ax = machine.axis(name)
        for kind, arr in checks:
            lim = float(getattr(ax, kind))
            col = np.abs(arr[:, j])
            starts, lens = _reference_runs(col > lim * (1 + RTOL) + ATOL)
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
        pos = samples.position[:, j]
        for kind, mask, lim in (
            ("travel", pos > ax.max + ATOL, ax.max),
            ("travel", pos < ax.min - ATOL, ax.min),
        ):
            starts, lens = _reference_runs(mask)
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


def reference_measure(plan: Plan, samples: Samples) -> Report:
    """Cycle time, lengths, peaks, chord error and limit hits of a sampled plan."""
    seg = plan.path.segments
    cat = seg["category"]
    length = seg["length"]

    def peaks(arr: np.ndarray) -> dict[str, float]:
        if not len(arr):
            return dict.fromkeys(samples.axes, 0.0)
        m = np.abs(arr).max(axis=0)
        return {a: float(v) for a, v in zip(samples.axes, m, strict=True)}

    hits, total = _reference_limit_hits(plan, samples)
    return Report(
        cycle=cycle_time(plan),
        feed_length=float(length[(cat == FEED) | (cat == PROBE)].sum()),
        rapid_length=float(length[cat == RAPID].sum()),
        segments=len(seg),
        samples=len(samples),
        peak_velocity=peaks(samples.velocity),
        peak_acceleration=peaks(samples.acceleration),
        peak_jerk=peaks(samples.jerk),
        chord_error=_reference_chord_error(plan, samples),
        hits=hits,
        hits_total=total,
    )


# ----------------------------------------------------------------------------- programs
def _program() -> list[canon.Command]:
    """Lines, a full circle, a helix, a dwell and traverses."""
    cmds: list[canon.Command] = [
        canon.SetFeedRate(2400.0),
        canon.StraightTraverse(0.0, 0.0, 5.0),
        canon.StraightFeed(0.0, 0.0, -1.0),
    ]
    for i in range(1, 40):
        cmds.append(canon.StraightFeed(i * 1.5, 3.0 * math.sin(i / 3.0), -1.0))
    cmds += [
        canon.ArcFeed(58.5, 3.0 * math.sin(13.0), 50.0, 3.0 * math.sin(13.0), 1, -1.0),
        canon.Dwell(0.1),
        canon.ArcFeed(58.5, 3.0 * math.sin(13.0), 53.0, 3.0 * math.sin(13.0), -2, -4.0),
        canon.StraightTraverse(0.0, 0.0, 5.0),
        canon.ProgramEnd(),
    ]
    return cmds


def _tight(machine: Machine, factor: float, travel: float) -> Machine:
    """``machine`` with every limit scaled by ``factor`` and travel ``[-travel, travel]``."""
    axes = tuple(
        dataclasses.replace(
            a,
            velocity=a.velocity * factor,
            acceleration=a.acceleration * factor,
            jerk=a.jerk * factor,
            min=-travel,
            max=travel,
        )
        for a in machine.axes
    )
    return Machine(machine.name, axes, machine.controller)


@pytest.mark.parametrize("accdec", ["trapezoid", "scurve"])
@pytest.mark.parametrize("factor, travel", [(1.0, math.inf), (0.3, 20.0), (0.05, 1.0)])
def test_reports_are_equal_to_the_former_measurements(accdec, factor, travel):
    machine = with_controller(DEFAULT_MACHINE, accdec=accdec)
    pl = plan(build_path(_program(), machine), machine)
    s = sample(pl)
    judged = dataclasses.replace(pl, machine=_tight(machine, factor, travel))
    new, ref = measure(judged, s), reference_measure(judged, s)
    assert new == ref
    if factor < 1:
        assert new.hits_total > 0
    else:
        assert new.hits_total == 0
    assert new.chord_error > 0  # the arcs were measured


def test_a_single_sample_and_the_empty_program_measure_as_before():
    short = [canon.SetFeedRate(100.0), canon.StraightFeed(1e-3, 0.0, 0.0)]
    for cmds in ([canon.SetFeedRate(100.0)], short):
        pl = plan(build_path(cmds, DEFAULT_MACHINE), DEFAULT_MACHINE)
        s = sample(pl)
        assert measure(pl, s) == reference_measure(pl, s)
