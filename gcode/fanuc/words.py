"""Word values of one Fanuc block: the no-decimal-point rule and the G-code groups.

A literal without a decimal point counts least input increments for lengths (IS-B:
0.001 mm, 0.0001 in) and angles (0.001 degree); F, S, T, H, D, L, P and the like are
integers as written (docs/dialects.md "Number format"). Where a code gives a word another
unit the rule follows the code: ``G04 X`` (0.001 s) and ``P`` (ms), ``G51 P/I/J/K``
(magnification in 0.00001), ``G68 R`` (0.001 degree), canned-cycle ``K`` (repeat count) and
``P`` (ms), ``G06.2 K/R/P`` (knot, weight, order). Values from variables and expressions
carry their value (no increments).
"""

from __future__ import annotations

from kernel.diagnostics import Diagnostic, Location

LENGTHS = frozenset(["X", "Y", "Z", "U", "V", "W", "I", "J", "K", "R", "Q", "E", ",C", ",R"])
ANGLES = frozenset("ABC")
#: Fanuc milling canned cycles (round(G*10))
CYCLES = frozenset({730, 740, 760, 810, 820, 830, 840, 850, 860, 870, 880, 890})
#: codes that belong to group 1 (motion) on a Fanuc mill
MOTION = frozenset({0, 10, 20, 30, 62, 330, 320}) | CYCLES
#: G65 argument specification I: address -> local variable number
ARGUMENTS = {
    "A": 1, "B": 2, "C": 3, "I": 4, "J": 5, "K": 6, "D": 7, "E": 8, "F": 9, "H": 11,
    "M": 13, "Q": 17, "R": 18, "S": 19, "T": 20, "U": 21, "V": 22, "W": 23, "X": 24,
    "Y": 25, "Z": 26,
}  # fmt: skip


def code10(value: float, letter: str, loc: Location) -> int:
    """``round(value * 10)`` of a G or M word, refusing more than one decimal."""
    code = round(value * 10)
    if abs(value * 10 - code) > 1e-6 or code < 0:
        raise Diagnostic(f"FANUC-BAD-{letter}", f"bad {letter} code {letter}{value:g}", loc)
    return code


def resolve(
    raw: dict[str, int | float],
    inch: bool,
    gset: set[int],
    cycle: bool,
    nurbs: bool,
    p_point_seconds: bool,
) -> dict[str, float]:
    """Values in program units (lengths), degrees, seconds (dwell) or plain numbers."""
    inc = 0.0001 if inch else 0.001
    out: dict[str, float] = {}
    for letter, val in raw.items():
        if type(val) is int:
            if letter in LENGTHS:
                out[letter] = val * inc
            elif letter in ANGLES:
                out[letter] = val * 0.001
            else:
                out[letter] = float(val)
        else:
            out[letter] = val
    if 40 in gset:  # G04: X/U seconds (0.001 s without a point), P milliseconds
        for letter in "XU":
            if letter in raw:
                v = raw[letter]
                out[letter] = v * 0.001 if type(v) is int else v
        if "P" in raw:
            v = raw["P"]
            literal_point = type(v) is float
            out["P"] = v if (p_point_seconds and literal_point) else v / 1000.0
    if 510 in gset:  # G51 magnification
        for letter in "PIJK":
            if letter in raw:
                v = raw[letter]
                out[letter] = v * 0.00001 if type(v) is int else v
    if 680 in gset and "R" in raw and type(raw["R"]) is int:
        out["R"] = raw["R"] * 0.001
    if cycle:
        if "K" in raw:
            out["K"] = float(raw["K"])
        if "P" in raw:
            out["P"] = raw["P"] / 1000.0
    if (650 in gset or 660 in gset) and type(raw.get("E")) is int:
        # a macro argument E has no thread-lead unit on a mill: shop macros pass codes
        # such as ``E41`` (G41) in it, taken as written
        out["E"] = float(raw["E"])
    if nurbs:
        for letter in "KRP":
            if letter in raw:
                out[letter] = float(raw[letter])
    return out
