"""G76 lathe threading cycle (LinuxCNC): repeated spindle-synchronised passes in the XZ plane.

Words: P pitch, Z end, I thread peak offset from the start X (negative: external thread),
J first cut depth, K full thread depth, R depth degression, Q compound slide angle (deg),
H spring passes, E taper length, L taper at entry (1), exit (2) or both (3). Pass depths
grow as ``I + J * n**(1/R)`` until the full depth ``|I| + |K|``, then the final depth is cut
``H + 1`` times; each pass retracts, moves in, cuts synchronised at the pitch, and
retracts (LinuxCNC ``convert_threading_cycle``, G76 documentation).
"""

from __future__ import annotations

import math

import kernel.limits as limits
from gcode.core.codes import Words
from gcode.ngc.context import NgcContext
from kernel.diagnostics import Diagnostic, Location
from kernel.ir import canon


def _check_passes(ratio: float, degression: float, spring: int, loc: Location) -> None:
    """LIMIT-COUNT before a G76 whose passes pass ``kernel.limits``' ``cycle_passes``: the
    depth grows as ``J * n**(1/R)`` up to ``K``, so about ``(K/J)**R`` passes, then ``H + 1``
    spring passes (a J of 1e-7 mm would cut millions of passes for minutes)."""
    limit = limits.current().cycle_passes
    # in logarithms: (K/J)**R overflows a float for a large R
    log_passes = degression * math.log(ratio) if ratio > 1.0 else 0.0
    passes = math.exp(min(log_passes, 700.0)) + max(spring, 0) + 1
    if passes > limit:
        raise limits.count_error("G76 threading passes", passes, limit, "cycle_passes", loc)


def threading_cycle(ctx: NgcContext, w: Words, end: list[float]) -> None:
    s = ctx.s
    v = w.values
    loc = ctx.loc
    ctx.comp_off("G76")
    if "p" not in v:
        raise Diagnostic("NGC-G76-P", "P word (pitch) missing with G76", loc)
    if "i" not in v or "j" not in v or "k" not in v:
        raise Diagnostic("NGC-G76-IJK", "I J or K words missing with G76", loc)
    i_num, j_num, k_num = v["i"], v["j"], v["k"]
    if i_num == 0:
        raise Diagnostic("NGC-G76-I", "in G76, I must not be 0", loc)
    if j_num <= 0:
        raise Diagnostic("NGC-G76-J", "in G76, J must be greater than 0", loc)
    if k_num <= j_num:
        raise Diagnostic("NGC-G76-K", "in G76, K must be greater than J", loc)
    if s.diameter_mode:  # rs274 output shows a quarter in G7 (halved twice)
        i_num, j_num, k_num = i_num / 4, j_num / 4, k_num / 4
    start = list(s.pos)
    start_y, start_z = start[1], start[2]
    boring = i_num > 0.0
    safe_x = start[0]
    full_dia_depth = abs(i_num)
    cut_increment = abs(j_num)
    full_height = abs(k_num)
    end_depth = full_height + full_dia_depth
    pitch = v["p"]
    angle = math.radians(v.get("q", 0.0))
    end_z = end[2]
    if end_z > start_z:
        angle = -angle
    spring = int(v.get("h", 0))
    degression = v.get("r", 1.0)
    if degression < 1.0:
        degression = 1.0
    taper = max(v.get("e", 0.0), 0.0)
    taper_pitch = pitch * math.hypot(taper, full_height) / taper if taper > 0 else pitch
    if end_z > start_z:
        taper = -taper
    _check_passes(full_height / cut_increment, degression, spring, loc)
    flags = max(int(v.get("l", 0)), 0)
    entry, exit_ = bool(flags & 1), bool(flags & 2)
    target_z = end_z + full_height * math.tan(angle)
    abc = start[3:]
    src = loc

    def x_at(depth: float) -> float:
        return safe_x + depth if boring else safe_x - depth

    def traverse(x: float, z: float) -> None:
        ctx.emit(canon.StraightTraverse(x, start_y, z, *abc, source=src))

    def feed(x: float, z: float) -> None:
        ctx.emit(canon.StraightFeed(x, start_y, z, *abc, source=src))

    def one_pass(depth: float, zoff: float) -> None:
        back = safe_x + depth - end_depth if boring else safe_x - depth + end_depth
        traverse(back, start_z - zoff)
        if taper and entry:
            ctx.emit(canon.DisableFeedOverride(source=src))
            ctx.emit(canon.StartSpeedFeedSynch(taper_pitch, False, source=src))
            feed(x_at(depth - full_height), start_z - zoff)
            feed(x_at(depth), start_z - zoff - taper)
            ctx.emit(canon.StartSpeedFeedSynch(pitch, False, source=src))
        else:
            traverse(x_at(depth), start_z - zoff)
            ctx.emit(canon.DisableFeedOverride(source=src))
            ctx.emit(canon.StartSpeedFeedSynch(pitch, False, source=src))
        if taper and exit_:
            feed(x_at(depth), target_z - zoff + taper)
            ctx.emit(canon.StartSpeedFeedSynch(taper_pitch, False, source=src))
            feed(x_at(depth - full_height), target_z - zoff)
        else:
            feed(x_at(depth), target_z - zoff)
        ctx.emit(canon.StopSpeedFeedSynch(source=src))
        traverse(back, target_z - zoff)
        ctx.emit(canon.EnableFeedOverride(source=src))

    depth = full_dia_depth + cut_increment
    n = 1
    while depth < end_depth:
        one_pass(depth, (depth - full_dia_depth) * math.tan(angle))
        n += 1
        depth = full_dia_depth + cut_increment * n ** (1.0 / degression)
    zoff = (end_depth - full_dia_depth) * math.tan(angle)
    for _ in range(spring + 1):
        one_pass(end_depth, zoff)
    ctx.emit(canon.StraightTraverse(*end, source=src))
    s.pos = list(end)
    s.tlo_lag = None
