"""Fanuc 0i-TF contour cycles G70, G71, G72, G73 (book Table A.1 formats ``G70 P Q``,
``G71 U R / P Q U W``, ``G72 W R / P Q U W``, ``G73 U W R / P Q U W``; Table 8.6 "complex
fixed cycles"). The finishing contour is the blocks P..Q (resolved by the reader); its
first block moves from the start point A to A', its last ends at B.

* G71 (stock removal in turning), type I: first block ``U``\\ (d) depth of cut (radius) and
  ``R``\\ (e) escape; second block ``U``\\ (du) X finishing allowance (a diameter in
  diameter mode), ``W``\\ (dw) Z allowance, ``F`` roughing feed. The contour shifted by
  (du/2, dw) is the roughing boundary. From A the tool steps d towards A' (rapid or feed as
  the P block's G00/G01), cuts along Z to the boundary, escapes e at 45 degrees (rapid),
  returns in Z to the start Z (rapid) and steps again, while the level stays outside the
  boundary; then it cuts once along the boundary from A' shifted to B shifted (the "rough
  finishing" of parameter 5105#1 = 0) and returns to A by rapid. A P block moving X only
  selects type I: the contour must change monotonically along both axes, else
  FANUC-CYCLE-PROFILE. A P block moving X and Z selects type II: the contour need only be
  monotonic in Z and may have pockets. Each level then cuts every stretch where the
  contour lies at or below it, in cutting order; the 0i-TF manual does not spell out how
  the tool reaches a pocket, so here it escapes as above, rises by rapid above the stock
  and the contour, travels to the pocket's entry, comes down by rapid to the level above
  (already cut there) and feeds the last depth; after the level's last stretch it returns
  to the start Z above the stock.
* G72 (stock removal in facing): the same with X and Z exchanged (first block ``W`` depth).
* G73 (pattern repeating): first block ``U``\\ (i) ``W``\\ (k) total relief (radius) and
  ``R``\\ (d) number of divisions; pass j = 1..d follows the contour shifted by
  (du/2 + i (d-j)/(d-1), dw + k (d-j)/(d-1)) from A and returns to A by rapid.
* G70 (finishing): the contour itself, with the F of its blocks, then rapid to A.

F, S and T inside P..Q apply to G70 only (0i-TF manual, multiple repetitive cycles); the
roughing cycles use the F of their own block (None: the modal feed).
"""

from __future__ import annotations

from collections.abc import Sequence

from gcode.fanuc.turning.profile import (
    Frame,
    first_non_monotone,
    material_intervals,
    normalise,
    split_at_a_extremes,
)
from gcode.fanuc.turning.types import (
    EPS,
    CycleSettings,
    CycleWords,
    LatheMove,
    MoveList,
    ProfileStep,
)

MAX_LAYERS = 100_000


def _contour(w: CycleWords, contour: Sequence[ProfileStep]) -> list[ProfileStep]:
    steps = list(contour)
    if steps:
        return steps
    missing = [k for k in ("P", "Q") if not w.has(k)]
    if missing:
        what = " and ".join(missing)
        raise w.error("FANUC-CYCLE-CONTOUR", f"{w.cycle}: contour block number {what} missing")
    raise w.error("FANUC-CYCLE-CONTOUR", f"{w.cycle}: no contour blocks between P and Q")


def follow(
    out: MoveList,
    steps: Sequence[ProfileStep],
    shift: tuple[float, float] = (0.0, 0.0),
    feeds: bool = False,
) -> None:
    """Move along ``steps`` shifted by (dx, dz); the first step is a straight move from
    wherever the tool is (the P block). ``feeds``: honour the F of each block (G70)."""
    dx, dz = shift
    for i, st in enumerate(steps):
        x, z = st.x + dx, st.z + dz
        f = st.feed if feeds else None
        if st.kind in ("cw", "ccw") and i > 0:
            out.arc(st.kind, x, z, st.cx + dx, st.cz + dz, feed=f)
        elif st.kind == "rapid":
            out.rapid(x, z)
        else:
            out.feed(x, z, feed=f)


def g70(w: CycleWords, contour: Sequence[ProfileStep]) -> list[LatheMove]:
    """Finishing pass along the contour P..Q with its own feeds; rapid back to A."""
    steps = _contour(w, contour)
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    follow(out, steps, feeds=True)
    out.rapid(w.x0, w.z0)
    return out.moves


def _sign(value: float) -> float:
    return 1.0 if value > 0 else -1.0


