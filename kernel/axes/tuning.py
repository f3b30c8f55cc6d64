"""PID gain tuning helpers (book §5.4.2): Ziegler-Nichols rules and relay auto-tuning.

* :func:`ziegler_nichols_step` and :func:`ziegler_nichols_ultimate`: Table 5.1 as printed
  (``T_u`` is the ultimate *period*; the book calls it a frequency, erratum 12).
* :func:`relay_amplitude_gain`, :func:`relay_process` and :func:`relay_ultimate`: the
  relay experiment's describing function (eq. 5.14), the process estimate (eqs. 5.19/5.20)
  and the ultimate gain and period of that model (eqs. 5.23/5.24).
* :func:`relay_experiment` runs that experiment on a profile axis' model (fig. 5.8).
* :func:`ultimate_point` finds K_u and T_u of a profile axis' own discrete loop (the
  ultimate-sensitivity experiment done on the model), and :func:`propose` turns them into
  gains for the profile with the Table 5.1 rules, in the book's PID form (eqs. 5.3/5.4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from kernel.axes.servo_model import closed_loop, drive, lifted_drive
from kernel.axes.servo_params import ServoParams
from kernel.diagnostics import Diagnostic


@dataclass(frozen=True, slots=True)
class Gains:
    """``K_p`` with integral time ``T_i`` (s; inf: none) and derivative time ``T_d`` (s)."""

    kp: float
    ti: float = math.inf
    td: float = 0.0

    def parallel(self) -> tuple[float, float, float]:
        """``(kp, ki, kd)`` of eq. 5.2 from eq. 5.4: ``ki = kp/T_i``, ``kd = kp T_d``."""
        return self.kp, (0.0 if math.isinf(self.ti) else self.kp / self.ti), self.kp * self.td


def ziegler_nichols_step(tau: float, delay: float, kind: str) -> Gains:
    """Table 5.1, step-response method: time constant ``tau`` and delay ``tau_d``."""
    r = tau / delay
    return {
        "p": Gains(r),
        "pi": Gains(0.9 * r, 3.3 * delay),
        "pid": Gains(1.2 * r, 2.0 * delay, 0.5 * delay),
    }[kind]


def ziegler_nichols_ultimate(ku: float, tu: float, kind: str) -> Gains:
    """Table 5.1, ultimate-sensitivity method: critical gain ``K_u`` and period ``T_u``."""
    return {
        "p": Gains(0.5 * ku),
        "pi": Gains(0.45 * ku, 0.8 * tu),
        "pid": Gains(0.6 * ku, 0.5 * tu, 0.125 * tu),
    }[kind]


def relay_amplitude_gain(d: float, a: float) -> float:
    """Eq. 5.14: the relay's describing function ``K_R = 4 d/(pi a)``."""
    return 4.0 * d / (math.pi * a)


def relay_process(
    omega: float, k_r: float, kc: float, ti: float, td: float = 0.0, alpha: float = 0.1
) -> tuple[float, float]:
    """Eqs. 5.19/5.20: dead time ``tau`` and time constant ``T_p`` of ``e^{-tau s}/(T_p s)``
    from the limit cycle (frequency ``omega``, relay gain ``K_R``) under the PID (5.16)."""
    w = omega
    tau = (math.atan(ti * w) + math.atan(td * w) - math.atan(alpha * td * w)) / w
    tp = (
        (1 + k_r)
        * kc
        * math.sqrt(ti**2 * w**2 + 1)
        * math.sqrt(td**2 * w**2 + 1)
        / (ti * w**2 * math.sqrt(alpha**2 * td**2 * w**2 + 1))
    )
    return tau, tp


def relay_ultimate(tau: float, tp: float) -> tuple[float, float]:
    """Eqs. 5.23/5.24 for the model ``e^{-tau s}/(T_p s)``: ``T_u = 4 tau``,
    ``K_u = 2 pi T_p / T_u``."""
    tu = 4.0 * tau
    return 2.0 * math.pi * tp / tu, tu


def _radius(p: ServoParams, kp: float) -> tuple[float, float]:
    q = replace(p, controller="p", kp=kp, ki=0.0, kd=0.0, feedforward="none")
    cl = closed_loop(q, drive(q), 0.0)
    ev = np.linalg.eigvals(cl.a)
    # the velocity-form controller's summing pole at z = 1 cancels a zero: not a mode
    ev = ev[np.abs(ev - 1.0) > 1e-7]
    i = int(np.argmax(np.abs(ev)))
    return float(abs(ev[i])), float(abs(np.angle(ev[i])))


