"""The angle an ARC_FEED sweeps, from its signed turns (NISTIR 5970 §3.6.1 ARC_FEED).

``rotation`` counts signed turns: > 0 counter-clockwise seen from the plane normal's + end,
< 0 clockwise. ``|rotation| = N >= 1`` sweeps an angle in ``((N-1) 2π, N 2π]``: the first
turn goes from the start's polar angle to the end's the short or long way round as the sign
says, an end on its start (within :data:`FULL_TURN_TOL` radians) making it a full circle, and
each further unit adds a full 2π. ``rotation = 0`` sweeps nothing (a move along the normal).

One rule for every reader, writer, planner and checker. :func:`arc_sweep` is the scalar form
and :func:`arc_sweeps` the numpy one; both run :func:`_first_turn` and :func:`_sweep`, and
differ only in how the full turn is picked (``if`` for a float, ``np.where`` for arrays).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:  # numpy only for the array form: the scalar form starts without it
    import numpy as np

TWO_PI = 2.0 * math.pi
FULL_TURN_TOL = 1e-12  # a first turn this small (radians) or less is a full circle

_T = TypeVar("_T", float, "np.ndarray")


def _pick_float(full: bool, whole: float, part: float) -> float:
    return whole if full else part


def _pick_array(full: np.ndarray, whole: float, part: np.ndarray) -> np.ndarray:
    import numpy as np

    return np.where(full, whole, part)


def _first_turn(turned: _T, pick: Callable[[Any, float, _T], _T]) -> _T:
    """``turned`` (angle end - start, times the turning sign) wrapped to (0, 2π]."""
    part = turned % TWO_PI
    return pick(part <= FULL_TURN_TOL, TWO_PI, part)


def _sweep(part: _T, turns: _T) -> _T:
    """The whole unsigned sweep of ``turns`` >= 1 turns whose first turn sweeps ``part``."""
    return part + TWO_PI * (turns - 1)


def first_turn(theta0: float, theta1: float, ccw: bool) -> float:
    """Angle (radians, in (0, 2π]) swept within the first turn from polar angle ``theta0``
    to ``theta1``, counter-clockwise when ``ccw``: an end on the start is a full circle."""
    return _first_turn((theta1 - theta0) if ccw else (theta0 - theta1), _pick_float)


def total_sweep(part: float, turns: int) -> float:
    """Unsigned sweep (radians) of ``turns`` >= 1 turns whose first turn sweeps ``part``:
    each turn past the first adds a full 2π."""
    return _sweep(part, turns)


def arc_sweep(theta0: float, theta1: float, rotation: int) -> float:
    """Signed angle (radians) an arc of ``rotation`` turns sweeps from polar angle ``theta0``
    to ``theta1`` (its sign is the rotation's; 0.0 for rotation 0)."""
    if rotation == 0:
        return 0.0
    part = first_turn(theta0, theta1, rotation > 0)
    return math.copysign(_sweep(part, abs(rotation)), rotation)


def arc_sweeps(theta0: np.ndarray, theta1: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """:func:`arc_sweep` of many arcs at once (float arrays of equal shape), bit for bit."""
    import numpy as np

    sign = np.where(rotation > 0, 1.0, -1.0)
    part = _first_turn(sign * (theta1 - theta0), _pick_array)
    return np.where(rotation == 0, 0.0, sign * _sweep(part, np.abs(rotation)))


__all__ = ["FULL_TURN_TOL", "TWO_PI", "arc_sweep", "arc_sweeps", "first_turn", "total_sweep"]
