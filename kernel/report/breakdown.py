"""Cycle time per tool and per operation, over a planned program.

A *stretch* runs from one tool change to the next (G-code and STEP-NC) or over one
workingstep (STEP-NC: every command carries its workingstep's entity id in
``source.workingstep``). :class:`Stretches` watches the canonical stream as it passes to the
planner and keeps only where each stretch starts (an index into the stream), so nothing of
the program is held; :func:`breakdown` then sums the plan's per-segment durations by stretch
and by activity, with the categories of :func:`kernel.report.measure.cycle_time`, so the
stretches of a program add up to its cycle time.

The stretch before the first tool change is labelled ``(start)`` (the spindle holds whatever
tool the machine had); a tool change's own time counts with the tool it loads. Stretches of
no time are left out. A tool used twice, with another between, gives two stretches, in
program order.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np

import kernel.ir.canon as canon
from kernel.path.segments import (
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
from kernel.report.clock import clock
from kernel.report.measure import CycleTime

START = "(start)"
OUTSIDE = "(outside workingsteps)"


@dataclass(frozen=True, slots=True)
class Mark:
    """Where a stretch begins: the index of its first canonical command, its label and, for
    a workingstep, the workingstep's entity id (``key``)."""

    index: int
    label: str
    key: int | None = None


@dataclass(slots=True)
class Stretches:
    """Tool and workingstep marks of a canonical stream, recorded by :meth:`watch`."""

    tools: list[Mark] = field(default_factory=lambda: [Mark(0, START)])
    operations: list[Mark] = field(default_factory=list)

    def watch(self, commands: Iterable[canon.Command]) -> Iterator[canon.Command]:
        """Pass ``commands`` through unchanged, recording the marks."""
        tools, ops = self.tools, self.operations
        ws: int | None = None
        seen_ws = False
        for i, cmd in enumerate(commands):
            cls = type(cmd)
            if cls is canon.ChangeTool or cls is canon.ChangeToolNumber:
                _mark(tools, Mark(i, _tool_label(cmd)))
            src = cmd.source
            here = src.workingstep if src is not None else None
            if here != ws or not ops:
                if here is not None:
                    seen_ws = True
                ws = here
                _mark(ops, Mark(i, f"#{here}" if here is not None else OUTSIDE, here))
            yield cmd
        if not seen_ws:
            ops.clear()  # G-code: no workingsteps, no operations


def _tool_label(cmd: canon.Command) -> str:
    """``T<n>`` of a tool change, or the tool's name where the program gives one (STEP-NC)."""
    if isinstance(cmd, canon.ChangeTool):
        return cmd.name or f"T{cmd.slot}"
    assert isinstance(cmd, canon.ChangeToolNumber)
    return f"T{cmd.number}"


def _mark(marks: list[Mark], mark: Mark) -> None:
    """Append ``mark``; one at the same index as the last replaces it (nothing ran between)."""
    if marks and marks[-1].index == mark.index:
        marks[-1] = mark
    else:
        marks.append(mark)


@dataclass(frozen=True, slots=True)
class Share:
    """One stretch's part of the cycle: its label, the tool it runs with, its first source
    line, when it starts (s from the program start) and its time by activity."""

    label: str
    tool: str
    line: int
    start: float
    cycle: CycleTime

    def to_dict(self) -> dict[str, object]:
        c = self.cycle
        return {
            "label": self.label,
            "tool": self.tool,
            "line": self.line,
            "start": self.start,
            "total": c.total,
            "cutting": c.cutting,
            "rapid": c.rapid,
            "dwell": c.dwell,
            "tool_change": c.tool_change,
            "other": c.other,
            "total_hms": clock(c.total),
        }


#: categories summed into each field of CycleTime (the rest of cycle_time's split)
PARTS = (
    (FEED, PROBE),
    (RAPID,),
    (DWELL,),
    (TOOL_CHANGE,),
    (ORIENT, STOP, MACHINE_FUNCTION),
)


