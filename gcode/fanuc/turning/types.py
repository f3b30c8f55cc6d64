"""Data shared by the Fanuc 0i-TF lathe cycles (gcode/fanuc_turning*.py): the contour step
and lathe move records of the reader/cycle interface, the
machine parameters a first cycle block stands for, and word access with diameter handling.

Coordinates are (x, z) with x a RADIUS in program length units; arcs lie in the ZX plane
(G18) and "cw"/"ccw" are G02/G03 as seen with Z to the right and X up.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import overload

from kernel.diagnostics import Diagnostic, Location

EPS = 1e-9


@dataclass(frozen=True)
class ProfileStep:
    """One block of a finishing contour (blocks P..Q of G70-G73), resolved by the reader:
    absolute, X as RADIUS, program length units."""

    kind: str  # "rapid" | "line" | "cw" | "ccw"   (arcs in the ZX plane, G18 sense)
    x: float  # end point, radius
    z: float
    cx: float = 0.0  # arc centre, absolute (radius, z); unused for lines
    cz: float = 0.0
    feed: float | None = None  # F programmed in this block (for G70), else None
    line: int = 0  # source line (for diagnostics)


@dataclass(frozen=True)
class LatheMove:
    """One motion of an expanded cycle (the reader turns it into canonical commands)."""

    kind: str  # "rapid" | "feed" | "cw" | "ccw" | "thread" | "dwell"
    x: float  # end point, radius, program units (for "dwell": the current position)
    z: float
    cx: float = 0.0  # arc centre, absolute
    cz: float = 0.0
    feed: float | None = None  # set this feed before the move (None: keep current)
    lead: float = 0.0  # "thread": lead along Z per spindle revolution
    seconds: float = 0.0  # "dwell"


@dataclass(frozen=True)
class CycleSettings:
    """Fanuc 0i-TF parameters that stand in for an omitted first cycle block.

    On the control the first block of a two-block cycle (``G71 U R``, ``G76 P Q R``, ...)
    writes these parameters, so a program that omits it uses what the parameters hold; the
    numbers are the 0i-TF parameter numbers. Lengths are radius values in program units.
    ``rough_finish`` is the inverse of parameter 5105#1 (RF1): G71/G72 type I end with a
    cut along the finishing-allowance contour.
    """

    depth_of_cut: float = 0.0  # 5132: G71/G72 depth of cut (first-block U / W)
    escape: float = 0.0  # 5133: G71/G72 escape (retract) amount e (first-block R)
    relief_x: float = 0.0  # 5135: G73 relief in X (first-block U, radius)
    relief_z: float = 0.0  # 5136: G73 relief in Z (first-block W)
    divisions: int = 1  # 5137: G73 number of divisions (first-block R)
    peck_return: float = 0.0  # 5139: G74/G75 return amount e (first-block R)
    thread_finish_passes: int = 1  # 5142: G76 m
    thread_chamfer: int = 0  # 5130: G76 r, in 0.1 x lead
    thread_angle: float = 60.0  # 5143: G76 tool nose angle a, degrees
    thread_min_depth: float = 0.0  # 5140: G76 minimum depth of cut (first-block Q)
    thread_allowance: float = 0.0  # 5141: G76 finishing allowance d (first-block R)
    rough_finish: bool = True  # not 5105#1 (RF1)


DEFAULT_SETTINGS = CycleSettings()


class CycleWords:
    """The programmed words of one cycle call, with the start point and diameter rule.

    ``X``/``U`` of the end point are diameters in diameter mode (Fanuc lathe X is a
    diameter: book Table A.1; research/seed-book-interp.md §Table A.1); ``U``/``W`` are
    increments from the cycle start point. First-block words carry a ``1`` prefix.
    """

    def __init__(
        self,
        cycle: str,
        start: tuple[float, float],
        params: Mapping[str, float],
        diameter: bool,
        line: int,
        path: str,
    ) -> None:
        self.cycle = cycle
        self.x0, self.z0 = float(start[0]), float(start[1])
        self.params = {k.upper(): float(v) for k, v in params.items()}
        self.diameter = diameter
        self.line = line
        self.path = path
        for key, value in self.params.items():
            if not math.isfinite(value):
                raise self.error("FANUC-CYCLE-WORD", f"{cycle}: word {key} is not a finite number")

    def error(self, code: str, message: str, line: int | None = None) -> Diagnostic:
        where = Location(self.path or None, line if line else self.line, 1)
        return Diagnostic(code, message, where)

    def has(self, key: str) -> bool:
        return key in self.params

    @overload
    def get(self, key: str) -> float | None: ...

    @overload
    def get(self, key: str, default: float) -> float: ...

    def get(self, key: str, default: float | None = None) -> float | None:
        """The word's value, else ``default``."""
        return self.params.get(key, default)

    def need(self, key: str, what: str) -> float:
        if key not in self.params:
            word = key[1:] + " in the first block" if key.startswith("1") else key
            raise self.error("FANUC-CYCLE-WORD", f"{self.cycle}: {what} ({word}) missing")
        return self.params[key]

    def radius(self, value: float) -> float:
        """A diameter-mode X-type value (X, U, second-block U) as a radius."""
        return value / 2.0 if self.diameter else value

    def opt_end_x(self) -> float | None:
        """End X (radius) from X (absolute) or U (incremental); X wins if both are given."""
        if "X" in self.params:
            return self.radius(self.params["X"])
        if "U" in self.params:
            return self.x0 + self.radius(self.params["U"])
        return None

    def opt_end_z(self) -> float | None:
        """End Z from Z (absolute) or W (incremental)."""
        if "Z" in self.params:
            return self.params["Z"]
        if "W" in self.params:
            return self.z0 + self.params["W"]
        return None

    def end_x(self) -> float:
        x = self.opt_end_x()
        if x is None:
            raise self.error("FANUC-CYCLE-WORD", f"{self.cycle}: end point X (or U) missing")
        return x

    def end_z(self) -> float:
        z = self.opt_end_z()
        if z is None:
            raise self.error("FANUC-CYCLE-WORD", f"{self.cycle}: end point Z (or W) missing")
        return z

    def positive(self, value: float, what: str, allow_zero: bool = False) -> float:
        bad = value < 0.0 or (value == 0.0 and not allow_zero)
        if bad:
            bound = "negative" if allow_zero else "zero or negative"
            raise self.error("FANUC-CYCLE-DEPTH", f"{self.cycle}: {what} is {bound} ({value:g})")
        return value


