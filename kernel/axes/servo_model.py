"""Discrete state-space models of one servo axis (book ch. 5), built from :class:`ServoParams`.

The drive (speed loop, current loop, motor) is discretised exactly (zero-order hold) at the
sub-period ``h = T/substeps``; its speed controller is digital at ``h``. Over one position
period the ``substeps`` sub-steps compose into one linear map (lifting), so the whole axis
(position controller eq. 5.10, drive, encoder delay) is a linear time-invariant system at
the position period T whose transfer functions run as IIR filters. The same sub-step
equations, with saturations, are what the compiled loop of :mod:`kernel.axes.servo` integrates.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.linalg import eig, expm
from scipy.signal import BadCoefficients, lfilter, ss2tf, tf2ss, zpk2sos

from kernel.axes.servo_params import ServoParams


def pid_coefficients(kp: float, ki: float, kd: float, period: float) -> tuple[float, float, float]:
    """Book eq. 5.8: ``k0 = kp + ki T + kd/T``, ``k1 = -kp - 2 kd/T``, ``k2 = kd/T``."""
    return kp + ki * period + kd / period, -kp - 2.0 * kd / period, kd / period


@dataclass(frozen=True, slots=True)
class Drive:
    """The drive at the sub-period: plant state ``p``, ``p+ = phi p + gamma a_cmd``.

    For ``transfer`` plants ``phi, gamma`` are the plant's own state-space at T (one
    sub-step) and the input is the loop output itself. ``cy``/``cv`` read position/velocity.
    """

    phi: np.ndarray
    gamma: np.ndarray
    cy: np.ndarray
    cv: np.ndarray
    h: float
    substeps: int
    transfer: bool
    #: position per period per unit loop output at steady velocity (transfer plants)
    velocity_gain: float = 1.0


def drive(p: ServoParams) -> Drive:
    """Discretise the drive: ZOH of ``a' = (a_cmd - a)/T_ei, v' = a - d v, y' = v``."""
    if p.plant == "transfer":
        num = np.asarray(p.numerator, dtype=float)
        den = np.asarray(p.denominator, dtype=float)
        size = max(num.size, den.size)  # powers of z^-1: pad both to the same length
        with warnings.catch_warnings():  # leading zero of a delaying numerator
            warnings.simplefilter("ignore", BadCoefficients)
            a, b, c, _ = tf2ss(np.pad(num, (0, size - num.size)), np.pad(den, (0, size - den.size)))
        rest = np.polydiv(den[::-1], np.array([-1.0, 1.0]))[0][::-1]  # den / (1 - z^-1)
        return Drive(
            a, b[:, 0], c[0], np.zeros_like(c[0]), p.period, 1, True, float(num.sum() / rest.sum())
        )
    h = p.period / p.substeps
    if p.current_time_constant > 0:
        tei = p.current_time_constant
        ac = np.array([[-1.0 / tei, 0, 0], [1.0, -p.damping, 0], [0, 1.0, 0]])
        bc = np.array([1.0 / tei, 0, 0])
        cy, cv = np.array([0, 0, 1.0]), np.array([0, 1.0, 0])
    else:
        ac = np.array([[-p.damping, 0], [1.0, 0]])
        bc = np.array([1.0, 0])
        cy, cv = np.array([0, 1.0]), np.array([1.0, 0])
    n = ac.shape[0]
    big = np.zeros((n + 1, n + 1))
    big[:n, :n], big[:n, n] = ac * h, bc * h
    e = expm(big)
    return Drive(e[:n, :n], e[:n, n], cy, cv, h, p.substeps, False)


def speed_integral_gain(p: ServoParams) -> float:
    """``K_pn/T_in`` per second (0 for a P speed loop)."""
    return p.speed_gain / p.speed_integral_time if p.speed_integral_time > 0 else 0.0


