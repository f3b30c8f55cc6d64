"""Number formatting and plane geometry shared by the G-code writers.

Numbers are written with the dialect's (or the user's) number of decimals, trailing zeros
removed, with a decimal point where the dialect requires one (Fanuc reads ``X10`` as ten
least input increments, so ``X10.`` is written) and at least ``min_decimals`` digits after
it (Sandia's block format example ``X25.0``, research/seed-sandia-full.md §3.3).
"""

from __future__ import annotations

from gcode.write.options import WriterOptions
from gcode.write.spec import Dialect
from kernel.diagnostics import Diagnostic
from kernel.ir import canon

#: plane -> (first axis, second axis, normal axis, centre word of first, of second)
#: (NISTIR 5970 §3.6.1: in the XZ plane the first axis is Z)
PLANE_AXES: dict[canon.Plane, tuple[str, str, str, str, str]] = {
    canon.Plane.XY: ("X", "Y", "Z", "I", "J"),
    canon.Plane.YZ: ("Y", "Z", "X", "J", "K"),
    canon.Plane.XZ: ("Z", "X", "Y", "K", "I"),
}

_UNITS = {"mm": canon.Units.MM, "inch": canon.Units.INCHES}


def clamped_uniform_knots(n_points: int, order: int) -> list[float]:
    """The knot vector LinuxCNC's G5.2 uses: clamped, uniform interior, on [0, 1]."""
    inner = n_points - order
    return [0.0] * order + [(i + 1) / (inner + 1) for i in range(inner)] + [1.0] * order


class Formatter:
    """Turns numbers into word values in the output units."""

    def __init__(self, d: Dialect, opts: WriterOptions) -> None:
        self.d, self.o = d, opts
        self.units_out: canon.Units | None = None
        self.scale = 1.0
        self.inch = False
        self.places = opts.decimals if opts.decimals is not None else d.decimals_mm
        self._memo: dict[tuple[float, int], str] = {}
        if opts.units is not None and opts.units not in _UNITS:
            raise Diagnostic("CONV-OPTION", f"units {opts.units!r}: use mm or inch")

    def set_output_units(self, ir_units: canon.Units) -> canon.Units:
        """Output units for a program in ``ir_units`` (the user's choice wins); returned."""
        out = _UNITS[self.o.units] if self.o.units else ir_units
        if out == canon.Units.CM:  # no G-code for centimetres: write millimetres
            out = canon.Units.MM
        self.units_out = out
        self.scale = ir_units.mm_per_unit / out.mm_per_unit
        self.inch = out == canon.Units.INCHES
        if self.o.decimals is None:
            self.places = self.d.decimals(self.inch)
        return out

    def number(self, value: float, places: int | None = None) -> str:
        """``value`` as a word value; memoised per (value, places): CAM output repeats."""
        key = (value, self.places if places is None else places)
        text = self._memo.get(key)
        if text is None:
            if len(self._memo) > 8192:
                self._memo.clear()
            text = self._memo[key] = self._number(value, key[1])
        return text

    def _number(self, value: float, p: int) -> str:
        s = f"{value:.{p}f}"
        if "." in s:
            s = s.rstrip("0")
            if s.endswith(".") and not self.d.point_required and self.d.min_decimals == 0:
                s = s[:-1]
        if self.d.min_decimals:
            whole, _, frac = s.partition(".")
            s = f"{whole}.{frac.ljust(self.d.min_decimals, '0')}"
        if s.lstrip("-").strip("0.") == "":
            s = s.lstrip("-")
        return s

    def length(self, value: float) -> str:
        return self.number(value)

    def angle(self, value: float) -> str:
        return self.number(value)

    def feed(self, value: float) -> str:
        return self.number(value)

    def speed(self, value: float) -> str:
        if abs(value - round(value)) < 1e-9:
            return str(round(value))
        return self.number(value)
