"""LinuxCNC 2.9's lathe cycles: G70 (finishing), G71/G71.1/G71.2 (roughing along Z) and
G72/G72.1/G72.2 (facing: roughing along X), as ``rs274`` runs them.

A cycle block names its profile with ``Q``: the number of an O-word subroutine
(``o100 sub`` ... ``o100 endsub``). The block first makes a rapid to its own X/Z; then the
subroutine is read, not run: its O-words and parameter assignments take effect, and of its
other lines only the motion words count (G0 is taken as G1; ``A`` adds a fillet and ``C`` a
chamfer at the move's end; ``U``/``W`` are increments in G90); feeds, speeds and M codes
there are ignored. The geometry (:mod:`gcode.ngc.lathe_profile`) then makes the moves, which
go out as the interpreter's own G0/G1/G2/G3 in absolute distance and centre modes, with
the cycle block's F and other axis words, as ``interp_g7x.cc``'s ``convert_g7x`` does.

Words: ``D`` finishing allowance (roughing) or first pass allowance (G70), ``E`` last pass
allowance (G70), ``P`` number of passes (G70), ``I`` depth of cut (default 1), ``R``
retract (default 0.5); X/Z the start point. Where each rule comes from is in
``docs/readers/rs274ngc.md`` (section "Lathe cycles").
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Callable

from gcode.core.blocks import Assignment, check_letter_uses, evaluate_block
from gcode.core.codes import Words
from gcode.core.state import CompCode
from gcode.ngc.context import NgcContext
from gcode.ngc.lathe_profile import (
    Arc,
    Chamfer,
    Fillet,
    Line,
    NoProgress,
    Profile,
    ProfileError,
    Segment,
)
from kernel.diagnostics import Diagnostic, Location
from kernel.ir.canon import Plane

#: G70, G71, G71.1, G71.2, G72, G72.1, G72.2 (code * 10)
LATHE_CYCLES = frozenset({700, 710, 711, 712, 720, 721, 722})

#: how the interpreter runs one motion block (``gcode.ngc.motion.execute_motion``)
RunMotion = Callable[[NgcContext, Words, int], None]


def _g(code: int) -> str:
    return f"G{code // 10}.{code % 10}"


class _Machine:
    """The cycle's moves as G0/G1/G2/G3 blocks of the interpreter with X and Z words (and I
    and K for arcs) only: rs274 fills in the block it read last, the profile's ``endsub``."""

    def __init__(self, ctx: NgcContext, run: RunMotion) -> None:
        self.ctx = ctx
        self.run = run

    def _words(self, code: int, end: complex, more: dict[str, float]) -> Words:
        if not (cmath.isfinite(end) and all(math.isfinite(m) for m in more.values())):
            raise ProfileError("the profile's geometry is degenerate (a point is not finite)")
        return Words(g={1: code}, values={**more, "x": end.imag, "z": end.real})

    def feed(self, end: complex) -> None:
        self.run(self.ctx, self._words(10, end, {}), 10)

    def rapid(self, end: complex) -> None:
        self.run(self.ctx, self._words(0, end, {}), 0)

    def arc(self, ccw: bool, centre: complex, end: complex) -> None:
        pos = self.ctx.s.pos
        if abs(pos[2] - end.real) < 1e-4 and abs(pos[0] - end.imag) < 1e-4:
            return  # rs274 skips an arc to where it already is
        code = 30 if ccw else 20
        more = {"i": centre.imag, "k": centre.real}
        self.run(self.ctx, self._words(code, end, more), code)


