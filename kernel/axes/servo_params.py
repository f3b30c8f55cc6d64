"""Servo parameters of one axis, read from the profile's ``[axes.<name>.servo]`` table.

The axis model (book ch. 5, fig. 5.2): a digital position loop P, PI or PID (eq. 5.8/5.10)
running every ``period``, whose output is a velocity command; a drive made of a speed loop
(P or PI), a current loop (first-order lag) and the motor and load (mass with viscous
damping), all normalised so that the "current" is the acceleration it produces (mm/s²);
optional speed or torque feedforward (§5.4.3.4-5) with a symmetrising filter on the
position command; saturation of the velocity command and of the current.

Instead of the drive, a discrete transfer function from the loop output to position may be
given (``plant = "transfer"``), e.g. the book's rotary table of eq. 5.11 (:data:`BOOK_PLANT`).
Every key is documented in ``docs/machine-profile.md`` under *Servo*.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from kernel.diagnostics import Diagnostic, Location

CONTROLLERS: tuple[str, ...] = ("p", "pi", "pid")
PLANTS: tuple[str, ...] = ("drive", "transfer")
FEEDFORWARD: tuple[str, ...] = ("none", "speed", "torque")
PREFILTERS: tuple[str, ...] = ("none", "fir", "fir_causal", "zpetc")

#: The book's rotary-table plant (eq. 5.11, code convention of §5.4.1, see
#: research/seed-book-motion.md §4.2): ``pos(k) = 1.782 pos(k-1) - 0.906 pos(k-2) +
#: 0.124 pos(k-3) + 0.007001 u(k-1) + 0.017284 u(k-2) + 0.002475 u(k-3)``.
BOOK_PLANT: dict[str, tuple[float, ...]] = {
    "numerator": (0.0, 0.007001, 0.017284, 0.002475),
    "denominator": (1.0, -1.782, 0.906, -0.124),
}


@dataclass(frozen=True, slots=True)
class ServoParams:
    """Servo settings of one axis. Units: mm (deg), s; gains as in book eq. 5.2.

    Position loop: ``kp`` (1/s, the K_v of eq. 5.38), ``ki`` (1/s²), ``kd`` (-), discrete
    form eq. 5.8 at ``period``; ``controller`` says which of them may be non-zero.
    Drive: ``speed_gain`` K_pn (1/s; the P speed loop alone has time constant 1/K_pn),
    ``speed_integral_time`` T_in (s, 0: P speed loop), ``current_time_constant`` T_ei (s),
    ``damping`` B/m (1/s); the drive is integrated ``substeps`` times per period.
    ``feedforward``: none, speed or torque; ``feedforward_gain`` scales it; with
    ``balance`` the position loop sees the command through a first-order filter whose time
    constant is the feedforward path's equivalent delay (``balance_time``, or computed when
    0), so it does not fight the feedforward. ``feedback_delay``: encoder periods.
    ``prefilter``: command pre-filter (book fig. 5.10a): ``fir`` (non-causal eq. 5.30),
    ``fir_causal`` (eq. 5.29) with ``fir_v2`` (s) and ``fir_v3`` (s²), or ``zpetc``.
    Limits: ``velocity_limit`` on the velocity command (mm/s), ``current_limit`` (A, with
    ``force_constant`` N/A and ``mass`` kg, or as acceleration ``acceleration_limit`` mm/s²).
    """

    period: float = 0.001
    controller: str = "p"
    kp: float = 30.0
    ki: float = 0.0
    kd: float = 0.0
    plant: str = "drive"
    speed_gain: float = 250.0
    speed_integral_time: float = 0.0
    current_time_constant: float = 0.0
    damping: float = 0.0
    substeps: int = 4
    numerator: tuple[float, ...] = ()
    denominator: tuple[float, ...] = ()
    feedforward: str = "none"
    feedforward_gain: float = 1.0
    balance: bool = True
    balance_time: float = 0.0
    feedback_delay: int = 0
    prefilter: str = "none"
    fir_v2: float = 0.0
    fir_v3: float = 0.0
    velocity_limit: float = math.inf
    current_limit: float = math.inf
    acceleration_limit: float = math.inf
    force_constant: float = 0.0
    mass: float = 0.0

    @property
    def accel_limit(self) -> float:
        """The current limit as the acceleration it allows (mm/s²)."""
        lim = self.acceleration_limit
        if math.isfinite(self.current_limit):
            lim = min(lim, 1000.0 * self.force_constant * self.current_limit / self.mass)
        return lim

    @property
    def amps_per_accel(self) -> float:
        """Current (A) per mm/s² of acceleration demand; NaN without force constant/mass."""
        if self.force_constant > 0 and self.mass > 0:
            return self.mass / (1000.0 * self.force_constant)
        return math.nan

    @property
    def saturates(self) -> bool:
        return math.isfinite(self.velocity_limit) or math.isfinite(self.accel_limit)


_FIELDS = {f.name: f for f in fields(ServoParams)}
_CHOICES = {
    "controller": CONTROLLERS,
    "plant": PLANTS,
    "feedforward": FEEDFORWARD,
    "prefilter": PREFILTERS,
}
_NONNEG = {
    "ki",
    "kd",
    "speed_integral_time",
    "current_time_constant",
    "damping",
    "balance_time",
    "force_constant",
    "mass",
    "fir_v2",
    "fir_v3",
}


def params_from_table(
    table: dict[str, Any], period: float, where: str = "servo", loc: Location | None = None
) -> ServoParams:
    """Validate an ``[axes.<name>.servo]`` table; ``period`` is the position-loop period.

    Raises ``SERVO-KEY`` (unknown key), ``SERVO-TYPE`` or ``SERVO-PARAM`` (bad value).
    ``plant = "book"`` is a shorthand for the book's rotary table (:data:`BOOK_PLANT`).
    """
    loc = loc or Location()
    kw: dict[str, Any] = {"period": period}
    for key, value in table.items():
        what = f"{where}.{key}"
        if key == "plant" and value == "book":
            kw.update(
                plant="transfer",
                numerator=BOOK_PLANT["numerator"],
                denominator=BOOK_PLANT["denominator"],
            )
            continue
        if key not in _FIELDS or key == "period":
            raise Diagnostic("SERVO-KEY", f"[{where}]: unknown key {key!r}", loc)
        if key in _CHOICES:
            if value not in _CHOICES[key]:
                raise Diagnostic(
                    "SERVO-PARAM", f"{what} must be one of {', '.join(_CHOICES[key])}", loc
                )
            kw[key] = value
        elif key == "balance":
            if not isinstance(value, bool):
                raise Diagnostic("SERVO-TYPE", f"{what} must be true or false", loc)
            kw[key] = value
        elif key in ("substeps", "feedback_delay"):
            if isinstance(value, bool) or not isinstance(value, int) or value < (key == "substeps"):
                raise Diagnostic(
                    "SERVO-PARAM", f"{what} must be an integer >= {int(key == 'substeps')}", loc
                )
            kw[key] = value
        elif key in ("numerator", "denominator"):
            if (
                not isinstance(value, list)
                or not value
                or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
            ):
                raise Diagnostic("SERVO-TYPE", f"{what} must be a list of numbers", loc)
            kw[key] = tuple(float(v) for v in value)
        else:
            kw[key] = _number(value, what, loc, key)
    return check(ServoParams(**kw), where, loc)


def _number(value: Any, what: str, loc: Location, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise Diagnostic("SERVO-TYPE", f"{what} must be a number, not {value!r}", loc)
    v = float(value)
    limit = key.endswith("_limit")
    if math.isnan(v) or (not limit and math.isinf(v)):
        raise Diagnostic("SERVO-PARAM", f"{what} must be finite", loc)
    if key in _NONNEG and v < 0:
        raise Diagnostic("SERVO-PARAM", f"{what} must not be negative", loc)
    if key not in _NONNEG and not v > 0:
        raise Diagnostic("SERVO-PARAM", f"{what} must be positive", loc)
    return v


def check(p: ServoParams, where: str = "servo", loc: Location | None = None) -> ServoParams:
    """Cross-field checks (controller kind vs gains, plant completeness, limits' units)."""
    loc = loc or Location()

    def bad(msg: str) -> Diagnostic:
        return Diagnostic("SERVO-PARAM", f"[{where}]: {msg}", loc)

    if not (p.period > 0 and math.isfinite(p.period)):
        raise bad(f"position-loop period {p.period!r} must be positive")
    if p.controller == "p" and (p.ki or p.kd):
        raise bad("controller 'p' takes no ki or kd; use 'pi' or 'pid'")
    if p.controller == "pi" and p.kd:
        raise bad("controller 'pi' takes no kd; use 'pid'")
    if p.plant == "transfer":
        if len(p.denominator) < 2 or p.denominator[0] == 0 or not p.numerator:
            raise bad("a transfer plant needs numerator and denominator (leading term != 0)")
        if p.numerator[0] != 0:
            raise bad("a transfer plant must delay its input (numerator[0] = 0)")
        if abs(sum(p.denominator)) > 1e-9 * sum(abs(c) for c in p.denominator):
            raise bad(
                "a transfer plant must integrate (denominator coefficients sum to 0): "
                "position is the integral of velocity"
            )
        if p.feedforward == "torque" or math.isfinite(p.accel_limit):
            raise bad("torque feedforward and current limits need plant = 'drive'")
    if math.isfinite(p.current_limit) and not (p.force_constant > 0 and p.mass > 0):
        raise bad("current_limit needs force_constant (N/A) and mass (kg)")
    return p
