"""The compiled scanner of the Part 21 reader (:mod:`stepnc.p21_scan`).

:func:`_scan` walks the DATA section's bytes and takes each well-formed simple instance
``#n=NAME(...);`` that the reader's fast path (:mod:`stepnc.p21_fast`) would take, without
decoding its values: it records the instance's id, entity name (interned in a hash table),
the span of its parameter list, its line and column. It stops before the first instance it
cannot take (a comment inside it, a typed parameter, a binary, a string with a backslash,
a complex instance, an id already defined, any defect), which the Python reader then reads
and reports. Every instance it takes is one on which :func:`stepnc.p21_fast.fast_params`
succeeds, so decoding it later gives the values the Python reader gives.

The source is compiled two ways, as :mod:`gcode.ngc.lane.fastlane_kernels` is: numba's JIT
(``@njit(cache=True)``, the fallback) and numba.pycc ahead of time into a plain extension
module (:func:`build`, run by :mod:`kernel.aot` in a child process as
``python -m stepnc.p21_kernels DIR NAME``). An AOT module does not check argument types:
:mod:`stepnc.p21_scan` passes exactly those of :data:`SIGNATURES`.
"""

from __future__ import annotations

import sys

from numba import njit
from numba import types as nt

from kernel.aot import build_module

#: why a scan returned
STOP = 0  # the instance at ``pos`` is not one the scanner takes (or ENDSEC, or the end)
FULL = 1  # the output arrays are full
ID_BIG = 2  # the id of the instance at ``pos`` is beyond the id table
NAMES_FULL = 3  # the entity-name hash table is half full

#: list nesting taken (the fast path's :data:`stepnc.p21_fast._DEPTH`)
DEPTH = 4
#: the longest run of digits taken in one number (``int()`` refuses over 4300)
MAX_DIGITS = 1000


@njit(cache=True)
def _blank(c):  # pragma: no cover - compiled
    """ASCII white space (a subset of the ``\\s`` of Python's patterns)."""
    return c == 32 or (9 <= c <= 13)


@njit(cache=True)
def _name_char(c):  # pragma: no cover - compiled
    return (65 <= c <= 90) or (97 <= c <= 122) or (48 <= c <= 57) or c == 95


@njit(cache=True)
def _digits(buf, i, n):  # pragma: no cover - compiled
    """The end of the run of decimal digits at ``i``."""
    while i < n and 48 <= buf[i] <= 57:
        i += 1
    return i


@njit(cache=True)
def _atom(buf, i, n):  # pragma: no cover - compiled
    """The end of the unquoted value at ``i`` (a number, ``#n``, ``.NAME.``, ``$`` or
    ``*``) when it is followed by a blank, ``,`` or ``)``; -1 otherwise."""
    c = buf[i]
    j = -1
    if c == 36 or c == 42:  # $ *
        j = i + 1
    elif c == 35:  # #n
        k = _digits(buf, i + 1, n)
        if i + 1 < k <= i + 1 + MAX_DIGITS:
            j = k
    elif c == 46:  # .NAME.
        k = i + 1
        if k < n and _name_char(buf[k]) and not (48 <= buf[k] <= 57):
            while k < n and _name_char(buf[k]):
                k += 1
            if k < n and buf[k] == 46:
                j = k + 1
    else:  # [+-]digits[.digits[(e|E)[+-]digits]]
        k = i
        if c == 43 or c == 45:
            k += 1
        d = _digits(buf, k, n)
        if k < d <= k + MAX_DIGITS:
            j = d
            if d < n and buf[d] == 46:
                f = _digits(buf, d + 1, n)
                j = f
                if f - d - 1 > MAX_DIGITS:
                    j = -1
                elif f < n and (buf[f] == 69 or buf[f] == 101):
                    e = f + 1
                    if e < n and (buf[e] == 43 or buf[e] == 45):
                        e += 1
                    x = _digits(buf, e, n)
                    j = x if e < x <= e + MAX_DIGITS else -1
    if j < 0 or j >= n:
        return -1
    c = buf[j]
    if _blank(c) or c == 44 or c == 41:
        return j
    return -1


