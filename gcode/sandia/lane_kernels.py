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

#: event kinds, as gcode.ngc.lane.fastlane's
_TRAVERSE = 0
_FEED_MOVE = 1
_SET_FEED = 2


@njit(cache=True)
def _blank(c):  # pragma: no cover - compiled
    return c == 32 or c == 9


@njit(cache=True)
def _value(buf, j, e, pow10):  # pragma: no cover - compiled
    """The plain decimal ``buf[j:e]`` as float() reads it (gcode.sandia.reader's
    ``_NUMBER``: ``[-+]?(digits[.digits]|.digits)``, at most 20 integer digits); ok False
    where it is not one, or has more than 15 digits (the general path reads those)."""
    if j < e and (buf[j] == 43 or buf[j] == 45):
        negative = buf[j] == 45
        j += 1
    else:
        negative = False
    mant = 0.0
    whole = 0
    frac = 0
    point = False
    while j < e:
        c = buf[j]
        if 48 <= c <= 57:
            mant = mant * 10.0 + (c - 48)
            if point:
                frac += 1
            else:
                whole += 1
        elif c == 46 and not point:
            point = True
        else:
            return 0.0, False
        j += 1
    if whole + frac == 0 or whole + frac > 15:
        return 0.0, False
    v = mant / pow10[frac]  # both exact: the correctly rounded quotient, as float()
    return (-v if negative else v), True


@njit(cache=True)
def _token_end(buf, j, e):  # pragma: no cover - compiled
    while j < e and not _blank(buf[j]):
        j += 1
    return j


@njit(cache=True)
def _skip(buf, j, e):  # pragma: no cover - compiled
    while j < e and _blank(buf[j]):
        j += 1
    return j


@njit(cache=True)
def _same(buf, j, e, word):  # pragma: no cover - compiled
    """Whether ``buf[j:e]`` is ``word``."""
    if e - j != len(word):
        return False
    for k in range(len(word)):  # noqa: SIM110 - a compiled loop, no generator
        if buf[j + k] != word[k]:
            return False
    return True


@njit(cache=True)
def _scan(buf, start, pos, speed, first_line, max_events, words):  # pragma: no cover - compiled
    """The run of lane lines from byte ``start`` (a line start) of ``buf``.

    ``pos``: x y z a b c before the run, ``speed`` the SetSpeed speed (0 for none);
    ``words``: the names ``MoveTo``, ``SetSpeed``, ``point_to_point_positioning``,
    ``speed=``, ``attributes`` and ``ABSOLUTE|CS_CURRENT`` joined by zero bytes. A lane
    line starts in column 1 with one of the three names, its words separated by blanks
    and tabs: ``MoveTo`` with X= Y= Z= (each at most once, a speed above 0 in force),
    ``SetSpeed v`` or ``SetSpeed speed=v`` (v >= 0), ``point_to_point_positioning`` with
    X= Y= Z= A= B= C= and ``attributes=ABSOLUTE|CS_CURRENT`` (each at most once); blank
    lines are skipped. The run ends before the first other line (the general reader
    takes it, and owns every diagnostic), at the end of ``buf`` or after ``max_events``.

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
    n_buf = len(buf)
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
    while j < n_buf and n < max_events:
        e = j
        while e < n_buf and buf[e] != 10:
            e += 1
        nxt = e + 1 if e < n_buf else e
        if j == e or _blank(buf[j]):
            if _skip(buf, j, e) != e:
                break  # indented: the general reader's (its column)
            j = nxt
            line_no += 1
            continue
        t = _token_end(buf, j, e)
        ok = True
        if _same(buf, j, t, move_to) or _same(buf, j, t, p2p):
            traverse = not _same(buf, j, t, move_to)
            for a in range(6):
                new[a] = cur[a]
            seen = 0
            k = _skip(buf, t, e)
            while k < e:
                t2 = _token_end(buf, k, e)
                if t2 - k >= 3 and buf[k + 1] == 61:  # X=...
                    c = buf[k]
                    a = -1
                    if 88 <= c <= 90:
                        a = c - 88
                    elif traverse and 65 <= c <= 67:
                        a = c - 62
                    if a < 0 or seen & (1 << a):
                        ok = False
                        break
                    v, good = _value(buf, k + 2, t2, pow10)
                    if not good:
                        ok = False
                        break
                    new[a] = v
                    seen |= 1 << a
                elif (
                    traverse
                    and not seen & 64
                    and t2 - k == len(attributes) + 1 + len(absolute)
                    and _same(buf, k, k + len(attributes), attributes)
                    and buf[k + len(attributes)] == 61
                    and _same(buf, k + len(attributes) + 1, t2, absolute)
                ):
                    seen |= 64
                else:
                    ok = False
                    break
                k = _skip(buf, t2, e)
            if not ok or (not traverse and speed == 0.0):
                break
            for a in range(6):
                cur[a] = new[a]
                out[n, a] = new[a]
            kind[n] = _TRAVERSE if traverse else _FEED_MOVE
        elif _same(buf, j, t, set_speed):
            k = _skip(buf, t, e)
            t2 = _token_end(buf, k, e)
            if k == e or _skip(buf, t2, e) != e:
                break  # not exactly one argument
            if t2 - k > len(speed_key) and _same(buf, k, k + len(speed_key), speed_key):
                k += len(speed_key)
            v, good = _value(buf, k, t2, pow10)
            if not good or v < 0.0:
                break
            speed = v
            set_any = True
            for a in range(6):
                out[n, a] = cur[a]
            kind[n] = _SET_FEED
        else:
            break
        feed[n] = speed
        line[n] = line_no
        n += 1
        j = nxt
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


_U8_RO = nt.Array(nt.uint8, 1, "C", readonly=True)
_I8 = nt.Array(nt.int8, 1, "C")
_I64 = nt.Array(nt.int64, 1, "C")
_F64 = nt.Array(nt.float64, 1, "C")
_F64_2D = nt.Array(nt.float64, 2, "C")

#: exported name -> (JIT function, explicit signature for numba.pycc)
SIGNATURES = {
    "scan": (
        _scan,
        nt.Tuple(
            (
                _I8,
                _F64_2D,
                _F64,
                _I64,
                nt.int64,
                nt.int64,
                _F64,
                nt.float64,
                nt.boolean,
            )
        )(_U8_RO, nt.int64, _F64, nt.float64, nt.int64, nt.int64, _U8_RO),
    ),
}

#: the JIT form under the exported name (the fallback when no AOT module can be built)
scan = _scan


if __name__ == "__main__":  # python -m MODULE DIR NAME: the AOT build (kernel.aot)
    build_module(sys.argv[1], sys.argv[2], SIGNATURES)
