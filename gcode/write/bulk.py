"""Runs of plain moves written in bulk: the writer's side of the interpreter's fast lane.

For a large program the RS274/NGC interpreter hands over runs of plain CAM lines (G0/G1
with X Y Z A B C and F, :class:`gcode.ngc.lane.fastlane.Run`) as arrays instead of command objects;
the other readers give command objects, whose plain moves and feed rates the writer
batches into the same arrays (:func:`run_of`) once a stream is large
(:data:`COMMANDS_BEFORE_BULK`). :func:`write_run` writes a run as the per-command handlers
would (``traverse``/``feed`` in gcode.write.handlers: the motion code when it changes, the
axis words whose text changes, the F word when it changes), formatted in compiled code
(:func:`gcode.ngc.lane.fastlane.gcode_text`); the text is the same, which tests/test_convert_bulk.py
checks against the per-command path for every program of every reader. A run the bulk
path cannot take exactly (inverse time, feed per revolution, a spindle-synchronised feed,
a kept cycle, a pending tool select, an axis the dialect lacks off zero,
a number too large for the kernel, a block too long) goes through the handlers command by
command.
"""

from __future__ import annotations

from collections.abc import Iterator
from operator import attrgetter

import numpy as np

from gcode.ngc.lane import fastlane
from gcode.write.context import WriterContext
from gcode.write.state import PLANE_AXES
from kernel.ir import canon

_LETTERS = "XYZABC"
#: a command stream (a reader other than RS274/NGC's fast lane) is batched into runs once
#: the writer has taken this many commands: a large program, worth loading the kernel
COMMANDS_BEFORE_BULK = 20_000
#: plain commands batched into one run at most, and at least (fewer go one by one: the
#: arrays would cost more than the handlers)
BATCH = 4096
BATCH_MIN = 16
#: command type -> event kind of a fast-lane run
KIND = {
    canon.StraightTraverse: fastlane.TRAVERSE,
    canon.StraightFeed: fastlane.FEED_MOVE,
    canon.SetFeedRate: fastlane.SET_FEED,
}
_POSITION = attrgetter("x", "y", "z", "a", "b", "c")


def run_of(commands: list[canon.Command], feed: float) -> fastlane.Run | None:
    """The plain commands (types in :data:`KIND`) as a run's arrays, as the fast lane would
    hand them over (``feed``: the rate in force before them); None without a motion."""
    kinds = [KIND[type(c)] for c in commands]
    last_move = len(kinds) - 1
    while last_move >= 0 and kinds[last_move] == fastlane.SET_FEED:
        last_move -= 1
    if last_move < 0:
        return None
    if fastlane.SET_FEED in kinds:
        rows: list[tuple[float, ...]] = []
        rates: list[float] = []
        here: tuple[float, ...] = (0.0,) * 6  # a feed change's row: never read as a position
        for c in commands:
            if isinstance(c, canon.SetFeedRate):  # KIND's SET_FEED
                feed = c.rate
            else:
                here = _POSITION(c)
            rows.append(here)
            rates.append(feed)
    else:
        rows = list(map(_POSITION, commands))
        rates = [feed] * len(rows)
    n = len(kinds)
    return fastlane.Run(
        np.array(kinds, dtype=np.int8),
        np.array(rows, dtype=np.float64).reshape(n, 6),
        np.array(rates, dtype=np.float64),
        np.zeros(n, dtype=np.int64),
        0,
        0,
        rows[last_move],
        rates[-1],
        kinds[last_move] == fastlane.TRAVERSE,
    )


def stretches(run: fastlane.Run, file: str | None) -> Iterator[fastlane.Run | canon.Command]:
    """A run that may hold arcs (``run.arc``) as what the writer takes: its stretches
    between arcs as runs without arc columns (a stretch without a move as its commands),
    and each arc as its ``ARC_FEED`` command, in order."""
    kind = run.kind
    if not len(kind):
        return
    arcs = np.flatnonzero(kind == fastlane.ARC).tolist()
    if not arcs:
        yield _part(run, 0, len(run))
        return
    assert run.arc is not None  # a run with ARC events has its arc columns
    start = 0
    for i in [*arcs, len(run)]:
        if i > start:
            moves = np.flatnonzero(kind[start:i] != fastlane.SET_FEED)
            if len(moves):
                yield _part(run, start, i, start + int(moves[-1]))
            else:
                yield from _part(run, start, i).commands(file)
        if i < len(run):
            e1, e2, c1, c2, turns, normal = run.arc[i].tolist()
            yield canon.ArcFeed(
                e1, e2, c1, c2, int(turns), normal, *run.position[i, 3:].tolist(),
                source=canon.Location(file, int(run.line[i]), 1),
            )  # fmt: skip
        start = i + 1


