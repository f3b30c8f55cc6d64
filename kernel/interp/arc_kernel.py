"""Compiled sampling of exact arcs (numba): position, velocity and acceleration of samples
on arcs and helices in one pass, for :class:`kernel.interp.interpolate._ArcBatch`.

It computes what :func:`kernel.path.geometry.evaluate` (``_arc``) and the chain rule of the
batch compute with numpy, sample by sample, with the same floating-point operations in the
same order (numba adds no fused multiply-adds without ``fastmath``), so the results are the
same bit for bit (tests/test_kernel_sampling_equivalence.py). Speed (issue 16): on
LinuxCNC-model plans most samples lie on blend arcs, and the numpy formulation makes a dozen
(n, 3) temporaries per batch. Compiled once and cached next to this file (``cache=True``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def arc_samples(
    rows: np.ndarray,
    gk: np.ndarray,
    local: np.ndarray,
    v: np.ndarray,
    v3: np.ndarray,
    a: np.ndarray,
    sweep_of: np.ndarray,
    sweep3_of: np.ndarray,
    radius_of: np.ndarray,
    radius_end_of: np.ndarray,
    length_of: np.ndarray,
    length3_of: np.ndarray,
    e1_of: np.ndarray,
    e2_of: np.ndarray,
    normal_of: np.ndarray,
    centre_of: np.ndarray,
    axial_of: np.ndarray,
    end_of: np.ndarray,
    pos: np.ndarray,
    vel: np.ndarray,
    acc: np.ndarray,
    jerk: np.ndarray,
) -> None:
    """Write rows ``rows`` of ``pos``, ``vel``, ``acc``, ``jerk`` (XYZ) for the samples at
    local path position ``local`` of arc rows ``gk`` with path speed ``v`` and acceleration
    ``a`` (trapezoidal motion: the path jerk is zero). The cubes ``v3``, ``sweep3_of`` and
    ``length3_of`` come from numpy's ``**`` (its power is not the C library's)."""
    for i in range(rows.size):
        k = gk[i]
        r = rows[i]
        sweep = sweep_of[k]
        r0 = radius_of[k]
        dr = radius_end_of[k] - radius_of[k]
        length = length_of[k]
        lam = min(max(local[i] / length, 0.0), 1.0)
        psi = sweep * lam
        c = math.cos(psi)
        s = math.sin(psi)
        rho = r0 + dr * lam
        ax = axial_of[k]
        axlam = ax * lam
        rho_sweep = rho * sweep
        sweep2 = sweep * sweep
        sweep3 = sweep3_of[k]
        length2 = length * length
        length3 = length3_of[k]
        two_dr_sweep = 2.0 * dr * sweep
        rho_sweep2 = rho * sweep2
        m3_dr_sweep2 = -3.0 * dr * sweep2
        rho_sweep3 = rho * sweep3
        vi = v[i]
        ai = a[i]
        for col in range(3):
            e1 = e1_of[k, col]
            e2 = e2_of[k, col]
            n = normal_of[k, col]
            w = c * e1 + s * e2
            wp = -s * e1 + c * e2
            p = end_of[k, col] if lam >= 1.0 else centre_of[k, col] + rho * w + axlam * n
            d1 = (dr * w + rho_sweep * wp + ax * n) / length
            d2 = (two_dr_sweep * wp - rho_sweep2 * w) / length2
            d3 = (m3_dr_sweep2 * w - rho_sweep3 * wp) / length3
            pos[r, col] = p
            vel[r, col] = d1 * vi
            acc[r, col] = d1 * ai + d2 * vi * vi
            jerk[r, col] = 0.0 + (3.0 * d2 * vi * ai + d3 * v3[i])
