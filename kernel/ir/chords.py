"""Equivalence of a source and an output that replaced its arcs by straight chords, as arrays
(issue 15: ``cnc convert --to sandia``'s check).

The Sandia generic language has no arc command, so its writer turns every ``ARC_FEED`` into
``MoveTo`` chords within the tolerance: a 200,000-line CAM program reads back as 2.3
million straight feeds. :func:`kernel.ir.equivalence.first_difference` accepts such chords
by its ``_cover`` rule (each chord ends on the arc, within the tolerance, further along it,
the last on its end), one command object at a time; :func:`kernel.ir.equivalence.equivalent`
(motion for motion) cannot. :func:`chords_equivalent` builds both streams' motion tables
(``equivalence._Table``, the reader's runs as arrays) and walks them with the same rule in
a compiled kernel (:mod:`kernel.ir.chord_kernels`, built once through :mod:`kernel.aot`).

Like :func:`~kernel.ir.equivalence.equivalent` it says True only where ``first_difference``
finds nothing, and False where it cannot tell: any difference, anything but straight
motions and arcs covered by straight feeds (probes, curves, dwells, arcs in the output), a
motion seeing other units or spindle, tool or coolant state than its source (even where
the rule would map them), and every comparison within a few ulps of its bound (the
kernel's ``hypot`` need not be CPython's to the last bit). ``first_difference`` then
decides, and says what differs.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from typing import Protocol, cast

import numpy as np

from kernel import aot
from kernel.ir import canon
from kernel.ir.equivalence import (
    _AXES,
    _EVENTS,
    _MOTION_KINDS,
    EXACT,
    Moves,
    _Block,
    _Kept,
    _mm,
    _restated,
    _State,
    _Table,
)

#: the compiled kernel (kernel.aot: built once into the user's cache, JIT fallback)
KERNELS = aot.Kernels(
    "kernel.ir.chord_kernels", "_chords_aot", "chord comparison kernel", "CNC_CHORDS_JIT"
)
_MOTIONS = _MOTION_KINDS


class _Runs(Protocol):
    """A run of motions as arrays (:class:`Moves`, or a reader's lane run)."""

    kind: np.ndarray
    position: np.ndarray
    feed: np.ndarray


#: a segment of the output: kinds, x y z a b c, feed rates, and the state all of it sees
Segment = tuple[np.ndarray, np.ndarray, np.ndarray, int]


class _Output:
    """The output stream as segments of motions seeing one state each, as ``_Table``
    reads a stream (the same state and feed rules, the same events) but without joining
    them: a run of the reader's lane is a segment as it came, so the 2.3 million chords of
    a large program are never copied. ``ok`` is False once it meets what only
    ``first_difference`` compares."""

    def __init__(self, states: dict[_State, int]) -> None:
        self.states = states
        self.ok = True
        self.events: list[tuple[int, str]] = []

    def segments(self, stream: Iterable[object]) -> Iterator[Segment]:  # noqa: C901
        feed = 0.0
        states = self.states
        current: _State = (0.0, canon.Direction.STOPPED, 0, False, False, canon.Plane.XY, None)
        state = states.setdefault(current, len(states))
        kinds: list[int] = []
        values: list[tuple[float, ...]] = []
        feeds: list[float] = []
        moves = 0

        def pending() -> Segment:
            segment = (
                np.array(kinds, dtype=np.int8),
                np.array(values, dtype=np.float64).reshape(len(kinds), 6),
                np.array(feeds, dtype=np.float64),
                state,
            )
            kinds.clear()
            values.clear()
            feeds.clear()
            return segment

        for c in stream:
            t = type(c)
            if t is canon.StraightFeed or t is canon.StraightTraverse:
                assert isinstance(c, canon.StraightFeed | canon.StraightTraverse)
                kinds.append(1 if t is canon.StraightFeed else 0)
                values.append((c.x, c.y, c.z, c.a, c.b, c.c))
                feeds.append(feed)
                moves += 1
                continue
            if t is Moves or not isinstance(c, canon.Command) and hasattr(c, "position"):
                run = cast(_Runs, c)
                if kinds:
                    yield pending()
                n = len(run.kind)
                if n:
                    if getattr(run, "arc", None) is not None:
                        self.ok = False  # arcs in the output: the rule compares them
                        return
                    yield run.kind, run.position, run.feed, state
                    moves += n - int(np.count_nonzero(run.kind == 2))
                    feed = float(run.feed[-1])
                continue
            if isinstance(c, _MOTIONS):
                self.ok = False  # arcs, probes, curves, dwells: first_difference's rules
                return
            if t is canon.SetFeedRate:
                assert isinstance(c, canon.SetFeedRate)
                feed = c.rate
                continue
            key = _restated(c, t, current)
            if isinstance(c, _EVENTS):
                text = c.text.strip() if isinstance(c, canon.Message) else c.to_text()
                self.events.append((moves, c.NAME + " " + text))
            if key is not None and key != current:  # a new state: the rows so far saw the old one
                if kinds:
                    yield pending()
                current = key
                state = states.setdefault(key, len(states))
        if kinds:
            yield pending()


class _SourceColumns:
    """The source's motion rows (:class:`~kernel.ir.equivalence._Table`'s kept blocks) as
    whole columns, with the id of the state each row sees (from the table's runs)."""

    def __init__(self, blocks: list[_Block], runs: list[tuple[int, int]]) -> None:
        self.kind = np.concatenate([b[0] for b in blocks]) if blocks else np.zeros(0, dtype=np.int8)
        self.values = np.concatenate([b[1] for b in blocks]) if blocks else np.zeros((0, 6))
        self.feed = np.concatenate([b[2] for b in blocks]) if blocks else np.zeros(0)
        arcs = [b[3] for b in blocks if b[3] is not None]
        self.arcs = np.concatenate(arcs) if arcs else np.zeros((0, 3))
        ids = np.array([sid for sid, _ in runs], dtype=np.int64)
        self.state = np.repeat(ids, [count for _, count in runs])


def chords_equivalent(
    source: Iterable[canon.Command | Moves],
    output: Iterable[object],
    tolerance: float,
    resolution: Mapping[canon.Units | None, float] | None = None,
) -> bool:
    """True when ``output`` (straight motions only; its runs as :class:`Moves` or a
    reader's lane runs) is equivalent to ``source`` by
    :func:`~kernel.ir.equivalence.first_difference`'s rule with ``tolerance`` (output
    length units) and ``resolution``; False where that rule must tell. Reads ``output``
    up to the first difference."""
    try:
        kernels = KERNELS.module()
    except ImportError:  # no compiled kernel and no numba: the rule decides
        return False
    states: dict[_State, int] = {}
    kept = _Kept()
    src = _Table(source, states, kept)
    if not src.ok:
        return False
    columns = _SourceColumns(kept.blocks, src.runs)
    rounding = resolution or {}
    n_src = len(columns.kind)
    done = np.zeros(n_src, dtype=np.int64)
    carry = np.zeros(4, dtype=np.int64)
    where = np.zeros(4)
    arrays = (
        np.ascontiguousarray(columns.kind, dtype=np.int8),
        np.ascontiguousarray(columns.values, dtype=np.float64),
        np.ascontiguousarray(columns.feed, dtype=np.float64),
        np.ascontiguousarray(columns.state, dtype=np.int64),
        np.ascontiguousarray(columns.arcs, dtype=np.float64).reshape(-1, 3),
    )
    out = _Output(states)
    tables: tuple[np.ndarray, ...] = ()
    known = -1
    for kind, position, feed, state in out.segments(output):
        if state >= known:  # per state id: what must be equal and the bounds, in mm
            keys = sorted(states, key=states.__getitem__)
            tables = _state_tables(keys, tolerance, rounding)
            known = len(keys)
        ok = kernels.cover(
            *arrays,
            np.ascontiguousarray(kind, dtype=np.int8),
            np.ascontiguousarray(position, dtype=np.float64).reshape(-1, 6),
            np.ascontiguousarray(feed, dtype=np.float64),
            state,
            *tables,
            carry,
            where,
            done,
        )
        if not ok:
            return False
    if not out.ok or carry[0] != n_src or carry[2]:
        return False
    if [e for _, e in src.events] != [e for _, e in out.events]:
        return False
    # every event in the same place: after the output motions of the source's before it
    return all(
        (int(done[moves - 1]) if moves else 0) == at
        for (moves, _), (at, _) in zip(src.events, out.events, strict=True)
    )


def _state_tables(
    keys: list[_State], tolerance: float, rounding: Mapping[canon.Units | None, float]
) -> tuple[np.ndarray, ...]:
    """Per state id: what must be equal (all but the plane), mm per unit, the bounds of a
    length and of a chord point's distance from its arc (mm), the plane's axes."""
    seen: dict[tuple[object, ...], int] = {}
    key = np.array([seen.setdefault(k[:5] + k[6:], len(seen)) for k in keys], dtype=np.int64)
    mm = np.array([_mm(k[6]) for k in keys])
    written = np.array([rounding.get(k[6], 0.0) for k in keys]) * mm * (1 + 1e-6)
    exact = np.maximum(EXACT * mm, written + 1e-9)
    cover = tolerance * mm + exact
    axes = np.array([_AXES[k[5]] for k in keys], dtype=np.int64).reshape(len(keys), 3)
    return key, mm, exact, cover, axes