class MoveList:
    """Collects lathe moves from a current position, dropping zero-length straight moves."""

    def __init__(self, x: float, z: float) -> None:
        self.x, self.z = x, z
        self.moves: list[LatheMove] = []
        self._feed: float | None = None

    def set_feed(self, feed: float | None) -> None:
        """The feed to state on the next feed-type move (once)."""
        self._feed = feed

    def _take_feed(self) -> float | None:
        feed, self._feed = self._feed, None
        return feed

    def _same(self, x: float, z: float) -> bool:
        return abs(x - self.x) <= EPS and abs(z - self.z) <= EPS

    def rapid(self, x: float, z: float) -> None:
        if not self._same(x, z):
            self.moves.append(LatheMove("rapid", x, z))
            self.x, self.z = x, z

    def feed(self, x: float, z: float, feed: float | None = None) -> None:
        if not self._same(x, z):
            f = feed if feed is not None else self._take_feed()
            self.moves.append(LatheMove("feed", x, z, feed=f))
            self.x, self.z = x, z

    def move(self, kind: str, x: float, z: float) -> None:
        """A rapid or feed move by contour kind ("rapid" or "line")."""
        if kind == "rapid":
            self.rapid(x, z)
        else:
            self.feed(x, z)

    def arc(
        self, kind: str, x: float, z: float, cx: float, cz: float, feed: float | None = None
    ) -> None:
        f = feed if feed is not None else self._take_feed()
        self.moves.append(LatheMove(kind, x, z, cx=cx, cz=cz, feed=f))
        self.x, self.z = x, z

    def thread(self, x: float, z: float, lead: float) -> None:
        if not self._same(x, z):
            self.moves.append(LatheMove("thread", x, z, lead=lead))
            self.x, self.z = x, z
