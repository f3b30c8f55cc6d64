"""Unit conversions between program units and machine units (mm, deg, s).

NISTIR 5970 §2.3.8: lengths are in the current length units (mm, cm or inches), rotary
positions in degrees, feed in length units (or degrees) per minute, dwell in seconds. The
kernel works in mm, deg and s throughout; these helpers are the only place the factors live.
"""

from __future__ import annotations

from kernel.ir.canon import Units

SECONDS_PER_MINUTE = 60.0


def mm_per_unit(units: Units) -> float:
    """Millimetres per program length unit (inch 25.4, cm 10, mm 1)."""
    return units.mm_per_unit


def length_to_mm(value: float, units: Units) -> float:
    """A length in program units, in millimetres."""
    return value * units.mm_per_unit


def per_minute_to_per_second(rate: float) -> float:
    """A rate per minute (F words, traverse rate) as a rate per second."""
    return rate / SECONDS_PER_MINUTE


def feed_to_mm_per_s(rate: float, units: Units) -> float:
    """A feed in program length units per minute, in mm/s."""
    return rate * units.mm_per_unit / SECONDS_PER_MINUTE


def mm_per_s_to_per_minute(rate: float) -> float:
    """mm/s (or deg/s) as mm/min (or deg/min), for reports in the units programs use."""
    return rate * SECONDS_PER_MINUTE
