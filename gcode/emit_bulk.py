"""Runs of plain moves written in bulk: the writer's side of the interpreter's fast lane.

For a large program the RS274/NGC interpreter hands over runs of plain CAM lines (G0/G1
with X Y Z A B C and F, :class:`gcode.fastlane.Run`) as arrays instead of command objects.
:func:`write_run` writes them as the per-command handlers would (``traverse``/``feed`` in
gcode.emit_handlers: the motion code when it changes, the axis words whose text changes,
the F word when it changes), formatted in compiled code
(:func:`gcode.fastlane.gcode_text`) without building a command object; the text is the
same, which tests/test_convert_bulk.py checks against the per-command path. A run the
bulk path cannot take exactly (inverse time, feed per revolution, a spindle-synchronised
feed, a kept cycle, a pending tool select, a diameter axis, an axis the dialect lacks, a
number too large for the kernel) goes through the handlers command by command.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gcode import fastlane
from kernel import canon

if TYPE_CHECKING:
    from gcode.emit import BlockWriter

_LETTERS = "XYZABC"


def can_take(w: BlockWriter, run: fastlane.Run) -> bool:
    """Whether :func:`write_run` may write ``run`` (it can still decline a number)."""
    if w.ended or w.skipping or w.pending_select is not None or w.sync is not None:
        return False
    if w.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or w.d.diameter or w.d.min_decimals:
        return False
    if w.d.structure != "blocks" or len(w.d.separator) != 1 or w.fmt.places > 12:
        return False
    if not w.d.axes.startswith("X"):  # the kernel writes X for a move to where it is
        return False
    missing = [i for i, letter in enumerate(_LETTERS) if letter not in w.d.axes]
    return not missing or not np.any(np.abs(run.position[:, missing]) > 1e-9)


def write_run(w: BlockWriter, run: fastlane.Run, file: str | None) -> bool:
    """Write the events of ``run`` (see module doc) into ``w.out``; False (nothing
    written) when the kernel cannot state a number or a block is too long, for the
    handlers to take (and refuse at the block's own line)."""
    w.flush()
    if not len(run):
        return True
    axes = [i for i, letter in enumerate(_LETTERS) if letter in w.d.axes]
    scale = w.fmt.scale
    scaled = np.array(run.position, dtype=np.float64)
    scaled[:, :3] *= scale
    codes = (w.d.rapid, w.d.linear)
    motion = codes.index(w.motion) if w.motion in codes else -1
    feed_words = (w.e_feed, "F" + w.fmt.feed(w.feed * scale))
    last = [w.words.get(_LETTERS[i]) for i in axes]
    letters = "".join(_LETTERS[i] for i in axes)
    done = fastlane.gcode_text(
        run, scaled, run.feed * scale, axes, letters, w.fmt.places, w.d.point_required,
        last, codes, motion, feed_words, w.d.separator,
    )  # fmt: skip
    if done is None:
        return False
    text, words, motion_after, feed_after = done
    lines = text[:-1].split("\n") if text else []
    limit = w.o.max_line_length or w.d.max_line_length
    if limit is not None and max(map(len, lines), default=0) > limit:
        return False  # the handlers refuse the long block at its own line
    for i, word in zip(axes, words, strict=True):
        w.words[_LETTERS[i]] = word or None
        w.cur[_LETTERS[i]] = float(scaled[-1, i])
    w.motion = codes[motion_after] if motion_after >= 0 else w.motion
    w.e_feed = feed_after or w.e_feed
    w.feed = float(run.feed[-1])
    w.report.commands += len(run)
    w.src = canon.Location(file, int(run.line[-1]), 1)
    if w.o.line_numbers:  # w.block numbers them (and checks the numbered length)
        for line in lines:
            w.block(line)
    else:
        w.out.extend(lines)
        w.report.blocks += len(lines)
    return True