def _part(run: fastlane.Run, i: int, j: int, last_move: int | None = None) -> fastlane.Run:
    """Events ``i`` to ``j`` of ``run`` as a run without arc columns; ``last_move``: the
    index of its last move (its end position)."""
    end = run.end_position if last_move is None else tuple(run.position[last_move].tolist())
    return fastlane.Run(
        run.kind[i:j],
        run.position[i:j],
        run.feed[i:j],
        run.line[i:j],
        0,
        0,
        end,
        float(run.feed[j - 1]),
        bool(run.kind[last_move] == fastlane.TRAVERSE) if last_move is not None else False,
    )


def can_take(w: WriterContext, run: fastlane.Run) -> bool:
    """Whether :func:`write_run` may write ``run`` (it can still decline: a number too
    large, an axis the dialect lacks off zero, a block too long)."""
    if w.ended or w.skipping or w.pending_select is not None or w.sync is not None:
        return False
    if w.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or w.d.min_decimals:
        return False
    if w.d.structure != "blocks" or len(w.d.separator) != 1 or w.fmt.places > 12:
        return False
    return w.d.axes.startswith("X")  # the kernel writes X for a move to where it is


def write_run(
    w: WriterContext, run: fastlane.Run, file: str | None, commands: list | None = None
) -> bool:
    """Write the events of ``run`` (see module doc) into ``w.out`` as one entry of several
    lines; False (nothing written) when the kernel cannot state a number or a block is too
    long, for the handlers to take (and refuse at the block's own line). ``commands``: the
    commands the run was made of (their locations), else it came from line ``run.line``
    of ``file``."""
    if not len(run):
        return True
    first = 0
    while first < len(run) - 1 and run.kind[first] == fastlane.SET_FEED:
        first += 1
    # the modal state is written, or refused, at the first move, as its handler would
    w.src = commands[first].source if commands else canon.Location(file, int(run.line[first]), 1)
    w.flush()
    layout = w.layout
    if layout is None:
        codes4 = (w.d.rapid, w.d.linear, w.d.arc_cw, w.d.arc_ccw)
        layout = w.layout = fastlane.GcodeLayout.of(codes4, w.d.axes, w.d.diameter)
    plane = None
    if run.arc is not None:
        if w.o.arc_format != "ijk" or w.centre_abs_on:
            return False
        axis1, axis2, normal, ci, cj = PLANE_AXES[w.plane]
        plane = fastlane.arc_plane(layout, axis1, axis2, normal, ci + cj)
        if plane is None:
            return False
    scale, codes = w.fmt.scale, layout.codes
    motion = codes.index(w.motion) if w.motion in codes else -1
    last = [w.words.get(_LETTERS[i]) for i in layout.axes]
    done = fastlane.gcode_text(
        run, scale, layout, w.fmt.places, w.d.point_required, last, motion, (w.e_feed, w.feed),
        w.d.separator, plane,
    )  # fmt: skip
    if done is None:
        return False
    text, words, motion_after, feed_after, longest, blocks = done
    limit = w.o.max_line_length or w.d.max_line_length
    if limit is not None and longest > limit:
        return False  # the handlers refuse the long block at its own line
    end = run.end_position
    for i, word in zip(layout.axes, words, strict=True):
        w.words[_LETTERS[i]] = word or None
        w.cur[_LETTERS[i]] = end[i] * scale if i < 3 else end[i]
    w.motion = codes[motion_after] if motion_after >= 0 else w.motion
    w.e_feed = feed_after or w.e_feed
    w.feed = run.end_feed
    w.report.commands += len(run)
    w.src = commands[-1].source if commands else canon.Location(file, int(run.line[-1]), 1)
    if not text:
        return True
    if w.o.line_numbers:  # w.block numbers them (and checks the numbered length)
        for line in text[:-1].split("\n"):
            w.block(line)
    else:
        w.out.append(text[:-1])
        w.report.blocks += blocks
    return True