def breakdown(
    plan: Plan,
    marks: list[Mark],
    names: Mapping[int, str] | None = None,
    tools: list[Mark] | None = None,
) -> list[Share]:
    """The plan's time by stretch (``marks`` in stream order) and activity.

    ``names`` relabels workingstep marks by entity id (their names in the STEP-NC file);
    ``tools``: the tool marks, to tell each stretch's tool (default: ``marks`` are tools)."""
    if not marks:
        return []
    seg = plan.path.segments
    n = len(marks)
    group = _groups(seg, marks)
    cat = seg["category"]
    dur = plan.duration
    parts = [
        np.bincount(group, weights=np.where(np.isin(cat, kinds), dur, 0.0), minlength=n)
        for kinds in PARTS
    ]
    count = np.bincount(group, minlength=n)
    first = np.zeros(n, dtype=np.int64)
    present, at = np.unique(group, return_index=True)
    first[present] = at
    firsts = [
        (int(seg["source"][k]), int(seg["line"][k]), float(plan.t_start[k])) if c else (0, 0, 0.0)
        for k, c in zip(first.tolist(), count.tolist(), strict=True)
    ]
    return _shares(marks, parts, count, firsts, names, tools)


def _groups(seg: np.ndarray, marks: list[Mark]) -> np.ndarray:
    """The stretch of every row: the last mark at or before its command."""
    starts = np.array([m.index for m in marks], dtype=np.int64)
    group = np.searchsorted(starts, seg["source"], side="right") - 1
    return np.clip(group, 0, len(marks) - 1)


def _shares(
    marks: list[Mark],
    parts: list[np.ndarray],
    count: np.ndarray,
    firsts: list[tuple[int, int, float]],
    names: Mapping[int, str] | None,
    tools: list[Mark] | None,
) -> list[Share]:
    """The shares of the stretches with time: ``parts`` (seconds per activity and
    stretch), ``count`` (rows per stretch) and ``firsts`` (source, line and start time of
    each stretch's first row)."""
    tool_marks = tools if tools is not None else marks
    tool_starts = np.array([m.index for m in tool_marks], dtype=np.int64)
    out = []
    for g, mark in enumerate(marks):
        values = [float(p[g]) for p in parts]
        total = sum(values)
        if not count[g] or total <= 0.0:
            continue
        source, line, start = firsts[g]
        t = max(int(np.searchsorted(tool_starts, source, side="right")) - 1, 0)
        label = names.get(mark.key, mark.label) if names and mark.key is not None else mark.label
        out.append(Share(label, tool_marks[t].label, line, start, CycleTime(total, *values)))
    return out


class StretchSums:
    """:func:`breakdown` over a plan that comes window by window (kernel.stream): per
    stretch of ``marks`` (a list the stream's :class:`Stretches` keeps growing), the
    seconds per activity summed row by row in program order, as :func:`breakdown`'s
    ``bincount`` sums them, so the shares are the same numbers."""

    def __init__(self, marks: list[Mark]) -> None:
        self.marks = marks
        self.parts = [np.zeros(0) for _ in PARTS]
        self.count = np.zeros(0, dtype=np.int64)
        self.firsts: list[tuple[int, int, float]] = []

    def add(self, plan: Plan) -> None:
        """Add the rows of one window of the plan (``t_start`` from the program start)."""
        marks = self.marks
        seg = plan.path.segments
        if not marks or not len(seg):
            return
        n = len(marks)
        grow = n - self.count.size
        if grow > 0:
            self.parts = [np.concatenate([p, np.zeros(grow)]) for p in self.parts]
            self.count = np.concatenate([self.count, np.zeros(grow, dtype=np.int64)])
            self.firsts.extend([(0, 0, 0.0)] * grow)
        group = _groups(seg, marks)
        cat = seg["category"]
        dur = plan.duration
        for p, kinds in zip(self.parts, PARTS, strict=True):
            np.add.at(p, group, np.where(np.isin(cat, kinds), dur, 0.0))
        present, at = np.unique(group, return_index=True)
        for g, k in zip(present.tolist(), at.tolist(), strict=True):
            if not self.count[g]:
                self.firsts[g] = (
                    int(seg["source"][k]),
                    int(seg["line"][k]),
                    float(plan.t_start[k]),
                )
        np.add.at(self.count, group, 1)

    def shares(
        self, names: Mapping[int, str] | None = None, tools: list[Mark] | None = None
    ) -> list[Share]:
        """:func:`breakdown`'s shares of the rows added."""
        marks = self.marks
        if not marks:
            return []
        grow = len(marks) - self.count.size
        parts = [np.concatenate([p, np.zeros(max(grow, 0))]) for p in self.parts]
        count = np.concatenate([self.count, np.zeros(max(grow, 0), dtype=np.int64)])
        firsts = self.firsts + [(0, 0, 0.0)] * max(grow, 0)
        return _shares(marks, parts, count, firsts, names, tools)


__all__ = ["OUTSIDE", "START", "Mark", "Share", "StretchSums", "Stretches", "breakdown"]
