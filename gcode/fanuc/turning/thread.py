"""Fanuc 0i-TF multiple threading cycle G76, two-block format (book Table A.1:
``G76 P Q R / X(U) Z(W) P Q R``; Table 8.6 "complex fixed cycle: thread cutting").

``G76 P(m)(r)(a) Q(dmin) R(d)`` ; ``G76 X(U) Z(W) R(i) P(k) Q(dd) F(L)``:

* ``1P`` = mmrraa as written: m finishing passes (01-99), r thread chamfer in 0.1 L
  (00-99), a tool nose angle in degrees (80, 60, 55, 30, 29, 0);
* ``1Q`` minimum depth of cut dmin, ``1R`` finishing allowance d (radius values);
* X/Z: the thread root at the end point, i: radius difference thread start minus end
  (taper, 0 = straight), k: thread height, dd: depth of the first cut (radius values,
  lengths in program units after the reader's no-decimal-point increment rule), L: lead.

The seeds do not spell the cycle out; this is the 0i-TF behaviour ("one-edge cutting",
constant cutting amount): the depth of the n-th rough pass below the crest is
``dd * sqrt(n)``, but at least ``dmin`` deeper than the pass before, until the roughing
depth ``k - d``; then ``m`` finishing passes at the full depth ``k``. Each pass is shifted
along Z so that the tool enters along one flank of the thread (flank infeed): a pass
``k - depth`` above the root starts ``(k - depth) * tan(a / 2)`` back towards the start
side, so the last passes run on the programmed thread. A pass: rapid Z to the shifted
start, rapid X in, thread to the end (with an optional 45-degree chamfer of r * L / 10 at
the exit, rising at most to x0), rapid X out to x0, rapid Z back to z0.
"""

from __future__ import annotations

import math

from gcode.fanuc.turning.single import thread_lead
from gcode.fanuc.turning.types import EPS, CycleSettings, CycleWords, LatheMove, MoveList

MAX_PASSES = 10_000


def _code(w: CycleWords, settings: CycleSettings) -> tuple[int, int, float]:
    """(m, r, a) from the first-block P word mmrraa, or the parameters."""
    if not w.has("1P"):
        return settings.thread_finish_passes, settings.thread_chamfer, settings.thread_angle
    value = w.params["1P"]
    if value < 0 or abs(value - round(value)) > 1e-6:
        raise w.error(
            "FANUC-CYCLE-WORD",
            f"G76: first-block P must be the integer mmrraa (passes, chamfer, angle): {value:g}",
        )
    code = int(round(value))
    m, r, a = code // 10000, (code // 100) % 100, code % 100
    if m < 1:
        raise w.error("FANUC-CYCLE-WORD", f"G76: finishing pass count m in P{code:06d} is 0")
    return m, r, float(a)


def pass_depths(first: float, rough: float, minimum: float) -> list[float]:
    """Rough pass depths below the crest: ``first * sqrt(n)``, each at least ``minimum``
    deeper than the one before, the last one exactly ``rough`` (constant cutting volume)."""
    depths: list[float] = []
    prev = 0.0
    n = 1
    while prev < rough - EPS and n <= MAX_PASSES:
        depth = max(first * math.sqrt(n), prev + minimum)
        depth = min(depth, rough)
        depths.append(depth)
        prev = depth
        n += 1
    return depths


def g76(w: CycleWords, settings: CycleSettings) -> list[LatheMove]:
    """Multi-pass threading; ends at the start point."""
    m, chamfer_tenths, angle = _code(w, settings)
    d_min = w.positive(w.get("1Q", settings.thread_min_depth), "minimum depth Q", True)
    allowance = w.positive(w.get("1R", settings.thread_allowance), "finishing allowance R", True)
    x_end = w.end_x()
    z_end = w.end_z()
    lead = thread_lead(w)
    height = w.positive(w.need("P", "thread height"), "thread height P")
    first = w.positive(w.need("Q", "first depth of cut"), "first depth of cut Q")
    taper = w.get("R", 0.0)
    if allowance >= height:
        raise w.error(
            "FANUC-CYCLE-DEPTH",
            f"G76: finishing allowance R{allowance:g} is not less than thread height P{height:g}",
        )
    outward = 1.0 if w.x0 > x_end else -1.0
    if abs(w.x0 - x_end) < height - EPS:
        raise w.error(
            "FANUC-CYCLE-GEOMETRY",
            "G76: the start point is inside the thread (closer to the root than the height P)",
        )
    if abs(z_end - w.z0) <= EPS:
        raise w.error("FANUC-CYCLE-GEOMETRY", "G76: thread length is zero (Z equals start Z)")
    cut_dir = 1.0 if z_end > w.z0 else -1.0
    flank = math.tan(math.radians(angle) / 2.0)
    chamfer = chamfer_tenths * lead / 10.0
    rough = pass_depths(first, height - allowance, d_min)
    if rough[-1] < height - allowance - EPS:
        raise w.error("FANUC-CYCLE-DEPTH", "G76: more than 10000 passes")
    out = MoveList(w.x0, w.z0)
    for depth in rough + [height] * m:
        above = height - depth  # distance of this pass above the root
        shift = -cut_dir * above * flank
        x_pass_end = x_end + outward * above
        z_start, z_stop = w.z0 + shift, z_end + shift
        out.rapid(w.x0, z_start)
        out.rapid(x_pass_end + taper, z_start)
        if chamfer > 0.0:
            out.thread(x_pass_end, z_stop - cut_dir * chamfer, lead)
            rise = min(chamfer, abs(w.x0 - x_pass_end))  # never beyond the start X
            out.thread(x_pass_end + outward * rise, z_stop, lead)
        else:
            out.thread(x_pass_end, z_stop, lead)
        out.rapid(w.x0, z_stop)
        out.rapid(w.x0, w.z0)
    return out.moves
