"""Fanuc 0i-TF lathe cycles as pure geometry: G70-G76 and G90/G92/G94 expanded into moves.

The Fanuc reader (gcode/fanuc/reader.py) resolves the words of a cycle call and,
for G70-G73, the contour blocks P..Q, and calls :func:`cycle_moves`; it turns the returned
:class:`LatheMove` list into canonical commands.
Nothing here parses text. The cycles are listed in the book's Table A.1 (seed 004,
Appendix A; research/seed-book-interp.md) and classified in Table 8.6 (single: G90, G92,
G94; complex: G70-G76); the seeds give formats only, so each module states the 0i-TF
motion sequence it implements:

* gcode/fanuc/turning/single.py: G90, G92, G94;
* gcode/fanuc/turning/contour.py: G70, G71 and G72 (type I, and type II with pockets), G73
  (geometry in gcode/fanuc/turning/profile.py);
* gcode/fanuc/turning/peck.py: G74, G75;
* gcode/fanuc/turning/thread.py: G76.

Word conventions (``params``): words as programmed, lengths already in program units (the
reader applies the no-decimal-point increment rule to every length, including G74/G75
P/Q and G76 P/Q/1Q); first-block words of the two-block cycles carry a ``1`` prefix.
G76's first-block ``1P`` is the code mmrraa as written (an integer, not a length).
X/U of end points and the second-block U (finishing allowance) of G71-G73 are diameters
in diameter mode; every other X-direction amount (G71 first-block U depth, G73 relief U,
tapers R, G74/G75 P and R, G76 P/Q/R) is a radius, as on the control.

Errors are :class:`~kernel.diagnostics.Diagnostic` with codes ``FANUC-CYCLE-*`` located at
the cycle block (or the contour block at fault); docs/errors.md, "Fanuc turning cycles".
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from gcode.fanuc.turning.contour import g70, g73, stock_removal
from gcode.fanuc.turning.peck import peck
from gcode.fanuc.turning.single import g90, g92, g94
from gcode.fanuc.turning.thread import g76
from gcode.fanuc.turning.types import (
    DEFAULT_SETTINGS,
    CycleSettings,
    CycleWords,
    LatheMove,
    ProfileStep,
)

__all__ = ["CYCLES", "CycleSettings", "LatheMove", "ProfileStep", "cycle_moves"]

CYCLES = ("G70", "G71", "G72", "G73", "G74", "G75", "G76", "G90", "G92", "G94")


def cycle_moves(
    cycle: str,
    start: tuple[float, float],
    params: Mapping[str, float],
    contour: Sequence[ProfileStep] = (),
    diameter: bool = True,
    line: int = 0,
    path: str = "",
    *,
    settings: CycleSettings | None = None,
) -> list[LatheMove]:
    """The moves of one lathe cycle call, from ``start`` (x radius, z) back to where the
    control leaves the tool (the start point for every cycle here).

    ``settings``: the machine parameters standing in for an omitted first block (optional
    keyword, an extension of the agreed interface; default :data:`DEFAULT_SETTINGS`).
    """
    name = cycle.strip().upper()
    w = CycleWords(name, start, params, diameter, line, path)
    cfg = settings or DEFAULT_SETTINGS
    if name == "G90":
        return g90(w)
    if name == "G92":
        return g92(w)
    if name == "G94":
        return g94(w)
    if name == "G70":
        return g70(w, contour)
    if name == "G71":
        return stock_removal(w, contour, cfg, facing=False)
    if name == "G72":
        return stock_removal(w, contour, cfg, facing=True)
    if name == "G73":
        return g73(w, contour, cfg)
    if name == "G74":
        return peck(w, cfg, grooving=False)
    if name == "G75":
        return peck(w, cfg, grooving=True)
    if name == "G76":
        return g76(w, cfg)
    raise w.error(
        "FANUC-CYCLE-UNKNOWN", f"{cycle!r} is not a Fanuc lathe cycle ({', '.join(CYCLES)})"
    )
