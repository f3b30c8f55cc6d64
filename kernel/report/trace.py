"""Per-axis traces: commanded motion through acc/dec, fine interpolation and servo, in chunks.

:func:`run` takes the interpolator's :class:`~kernel.interp.samples.Samples` and yields tables
(dicts of equal-length column arrays) of at most ``chunk`` rows, so a long program never
holds more than one chunk of trace columns; the column schema is :func:`columns` and is
documented in ``docs/traces.md``. The pipeline (book fig. 4.1 and ch. 6):

1. acc/dec after interpolation, when the profile's ``[accdec]`` asks for it
   (:func:`kernel.axes.accdec.apply`);
2. fine interpolation from the interpolation period to the servo period (``[servo]
   period``; book eq. 3.72);
3. per-axis servo (:class:`kernel.axes.servo.AxisServo`, pre-filter included), then a settling
   tail holding the last command;
4. following error per axis and the contour error against the programmed path
   (:class:`kernel.axes.contour.ContourMeter`), with their maxima (:class:`ErrorTracker`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import kernel.axes.accdec as accdec
from kernel.axes.contour import ContourMeter, ErrorTracker, predict_arcs
from kernel.axes.servo import AxisServo, prefilter
from kernel.axes.servo_params import ServoParams, params_from_table
from kernel.diagnostics import Diagnostic
from kernel.interp.samples import Samples
from kernel.machine import Machine

CHUNK = 65_536
PER_AXIS: tuple[str, ...] = (
    "cmd_pos",
    "act_pos",
    "cmd_vel",
    "act_vel",
    "cmd_acc",
    "act_acc",
    "following_error",
)
XYZ = ("x", "y", "z")


#: the columns a stock simulation adds (kernel.stock.removal)
REMOVAL = ("removed_mm3", "mrr_mm3_s")


def columns(axes: tuple[str, ...], removal: bool = False) -> list[str]:
    """The trace columns, in order: time, segment, source line, per-axis groups, contour,
    and with ``removal`` (a stock given) the removed volume and removal rate."""
    out = ["t", "segment", "source_line"]
    for a in axes:
        out += [f"{a}_{c}" for c in PER_AXIS]
    return [*out, "contour_error", *(REMOVAL if removal else ())]


def column_dtypes(axes: tuple[str, ...], removal: bool = False) -> dict[str, np.dtype]:
    """Storage type of every column: segment int64, source line int32, the rest float64."""
    out = {c: np.dtype(np.float64) for c in columns(axes, removal)}
    out["segment"] = np.dtype(np.int64)
    out["source_line"] = np.dtype(np.int32)
    return out


#: the longest settle after the last command (s): the default is 8/kp, at most 2 s
MAX_SETTLE = 60.0


@dataclass(frozen=True, slots=True)
class Setup:
    """What the trace stage reads from a machine profile."""

    period: float | None
    axes: dict[str, ServoParams]
    accdec: accdec.AccDecConfig
    settle: float
    fine: str = "linear"


def setup(machine: Machine, interpolation_period: float) -> Setup:
    """Servo period and per-axis parameters: ``[servo]`` (``period``, ``settle``, ``fine``
    and defaults for every axis) overridden by each ``[axes.<name>.servo]``."""
    at = machine.where.at
    top = machine.extra.get("servo", {})
    if not isinstance(top, dict):
        raise Diagnostic("SERVO-TYPE", "[servo] must be a table", at("servo"))
    top = dict(top)
    period = top.pop("period", None)
    settle = top.pop("settle", None)
    fine = top.pop("fine", "linear")
    if fine not in ("linear", "moving_average"):
        raise Diagnostic(
            "SERVO-PARAM", "servo.fine must be linear or moving_average", at("servo", "fine")
        )
    for key, val in (("period", period), ("settle", settle)):
        if val is not None and (
            isinstance(val, bool) or not isinstance(val, int | float) or not val > 0
        ):
            raise Diagnostic(
                "SERVO-PARAM", f"servo.{key} must be a positive number", at("servo", key)
            )
    if settle is not None and settle > MAX_SETTLE:
        # each second is a thousand servo samples per axis at 1 ms, simulated and written
        raise Diagnostic(
            "SERVO-PARAM",
            f"servo.settle must be at most {MAX_SETTLE:g} s, got {settle:g}",
            at("servo", "settle"),
        )
    servo_period = float(period) if period is not None else interpolation_period
    axes = {}
    for ax in machine.axes:
        table = {**top, **ax.servo}
        where = at("axes", ax.name, "servo") if ax.servo else at("servo")
        axes[ax.name] = params_from_table(table, servo_period, f"axes.{ax.name}.servo", where)
    if settle is None:
        slowest = min((p.kp for p in axes.values()), default=1.0)
        settle = min(2.0, max(0.05, 8.0 / slowest))
    return Setup(period, axes, accdec.config_from_machine(machine), float(settle), fine)


def fine_ratio(interpolation_period: float, servo_period: float) -> int:
    """``T_ipo / T_pos`` as an integer (book ch. 6: 8 ms / 1 ms); ``SERVO-PERIOD`` else."""
    r = interpolation_period / servo_period
    n = round(r)
    if n < 1 or abs(r - n) > 1e-6 * r:
        raise Diagnostic(
            "SERVO-PERIOD",
            f"servo period {servo_period} s must divide the interpolation period "
            f"{interpolation_period} s a whole number of times",
        )
    return int(n)


@dataclass
class Trace:
    """A running trace: iterate :meth:`chunks`; :attr:`errors` holds the maxima after."""

    samples: Samples
    setup: Setup
    segments: np.ndarray | None = None
    chunk: int = CHUNK
    errors: ErrorTracker = field(init=False)
    _commanded: Samples | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        if self.chunk < 1:
            raise Diagnostic("TRACE-CHUNK", f"chunk size {self.chunk} must be positive")
        self.errors = ErrorTracker(self.samples.axes)

    def predicted(self) -> dict[str, object] | None:
        """What the acc/dec-after-interpolation filter predicts for the program's arcs
        (book Table 4.5, exact forms), or None when no such filter is configured."""
        cfg = self.setup.accdec
        if not cfg.filters_after or self.segments is None:
            return None
        peak = predict_arcs(self.segments, cfg.kind.value, cfg.tau)
        return {"accdec": cfg.kind.value, "tau": cfg.tau, "max_arc_error": peak.to_dict()}

    @property
    def rows(self) -> int:
        """Rows the trace will have: the servo-period command plus the settling tail."""
        s = self.commanded()
        return len(s) + int(math.ceil(self.setup.settle / s.period)) if len(s) else 0

    def commanded(self) -> Samples:
        """The command the servo gets: filtered after interpolation, at the servo period."""
        if self._commanded is None:
            self._commanded = self._command()
        return self._commanded

    def _command(self) -> Samples:
        s = self.samples
        cfg = self.setup.accdec
        if cfg.filters_after:
            stops = self.segments["exact_stop"] if self.segments is not None else False
            s = accdec.apply(s, cfg, stops)
        if self.setup.period is not None:
            ratio = fine_ratio(s.period, self.setup.period)
            if self.setup.fine == "moving_average" and ratio % 2:
                raise Diagnostic(
                    "SERVO-PERIOD",
                    f"moving-average fine interpolation needs an even ratio, not {ratio}",
                )
            s = accdec.fine_interpolate(s, ratio, self.setup.fine)
        return s

    def lag_samples(self, period: float) -> int:
        """How far back the contour meter looks: 6 position-loop time constants, the
        balancing delay and the acc/dec time."""
        p = self.setup.axes.values()
        lag = max((6.0 / q.kp + 2 * q.balance_time for q in p), default=0.0)
        cfg = self.setup.accdec
        if cfg.filters_after:
            lag += 3 * cfg.tau
        return int(math.ceil(lag / period)) + 1

    def chunks(self) -> Iterator[dict[str, np.ndarray]]:
        """Yield trace tables of at most ``chunk`` rows (the schema of :func:`columns`)."""
        s = self.commanded()
        axes = s.axes
        n_cmd = len(s)
        if n_cmd == 0:
            return
        period = s.period
        n_settle = int(math.ceil(self.setup.settle / period))
        n = n_cmd + n_settle
        cmd = {}
        servos = {}
        for i, a in enumerate(axes):
            params = self.setup.axes.get(a, ServoParams(period=period))
            cmd[a] = prefilter(params, s.position[:, i]) if params.prefilter != "none" else None
            servos[a] = AxisServo(params, outputs=("position", "velocity"))
        xyz = [axes.index(a) for a in XYZ if a in axes]
        meter = None
        if self.segments is not None and len(self.segments) and len(xyz) == 3:
            meter = ContourMeter(self.segments, self.lag_samples(period))
        for lo in range(0, n, self.chunk):
            hi = min(n, lo + self.chunk)
            idx = np.minimum(np.arange(lo, hi), n_cmd - 1)
            hold = np.arange(lo, hi) >= n_cmd
            table: dict[str, Any] = {"t": np.arange(lo, hi) * period}
            seg = s.segment[idx]
            line = s.source_line[idx]
            table["segment"] = seg.astype(np.int64, copy=False)
            table["source_line"] = line.astype(np.int32, copy=False)
            act = np.empty((hi - lo, len(axes)))
            following = {}
            for i, a in enumerate(axes):
                pos = s.position[idx, i]
                vel = np.where(hold, 0.0, s.velocity[idx, i])
                acc_c = np.where(hold, 0.0, s.acceleration[idx, i])
                fed = cmd[a][idx] if cmd[a] is not None else pos
                nxt = None
                if hi < n:
                    j = min(hi, n_cmd - 1)
                    nxt = float(cmd[a][j] if cmd[a] is not None else s.position[j, i])
                res = servos[a].step(fed, nxt)
                act[:, i] = res.position
                fe = pos - res.position
                following[a] = fe
                table[f"{a}_cmd_pos"] = pos
                table[f"{a}_act_pos"] = res.position
                table[f"{a}_cmd_vel"] = vel
                table[f"{a}_act_vel"] = res.velocity
                table[f"{a}_cmd_acc"] = acc_c
                table[f"{a}_act_acc"] = res.acceleration
                table[f"{a}_following_error"] = fe
            contour = meter.step(act[:, xyz], seg) if meter is not None else None
            table["contour_error"] = contour if contour is not None else np.full(hi - lo, np.nan)
            self.errors.update(table["t"], seg, line, following, contour)
            yield table