def stock_removal(
    w: CycleWords, contour: Sequence[ProfileStep], settings: CycleSettings, facing: bool
) -> list[LatheMove]:
    """G71 (``facing`` False) or G72 (True), type I or II, in the normalised frame."""
    steps = _contour(w, contour)
    depth_key = "1W" if facing else "1U"
    depth = w.positive(w.get(depth_key, settings.depth_of_cut), f"depth of cut {depth_key[1:]}")
    escape = w.positive(w.get("1R", settings.escape), "escape amount R", allow_zero=True)
    shift = (w.radius(w.get("U", 0.0)), w.get("W", 0.0))
    ax, az = steps[0].x, steps[0].z
    bx, bz = steps[-1].x, steps[-1].z
    step_move = (az - w.z0) if facing else (ax - w.x0)
    cut_move = (bx - ax) if facing else (bz - az)
    step_axis, cut_axis = ("Z", "X") if facing else ("X", "Z")
    if abs(step_move) <= EPS:
        raise w.error(
            "FANUC-CYCLE-GEOMETRY",
            f"{w.cycle}: the first contour block (A to A') does not move in {step_axis}",
            steps[0].line or None,
        )
    if abs(cut_move) <= EPS:
        raise w.error(
            "FANUC-CYCLE-GEOMETRY",
            f"{w.cycle}: the contour from A' to B does not move in {cut_axis}",
            steps[-1].line or None,
        )
    frame = Frame(facing, -_sign(step_move), -_sign(cut_move))
    segs = normalise(steps[1:], frame, (ax, az), shift)
    # 0i-TF: a P block moving along the stepping axis only selects type I (monotone in both
    # axes); a P block moving both axes selects type II (monotone along the cutting axis,
    # pockets allowed).
    cross_move = (ax - w.x0) if facing else (az - w.z0)
    type2 = abs(cross_move) > EPS
    bad = first_non_monotone(segs, along_b_only=type2)
    if bad is not None:
        rule = (
            f"type II contour must change monotonically in {cut_axis}"
            if type2
            else "type I contour must change monotonically in X and Z (for pockets, program "
            "both X and Z in the P block: type II)"
        )
        raise w.error(
            "FANUC-CYCLE-PROFILE", f"{w.cycle}: {rule}; this block reverses", bad.line or None
        )
    pieces = split_at_a_extremes(segs)
    a0, b0 = frame.ab(w.x0, w.z0)
    a_first, b_first = frame.ab(ax + shift[0], az + shift[1])
    a_low = min([a_first] + [min(p.a0, p.a1) for p in pieces])
    a_high = max([a_first] + [max(p.a0, p.a1) for p in pieces])
    b_last = pieces[-1].b1 if pieces else b_first
    if a_low >= a0 - EPS:
        raise w.error(
            "FANUC-CYCLE-GEOMETRY",
            f"{w.cycle}: the start point is not outside the contour plus finishing allowance",
        )
    levels: list[float] = []
    k = 1
    while a0 - k * depth > a_low + EPS:
        levels.append(a0 - k * depth)
        k += 1
        if k > MAX_LAYERS:
            raise w.error("FANUC-CYCLE-DEPTH", f"{w.cycle}: more than {MAX_LAYERS} cuts")
    if not settings.rough_finish:
        levels.append(a_low)
    infeed = "rapid" if steps[0].kind == "rapid" else "line"
    clear = max(a0, a_high)  # above the stock and the whole contour
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    pos = [a0, b0]

    def go(kind: str, a: float, b: float) -> None:
        x, z = frame.xz(a, b)
        out.move(kind, x, z)
        pos[:] = [a, b]

    for level in levels:
        spans = material_intervals(pieces, level, b0, b_first, b_last)
        for i, (hi, lo) in enumerate(spans):
            if i == 0 and hi >= b0 - EPS:
                go(infeed, level, b0)  # type I: straight in at the start Z
            else:  # a pocket: over the top, down the cleared column above its entry
                go("rapid", clear, pos[1])
                go("rapid", clear, hi)
                go("rapid", min(level + depth, clear), hi)
                go("line", level, hi)
            go("line", level, lo)
            go("rapid", level + escape, min(lo + escape, hi))
        if len(spans) == 1 and spans[0][0] >= b0 - EPS:
            go("rapid", pos[0], b0)  # type I: back to the start Z at the escape height
        elif spans:
            go("rapid", clear, pos[1])
            go("rapid", clear, b0)
    if settings.rough_finish:
        follow(out, steps, shift)
    out.rapid(w.x0, w.z0)
    return out.moves


def g73(w: CycleWords, contour: Sequence[ProfileStep], settings: CycleSettings) -> list[LatheMove]:
    """Pattern repeating: d passes along the contour, relief shrinking to the allowance."""
    steps = _contour(w, contour)
    relief_x = w.get("1U", settings.relief_x)
    relief_z = w.get("1W", settings.relief_z)
    count = w.get("1R", float(settings.divisions))
    if count < 1 or abs(count - round(count)) > 1e-6:
        raise w.error(
            "FANUC-CYCLE-DEPTH",
            f"G73: number of divisions R must be a whole number >= 1 ({count:g})",
        )
    d = int(round(count))
    if d > MAX_LAYERS:
        raise w.error("FANUC-CYCLE-DEPTH", f"G73: more than {MAX_LAYERS} divisions")
    allow_x, allow_z = w.radius(w.get("U", 0.0)), w.get("W", 0.0)
    out = MoveList(w.x0, w.z0)
    out.set_feed(w.get("F"))
    for j in range(1, d + 1):
        frac = (d - j) / (d - 1) if d > 1 else 0.0
        follow(out, steps, (allow_x + relief_x * frac, allow_z + relief_z * frac))
        out.rapid(w.x0, w.z0)
    return out.moves
