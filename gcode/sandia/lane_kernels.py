"""The compiled kernel of the Sandia read-back lane (:mod:`gcode.sandia.lane`).

One scanner: a run of the lines the Sandia writer emits by the million (``MoveTo X= Y=
Z=``, ``SetSpeed v``, ``point_to_point_positioning ... attributes=ABSOLUTE|CS_CURRENT``)
read from the program's bytes into the fast lane's event arrays
(:class:`gcode.ngc.lane.fastlane.Run`). Compiled ahead of time by numba.pycc through
:mod:`kernel.aot` (``python -m gcode.sandia.lane_kernels DIR NAME``), numba's JIT as the
fallback; the AOT entry point takes exactly the argument types of :data:`SIGNATURES`.
"""

from __future__ import annotations

import sys

import numpy as np
from numba import njit
from numba import types as nt

from kernel.aot import build_module
from kernel.array_types import F64, F64_2D, I8, I64, U8_RO

#: event kinds, as gcode.ngc.lane.fastlane's
_TRAVERSE = 0
_FEED_MOVE = 1
_SET_FEED = 2


@njit(cache=True)
def _number(buf, k, size, pow10):  # pragma: no cover - compiled
    """The plain decimal at ``k`` up to a blank, a line end or the end of ``buf``, as
    float() reads it (gcode.sandia.reader's ``_NUMBER``: ``[-+]?(digits[.digits]|.digits)``):
    (value, the index after it, ok); not ok where it is not one, or has more than 15
    digits (the general path reads those)."""
    negative = False
    if k < size and (buf[k] == 43 or buf[k] == 45):
        negative = buf[k] == 45
        k += 1
    mant = 0
    whole = 0
    frac = 0
    point = False
    while k < size:
        c = buf[k]
        if 48 <= c <= 57:
            mant = mant * 10 + (np.int64(c) - 48)  # exact: at most 15 digits are kept
            if point:
                frac += 1
            else:
                whole += 1
        elif c == 46 and not point:
            point = True
        elif c == 32 or c == 9 or c == 10:
            break
        else:
            return 0.0, k, False
        k += 1
    if whole + frac == 0 or whole + frac > 15:
        return 0.0, k, False
    v = float(mant) / pow10[frac]  # both exact: the correctly rounded quotient, as float()
    return (-v if negative else v), k, True


@njit(cache=True)
def _starts(buf, j, size, word):  # pragma: no cover - compiled
    """Whether ``buf[j:]`` starts with ``word``."""
    if j + len(word) > size:
        return False
    for k in range(len(word)):  # noqa: SIM110 - a compiled loop, no generator
        if buf[j + k] != word[k]:
            return False
    return True


@njit(cache=True)
def _ends(buf, k, size):  # pragma: no cover - compiled
    """Whether a word ends at ``k``: a blank, a line end or the end of ``buf``."""
    return k == size or buf[k] == 32 or buf[k] == 9 or buf[k] == 10


@njit(cache=True)
def _skip(buf, k, size):  # pragma: no cover - compiled
    while k < size and (buf[k] == 32 or buf[k] == 9):
        k += 1
    return k


