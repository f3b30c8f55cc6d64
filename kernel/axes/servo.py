"""Servo simulation of each axis (book ch. 5 and §6.2.5), chunk by chunk.

:class:`AxisServo` follows one axis' commanded positions (the interpolator's samples at the
position period) through the position loop, feedforward and drive of
:mod:`kernel.axes.servo_params`. Without limits the axis is linear, and its closed-loop transfer
functions (:mod:`kernel.axes.servo_model`) run as IIR filters over whole arrays
(``scipy.signal.lfilter``) with their states carried from chunk to chunk. With a velocity or
current limit the same equations run in a compiled loop (numba) that saturates; both paths
agree (within 1e-5 mm in the tests) while no limit is reached.

Feedforward signals come from the command itself: the velocity command of a period is the
move to the next sample (non-causal, book §5.4.3.3: a CNC has the next positions buffered),
the torque (acceleration) command is the velocity step at the period start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numba import njit
from scipy.signal import lfilter

from kernel.axes.feedforward import apply_fir, apply_zpetc, zpetc
from kernel.axes.servo_model import (
    balance_coefficient,
    closed_loop,
    drive,
    equivalent_delay,
    pid_coefficients,
    reference_pole,
    run_sections,
    sections,
    siso_zpk,
    speed_integral_gain,
)
from kernel.axes.servo_params import ServoParams

OUTPUTS: tuple[str, ...] = ("position", "velocity", "velocity_command", "acceleration_demand")


@dataclass(frozen=True, slots=True)
class AxisResult:
    """One axis over one chunk (arrays of the chunk's length; mm, s)."""

    command: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    velocity_command: np.ndarray
    acceleration_demand: np.ndarray
    current: np.ndarray

    @property
    def following_error(self) -> np.ndarray:
        """Commanded minus actual position (book §5.5)."""
        return self.command - self.position


class AxisServo:
    """A stateful simulator of one axis; feed it consecutive chunks with :meth:`step`."""

    def __init__(self, params: ServoParams, outputs: tuple[str, ...] = OUTPUTS) -> None:
        """``outputs`` limits what the linear path computes (the others come back NaN);
        position is always computed."""
        p = self.params = params
        self._wanted = {OUTPUTS.index(o) for o in outputs} | {0}
        self.drive = d = drive(p)
        if p.feedforward == "none":
            self.ff_scale = 0.0
        else:
            self.ff_scale = p.feedforward_gain * (p.period / d.velocity_gain if d.transfer else 1.0)
        self.torque = p.feedforward == "torque"
        self.balance_time = 0.0
        if p.feedforward != "none" and p.balance:
            self.balance_time = p.balance_time or max(0.0, equivalent_delay(p, d, self.ff_scale))
        self.beta = balance_coefficient(self.balance_time, p.period)
        self._r0: float | None = None
        self._rb_prev = 0.0
        self._vff_prev = 0.0
        self._y_prev: float | None = None
        self._v_prev: float | None = None
        self.linear = not p.saturates
        if self.linear:
            self._sos = sections(closed_loop(p, d, self.ff_scale))
            self._zi: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}
        else:
            n = d.phi.shape[0]
            # u_fb(k-1), e(k-1), e(k-2), speed-loop integral, torque-ff speed reference
            self._ctrl = np.zeros(5)
            self._pst = np.zeros(n)
            self._dbuf = np.zeros(max(1, p.feedback_delay))
            self._head = np.zeros(1, dtype=np.int64)

    def _signals(self, r: np.ndarray, r_next: float | None) -> tuple[np.ndarray, ...]:
        p = self.params
        if self._r0 is None:
            self._r0 = float(r[0])
        dev = r - self._r0
        nxt = dev[-1] if r_next is None else r_next - self._r0
        vff = np.diff(dev, append=nxt) / p.period
        if self.torque:
            aff = p.feedforward_gain * np.diff(vff, prepend=self._vff_prev) / p.period
        else:
            aff = np.zeros_like(vff)
        self._vff_prev = float(vff[-1])
        if self.beta:
            # the first-order symmetrising filter, an IIR over the chunk
            rb, _ = lfilter(
                [1.0 - self.beta], [1.0, -self.beta], dev, zi=[self.beta * self._rb_prev]
            )
            self._rb_prev = float(rb[-1])
        else:
            rb = dev
        return dev, rb, vff, aff

    def step(self, r: np.ndarray, r_next: float | None = None) -> AxisResult:
        """Simulate a chunk of commanded positions ``r``; ``r_next`` is the command after
        the chunk (None at the end of the program: the axis holds its last command)."""
        r = np.asarray(r, dtype=float)
        p = self.params
        if r.size == 0:
            e = np.zeros(0)
            return AxisResult(e, e, e, e, e, e, e)
        dev, rb, vff, aff = self._signals(r, r_next)
        run = self._linear if self.linear else self._saturating
        y_dev, v, u, adem = run(rb, vff, aff)
        y = y_dev + self._r0
        if self.drive.transfer:
            prev = y[0] if self._y_prev is None else self._y_prev
            v = np.diff(y, prepend=prev) / p.period
            adem = np.full_like(y, math.nan)
        self._y_prev = float(y[-1])
        vprev = v[0] if self._v_prev is None else self._v_prev
        acc = np.diff(v, prepend=vprev) / p.period
        self._v_prev = float(v[-1])
        cur = adem * self.params.amps_per_accel
        return AxisResult(r, y, v, acc, u, adem, cur)

    def _linear(self, rb: np.ndarray, vff: np.ndarray, aff: np.ndarray) -> list[np.ndarray]:
        inputs = {0: rb, 1: vff, 2: aff}
        outs = [np.zeros_like(rb) for _ in OUTPUTS]
        for o in range(len(OUTPUTS)):
            if o not in self._wanted:
                outs[o][:] = math.nan
        for (i, o), sos in self._sos.items():
            if (i == 2 and not self.torque) or o not in self._wanted:
                continue
            y, self._zi[i, o] = run_sections(sos, inputs[i], self._zi.get((i, o)))
            outs[o] += y
        return outs

    def _saturating(self, rb: np.ndarray, vff: np.ndarray, aff: np.ndarray) -> list[np.ndarray]:
        p, d = self.params, self.drive
        k0, k1, k2 = pid_coefficients(p.kp, p.ki, p.kd, p.period)
        n = rb.size
        y, v, u, a = (np.empty(n) for _ in range(4))
        _loop(
            rb,
            vff,
            aff,
            k0,
            k1,
            k2,
            self.ff_scale,
            p.velocity_limit,
            p.accel_limit,
            p.speed_gain,
            speed_integral_gain(p) * d.h,
            d.phi,
            d.gamma,
            d.cy,
            d.cv,
            d.substeps,
            d.transfer,
            p.feedback_delay,
            self.ff_scale * p.period if self.torque else 0.0,
            reference_pole(p, d),
            self.torque,
            self._ctrl,
            self._pst,
            self._dbuf,
            self._head,
            y,
            v,
            u,
            a,
        )
        return [y, v, u, a]


