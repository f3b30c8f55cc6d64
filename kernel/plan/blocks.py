"""The book's ADCBI acc/dec controller per block, in whole interpolation periods (§6.3.2-6.3.3).

``LineNormalBlock`` / ``LineSmallBlock`` (and their arc twins, in angle units) turn a
block's boundary speeds into per-iteration speeds and displacements (eqs. 4.55/4.56):

* the acceleration closest to the maximum that makes the ramp a whole number of periods:
  ``N_acc = ceil((V_max - V_s)/(A T))``, ``a1 = (V_max - V_s)/(N_acc T)``, likewise for
  deceleration; a whole number of cruise periods ``N_const = floor(...)``;
* a small block (no cruise) with ``V_max^2 = A S + (V_s^2 + V_e^2)/2`` (equal A and D),
  ramps rounded up to whole periods and ``V_max`` recomputed so the ramps cover ``S``;
* the residual length ``dError`` spread evenly over the iterations
  (``LinearIPO_Pre``), so the displacements sum exactly to the block length.

(research/seed-book-motion.md §5.9-5.10 and TC-13, TC-44.) The sampled interpolator
(kernel.interp.interpolate) evaluates the continuous-time profile instead; this module is the
book's discrete form, for reference and tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kernel.diagnostics import Diagnostic


@dataclass(frozen=True, slots=True)
class BlockIterations:
    """Per-iteration speeds (at the end of each period) and displacements of one block."""

    n_acc: int
    n_const: int
    n_dec: int
    accel: float  # a1
    decel: float  # a3
    v_max: float
    residual: float  # dError, spread over the iterations
    speed: np.ndarray
    displacement: np.ndarray


def _ramp(v0: float, v1: float, n: int, period: float) -> tuple[np.ndarray, np.ndarray]:
    """Speeds at the end of each of ``n`` periods from ``v0`` to ``v1`` and the distances
    ``L_i = T (V_i + V_i+1)/2`` of eqs. 4.55/4.56."""
    if n == 0:
        return np.zeros(0), np.zeros(0)
    v = v0 + (v1 - v0) * np.arange(1, n + 1) / n
    prev = np.concatenate([[v0], v[:-1]])
    return v, period * (prev + v) / 2.0


def block_iterations(
    length: float,
    v_start: float,
    v_max: float,
    v_end: float,
    accel: float,
    decel: float,
    period: float,
) -> BlockIterations:
    """``LineNormalBlock`` when the block can cruise at ``v_max``, else ``LineSmallBlock``."""
    if min(length, accel, decel, period) <= 0 or v_max <= 0:
        raise Diagnostic(
            "PLAN-BLOCK", "block needs a positive length, feed, accelerations and period"
        )
    at = accel * period
    dt = decel * period
    n_acc = math.ceil((v_max - v_start) / at - 1e-12) if v_max > v_start else 0
    n_dec = math.ceil((v_max - v_end) / dt - 1e-12) if v_max > v_end else 0
    s_acc = (v_start + v_max) * n_acc * period / 2
    s_dec = (v_max + v_end) * n_dec * period / 2
    vp = v_max
    if s_acc + s_dec > length:  # small block: equal A and D (the book's assumption)
        a = min(accel, decel)
        vp = math.sqrt(a * length + (v_start**2 + v_end**2) / 2)
        n_acc = math.ceil((vp - v_start) / (a * period) - 1e-12) if vp > v_start else 0
        n_dec = math.ceil((vp - v_end) / (a * period) - 1e-12) if vp > v_end else 0
        for _ in range(64):  # recompute V_max for the whole-period ramps
            n = n_acc + n_dec
            vp = (2 * length / period - v_start * n_acc - v_end * n_dec) / max(n, 1)
            if vp >= max(v_start, v_end) - 1e-12 or n == 0:
                break
            if n_acc and (vp < v_start or n_acc >= n_dec):
                n_acc -= 1
            else:
                n_dec -= 1
        s_acc = (v_start + vp) * n_acc * period / 2
        s_dec = (vp + v_end) * n_dec * period / 2
    n_const = max(0, math.floor((length - s_acc - s_dec) / (vp * period) + 1e-12))
    residual = length - s_acc - s_dec - n_const * vp * period
    v1, d1 = _ramp(v_start, vp, n_acc, period)
    v3, d3 = _ramp(vp, v_end, n_dec, period)
    speed = np.concatenate([v1, np.full(n_const, vp), v3])
    disp = np.concatenate([d1, np.full(n_const, vp * period), d3])
    if disp.size == 0:
        speed, disp = np.array([v_end]), np.zeros(1)
    disp = disp + residual / disp.size
    a1 = (vp - v_start) / (n_acc * period) if n_acc else 0.0
    a3 = (vp - v_end) / (n_dec * period) if n_dec else 0.0
    return BlockIterations(n_acc, n_const, n_dec, a1, a3, vp, residual, speed, disp)