def lathe_cycle(ctx: NgcContext, w: Words, code: int, run: RunMotion) -> None:
    """Run one G70/G71/G72 block (``code``: 700, 710, 711, 712, 720, 721, 722)."""
    s = ctx.s
    loc = ctx.loc
    v = w.values
    if "q" not in v:
        raise Diagnostic("NGC-G7X-Q", "G7x.x requires a Q word", loc)
    if code != 700 and s.comp_side is not CompCode.G40:
        raise Diagnostic(
            "NGC-G7X-COMP", f"{_g(code)} cannot be used with cutter compensation enabled", loc
        )
    if s.plane is not Plane.XZ:
        raise Diagnostic("NGC-G7X-PLANE", f"{_g(code)} can only be used in XZ plane (G18)", loc)
    incremental, ijk_incremental = not s.absolute, not s.ijk_absolute
    diameter = s.diameter_mode
    x, z = s.pos[0], s.pos[2]
    vx = v.get("x", 0.0) / (2.0 if diameter else 1.0)  # rs274 halves X as it reads it
    if incremental:
        x += vx
        z += v.get("z", 0.0)
    else:
        x = vx if "x" in v else x
        z = v.get("z", z)
    s.absolute = s.ijk_absolute = True  # the cycle's moves are absolute (switch_settings)
    try:
        before = list(s.pos)
        _rapid_to_start(ctx, Words(g={1: 0}, values={k: v[k] for k in "xyzabc" if k in v}), run)
        s.diameter_mode = False  # the cycle works in radius (X read halved)
        q = v["q"]
        if abs(q - round(q)) > 1e-4:  # rs274 calls "O<q> CALL" and reads an integer
            raise Diagnostic("NGC-G7X-Q", "non integer value for integer (the Q word)", loc)
        name = str(int(round(q)))
        try:
            segments = _read_profile(
                ctx, name, complex(z, x), (incremental, ijk_incremental, diameter), loc
            )
        except Diagnostic as exc:
            # rs274 reads the profile while it executes the cycle block: that block fails
            if exc.location.line == loc.line and exc.location.file == loc.file:
                raise
            where = exc.location
            raise Diagnostic(exc.code, f"{exc.message} (profile o{name}, {where})", loc) from None
        ctx.loc = loc
        if len(segments) <= 1:
            return
        # the cycle's moves start from where the block began (LinuxCNC >= 2.9.3, commit
        # b1f3e7d8b8): a compensated G70's entry move is made from there, not from the
        # profile's end where reading the profile left the position
        s.pos[0], s.pos[2] = before[0], before[2]
        i = v.get("i", 1.0)
        if i <= 0:
            raise Diagnostic("NGC-G7X-I", "G7X error: I must be greater than zero.", loc)
        profile = Profile(segments)
        machine = _Machine(ctx, run)
        d = v.get("d", 0.0)
        try:
            if code == 700:
                profile.finishing(machine, x, z, d, v.get("e", 0.0), v.get("p", 1.0))
            else:
                profile.roughing(
                    machine, code % 10, x, z, 0.0, 0.0, d, i, v.get("r", 0.5), code >= 720
                )
        except NoProgress as exc:
            raise Diagnostic(
                "NGC-G7X-NO-PROGRESS",
                f"G7X error: {exc} (LinuxCNC 2.9.0's rs274 repeats this layer for ever)",
                loc,
            ) from None
        except ProfileError as exc:
            raise Diagnostic("NGC-G7X-PROFILE", f"G7X error: {exc}", loc) from None
        except (ZeroDivisionError, ValueError, IndexError):
            raise Diagnostic(
                "NGC-G7X-PROFILE", "G7X error: the profile's geometry is degenerate", loc
            ) from None
    finally:
        s.absolute = not incremental
        s.ijk_absolute = not ijk_incremental
        s.diameter_mode = diameter


def _rapid_to_start(ctx: NgcContext, words: Words, run: RunMotion) -> None:
    """The cycle block's rapid to its own X/Z, with cutter compensation suspended for that
    move (LinuxCNC >= 2.9.3, commit f648d01c72): only the cycle's own moves are
    compensated."""
    comp = ctx.comp
    if comp is None or not comp.engaged:
        run(ctx, words, 0)
        return
    with comp.suspended():
        run(ctx, words, 0)