@njit(cache=True)
def _loop(
    rb,
    vff,
    aff,
    k0,
    k1,
    k2,
    ffs,
    vlim,
    alim,
    kpn,
    kin_h,
    phi,
    gamma,
    cy,
    cv,
    substeps,
    transfer,
    delay,
    ramp,
    alpha,
    torque,
    ctrl,
    pst,
    dbuf,
    head,
    out_y,
    out_v,
    out_u,
    out_a,
):  # noqa: ANN001
    """The axis equations of :mod:`kernel.axes.servo_model` with saturations, period by period.

    Anti-windup: the position controller's state is the saturated output minus the
    feedforward (velocity form eq. 5.10); the speed-loop integral stops while the current
    is limited.
    """
    n = rb.shape[0]
    m = pst.shape[0]
    for k in range(n):
        y = 0.0
        for j in range(m):
            y += cy[j] * pst[j]
        vel = 0.0
        for j in range(m):
            vel += cv[j] * pst[j]
        ymeas = dbuf[head[0]] if delay > 0 else y
        e = rb[k] - ymeas
        ufb = ctrl[0] + k0 * e + k1 * ctrl[1] + k2 * ctrl[2]
        uff = ffs * vff[k]
        u = ufb + uff
        if u > vlim:
            u = vlim
        elif u < -vlim:
            u = -vlim
        ctrl[0] = u - uff
        ctrl[2] = ctrl[1]
        ctrl[1] = e
        out_y[k] = y
        out_v[k] = vel
        out_u[k] = u
        if delay > 0:
            dbuf[head[0]] = y
            head[0] = (head[0] + 1) % delay
        if transfer:
            out_a[k] = math.nan
            new = np.empty(m)
            for i in range(m):
                s = gamma[i] * u
                for j in range(m):
                    s += phi[i, j] * pst[j]
                new[i] = s
            pst[:] = new
            continue
        for sub in range(substeps):
            vs = 0.0
            for j in range(m):
                vs += cv[j] * pst[j]
            q = u - ramp * aff[k] * (1.0 - sub / substeps)
            if torque:  # torque feedforward: the reference through the current-loop model
                q = alpha * ctrl[4] + (1.0 - alpha) * q
                ctrl[4] = q
            ev = q - vs
            acmd = kpn * ev + ctrl[3] + aff[k]
            if acmd > alim:
                acmd = alim
            elif acmd < -alim:
                acmd = -alim
            else:
                ctrl[3] += kin_h * ev
            if sub == 0:
                out_a[k] = acmd
            new = np.empty(m)
            for i in range(m):
                s = gamma[i] * acmd
                for j in range(m):
                    s += phi[i, j] * pst[j]
                new[i] = s
            pst[:] = new


