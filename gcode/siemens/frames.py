"""The programmable frame of the 840D: translation, rotation, scale and mirror.

840D sl programming manual, fundamentals, "Coordinate transformations (frames)":
``TRANS``, ``ROT``, ``SCALE`` and ``MIRROR`` replace the whole programmable frame;
``ATRANS``, ``AROT``, ``ASCALE`` and ``AMIRROR`` add to it in the current (already
rotated, scaled, mirrored) coordinate system. A program point ``p`` is at ``T + L p``
relative to the settable work offset (G54...), with ``L = rotation x scale x mirror``.

In the IR the translation ``T`` is an offset (like the RS274/NGC G52/G92 offset) and the
motions carry ``L p``: rotation, scale and mirror are applied to program coordinates.
``ROT RPL=a`` turns about the normal of the active plane; ``ROT X Y Z`` turns in the
order Z, Y, X (the 840D's default RPY convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Matrix = tuple[tuple[float, float, float], ...]
IDENTITY: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
_NORMAL = {"XY": 2, "ZX": 1, "YZ": 0}


@dataclass(frozen=True, slots=True)
class Frame:
    t: tuple[float, float, float] = (0.0, 0.0, 0.0)
    m: Matrix = IDENTITY
    inv: Matrix = IDENTITY  # the inverse of m (kept with it: motions need it often)

    @property
    def linear(self) -> bool:
        """True when rotation, scale or mirror is active."""
        return self.m != IDENTITY

    def apply(self, p: list[float]) -> list[float]:
        m = self.m
        return [m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] for r in range(3)]

    def inverse(self, q: list[float]) -> list[float]:
        m = self.inv
        return [m[r][0] * q[0] + m[r][1] * q[1] + m[r][2] * q[2] for r in range(3)]

    def scaled(self, k: float) -> Frame:
        """The frame after a change of length units by ``k``."""
        x, y, z = self.t
        return Frame((x * k, y * k, z * k), self.m, self.inv)


def _matrix(m: np.ndarray) -> Matrix:
    m = np.where(np.abs(m) < 1e-15, 0.0, m)
    return tuple((float(row[0]), float(row[1]), float(row[2])) for row in m)


def _rot_axis(axis: int, degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]  # right-handed about X, Y, Z
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


def rotation(values: dict[str, float], rpl: float | None, plane: str) -> np.ndarray:
    """The rotation of ``ROT``/``AROT``: RPL about the plane normal, else Z, Y, X angles."""
    if rpl is not None:
        return _rot_axis(_NORMAL[plane], rpl)
    r = np.eye(3)
    for axis, letter in ((2, "Z"), (1, "Y"), (0, "X")):
        if letter in values:
            r = r @ _rot_axis(axis, values[letter])
    return r


def change(frame: Frame, op: str, values: dict[str, float], rpl: float | None, plane: str) -> Frame:
    """The frame after one frame instruction (``op`` in blocks.FRAMES)."""
    additive = op.startswith("A")
    base = op[1:] if additive else op
    m = np.array(frame.m) if additive else np.eye(3)
    t = np.array(frame.t) if additive else np.zeros(3)
    vec = np.array([values.get(k, 0.0) for k in "XYZ"])
    if base == "TRANS":
        t = t + m @ vec
    elif base == "ROT":
        m = m @ rotation(values, rpl, plane)
    elif base == "SCALE":
        m = m @ np.diag([values.get(k, 1.0) for k in "XYZ"])
    else:  # MIRROR: the axes named are mirrored (their value is not used)
        m = m @ np.diag([-1.0 if k in values else 1.0 for k in "XYZ"])
    return Frame(
        (float(t[0]), float(t[1]), float(t[2])),
        _matrix(m),
        _matrix(np.linalg.inv(m)),
    )


def plane_map(frame: Frame, axes: tuple[int, int, int]) -> tuple[float, bool] | None:
    """How the frame maps the arc plane ``axes`` = (first, second, normal): (in-plane
    scale, mirrored) when it keeps the plane and its circles circles, else None."""
    m = np.array(frame.m)
    f, s, n = axes
    if abs(m[n, f]) > 1e-9 or abs(m[n, s]) > 1e-9 or abs(m[f, n]) > 1e-9 or abs(m[s, n]) > 1e-9:
        return None
    block = m[np.ix_([f, s], [f, s])]
    gram = block.T @ block
    k2 = gram[0, 0]
    if (
        k2 < 1e-18
        or abs(gram[1, 1] - k2) > 1e-9 * max(1.0, k2)
        or abs(gram[0, 1]) > 1e-9 * max(1.0, k2)
    ):
        return None
    return math.sqrt(k2), float(np.linalg.det(block)) < 0