def lifted_drive(p: ServoParams, d: Drive, ff_scale: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """One position period of the drive: ``w+ = M w + N [u, a_ff]``, ``w = [I, p, (q)]``.

    A sub-step ``j``: ``a_cmd = K_pn (q_j - v) + I + a_ff``, ``I+ = I + (K_pn/T_in) h
    (q_j - v)``, ``p+ = phi p + gamma a_cmd``, where the speed reference ``q_j`` is ``u``,
    except with torque feedforward: there the speed loop is given the velocity the torque
    command itself produces (so it does not fight it), a ramp from the last period's velocity
    ``u - c_j ff_scale a_ff T`` (``c_j = 1 - j/n``) through a model of the current loop,
    ``q+ = alpha q + (1 - alpha) ramp_j``, ``alpha = exp(-h/T_ei)``, ``q_j`` taken after the
    update. Transfer plants: ``w = p``, ``p+ = phi p + gamma u``.
    """
    if d.transfer:
        return d.phi, np.column_stack([d.gamma, np.zeros_like(d.gamma)])
    n = d.phi.shape[0]
    kpn, kin = p.speed_gain, speed_integral_gain(p) * d.h
    nq = 1 if p.feedforward == "torque" else 0
    alpha = reference_pole(p, d)
    size = 1 + n + nq
    m, acc = np.eye(size), np.zeros((size, 2))
    for j in range(d.substeps):
        ramp = ref_ramp(p, d, j) * ff_scale * p.period
        # q_j (after update) as a row over [w, u, a_ff]
        q_w, q_in = np.zeros(size), np.array([1.0, -ramp])
        if nq:
            q_w[-1] = alpha
            q_in = (1.0 - alpha) * q_in
        ev_w = q_w.copy()
        ev_w[1 : 1 + n] -= d.cv
        s = np.zeros((size, size))
        r = np.zeros((size, 2))
        s[0], r[0] = kin * ev_w, kin * q_in
        s[0, 0] += 1.0
        acmd_w = kpn * ev_w
        acmd_w[0] += 1.0
        acmd_in = kpn * q_in + np.array([0.0, 1.0])
        s[1 : 1 + n] = np.outer(d.gamma, acmd_w)
        s[1 : 1 + n, 1 : 1 + n] += d.phi
        r[1 : 1 + n] = np.outer(d.gamma, acmd_in)
        if nq:
            s[-1], r[-1] = q_w, q_in
        acc = s @ acc + r
        m = s @ m
    return m, acc


def reference_pole(p: ServoParams, d: Drive) -> float:
    """``alpha`` of the current-loop model in the torque-feedforward speed reference."""
    tei = p.current_time_constant
    return math.exp(-d.h / tei) if tei > 0 else 0.0


def ref_ramp(p: ServoParams, d: Drive, j: int) -> float:
    """``c_j`` of :func:`lifted_drive` (0 unless torque feedforward)."""
    return 1.0 - j / d.substeps if p.feedforward == "torque" else 0.0


@dataclass(frozen=True, slots=True)
class Closed:
    """The whole axis at period T: ``x+ = A x + B [r_b, v_ff, a_ff]``, outputs ``C x + D in``.

    Outputs (rows): actual position, actual velocity, velocity command u, acceleration
    demand (the normalised current at the start of the period).
    """

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    d: np.ndarray


def closed_loop(p: ServoParams, d: Drive, ff_scale: float) -> Closed:
    """Assemble controller (eq. 5.10), lifted drive and encoder delay into one system.

    States ``[u_fb(k-1), e(k-1), e(k-2), w..., m_1..m_delay]``; ``e = r_b - y_meas``,
    ``u_fb = u_fb(k-1) + k0 e + k1 e(k-1) + k2 e(k-2)``, ``u = u_fb + ff_scale v_ff``.
    """
    k0, k1, k2 = pid_coefficients(p.kp, p.ki, p.kd, p.period)
    m, nn = lifted_drive(p, d, ff_scale)
    nw = m.shape[0]
    off = 0 if d.transfer else 1  # w = [I, p, (q)] for drives
    npl = d.phi.shape[0]
    cy_w, cv_w = np.zeros(nw), np.zeros(nw)
    cy_w[off : off + npl], cv_w[off : off + npl] = d.cy, d.cv
    nd = p.feedback_delay
    nx = 3 + nw + nd
    iw = slice(3, 3 + nw)
    # y_meas as a row over x
    ymeas = np.zeros(nx)
    if nd:
        ymeas[3 + nw + nd - 1] = 1.0
    else:
        ymeas[iw] = cy_w
    # e = r_b - ymeas ; inputs (r_b, v_ff, a_ff)
    e_x, e_in = -ymeas, np.array([1.0, 0, 0])
    ufb_x = np.zeros(nx)
    ufb_x[0], ufb_x[1], ufb_x[2] = 1.0, k1, k2
    ufb_x += k0 * e_x
    ufb_in = k0 * e_in
    u_x, u_in = ufb_x, ufb_in + np.array([0, ff_scale, 0])
    a = np.zeros((nx, nx))
    b = np.zeros((nx, 3))
    a[0], b[0] = ufb_x, ufb_in
    a[1], b[1] = e_x, e_in
    a[2, 1] = 1.0
    aff_in = np.array([0, 0, 1.0 if not d.transfer else 0.0])
    a[iw, iw] = m
    a[iw] += np.outer(nn[:, 0], u_x)
    b[iw] = np.outer(nn[:, 0], u_in) + np.outer(nn[:, 1], aff_in)
    if nd:
        a[3 + nw, iw] = cy_w
        for j in range(1, nd):
            a[3 + nw + j, 3 + nw + j - 1] = 1.0
    c = np.zeros((4, nx))
    dd = np.zeros((4, 3))
    c[0, iw], c[1, iw] = cy_w, cv_w
    c[2], dd[2] = u_x, u_in
    if not d.transfer:
        # a_cmd at the first sub-step: K_pn (u - v) + I + a_ff
        # a_cmd at the first sub-step: K_pn (q_0 - v) + I + a_ff (see lifted_drive)
        ramp0 = ref_ramp(p, d, 0) * ff_scale * p.period
        q_x, q_in = u_x.copy(), u_in - ramp0 * aff_in
        if p.feedforward == "torque":
            alpha = reference_pole(p, d)
            q_x = (1.0 - alpha) * q_x
            q_x[3 + nw - 1] += alpha
            q_in = (1.0 - alpha) * q_in
        c[3] = p.speed_gain * (q_x - np.pad(cv_w, (3, nd)))
        c[3, 3] += 1.0
        dd[3] = p.speed_gain * q_in + aff_in
    return Closed(a, b, c, dd)


@dataclass(frozen=True, slots=True)
class Sections:
    """A transfer function as second-order sections followed by a pure delay of
    ``delay`` samples (its relative degree; zpk2sos would otherwise pad zeros at z = 0)."""

    sos: np.ndarray
    delay: int


def sections(cl: Closed) -> dict[tuple[int, int], Sections]:
    """Second-order sections ``sos[(input, output)]`` of the closed loop's transfer functions.

    Factored (zeros, poles, gain) rather than expanded into one polynomial: the loop has
    several poles close to z = 1 (the position integrator), where an expanded high-order
    denominator loses digits. Pairs with zero gain are left out.
    """
    out: dict[tuple[int, int], Sections] = {}
    for i in range(cl.b.shape[1]):
        for o in range(cl.c.shape[0]):
            if not (np.any(cl.b[:, i]) or cl.d[o, i]):
                continue
            z, p, k = siso_zpk(cl.a, cl.b[:, i], cl.c[o], float(cl.d[o, i]))
            if k == 0 or not np.isfinite(k):
                continue
            out[i, o] = Sections(zpk2sos(z, p, k), len(p) - len(z))
    return out


def siso_zpk(
    a: np.ndarray, b: np.ndarray, c: np.ndarray, d: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """Zeros, poles and gain of ``c (zI - a)^-1 b + d`` without expanding polynomials.

    Poles are the eigenvalues of ``a``; zeros the finite generalised eigenvalues of the
    Rosenbrock pencil ``([[a, b], [c, d]], diag(I, 0))``; the gain matches the response at
    ``z = 2``, a point that is neither.
    """
    n = a.shape[0]
    poles = np.linalg.eigvals(a)
    m = np.block([[a, b[:, None]], [c[None, :], np.array([[d]])]])
    e = np.zeros((n + 1, n + 1))
    e[:n, :n] = np.eye(n)
    with np.errstate(all="ignore"):
        zeros = eig(m, e, right=False)
    zeros = zeros[np.isfinite(zeros) & (np.abs(zeros) < 1e9)]
    z0 = 2.0
    g = float(c @ np.linalg.solve(z0 * np.eye(n) - a, b) + d)
    k = g * np.prod(z0 - poles) / np.prod(z0 - zeros)
    return zeros, poles, float(np.real(k))


def run_sections(
    sec: Sections, x: np.ndarray, state: tuple[np.ndarray, np.ndarray] | None
) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Run cascaded second-order sections, each an ``lfilter`` IIR, then the delay; the
    state (section states, delay line) carries from chunk to chunk."""
    if state is None:
        state = (np.zeros((sec.sos.shape[0], 2)), np.zeros(sec.delay))
    zi, line = state
    y = x
    zf = np.empty_like(zi)
    for j, row in enumerate(sec.sos):
        y, zf[j] = lfilter(row[:3], row[3:], y, zi=zi[j])
    if sec.delay:
        both = np.concatenate([line, y])
        y, line = both[: x.size], both[x.size :]
    return y, (zf, line)


def balance_coefficient(balance_time: float, period: float) -> float:
    """Pole of the symmetrising filter ``(1-b)/(1 - b z^-1)``: its ramp lag is exactly
    ``balance_time`` when ``b = T_s/(T_s + T)``."""
    return balance_time / (balance_time + period)


def equivalent_delay(p: ServoParams, d: Drive, ff_scale: float) -> float:
    """Steady lag of the open feedforward path on a unit-speed ramp from rest (s).

    It is the speed loop's equivalent time constant for speed feedforward (book eq. 5.39's
    T_en) and ``T_ei + T/2`` for torque feedforward (eq. 5.40): the following error a
    balanced feedforward leaves is the feed times this delay.
    """
    m, nn = lifted_drive(p, d, ff_scale)
    off = 0 if d.transfer else 1
    cy = np.zeros(m.shape[0])
    cy[off : off + d.phi.shape[0]] = d.cy
    slow = max(1.0 / p.speed_gain, p.speed_integral_time, p.current_time_constant, p.period)
    if d.transfer:
        poles = np.abs(np.roots(p.denominator))
        stable = poles[poles < 1 - 1e-9]
        if stable.size:
            slow = max(slow, -p.period / np.log(max(stable.max(), 1e-12)))
    n = int(min(max(2000, 40 * slow / p.period), 200_000))
    k = np.arange(n + 1, dtype=float)
    r = k * p.period
    v = np.ones(n + 1)
    acc = np.zeros(n + 1)
    acc[0] = p.feedforward_gain / p.period  # velocity steps from 0 to 1 at k = 0
    if p.feedforward != "torque":
        acc[:] = 0.0
    u = ff_scale * v
    num_u, den = ss2tf(m, nn[:, 0:1], cy[None, :], np.zeros((1, 1)))
    num_a, _ = ss2tf(m, nn[:, 1:2], cy[None, :], np.zeros((1, 1)))
    y = lfilter(num_u[0], den, u) + lfilter(num_a[0], den, acc)
    lag = r - y
    return float(lag[-1])