def prefilter(params: ServoParams, command: np.ndarray) -> np.ndarray:
    """The command the position loop is given after the profile's pre-filter (fig. 5.10a).

    ZPETC inverts the axis' own linear closed loop (command to position, limits ignored).
    """
    r = np.asarray(command, dtype=float)
    p = params
    if p.prefilter == "none" or r.size == 0:
        return r
    if p.prefilter in ("fir", "fir_causal"):
        return apply_fir(r, p.fir_v2, p.fir_v3, p.period, causal=p.prefilter == "fir_causal")
    d = drive(p)
    scale = AxisServo(replace(p, prefilter="none")).ff_scale
    cl = closed_loop(p, d, scale)
    zeros, poles, gain = siso_zpk(cl.a, cl.b[:, 0], cl.c[0], float(cl.d[0, 0]))
    zeros, poles = cancel(zeros, poles)
    num = np.concatenate([np.zeros(len(poles) - len(zeros)), gain * np.real(np.poly(zeros))])
    return r[0] + apply_zpetc(zpetc(num, np.real(np.poly(poles))), r - r[0])


def cancel(
    zeros: np.ndarray, poles: np.ndarray, tol: float = 1e-6
) -> tuple[np.ndarray, np.ndarray]:
    """Drop pole-zero pairs closer than ``tol`` (modes the command cannot excite or see)."""
    zs, ps = list(zeros), list(poles)
    for z in list(zs):
        if not ps:
            break
        j = int(np.argmin([abs(z - q) for q in ps]))
        if abs(z - ps[j]) < tol * max(1.0, abs(z)):
            ps.pop(j)
            zs.remove(z)
    return np.array(zs, dtype=complex), np.array(ps, dtype=complex)


def simulate_axis(params: ServoParams, command: np.ndarray) -> AxisResult:
    """Simulate a whole command array in one chunk (pre-filter included)."""
    r = np.asarray(command, dtype=float)
    res = AxisServo(params).step(prefilter(params, r))
    return replace(res, command=r)