def _read_profile(
    ctx: NgcContext, name: str, start: complex, modes: tuple[bool, bool, bool], loc: Location
) -> list[Segment]:
    """The segments of subroutine ``name`` from ``start`` (read, not run); ``modes``: the
    program's distance and centre modes are incremental (G91, G91.1), and G7 was on."""
    incremental, diameter = modes[0], modes[2]
    s = ctx.s
    flow = ctx.flow
    floor = flow.call_level + 1
    flow.call(name, [], loc)
    segments: list[Segment] = []
    while True:
        block = flow.next_block(floor)
        if block is None:
            if flow.call_level >= floor:
                flow.end_of_file()
            return segments
        file = flow.file.path
        cached = block.cached_words
        if cached is not None:  # a plain axis line, evaluated by the lexer
            words, assigns = cached, list[Assignment]()
            here = Location(file, block.line, block.col0)
        elif block.words or block.assignments:
            here = Location(file, block.line, block.words[0].column if block.words else 1)
            words, assigns = evaluate_block(block, ctx.params, file)
        else:
            continue
        ctx.loc = here
        g = words.g
        v = words.values
        motion = g.get(1, s.motion_mode if words.has_axis() else None)
        checked = Words(
            g=g,
            m=words.m,
            values={k: x for k, x in v.items() if k not in "uw"},
            columns=words.columns,
        )
        check_letter_uses(checked, motion, here)
        for target, value, at in assigns:
            if isinstance(target, str):
                ctx.params.set_named(target, value, at)
            else:
                ctx.params.set_numbered(target, value, at)
        end = _end_point(words, start, incremental, diameter, here)
        if 1 in g:
            s.motion_mode = g[1]
        mode = s.motion_mode
        if end == start:
            continue
        if mode in (0, 10):
            segments.append(Line(start, end))
        elif mode in (20, 30):
            segments.append(_arc(words, start, end, mode == 30, modes[1], here))
        if mode in (0, 10, 20, 30):
            if "a" in v and "c" in v:
                raise Diagnostic(
                    "NGC-G7X-CORNER", "G7X error: Both A and C parameters on a corner", here
                )
            if "a" in v:
                segments.append(Fillet(v["a"], end))
            if "c" in v:
                segments.append(Chamfer(v["c"], end))
        s.pos[0], s.pos[2] = end.imag, end.real
        start = end


def _end_point(
    words: Words, start: complex, incremental: bool, diameter: bool, here: Location
) -> complex:
    """A profile line's end: X/Z, or U/W increments in G90 (X and U halved in G7)."""
    v = words.values
    z, x = (0.0, 0.0) if incremental else (start.real, start.imag)
    for inc, axis, half in (("u", "x", True), ("w", "z", False)):
        if inc in v:
            if incremental:
                raise Diagnostic(
                    "NGC-G7X-UW",
                    f"G7x error: Cannot use {inc.upper()} in incremental mode (G91)",
                    here,
                )
            if axis in v:
                raise Diagnostic(
                    "NGC-G7X-UW",
                    f"G7x error: Cannot use {inc.upper()} and {axis.upper()} in the same block",
                    here,
                )
            step = v[inc] / 2 if half and diameter else v[inc]
            if axis == "x":
                x += step
            else:
                z += step
        elif axis in v:
            if axis == "x":
                x = v["x"] / 2 if diameter else v["x"]
            else:
                z = v["z"]
    end = complex(z, x)
    return end + start if incremental else end


def _arc(
    words: Words, start: complex, end: complex, ccw: bool, ijk_incremental: bool, here: Location
) -> Arc:
    """A profile arc from its R word, or its I/K centre (relative in G91.1)."""
    v = words.values
    if "r" in v:
        if "i" in v or "k" in v:
            raise Diagnostic("NGC-G7X-ARC", "G7X error: both R and I or K flag used for arc", here)
        r = v["r"]
        chord = end - start
        n2 = abs(chord) ** 2
        h = (r * r - n2 / 4) / n2
        if h < 0:
            raise Diagnostic("NGC-G7X-ARC", "G7X error: arc radius too small to reach end", here)
        d = 1j * h**0.5 * chord
        centre = (start + end) / 2.0 + (d if ccw else -d)
    else:
        if "i" not in v and "k" not in v:
            raise Diagnostic(
                "NGC-G7X-ARC", "G7X error: either I or K must be present for arc", here
            )
        centre = complex(v.get("k", 0.0), v.get("i", 0.0))
        if ijk_incremental:
            centre += start
    return Arc(ccw, start, centre, end)
