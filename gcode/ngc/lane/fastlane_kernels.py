"""The compiled kernels of the fast lane (:mod:`gcode.ngc.lane.fastlane`): scanner and text
formatters.

The source is shared by two ways of compiling it: numba's JIT (``@njit(cache=True)``,
imported only as a fallback) and numba.pycc ahead of time into a plain extension module
that needs neither numba nor its compile at run time (:func:`build`, run by
:mod:`gcode.ngc.lane.fastlane` in a child process as
``python -m gcode.ngc.lane.fastlane_kernels DIR NAME``).
The AOT entry points take exactly the argument types in :data:`SIGNATURES`; an AOT module
does not check types, so :mod:`gcode.ngc.lane.fastlane` converts every argument before the call.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from numba import njit
from numba import types as nt

from kernel.aot import build_module
from kernel.array_types import F64, F64_2D, I8, I64, U8, U8_RO


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
def _two_product(a, b):  # pragma: no cover - compiled
    """``a * b`` as an exact sum hi + lo (Veltkamp split, Dekker's product)."""
    p = a * b
    c = 134217729.0 * a
    a_hi = c - (c - a)
    a_lo = a - a_hi
    c = 134217729.0 * b
    b_hi = c - (c - b)
    b_lo = b - b_hi
    return p, ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo


@njit(cache=True)
def _py_hypot(x, y):  # pragma: no cover - compiled
    """``math.hypot(x, y)`` to the last bit: CPython's algorithm (since 3.10) of a lossless
    scaling by a power of two, exact squares summed around 1.0 with their rounding errors,
    a square root and one differential correction. -1.0 for a value too small to scale
    (the caller leaves the line to the general path)."""
    x = abs(x)
    y = abs(y)
    m = x if x > y else y
    if m == 0.0 or math.isinf(m):
        return m
    e = math.frexp(m)[1]
    if e < -1000:
        return -1.0
    scale = math.ldexp(1.0, -e)
    csum = 1.0
    frac1 = 0.0
    frac2 = 0.0
    for v in (x * scale, y * scale):
        hi, lo = _two_product(v, v)
        total = csum + hi
        frac2 += (csum - total) + hi
        csum = total
        frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _two_product(-h, h)
    total = csum + hi
    frac2 += (csum - total) + hi
    csum = total
    frac1 += lo
    h += (csum - 1.0 + (frac1 + frac2)) / (2.0 * h)
    return h / scale


@njit(cache=True)
def _radius_centre(s1, s2, e1, e2, radius, clockwise, reach):  # pragma: no cover - compiled
    """The centre of an R arc as gcode.core.arcs.radius_format computes it (LinuxCNC
    ``arc_data_r``), with the same operations in the same order; ok False where that
    function would raise, or near its limits (the general path decides those)."""
    abs_r = abs(radius)
    if (s1 == e1 and s2 == e2) or abs_r == 0.0:
        return 0.0, 0.0, False
    mid1 = (e1 + s1) / 2.0
    mid2 = (e2 + s2) / 2.0
    half = _py_hypot(mid1 - e1, mid2 - e2)
    if half < 0.0 or half - abs_r > reach * (1.0 - 1e-6):
        return 0.0, 0.0, False
    if half / abs_r > 1.0 - 1e-12:
        half = abs_r
    theta = math.atan2(e2 - s2, e1 - s1)
    if (clockwise and radius > 0) or (not clockwise and radius < 0):
        theta += -math.pi / 2
    else:
        theta += math.pi / 2
    turn2 = math.acos(max(-1.0, min(1.0, half / abs_r)))
    offset = abs_r * math.sin(turn2)
    return mid1 + offset * math.cos(theta), mid2 + offset * math.sin(theta), True


@njit(cache=True)
def _arc_radii_agree(r1, r2, tol, zero):  # pragma: no cover - compiled
    """The centre-format checks of gcode.core.arcs.centre_format, decided only where they
    hold with a margin far above the last-bit difference between ``sqrt(x*x + y*y)`` and
    Python's ``math.hypot``: False sends the line to the general interpreter, which decides
    (and owns the diagnostic)."""
    big = r1 if r1 > r2 else r2
    m = 1e-9 * (1.0 + big)
    if r1 < zero + m or r2 < zero + m:
        return False
    err = abs(r1 - r2)
    return err <= tol - m or err + m <= 0.001 * big


@njit(cache=True)
def _scan(
    buf,
    start,
    slot_of,
    pow10,
    pos,
    feed,
    incremental,
    motion,
    first_line,
    max_events,
    arcs,
    bare,
    plane,
    arc_tol,
    ijk_absolute,
    point_slots,
):  # pragma: no cover - compiled
    n = buf.shape[0]
    kind = np.empty(max_events, dtype=np.int8)
    out_pos = np.empty((max_events, 6), dtype=np.float64)
    out_feed = np.empty(max_events, dtype=np.float64)
    out_line = np.empty(max_events, dtype=np.int64)
    out_arc = np.empty((max_events, 6), dtype=np.float64)
    cur = pos.copy()
    end = pos.copy()
    words = np.zeros(13, dtype=np.float64)
    f1 = plane[0]
    f2 = plane[1]
    fn = plane[2]
    ci = plane[3]
    cj = plane[4]
    ck = plane[5]
    c1 = 0.0
    c2 = 0.0
    k = 0
    i = start
    line_no = first_line
    while i < n and k + 2 <= max_events:
        line_start = i
        e = i
        while e < n and buf[e] != 10:
            e += 1
        next_line = e + 1 if e < n else n
        while e > i and buf[e - 1] == 13:  # every CR before the LF, as rstrip("\r\n")
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
            if slot >= 9 and not arcs:
                ok = False
                break
            first = False
            v, j, good, point = _number(buf, _skip_blanks(buf, j + 1, e), e, pow10)
            if not good or (slot == 8 and (point or v < 0.0)):
                ok = False
                break
            if (point_slots >> slot) & 1 and not point:  # a number the reader reads otherwise
                ok = False
                break
            words[slot] = v
            have |= 1 << slot
            j = _skip_blanks(buf, j, e)
        axes = have & 63
        line_motion = motion
        if ok and have & 128:
            g = words[7]
            if g == 0.0 or g == 1.0 or (arcs and (g == 2.0 or g == 3.0)):
                line_motion = int(g)
            else:
                ok = False
            # G0/G1 with no axis word still moves, to the current point (rs274); a bare
            # G2/G3 is the general path's
            if not axes and (not bare or line_motion >= 2):
                ok = False
        moving = axes != 0 or (have & 128) != 0
        centre_words = have & 3584  # I J K
        if ok and (centre_words or have & 4096) and (line_motion < 2 or not axes):
            ok = False
        if ok and have & 64 and words[6] <= 0.0:
            ok = False
        line_feed = words[6] if have & 64 else feed
        if ok and moving and line_motion != 0 and line_feed <= 0.0:
            ok = False
        if ok and moving:
            for a in range(6):
                if (axes >> a) & 1:
                    end[a] = cur[a] + words[a] if incremental else words[a]
                else:
                    end[a] = cur[a]
        if ok and moving and line_motion >= 2:
            # centre or radius format in the run's plane (gcode.ngc.motion.arc); P and the plane's
            # normal centre word are the general path's
            has_i = (have >> ci) & 1
            has_j = (have >> cj) & 1
            if have & 4096:
                # radius format: an in-plane axis word and no centre word
                if centre_words or not ((axes >> f1) & 1 or (axes >> f2) & 1):
                    ok = False
                else:
                    c1, c2, ok = _radius_centre(
                        cur[f1], cur[f2], end[f1], end[f2], words[12], line_motion == 2, arc_tol[2]
                    )
            elif (have >> ck) & 1 or not (has_i or has_j):
                ok = False
            elif ijk_absolute:
                if not (has_i and has_j):
                    ok = False
                c1 = words[ci]
                c2 = words[cj]
            else:
                c1 = cur[f1] + (words[ci] if has_i else 0.0)
                c2 = cur[f2] + (words[cj] if has_j else 0.0)
            if ok and not have & 4096:
                r1 = np.sqrt((cur[f1] - c1) ** 2 + (cur[f2] - c2) ** 2)
                r2 = np.sqrt((end[f1] - c1) ** 2 + (end[f2] - c2) ** 2)
                if not _arc_radii_agree(r1, r2, arc_tol[0], arc_tol[1]):
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
        if moving:
            for a in range(6):
                cur[a] = end[a]
            if line_motion >= 2:
                kind[k] = 3
                out_arc[k, 0] = end[f1]
                out_arc[k, 1] = end[f2]
                out_arc[k, 2] = c1
                out_arc[k, 3] = c2
                out_arc[k, 4] = -1.0 if line_motion == 2 else 1.0
                out_arc[k, 5] = end[fn]
            else:
                kind[k] = line_motion
            for a in range(6):
                out_pos[k, a] = cur[a]
            out_feed[k] = feed
            out_line[k] = line_no
            k += 1
        motion = line_motion
        i = next_line
        line_no += 1
    return (
        kind[:k],
        out_pos[:k],
        out_feed[:k],
        out_line[:k],
        out_arc[:k],
        i,
        line_no,
        cur,
        feed,
        motion,
    )


@njit(cache=True)
def _put_int(out, o, v, width, fill):  # pragma: no cover - compiled
    """Write non-negative ``v`` right-aligned in at least ``width`` columns."""
    t = 1
    p = 10
    while p <= v and t < 19:
        p *= 10
        t += 1
    for _ in range(width - t):
        out[o] = fill
        o += 1
    for q in range(t - 1, -1, -1):
        out[o + q] = 48 + v % 10
        v //= 10
    return o + t


@njit(cache=True, error_model="numpy")
def _put_fixed4(out, o, v):  # pragma: no cover - compiled
    """Write ``v`` with four decimals; returns (offset, needs Python formatting).

    Digits come from unsigned arithmetic (divisions by constants compile to multiplies).
    """
    a = -v if v < 0.0 else v
    if not a < 1e12:
        return o, True
    scaled = a * 10000.0
    frac = scaled - np.floor(scaled)
    tie = abs(frac - 0.5) < 1e-6
    ten = np.uint64(10)
    zero = np.uint64(48)  # "0"
    q = np.uint64(np.floor(scaled + 0.5))
    if v < 0.0 and q != 0:
        out[o] = 45
        o += 1
    whole = q // np.uint64(10000)
    r = q - whole * np.uint64(10000)
    t = 1
    p = ten
    while p <= whole:  # whole < 1e8: no overflow
        p *= ten
        t += 1
    for j in range(t - 1, -1, -1):
        d = whole // ten
        out[o + j] = zero + (whole - d * ten)
        whole = d
    o += t
    out[o] = 46
    for j in range(4, 0, -1):
        d = r // ten
        out[o + j] = zero + (r - d * ten)
        r = d
    return o + 5, tie


@njit(cache=True)
def _format(kind, pos, feed, seq0, names, name_len):  # pragma: no cover - compiled
    """Canonical text of the events (bytes), which lines need Python formatting, how many."""
    return _format_arcs(kind, pos, feed, np.zeros((0, 6), dtype=np.float64), seq0, names, name_len)


@njit(cache=True)
def _format_arcs(kind, pos, feed, arc, seq0, names, name_len):  # pragma: no cover - compiled
    """:func:`_format` of events that may hold arcs: an ``ARC_FEED`` (kind 3) prints its row
    of ``arc`` (in-plane end, centre, the signed turns as an integer, the end on the normal
    axis), then A B C."""
    m = kind.shape[0]
    out = np.empty(m * 260 + 16, dtype=np.uint8)
    python = np.zeros(m, dtype=np.bool_)
    flagged = 0
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
        elif kk == 3:
            for a in range(9):
                if a:
                    out[o] = 44
                    out[o + 1] = 32
                    o += 2
                if a == 4:
                    turns = int(arc[k, 4])
                    if turns < 0:
                        out[o] = 45
                        o += 1
                        turns = -turns
                    o = _put_int(out, o, turns, 0, 32)
                    continue
                v = arc[k, a] if a < 4 else (arc[k, 5] if a == 5 else pos[k, a - 3])
                o, flag = _put_fixed4(out, o, v)
                python[k] |= flag
        else:
            for a in range(6):
                if a:
                    out[o] = 44
                    out[o + 1] = 32
                    o += 2
                o, flag = _put_fixed4(out, o, pos[k, a])
                python[k] |= flag
        if python[k]:
            flagged += 1
        out[o] = 41
        out[o + 1] = 10
        o += 2
    return out[:o], python, flagged


@njit(cache=True, error_model="numpy")
def _put_num(out, o, v, places, point):  # pragma: no cover - compiled
    """``v`` as a G-code word value (gcode.write.state.Formatter rules): ``places``
    decimals, trailing zeros dropped, the point kept when ``point`` (Fanuc), no ``-0``.
    Returns (offset, too large for the kernel: 1e12 or more)."""
    a = -v if v < 0.0 else v
    if not a < 1e12:
        return o, True
    scale = 1.0
    for _ in range(places):
        scale *= 10.0
    scaled = a * scale
    low = np.floor(scaled)
    if abs(scaled - low - 0.5) < 1e-6:
        # near a rounding tie: decide it on the exact product a * 10^places, as Python's
        # correctly rounded "%.*f" does (Veltkamp split, Dekker's two-product; exact ties
        # go to the even digit)
        c = 134217729.0 * a
        a_hi = c - (c - a)
        a_lo = a - a_hi
        c = 134217729.0 * scale
        s_hi = c - (c - scale)
        s_lo = scale - s_hi
        err = ((a_hi * s_hi - scaled) + a_hi * s_lo + a_lo * s_hi) + a_lo * s_lo
        d = (scaled - (low + 0.5)) + err
        if d > 0.0 or (d == 0.0 and low % 2.0 == 1.0):
            low += 1.0
        q = np.uint64(low)
    else:
        q = np.uint64(np.floor(scaled + 0.5))
    if q >= np.uint64(10) ** np.uint64(17):
        return o, True
    ten = np.uint64(10)
    if v < 0.0 and q != 0:
        out[o] = 45
        o += 1
    div = np.uint64(1)
    for _ in range(places):
        div *= ten
    whole = q // div
    r = q - whole * div
    t = 1
    p = ten
    while p <= whole:
        p *= ten
        t += 1
    for j in range(t - 1, -1, -1):
        d = whole // ten
        out[o + j] = 48 + (whole - d * ten)
        whole = d
    o += t
    if places == 0:
        return o, False
    digits = places
    while digits > 0 and r % ten == 0:  # trailing zeros of the fraction
        r //= ten
        digits -= 1
    if digits == 0:
        if point:
            out[o] = 46
            o += 1
        return o, False
    out[o] = 46
    for j in range(digits, 0, -1):
        d = r // ten
        out[o + j] = 48 + (r - d * ten)
        r = d
    return o + digits + 1, False


@njit(cache=True)
def _read_words(state, rows, width):  # pragma: no cover - compiled
    """The zero-terminated words of ``state`` as rows of a (``rows``, ``width``) array and
    their lengths; the last length is -1 when a word does not fit."""
    words = np.zeros((rows, width), dtype=np.uint8)
    lens = np.zeros(rows, dtype=np.int64)
    r = 0
    for b in state:
        if r >= rows:
            break
        if b == 0:
            r += 1
        elif lens[r] >= width:
            lens[rows - 1] = -1
            break
        else:
            words[r, lens[r]] = b
            lens[r] += 1
    return words, lens


@njit(cache=True)
def _write_words(words, lens, rows):  # pragma: no cover - compiled
    """The first ``rows`` words, each followed by a zero byte (the form _read_words reads)."""
    out = np.empty(rows * (words.shape[1] + 1), dtype=np.uint8)
    o = 0
    for r in range(rows):
        for j in range(lens[r]):
            out[o] = words[r, j]
            o += 1
        out[o] = 0
        o += 1
    return out[:o]


@njit(cache=True)
def _gcode(
    kind,
    pos,
    feed,
    scale,
    axes,
    factor,
    absent,
    letters,
    places,
    point,
    state,
    codes,
    code_len,
    motion,
    feed0,
    sep,
):  # pragma: no cover - compiled
    """:func:`_gcode_arcs` for a run without arcs."""
    return _gcode_arcs(
        kind,
        pos,
        feed,
        np.zeros((0, 6), dtype=np.float64),
        scale,
        axes,
        factor,
        absent,
        letters,
        places,
        point,
        state,
        codes,
        code_len,
        motion,
        feed0,
        sep,
        np.zeros(6, dtype=np.int64),
    )


@njit(cache=True)
def _word_value(word, n):  # pragma: no cover - compiled
    """The number of an axis word (its letter first) as ``float()`` reads it, and whether
    it is exact here (a mantissa of at most 15 digits over a power of ten)."""
    j = 1
    negative = n > 1 and word[1] == 45
    if negative:
        j = 2
    m = 0
    digits = 0
    frac = -1
    while j < n:
        b = word[j]
        if b == 46:
            frac = 0
        else:
            m = m * 10 + (b - 48)
            digits += 1
            if frac >= 0:
                frac += 1
        j += 1
    if digits == 0 or digits > 15:
        return 0.0, False
    div = 1.0
    for _ in range(max(frac, 0)):
        div *= 10.0
    v = m / div
    return (-v if negative else v), True


@njit(cache=True)
def _gcode_arcs(
    kind,
    pos,
    feed,
    arc,
    scale,
    axes,
    factor,
    absent,
    letters,
    places,
    point,
    state,
    codes,
    code_len,
    motion,
    feed0,
    sep,
    plane,
):  # pragma: no cover - compiled
    """G-code blocks of a run's events (gcode.write.bulk.write_run's rules), joined by
    newlines. ``pos`` and ``feed`` are in program units (X Y Z and F times ``scale`` are the
    output's), an axis word's value is times its ``factor`` (2 on a diameter axis); ``state``
    holds the axis words last written and the F word last written
    (letters included, each ending in a zero byte, empty when unknown); ``feed0`` is the
    feed rate in force; ``absent``: the axes the dialect lacks. Arcs (kind 3, ``arc``'s
    rows as ARC_FEED takes them, one turn) are written as gcode.write.handlers.arc writes
    them with incremental centres: codes rows 2 and 3 (clockwise, counter-clockwise),
    both in-plane end words, the changed others, the centre words; ``plane`` holds the
    positions in ``axes`` of the plane's first and second axes, the normal axis (0-2), the
    centre words' letters in the order they are written, and 1 when that order is the
    second axis's centre first (the XZ plane's I before K). Returns (text, whether the
    kernel cannot write the run: a number too large, an absent axis off zero, an arc it
    does not take, the motion code index after, the longest block, the number of blocks,
    ``state`` after)."""
    m = kind.shape[0]
    na = axes.shape[0]
    for k in range(m):
        for a in absent:
            if abs(pos[k, a]) > 1e-9:  # the handlers refuse it at its line
                return np.empty(0, dtype=np.uint8), True, motion, 0, 0, state.copy()
    last, last_len = _read_words(state, na + 2, 64)
    too_large = last_len[na + 1] < 0
    fw = na + 1  # row of the F word of the feed in force; row na: the F word written
    last[fw, 0] = 70
    n, big = _put_num(last[fw], 1, feed0 * scale, places, point)
    too_large |= big
    last_len[fw] = n
    out = np.empty(m * (12 + 32 * (na + 3)) + 64, dtype=np.uint8)
    word = np.empty(32, dtype=np.uint8)
    centre = np.empty((2, 32), dtype=np.uint8)
    centre_len = np.zeros(2, dtype=np.int64)
    target = np.empty(6, dtype=np.float64)
    p1, p2 = plane[0], plane[1]
    last_value = np.full(max(na, 1), np.nan)  # the value each axis word was last made of
    in_plane = np.zeros(max(na, 1), dtype=np.bool_)  # written in every arc block
    if na:
        in_plane[p1] = True
        in_plane[p2] = True
    o = 0
    longest = 0
    blocks = 0
    for k in range(m):
        kk = kind[k]
        if kk == 2:  # SET_FEED: the F word of the new rate, written with the next move
            n, big = _put_num(last[fw], 1, feed[k] * scale, places, point)
            too_large |= big
            last_len[fw] = n
            continue
        is_arc = kk == 3
        code = kk
        for a in range(6):
            target[a] = pos[k, a] * scale if a < 3 else pos[k, a]
        if is_arc:
            turns = arc[k, 4]
            if turns != 1.0 and turns != -1.0:
                too_large = True
                break
            code = 3 if turns > 0 else 2
            # the start: the in-plane words last written, as the reader reads them back
            start1, ok1 = _word_value(last[p1], last_len[p1])
            start2, ok2 = _word_value(last[p2], last_len[p2])
            if not (ok1 and ok2):
                too_large = True
                break
            target[axes[p1]] = arc[k, 0] * scale
            target[axes[p2]] = arc[k, 1] * scale
            target[plane[2]] = arc[k, 5] * scale
            for c in range(2):  # row c: the centre word written c-th
                first = (c == 0) != (plane[5] != 0)
                centre[c, 0] = plane[3 + c]
                value = arc[k, 2] * scale - start1 if first else arc[k, 3] * scale - start2
                n, big = _put_num(centre[c], 1, value, places, point)
                too_large |= big
                centre_len[c] = n
        start = o
        if code != motion:
            motion = code
            for j in range(code_len[code]):
                out[o] = codes[code, j]
                o += 1
        changed = False
        for a in range(na):
            v = target[axes[a]] * factor[a]
            if v == last_value[a]:  # the text of the value formatted last: no formatting
                if is_arc and in_plane[a]:
                    if o > start:
                        out[o] = sep
                        o += 1
                    for j in range(last_len[a]):
                        out[o] = last[a, j]
                        o += 1
                continue
            last_value[a] = v
            word[0] = letters[a]
            n, big = _put_num(word, 1, v, places, point)
            too_large |= big
            same = _same_arr(word, n, last[a], last_len[a])
            if not same:
                for j in range(n):
                    last[a, j] = word[j]
                last_len[a] = n
                changed = True
            if not same or (is_arc and in_plane[a]):
                if o > start:
                    out[o] = sep
                    o += 1
                for j in range(n):
                    out[o] = word[j]
                    o += 1
        if is_arc:
            for c in range(2):
                if o > start:
                    out[o] = sep
                    o += 1
                for j in range(centre_len[c]):
                    out[o] = centre[c, j]
                    o += 1
        elif not changed:  # the handlers write the first axis (X) of a move in place
            if o > start:
                out[o] = sep
                o += 1
            for j in range(last_len[0]):
                out[o] = last[0, j]
                o += 1
        if not _same_arr(last[fw], last_len[fw], last[na], last_len[na]):  # feed_word
            for j in range(last_len[fw]):
                last[na, j] = last[fw, j]
            last_len[na] = last_len[fw]
            if o > start:
                out[o] = sep
                o += 1
            for j in range(last_len[fw]):
                out[o] = last[fw, j]
                o += 1
        longest = max(longest, o - start)
        blocks += 1
        out[o] = 10
        o += 1
    return out[:o], too_large, motion, longest, blocks, _write_words(last, last_len, na + 1)


@njit(cache=True)
def _sandia(pts, scale, places, state, known):  # pragma: no cover - compiled
    """``MoveTo`` lines to the points (N, 3; x y z in program units, times ``scale`` in the
    output's), each axis written when its text changes (gcode.write.sandia_chords
    .move_lines' rule: a line where none does repeats X); numbers as the Formatter writes
    them with at least one decimal. ``state``: the X, Y, Z texts written last (no letter,
    each ending in a zero byte); ``known`` False writes every axis on the first line.
    Returns (text, the offset where each line starts and the text's length, a number too
    large for the kernel, ``state`` after)."""
    m = pts.shape[0]
    last, last_len = _read_words(state, 3, 32)
    too_large = last_len[2] < 0
    out = np.empty(m * 100 + 16, dtype=np.uint8)
    starts = np.empty(m + 1, dtype=np.int64)
    word = np.empty(32, dtype=np.uint8)
    head = np.array([77, 111, 118, 101, 84, 111], dtype=np.uint8)  # "MoveTo"
    o = 0
    for k in range(m):
        starts[k] = o
        for j in range(6):
            out[o + j] = head[j]
        o += 6
        changed = False
        for a in range(3):
            if k and pts[k, a] == pts[k - 1, a]:
                continue  # the text of the line before, which ``last`` holds
            n, big = _put_num(word, 0, pts[k, a] * scale, places, True)
            too_large |= big
            if word[n - 1] == 46:  # at least one decimal: "12." -> "12.0"
                word[n] = 48
                n += 1
            if known and _same_arr(word, n, last[a], last_len[a]):
                continue
            for j in range(n):
                last[a, j] = word[j]
            last_len[a] = n
            out[o] = 32
            out[o + 1] = 88 + a  # X Y Z
            out[o + 2] = 61  # =
            o += 3
            for j in range(n):
                out[o] = word[j]
                o += 1
            changed = True
        if not changed:
            out[o] = 32
            out[o + 1] = 88
            out[o + 2] = 61
            o += 3
            for j in range(last_len[0]):
                out[o] = last[0, j]
                o += 1
        known = True
        out[o] = 10
        o += 1
    starts[m] = o
    return out[:o], starts, too_large, _write_words(last, last_len, 3)


@njit(cache=True)
def _same_arr(a, la, b, lb):  # pragma: no cover - compiled
    if la != lb:
        return False
    for j in range(la):  # noqa: SIM110 - a compiled loop, no generator
        if a[j] != b[j]:
            return False
    return True


#: exported name -> (JIT function, explicit signature for numba.pycc)
SIGNATURES = {
    "scan": (
        _scan,
        nt.Tuple((I8, F64_2D, F64, I64, F64_2D, nt.int64, nt.int64, F64, nt.float64, nt.int64))(
            U8_RO,
            nt.int64,
            I64,
            F64,
            F64,
            nt.float64,
            nt.boolean,
            nt.int64,
            nt.int64,
            nt.int64,
            nt.boolean,
            nt.boolean,
            I64,
            F64,
            nt.boolean,
            nt.int64,
        ),
    ),
    "format": (
        _format,
        nt.Tuple((U8, nt.Array(nt.boolean, 1, "C"), nt.int64))(
            I8, F64_2D, F64, nt.int64, nt.Array(nt.uint8, 2, "C"), I64
        ),
    ),
    "format_arcs": (
        _format_arcs,
        nt.Tuple((U8, nt.Array(nt.boolean, 1, "C"), nt.int64))(
            I8, F64_2D, F64, F64_2D, nt.int64, nt.Array(nt.uint8, 2, "C"), I64
        ),
    ),
    "gcode": (
        _gcode,
        nt.Tuple((U8, nt.boolean, nt.int64, nt.int64, nt.int64, U8))(
            I8,
            F64_2D,
            F64,
            nt.float64,
            I64,
            F64,
            I64,
            U8,
            nt.int64,
            nt.boolean,
            U8_RO,
            nt.Array(nt.uint8, 2, "C"),
            I64,
            nt.int64,
            nt.float64,
            nt.uint8,
        ),
    ),
    "gcode_arcs": (
        _gcode_arcs,
        nt.Tuple((U8, nt.boolean, nt.int64, nt.int64, nt.int64, U8))(
            I8,
            F64_2D,
            F64,
            F64_2D,
            nt.float64,
            I64,
            F64,
            I64,
            U8,
            nt.int64,
            nt.boolean,
            U8_RO,
            nt.Array(nt.uint8, 2, "C"),
            I64,
            nt.int64,
            nt.float64,
            nt.uint8,
            I64,
        ),
    ),
    "sandia": (
        _sandia,
        nt.Tuple((U8, I64, nt.boolean, U8))(F64_2D, nt.float64, nt.int64, U8_RO, nt.boolean),
    ),
}

#: the JIT forms under the exported names (the fallback when no AOT module can be built)
scan = _scan
format = _format  # noqa: A001 - the exported name
format_arcs = _format_arcs
gcode = _gcode
gcode_arcs = _gcode_arcs
sandia = _sandia


if __name__ == "__main__":  # python -m MODULE DIR NAME: the AOT build (kernel.aot)
    build_module(sys.argv[1], sys.argv[2], SIGNATURES)