def ultimate_point(params: ServoParams, kp_max: float = 1e6) -> tuple[float, float]:
    """``(K_u, T_u)`` of the axis under P control: the gain at which the discrete loop's
    largest pole reaches the unit circle, and the period of that oscillation.

    Raises ``SERVO-TUNE`` if the loop stays stable up to ``kp_max`` (the method does not
    apply, book §5.4.2.1).
    """
    lo, hi = 1e-9, 1.0
    while _radius(params, hi)[0] < 1.0:
        lo, hi = hi, hi * 2.0
        if hi > kp_max:
            raise Diagnostic(
                "SERVO-TUNE",
                "the loop does not oscillate under P control; "
                "the ultimate-sensitivity method does not apply",
            )
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        if _radius(params, mid)[0] < 1.0:
            lo = mid
        else:
            hi = mid
        if hi / lo < 1 + 1e-10:
            break
    theta = _radius(params, hi)[1]
    tu = 2.0 * math.pi * params.period / theta if theta > 0 else 2.0 * params.period
    return hi, tu


@dataclass(frozen=True, slots=True)
class Proposal:
    """Proposed gains, the ultimate point they came from and the resulting loop's largest
    pole radius (``stable`` when below 1: Ziegler-Nichols PI on an already integrating
    axis can oscillate, and this says so instead of hiding it)."""

    params: ServoParams
    ku: float
    tu: float
    radius: float

    @property
    def stable(self) -> bool:
        return self.radius < 1.0


def propose(params: ServoParams, kind: str = "pid") -> Proposal:
    """Ziegler-Nichols gains (ultimate-sensitivity column) for a profile axis."""
    ku, tu = ultimate_point(params)
    kp, ki, kd = ziegler_nichols_ultimate(ku, tu, kind).parallel()
    q = replace(params, controller=kind, kp=kp, ki=ki, kd=kd)
    ev = np.linalg.eigvals(closed_loop(q, drive(q), 0.0).a)
    ev = ev[np.abs(ev - 1.0) > 1e-7]
    return Proposal(q, ku, tu, float(np.abs(ev).max()))


@dataclass(frozen=True, slots=True)
class RelayResult:
    """What a relay experiment measured and what it concludes (book §5.4.2.2, fig. 5.8)."""

    omega: float  # limit-cycle frequency, rad/s
    amplitude: float  # amplitude of the signal entering the relay, mm
    k_r: float  # describing-function gain, eq. 5.14
    tau: float  # dead time of e^{-tau s}/(T_p s), eq. 5.19
    tp: float  # its time constant, eq. 5.20
    ku: float  # eq. 5.24
    tu: float  # eq. 5.23


def relay_experiment(
    params: ServoParams, d: float = 1.0, kc: float = 1.0, ti: float = 1.0, cycles: int = 12
) -> RelayResult:
    """Run the relay experiment on the axis model and estimate the ZN ultimate point.

    Switch b of fig. 5.6: the PI (``kc``, ``ti``) gets ``d sign(r - y) - y`` with ``r = 0``
    (eq. 5.13), its output drives the axis (velocity command to position). After the
    limit cycle settles, its frequency and the relay input's amplitude give ``K_R``
    (eq. 5.14), the process estimate (eqs. 5.19/5.20) and ``K_u``, ``T_u`` (5.23/5.24).
    The relay is the one nonlinearity, so the loop runs sample by sample (a one-off).
    """
    q = replace(params, controller="p", kp=1.0, ki=0.0, kd=0.0, feedforward="none")
    dr = drive(q)
    m, nn = lifted_drive(q, dr)  # the open axis: loop output u to position
    off = 0 if dr.transfer else 1
    cy = np.zeros(m.shape[0])
    cy[off : off + dr.phi.shape[0]] = dr.cy
    period = params.period
    k0, k1 = kc * (1.0 + period / ti), -kc  # PI in velocity form, eq. 5.8
    n = int(max(cycles * 40 * max(1.0 / params.speed_gain, period) / period, 4000))
    x = np.zeros(m.shape[0])
    y = np.empty(n)
    u = e1 = 0.0
    for k in range(n):
        y[k] = cy @ x
        e = d * (1.0 if -y[k] >= 0 else -1.0) - y[k]
        u = u + k0 * e + k1 * e1
        e1 = e
        x = m @ x + nn[:, 0] * u
    tail = y[n // 2 :]
    crossings = np.flatnonzero(np.diff(np.signbit(tail - tail.mean())))
    if crossings.size < 4:
        raise Diagnostic("SERVO-TUNE", "the relay experiment found no limit cycle")
    t_osc = 2.0 * float(np.mean(np.diff(crossings))) * period
    omega = 2.0 * math.pi / t_osc
    amplitude = float(tail.max() - tail.min()) / 2.0
    k_r = relay_amplitude_gain(d, amplitude)
    tau, tp = relay_process(omega, k_r, kc, ti, 0.0)
    ku, tu = relay_ultimate(tau, tp)
    return RelayResult(omega, amplitude, k_r, tau, tp, ku, tu)
