"""Compiled fast lane for the commonest CAM lines: plain axis, feed and G0/G1 words.

A CAM post's output is mostly lines like ``X12.5 Y-3.25 Z-1.0`` or ``F800`` while the
modal state stays simple (G0 or G1, G94, no cutter compensation, no canned cycle).
Interpreting them one by one through the general machinery costs microseconds a line;
this module scans a run of such lines straight from the program's bytes with a
numba-compiled loop and returns the resulting events as arrays (:func:`scan`), and
formats events as canonical text in compiled code too (:func:`events_text`).

Semantics are exactly those of the general interpreter for these lines (NIST RS274/NGC v3
§3.3 and §3.8 order of execution; LinuxCNC): blanks and tabs are ignored; an ``F`` word
emits ``SET_FEED_RATE`` each time it appears, before the line's motion; a line with axis
words emits one ``STRAIGHT_TRAVERSE`` (G0) or ``STRAIGHT_FEED`` (G1) to the new position
even when it equals the current one; in G91 the words are increments. A line is *plain*
when it holds an optional integer ``N`` word first, then words among X Y Z A B C F and one
G0/G1 (only beside an axis word), each letter at most once, each with a plain decimal
number, and ``F`` positive.
A run ends before the first line that is not plain or that would feed at a zero feed rate;
the general interpreter takes that line, and owns every diagnostic.

Numbers are parsed as an integer mantissa over a power of ten: the correctly rounded
value, the same as ``float()``, for mantissas of up to 15 digits (longer ones end the run).
Formatting matches ``f"{v:.4f}"``; the rare values on a rounding tie within floating-point
noise are flagged and re-formatted in Python.

Compilation is cached on disk by numba; the first use in a process costs a few tenths of
a second, so the interpreter uses the lane only for large programs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from kernel import canon

#: event kinds
TRAVERSE = 0  # STRAIGHT_TRAVERSE to ``position``
FEED_MOVE = 1  # STRAIGHT_FEED to ``position``
SET_FEED = 2  # SET_FEED_RATE(``feed``)

#: letter -> slot: 0-5 axes X Y Z A B C, 6 F, 7 G (0/1 only), 8 N; -1 other
_SLOT = np.full(256, -1, dtype=np.int64)
for _k, _c in enumerate("XYZABCFGN"):
    _SLOT[ord(_c)] = _k
    _SLOT[ord(_c.lower())] = _k
_POW10 = 10.0 ** np.arange(23)


@dataclass(frozen=True, slots=True)
class Run:
    """Events of a run of plain lines, in program order.

    ``kind[i]`` is :data:`TRAVERSE`, :data:`FEED_MOVE` or :data:`SET_FEED`;
    ``position[i]`` (x y z a b c, program coordinates) is the position after the event,
    ``feed[i]`` the feed rate in force, ``line[i]`` the 1-based program line. ``consumed``
    is the number of bytes and ``lines`` the number of program lines taken; the state after
    the run is ``end_position``, ``end_feed`` and ``end_traverse`` (True in G0).
    """

    kind: np.ndarray
    position: np.ndarray
    feed: np.ndarray
    line: np.ndarray
    consumed: int
    lines: int
    end_position: tuple[float, ...]
    end_feed: float
    end_traverse: bool

    def __len__(self) -> int:
        return int(self.kind.shape[0])

    def commands(self, file: str | None = None) -> list[canon.Command]:
        """The events as IR command objects, each with its source line."""
        out: list[canon.Command] = []
        loc = canon.Location
        for k, pos, fv, ln in zip(
            self.kind.tolist(),
            self.position.tolist(),
            self.feed.tolist(),
            self.line.tolist(),
            strict=True,
        ):
            src = loc(file, ln, 1)
            if k == TRAVERSE:
                out.append(canon.StraightTraverse(*pos, source=src))
            elif k == FEED_MOVE:
                out.append(canon.StraightFeed(*pos, source=src))
            else:
                out.append(canon.SetFeedRate(fv, source=src))
        return out


@njit(cache=True)
def _skip_blanks(buf, j, e):  # pragma: no cover - compiled
    while j < e and (buf[j] == 32 or buf[j] == 9):
        j += 1
    return j


@njit(cache=True)
def _number(buf, j, e, pow10):  # pragma: no cover - compiled
    """Parse ``[+-]digits[.digits]`` (blanks allowed inside) at ``j``.

    Returns (value, next index, ok, had a point).
    """
    negative = False
    if j < e and (buf[j] == 43 or buf[j] == 45):
        negative = buf[j] == 45
        j = _skip_blanks(buf, j + 1, e)
    mant = 0.0
    ndig = 0
    nfrac = 0
    point = False
    while j < e:
        c = buf[j]
        if 48 <= c <= 57:
            mant = mant * 10.0 + (c - 48)
            ndig += 1
            if point:
                nfrac += 1
        elif c == 46 and not point:
            point = True
        elif c != 32 and c != 9:
            break
        j += 1
    if ndig == 0 or ndig > 15:
        return 0.0, j, False, point
    v = mant / pow10[nfrac]
    return (-v if negative else v), j, True, point


@njit(cache=True)
def _scan(buf, start, slot_of, pow10, pos, feed, incremental, traverse, first_line, max_events):
    # pragma: no cover - compiled
    n = buf.shape[0]
    kind = np.empty(max_events, dtype=np.int8)
    out_pos = np.empty((max_events, 6), dtype=np.float64)
    out_feed = np.empty(max_events, dtype=np.float64)
    out_line = np.empty(max_events, dtype=np.int64)
    cur = pos.copy()
    words = np.zeros(9, dtype=np.float64)
    k = 0
    i = start
    line_no = first_line
    while i < n and k + 2 <= max_events:
        line_start = i
        e = i
        while e < n and buf[e] != 10:
            e += 1
        next_line = e + 1 if e < n else n
        if e > i and buf[e - 1] == 13:
            e -= 1
        have = 0
        ok = True
        j = _skip_blanks(buf, i, e)
        first = True
        while j < e:
            c = buf[j]
            slot = slot_of[c]
            if slot < 0 or (have >> slot) & 1 or (slot == 8 and not first):
                ok = False
                break
            first = False
            v, j, good, point = _number(buf, _skip_blanks(buf, j + 1, e), e, pow10)
            if not good or (slot == 8 and (point or v < 0.0)):
                ok = False
                break
            words[slot] = v
            have |= 1 << slot
            j = _skip_blanks(buf, j, e)
        line_traverse = traverse
        if ok and have & 128:
            # G0/G1 with no axis word still moves, to the current point (rs274): general path
            if not have & 63:
                ok = False
            elif words[7] == 0.0 or words[7] == 1.0:
                line_traverse = words[7] == 0.0
            else:
                ok = False
        if ok and have & 64 and words[6] <= 0.0:
            ok = False
        line_feed = words[6] if have & 64 else feed
        axes = have & 63
        if ok and axes and not line_traverse and line_feed <= 0.0:
            ok = False
        if not ok:
            i = line_start
            break
        if have & 64:
            feed = line_feed
            kind[k] = 2
            out_feed[k] = feed
            out_line[k] = line_no
            for a in range(6):
                out_pos[k, a] = cur[a]
            k += 1
        if axes:
            for a in range(6):
                if (axes >> a) & 1:
                    if incremental:
                        cur[a] += words[a]
                    else:
                        cur[a] = words[a]
            kind[k] = 0 if line_traverse else 1
            for a in range(6):
                out_pos[k, a] = cur[a]
            out_feed[k] = feed
            out_line[k] = line_no
            k += 1
        traverse = line_traverse
        i = next_line
        line_no += 1
    return kind[:k], out_pos[:k], out_feed[:k], out_line[:k], i, line_no, cur, feed, traverse


def scan(
    buf: np.ndarray,
    start: int,
    position: tuple[float, ...] | list[float],
    feed: float,
    *,
    incremental: bool,
    traverse: bool,
    first_line: int,
    max_events: int = 8192,
) -> Run:
    """The run of plain lines that starts at byte ``start`` of ``buf`` (a uint8 array).

    ``position`` (x y z a b c, program coordinates) and ``feed`` are the interpreter's
    state before the run, ``incremental`` is G91 and ``traverse`` G0 (else G1). The run
    ends at the first line the lane cannot take, at the end of the buffer, or after about
    ``max_events`` events. ``buf`` must end at a line end or at the end of the file.
    """
    kind, pos, feed_arr, line, end, line_no, cur, end_feed, end_trav = _scan(
        buf,
        start,
        _SLOT,
        _POW10,
        np.asarray(position, dtype=np.float64),
        float(feed),
        incremental,
        traverse,
        first_line,
        max_events,
    )
    return Run(
        kind,
        pos,
        feed_arr,
        line,
        int(end - start),
        int(line_no - first_line),
        tuple(cur.tolist()),
        float(end_feed),
        bool(end_trav),
    )


# ---------------------------------------------------------------- compiled text formatting
@njit(cache=True)
def _put_int(out, o, v, width, fill):  # pragma: no cover - compiled
    """Write non-negative ``v`` right-aligned in at least ``width`` columns."""
    tmp = np.empty(20, dtype=np.uint8)
    t = 0
    while True:
        tmp[t] = 48 + v % 10
        v //= 10
        t += 1
        if v == 0:
            break
    for _ in range(width - t):
        out[o] = fill
        o += 1
    for q in range(t - 1, -1, -1):
        out[o] = tmp[q]
        o += 1
    return o


@njit(cache=True)
def _put_fixed4(out, o, v):  # pragma: no cover - compiled
    """Write ``v`` with four decimals; returns (offset, needs Python formatting)."""
    a = -v if v < 0.0 else v
    if not a < 1e12:
        return o, True
    scaled = a * 10000.0
    frac = scaled - np.floor(scaled)
    tie = abs(frac - 0.5) < 1e-6
    q = np.int64(np.floor(scaled + 0.5))
    if v < 0.0 and q != 0:
        out[o] = 45
        o += 1
    o = _put_int(out, o, q // 10000, 1, 48)
    out[o] = 46
    r = q % 10000
    out[o + 1] = 48 + r // 1000
    out[o + 2] = 48 + (r // 100) % 10
    out[o + 3] = 48 + (r // 10) % 10
    out[o + 4] = 48 + r % 10
    return o + 5, tie


@njit(cache=True)
def _format(kind, pos, feed, seq0, names, name_len):  # pragma: no cover - compiled
    m = kind.shape[0]
    out = np.empty(m * 200 + 16, dtype=np.uint8)
    python = np.zeros(m, dtype=np.bool_)
    o = 0
    for k in range(m):
        o = _put_int(out, o, seq0 + k, 5, 32)
        for c in (32, 78, 46, 46, 46, 46, 46, 32):  # " N..... "
            out[o] = c
            o += 1
        kk = kind[k]
        for q in range(name_len[kk]):
            out[o] = names[kk, q]
            o += 1
        out[o] = 40
        o += 1
        if kk == 2:
            o, flag = _put_fixed4(out, o, feed[k])
            python[k] |= flag
        else:
            for a in range(6):
                if a:
                    out[o] = 44
                    out[o + 1] = 32
                    o += 2
                o, flag = _put_fixed4(out, o, pos[k, a])
                python[k] |= flag
        out[o] = 41
        out[o + 1] = 10
        o += 2
    return out[:o], python


_NAMES = (b"STRAIGHT_TRAVERSE", b"STRAIGHT_FEED", b"SET_FEED_RATE")
_NAME_TABLE = np.zeros((3, max(len(n) for n in _NAMES)), dtype=np.uint8)
for _k, _n in enumerate(_NAMES):
    _NAME_TABLE[_k, : len(_n)] = np.frombuffer(_n, dtype=np.uint8)
_NAME_LEN = np.array([len(n) for n in _NAMES], dtype=np.int64)


def events_text(run: Run, seq0: int) -> str:
    """Canonical text of a run's events numbered from ``seq0``.

    Identical to ``kernel.canon.write_text(run.commands(), seq0)`` joined with newlines
    (each line ends in a newline).
    """
    if len(run) == 0:
        return ""
    raw, python = _format(run.kind, run.position, run.feed, seq0, _NAME_TABLE, _NAME_LEN)
    text = raw.tobytes().decode("ascii")
    if not python.any():
        return text
    lines = text.split("\n")
    cmds = run.commands()
    for r in np.flatnonzero(python).tolist():
        lines[r] = f"{seq0 + r:5d} N..... {cmds[r].to_text()}"
    return "\n".join(lines)