@njit(cache=True)
def _scan(
    buf,
    pos,
    rows,
    ids,
    names,
    body_s,
    body_e,
    lines,
    cols,
    seen,
    ht_start,
    ht_len,
    ht_id,
    n_names,
    line_no,
    last_nl,
):  # pragma: no cover - compiled
    """Take instances from byte ``pos`` on into row ``rows`` onwards of the output arrays.

    ``line_no`` is the line of ``pos`` and ``last_nl`` the offset of the last newline before
    it (-1: none). ``seen[id]`` is non-zero for an id already defined; the scanner sets it
    to row + 1. Returns (position after the last instance taken, rows, line number there,
    last newline before it, names, why it stopped, the id beyond ``seen`` with ID_BIG)."""
    n = buf.shape[0]
    cap = ids.shape[0]
    n_ids = seen.shape[0]
    hsize = ht_id.shape[0]
    status = STOP
    big = -1
    while True:
        if rows >= cap:
            status = FULL
            break
        i = pos
        ln = line_no
        nl = last_nl
        # blanks and comments before the instance
        good = True
        while i < n:
            c = buf[i]
            if c == 10:
                ln += 1
                nl = i
                i += 1
            elif _blank(c):
                i += 1
            elif c == 47 and i + 1 < n and buf[i + 1] == 42:
                k = i + 2
                while k + 1 < n and not (buf[k] == 42 and buf[k + 1] == 47):
                    k += 1
                if k + 1 >= n:
                    good = False
                    break
                for q in range(i, k):
                    if buf[q] == 10:
                        ln += 1
                        nl = q
                i = k + 2
            else:
                break
        if not good or i >= n or buf[i] != 35:
            break
        start = i
        col = start - nl
        start_line = ln
        d = _digits(buf, i + 1, n)
        if d == i + 1 or d - i - 1 > 18:
            break
        ident = 0
        for q in range(i + 1, d):
            ident = ident * 10 + (buf[q] - 48)
        i = d
        while i < n and _blank(buf[i]):
            if buf[i] == 10:
                ln += 1
                nl = i
            i += 1
        if i >= n or buf[i] != 61:  # =
            break
        i += 1
        while i < n and _blank(buf[i]):
            if buf[i] == 10:
                ln += 1
                nl = i
            i += 1
        if i >= n or not _name_char(buf[i]) or 48 <= buf[i] <= 57:
            break
        name_s = i
        while i < n and _name_char(buf[i]):
            i += 1
        name_e = i
        while i < n and _blank(buf[i]):
            if buf[i] == 10:
                ln += 1
                nl = i
            i += 1
        if i >= n or buf[i] != 40:  # (
            break
        bs = i
        i += 1
        depth = 1
        after_value = False  # else after '(' (first) or ','
        first = True
        while good:
            while i < n and _blank(buf[i]):
                if buf[i] == 10:
                    ln += 1
                    nl = i
                i += 1
            if i >= n:
                good = False
                break
            c = buf[i]
            if after_value:
                if c == 44:  # ,
                    after_value = False
                    first = False
                    i += 1
                elif c == 41:  # )
                    depth -= 1
                    i += 1
                    if depth == 0:
                        break
                else:
                    good = False
                continue
            if c == 41 and first:  # () : an empty list
                depth -= 1
                i += 1
                after_value = True
                if depth == 0:
                    break
                continue
            if c == 40:
                if depth == DEPTH:
                    good = False
                    break
                depth += 1
                i += 1
                first = True
                continue
            if c == 39:  # a string: '' inside, no backslash
                k = i + 1
                while True:
                    if k >= n:
                        good = False
                        break
                    b = buf[k]
                    if b == 39:
                        if k + 1 < n and buf[k + 1] == 39:
                            k += 2
                            continue
                        break
                    if b == 92:
                        good = False
                        break
                    if b == 10:
                        ln += 1
                        nl = k
                    k += 1
                if not good:
                    break
                i = k + 1
                after_value = True
                continue
            k = _atom(buf, i, n)
            if k < 0:
                good = False
                break
            i = k
            after_value = True
        if not good:
            break
        be = i
        while i < n and _blank(buf[i]):
            if buf[i] == 10:
                ln += 1
                nl = i
            i += 1
        if i >= n or buf[i] != 59:  # ;
            break
        i += 1
        if ident >= n_ids:
            status = ID_BIG
            big = ident
            break
        if seen[ident] != 0:
            break
        # the entity name's slot in the hash table (FNV-1a of its bytes)
        h = 2166136261
        for q in range(name_s, name_e):
            h = ((h ^ buf[q]) * 16777619) & 0xFFFFFFFF
        slot = h & (hsize - 1)
        length = name_e - name_s
        while ht_id[slot] >= 0:
            if ht_len[slot] == length:
                o = ht_start[slot]
                same = True
                for q in range(length):
                    if buf[o + q] != buf[name_s + q]:
                        same = False
                        break
                if same:
                    break
            slot = (slot + 1) & (hsize - 1)
        if ht_id[slot] < 0:
            if 2 * (n_names + 1) > hsize:
                status = NAMES_FULL
                break
            ht_id[slot] = n_names
            ht_start[slot] = name_s
            ht_len[slot] = length
            n_names += 1
        ids[rows] = ident
        names[rows] = ht_id[slot]
        body_s[rows] = bs
        body_e[rows] = be
        lines[rows] = start_line
        cols[rows] = col
        rows += 1
        seen[ident] = rows
        pos = i
        line_no = ln
        last_nl = nl
    return pos, rows, line_no, last_nl, n_names, status, big


_U8_RO = nt.Array(nt.uint8, 1, "C", readonly=True)
_I32 = nt.Array(nt.int32, 1, "C")
_I64 = nt.Array(nt.int64, 1, "C")

#: exported name -> (JIT function, explicit signature for numba.pycc)
SIGNATURES = {
    "scan": (
        _scan,
        nt.UniTuple(nt.int64, 7)(
            _U8_RO,
            nt.int64,
            nt.int64,
            _I32,
            _I32,
            _I32,
            _I32,
            _I32,
            _I32,
            _I32,
            _I64,
            _I64,
            _I32,
            nt.int64,
            nt.int64,
            nt.int64,
        ),
    ),
}

#: the JIT form under the exported name (the fallback when no AOT module can be built)
scan = _scan


if __name__ == "__main__":  # python -m MODULE DIR NAME: the AOT build (kernel.aot)
    build_module(sys.argv[1], sys.argv[2], SIGNATURES)
