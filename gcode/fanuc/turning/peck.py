"""Fanuc 0i-TF peck cycles G74 (end face peck drilling / face grooving) and G75 (OD/ID
grooving), two-block format (book Table A.1: ``G74 R / X(U) Z(W) P Q R``, same for G75).

``G74 R(e)`` ; ``G74 X(U) Z(W) P(di) Q(dk) R(dd) F``:

* e: return amount after each peck (rapid back), di: X shift between plunges, dk: depth of
  each peck in Z, dd: relief at the bottom of each plunge, all radius values without sign
  (the reader has applied the no-decimal-point increment rule, so P5000 arrives as 5.0 mm);
* from A = (x0, z0) the tool pecks along Z towards Z: feed dk, rapid back e, feed dk + e,
  ... the last peck ending at Z; at the bottom of every plunge but the first it moves dd
  back against the shift direction, into the groove already cut (rapid; with X omitted, a
  single plunge, the sign of dd gives the direction), returns to z0 by rapid and shifts di
  towards X by rapid for the next plunge; the last plunge is at X itself. Finally it
  returns to x0 by rapid. Without X (or with X = x0) it is a peck drilling cycle at x0.
* G75 is G74 with the axes exchanged: pecks of di along X, plunges shifted by dk along Z,
  relief dd in Z.

The seeds name the cycles only (Table 8.6: "peck drilling in Z-axis", "grooving in
X-axis"); the sequence above is the 0i-TF manual's.
"""

from __future__ import annotations

import math

from gcode.fanuc.turning.types import EPS, CycleSettings, CycleWords, LatheMove, MoveList

MAX_STEPS = 100_000


def _stations(start: float, end: float, step: float) -> list[float]:
    """start, start +- step, ..., end (the last shift partial)."""
    if abs(end - start) <= EPS:
        return [start]
    direction = 1.0 if end > start else -1.0
    n = math.ceil(abs(end - start) / step - 1e-9)
    return [start + direction * min(i * step, abs(end - start)) for i in range(n + 1)]


def peck(w: CycleWords, settings: CycleSettings, grooving: bool) -> list[LatheMove]:
    """G74 (``grooving`` False: pecks along Z) or G75 (True: pecks along X)."""
    ret = w.positive(w.get("1R", settings.peck_return), "return amount R", allow_zero=True)
    x_end = w.opt_end_x()
    z_end = w.opt_end_z()
    x_end = w.x0 if x_end is None else x_end
    z_end = w.z0 if z_end is None else z_end
    # (peck axis start, end, peck depth), (shift axis start, end, shift)
    if grooving:
        p0, p1, s0, s1 = w.x0, x_end, w.z0, z_end
        peck_key, shift_key = "P", "Q"
    else:
        p0, p1, s0, s1 = w.z0, z_end, w.x0, x_end
        peck_key, shift_key = "Q", "P"
    if abs(p1 - p0) <= EPS:
        axis = "X" if grooving else "Z"
        raise w.error("FANUC-CYCLE-DEPTH", f"{w.cycle}: no depth: end {axis} equals the start")
    depth = abs(p1 - p0)
    peck_len = w.get(peck_key)
    peck_len = depth if peck_len is None or peck_len == 0.0 else abs(peck_len)
    multi = abs(s1 - s0) > EPS
    shift = abs(w.get(shift_key, 0.0))
    if multi and shift <= EPS:
        raise w.error(
            "FANUC-CYCLE-DEPTH",
            f"{w.cycle}: shift {shift_key} between plunges is zero but the end point needs several",
        )
    relief = w.get("R", 0.0)
    if multi:
        relief = -abs(relief) if s1 > s0 else abs(relief)
    if depth / peck_len > MAX_STEPS:
        raise w.error("FANUC-CYCLE-DEPTH", f"{w.cycle}: more than {MAX_STEPS} pecks")
    if multi and abs(s1 - s0) / shift > MAX_STEPS:
        raise w.error("FANUC-CYCLE-DEPTH", f"{w.cycle}: more than {MAX_STEPS} plunges")
    plunges = abs(s1 - s0) / shift + 1 if multi else 1
    if depth / peck_len * plunges > MAX_STEPS:  # each bound alone still allows their product
        raise w.error("FANUC-CYCLE-DEPTH", f"{w.cycle}: more than {MAX_STEPS} pecks in all")
    stations = _stations(s0, s1, shift) if multi else [s0]
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    direction = 1.0 if p1 > p0 else -1.0

    def go(kind: str, p: float, s: float) -> None:
        x, z = (p, s) if grooving else (s, p)
        out.move(kind, x, z)

    for i, s in enumerate(stations):
        go("rapid", p0, s)
        reached = 0.0
        while reached < depth - EPS:
            if reached > 0.0:
                go("rapid", p0 + direction * max(reached - ret, 0.0), s)
            reached = min(reached + peck_len, depth)
            go("line", p0 + direction * reached, s)
        side = 0.0 if multi and i == 0 else relief  # the first plunge has no wall behind it
        go("rapid", p1, s + side)
        go("rapid", p0, s + side)
    go("rapid", p0, s0)
    return out.moves
