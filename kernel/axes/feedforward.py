"""Command pre-filters for feedforward of type (a) (book §5.4.3, fig. 5.10a).

* :func:`fir_coefficients` / :func:`apply_fir`: the practical position + velocity +
  acceleration feedforward as a causal (eq. 5.29) or non-causal (eq. 5.30) FIR filter;
* :class:`Zpetc` / :func:`apply_zpetc`: zero phase error tracking control (eqs. 5.26-5.28):
  the inverse of the closed loop with its unstable zeros replaced by their mirror images.

All filters work on a whole command array (the CNC has the future commands buffered, book
§5.4.3.3); the non-causal parts read ahead and hold the last command at the end.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from kernel.diagnostics import Diagnostic


def fir_coefficients(v2: float, v3: float, period: float) -> tuple[float, float, float]:
    """Eq. 5.29: ``a0 = V3/T²``, ``a1 = -V2/T - 2 V3/T²``, ``a2 = 1 + V2/T + V3/T²``.

    ``G(z) = a0 z^-2 + a1 z^-1 + a2 = 1 + V2 (1 - z^-1)/T + V3 (1 - z^-1)²/T²``: the
    command plus ``V2`` times its velocity plus ``V3`` times its acceleration (unit DC gain).
    """
    t2 = period * period
    return v3 / t2, -v2 / period - 2.0 * v3 / t2, 1.0 + v2 / period + v3 / t2


def apply_fir(
    command: np.ndarray, v2: float, v3: float, period: float, causal: bool = True
) -> np.ndarray:
    """Filter a command: causal eq. 5.29, or non-causal eq. 5.30 ``a0 + a1 z + a2 z²``
    (the same filter two samples ahead, so the lead does not come with a delay)."""
    a0, a1, a2 = fir_coefficients(v2, v3, period)
    r = np.asarray(command, dtype=float)
    if r.size == 0:
        return r.copy()
    if causal:
        # hold the first command before the start (the axis was at rest there)
        padded = np.concatenate([np.full(2, r[0]), r])
        return lfilter([a2, a1, a0], [1.0], padded)[2:]
    padded = np.concatenate([r, np.full(2, r[-1])])
    return a0 * padded[:-2] + a1 * padded[1:-1] + a2 * padded[2:]


@dataclass(frozen=True, slots=True)
class Zpetc:
    """Eq. 5.27: ``G^-1(z) = z^d A(z^-1) B^u(z) / (B^s(z^-1) B^u(1)²)`` for a closed loop
    ``G = z^-d B^s(z^-1) B^u(z^-1) / A(z^-1)`` (coefficients in powers of ``z^-1``)."""

    a: np.ndarray
    b_stable: np.ndarray
    b_unstable: np.ndarray
    delay: int

    @property
    def gain(self) -> float:
        return 1.0 / float(np.sum(self.b_unstable)) ** 2


def zpetc(num: np.ndarray, den: np.ndarray, radius: float = 1.0) -> Zpetc:
    """Split the closed loop ``num/den`` (in ``z^-1``) into delay, stable and unstable zeros
    (eq. 5.26); zeros with ``|z| >= radius`` count as unstable (outside the unit circle; the
    book's "left half plane" means the sampling zeros on the negative real axis)."""
    num = np.trim_zeros(np.asarray(num, dtype=float), "b")
    den = np.asarray(den, dtype=float)
    nz = np.flatnonzero(num)
    if nz.size == 0:
        raise Diagnostic("SERVO-PARAM", "ZPETC: the closed loop has a zero numerator")
    d = int(nz[0])
    b = num[d:]
    zeros = np.roots(b)
    bad = np.abs(zeros) >= radius
    bu = np.real(np.poly(zeros[bad])) if bad.any() else np.array([1.0])
    bs = np.real(np.poly(zeros[~bad])) * b[0]
    return Zpetc(den / den[0], bs, bu, d)


def apply_zpetc(z: Zpetc, command: np.ndarray) -> np.ndarray:
    """Pre-filter a command with ZPETC: ``A(z^-1)/B^s(z^-1)`` causally, then the
    non-causal ``z^d B^u(z)`` reading ``d + len(B^u) - 1`` samples ahead."""
    r = np.asarray(command, dtype=float)
    if r.size == 0:
        return r.copy()
    lead = z.delay + z.b_unstable.size - 1
    pre = len(z.a) + len(z.b_stable)
    padded = np.concatenate([np.full(pre, r[0]), r, np.full(lead, r[-1])])
    x = lfilter(z.a, z.b_stable, padded)
    # z^d B^u(z) = sum_j bu_j z^(d + j): y(k) = sum_j bu_j x(k + d + j)
    n = r.size
    y = np.zeros(n)
    for j, c in enumerate(z.b_unstable):
        s = pre + z.delay + j
        y += c * x[s : s + n]
    return y * z.gain