@njit(cache=True)
def _scan(buf, start, pos, speed, first_line, max_events, words):  # pragma: no cover - compiled
    """The run of lane lines from byte ``start`` (a line start) of ``buf``.

    ``pos``: x y z a b c before the run, ``speed`` the SetSpeed speed (0 for none);
    ``words``: the names ``MoveTo``, ``SetSpeed``, ``point_to_point_positioning``,
    ``speed=``, ``attributes=`` and ``ABSOLUTE|CS_CURRENT`` joined by zero bytes. A lane
    line starts in column 1 with one of the three names, its words separated by blanks
    and tabs: ``MoveTo`` with X= Y= Z= (each at most once, a speed above 0 in force),
    ``SetSpeed v`` or ``SetSpeed speed=v`` (v >= 0), ``point_to_point_positioning`` with
    X= Y= Z= A= B= C= and ``attributes=ABSOLUTE|CS_CURRENT`` (each at most once); blank
    lines are skipped. The run ends before the first other line (the general reader
    takes it, and owns every diagnostic), at the end of ``buf`` or after ``max_events``.
    One pass over the bytes: each word is read where it starts.

    Returns (kinds, positions after each event, speed in force, source lines, byte
    offset after the run, the next line's number, the position after, the speed after,
    whether a SetSpeed was read)."""
    cut = [0]
    for k in range(len(words)):
        if words[k] == 0:
            cut.append(k + 1)
    move_to = words[cut[0] : cut[1] - 1]
    set_speed = words[cut[1] : cut[2] - 1]
    p2p = words[cut[2] : cut[3] - 1]
    speed_key = words[cut[3] : cut[4] - 1]
    attributes = words[cut[4] : cut[5] - 1]
    absolute = words[cut[5] : cut[6] - 1]
    pow10 = np.empty(23)
    pow10[0] = 1.0
    for k in range(1, 23):
        pow10[k] = pow10[k - 1] * 10.0
    size = len(buf)
    kind = np.empty(max_events, dtype=np.int8)
    out = np.empty((max_events, 6))
    feed = np.empty(max_events)
    line = np.empty(max_events, dtype=np.int64)
    cur = pos.copy()
    new = np.empty(6)
    n = 0
    j = start
    line_no = first_line
    set_any = False
    while j < size and n < max_events:
        c = buf[j]
        if c == 10 or c == 32 or c == 9:  # a blank line is skipped; an indented one ends
            k = _skip(buf, j, size)
            if k < size and buf[k] != 10:
                break
            j = k + 1 if k < size else k
            line_no += 1
            continue
        if c == 77 and _starts(buf, j, size, move_to):
            code = _FEED_MOVE
            k = j + len(move_to)
        elif c == 112 and _starts(buf, j, size, p2p):
            code = _TRAVERSE
            k = j + len(p2p)
        elif c == 83 and _starts(buf, j, size, set_speed):
            code = _SET_FEED
            k = j + len(set_speed)
        else:
            break
        if not _ends(buf, k, size):
            break
        k = _skip(buf, k, size)
        ok = True
        if code == _SET_FEED:
            if _starts(buf, k, size, speed_key):
                k += len(speed_key)
            v, k, ok = _number(buf, k, size, pow10)
            k = _skip(buf, k, size)
            if not ok or v < 0.0 or not (k == size or buf[k] == 10):
                break  # malformed, negative, or not exactly one argument
            speed = v
            set_any = True
            for a in range(6):
                out[n, a] = cur[a]
        else:
            for a in range(6):
                new[a] = cur[a]
            seen = 0
            while k < size and buf[k] != 10:
                a = -1
                if k + 1 < size and buf[k + 1] == 61:  # X=...
                    letter = buf[k]
                    if 88 <= letter <= 90:
                        a = letter - 88
                    elif code == _TRAVERSE and 65 <= letter <= 67:
                        a = letter - 62
                if a >= 0 and not seen & (1 << a):
                    v, k, ok = _number(buf, k + 2, size, pow10)
                    if not ok:
                        break
                    new[a] = v
                    seen |= 1 << a
                elif (
                    code == _TRAVERSE
                    and not seen & 64
                    and _starts(buf, k, size, attributes)
                    and _starts(buf, k + len(attributes), size, absolute)
                    and _ends(buf, k + len(attributes) + len(absolute), size)
                ):
                    seen |= 64
                    k += len(attributes) + len(absolute)
                else:
                    ok = False
                    break
                k = _skip(buf, k, size)
            if not ok or (code == _FEED_MOVE and speed == 0.0):
                break
            for a in range(6):
                cur[a] = new[a]
                out[n, a] = new[a]
        kind[n] = code
        feed[n] = speed
        line[n] = line_no
        n += 1
        j = k + 1 if k < size else k
        line_no += 1
    return (
        kind[:n].copy(),
        out[:n].copy(),
        feed[:n].copy(),
        line[:n].copy(),
        j,
        line_no,
        cur,
        speed,
        set_any,
    )


#: exported name -> (JIT function, explicit signature for numba.pycc)
SIGNATURES = {
    "scan": (
        _scan,
        nt.Tuple(
            (
                I8,
                F64_2D,
                F64,
                I64,
                nt.int64,
                nt.int64,
                F64,
                nt.float64,
                nt.boolean,
            )
        )(U8_RO, nt.int64, F64, nt.float64, nt.int64, nt.int64, U8_RO),
    ),
}

#: the JIT form under the exported name (the fallback when no AOT module can be built)
scan = _scan


if __name__ == "__main__":  # python -m MODULE DIR NAME: the AOT build (kernel.aot)
    build_module(sys.argv[1], sys.argv[2], SIGNATURES)
