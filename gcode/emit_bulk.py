"""Runs of plain moves written in bulk: the writer's side of the interpreter's fast lane.

For a large program the RS274/NGC interpreter hands over runs of plain CAM lines (G0/G1
with X Y Z A B C and F, :class:`gcode.fastlane.Run`) as arrays instead of command objects.
:func:`write_run` writes them as the per-command handlers would (``traverse``/``feed`` in
gcode.emit_handlers: the motion code when it changes, the axis words whose text changes,
the F word when it changes) but formats each axis column in one pass and never builds a
command object; the text is the same, which tests/test_convert_bulk.py checks against the
per-command path. A run the bulk path cannot take exactly (inverse time, feed per
revolution, a spindle-synchronised feed, a kept cycle, a pending tool select, a diameter
axis, an axis the dialect lacks) goes through the handlers command by command.
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
    """Whether :func:`write_run` writes ``run`` exactly as the handlers would."""
    if w.ended or w.skipping or w.pending_select is not None or w.sync is not None:
        return False
    if w.feed_mode != canon.FeedMode.UNITS_PER_MINUTE or w.d.diameter or w.d.min_decimals:
        return False
    if w.d.structure != "blocks":
        return False
    missing = [i for i, letter in enumerate(_LETTERS) if letter not in w.d.axes]
    return not missing or not np.any(np.abs(run.position[:, missing]) > 1e-9)


def column(w: BlockWriter, values: np.ndarray) -> list[str]:
    """``Formatter.number`` of every value, in one pass (the memo does not pay for CAM
    coordinates, which rarely repeat)."""
    if values.size and (values == values[0]).all():  # an axis that does not move (A B C)
        return [w.fmt.number(float(values[0]))] * values.size
    p = w.fmt.places
    listed = values.tolist()
    spec = f"%.{p}f"
    if p == 0:
        out = [spec % v for v in listed]
    elif w.d.point_required:
        out = [(spec % v).rstrip("0") for v in listed]
    else:
        out = [(spec % v).rstrip("0").rstrip(".") for v in listed]
    for i in np.flatnonzero(np.abs(values) <= 10.0**-p).tolist():  # "-0": the exact rule
        out[i] = w.fmt.number(listed[i])
    return out


def write_run(w: BlockWriter, run: fastlane.Run, file: str | None) -> None:
    """Write the events of ``run`` (see module doc) into ``w.out``: each axis column
    formatted in one pass, then per move the motion code where it changes, the axis words
    whose text changes and the F word where the feed in force changes."""
    w.flush()
    w.report.commands += len(run)
    if not len(run):
        return
    w.src = canon.Location(file, int(run.line[-1]), 1)
    if _compiled(w, run):
        return
    kind = run.kind.tolist()
    feeds = run.feed.tolist()
    scale = w.fmt.scale
    words, cur = w.words, w.cur
    moving, columns = [], []
    for i, letter in enumerate(_LETTERS):
        if letter not in w.d.axes:
            continue
        values = run.position[:, i] * (scale if i < 3 else 1.0)
        if (
            i > 0
            and (values == values[0]).all()
            and letter + w.fmt.number(float(values[0])) == words.get(letter)
        ):
            continue  # an axis that stays (A B C, often Z): its word never changes here
        moving.append(i)
        columns.append([letter + t for t in column(w, values)])
    rapid, linear = w.d.rapid, w.d.linear
    x_moves = bool(moving) and moving[0] == 0
    last = [words.get(_LETTERS[i]) for i in moving]
    axes = range(len(moving))
    sep, lines = w.d.separator, []
    feed_text = "F" + w.fmt.feed(w.feed * scale)
    for n, k in enumerate(kind):
        if k == fastlane.SET_FEED:
            w.feed = feeds[n]
            feed_text = "F" + w.fmt.feed(w.feed * scale)
            continue
        out = []
        code = rapid if k == fastlane.TRAVERSE else linear
        if code != w.motion:
            w.motion = code
            out.append(code)
        changed = False
        for a in axes:
            word = columns[a][n]
            if word != last[a]:
                last[a] = word
                out.append(word)
                changed = True
        if not changed:  # a move to where the tool is: the handlers write its first axis
            out.append(last[0] if x_moves else words.get("X") or "X")
        if feed_text != w.e_feed:  # BlockWriter.feed_word, per minute
            w.e_feed = feed_text
            out.append(feed_text)
        lines.append(sep.join(out))
    for a, i in enumerate(moving):
        words[_LETTERS[i]] = last[a]
    end = run.end_position
    for i, letter in enumerate(_LETTERS):
        if letter in w.d.axes:
            cur[letter] = end[i] * (scale if i < 3 else 1.0)
    limit = w.o.max_line_length or w.d.max_line_length
    if w.o.line_numbers or (limit is not None and max(map(len, lines), default=0) > limit):
        for line in lines:  # numbered, or a block too long: w.block numbers or refuses
            w.block(line)
    else:
        w.out.extend(lines)
        w.report.blocks += len(lines)


def _compiled(w: BlockWriter, run: fastlane.Run) -> bool:
    """The run formatted by the compiled kernel (:func:`gcode.fastlane.gcode_text`), when
    it can state every number exactly; False leaves the run to the Python loop."""
    axes = [i for i, letter in enumerate(_LETTERS) if letter in w.d.axes]
    if not axes or axes[0] != 0 or len(w.d.separator) != 1 or w.fmt.places > 12:
        return False
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
    for i, word in zip(axes, words, strict=True):
        w.words[_LETTERS[i]] = word or None
        w.cur[_LETTERS[i]] = float(scaled[-1, i])
    w.motion = codes[motion_after] if motion_after >= 0 else w.motion
    w.e_feed = feed_after or w.e_feed
    w.feed = float(run.feed[-1])
    limit = w.o.max_line_length or w.d.max_line_length
    if w.o.line_numbers or (limit is not None and max(map(len, lines), default=0) > limit):
        for line in lines:  # numbered, or a block too long: w.block numbers or refuses
            w.block(line)
    else:
        w.out.extend(lines)
        w.report.blocks += len(lines)
    return True
