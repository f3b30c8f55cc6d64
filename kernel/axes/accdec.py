"""Acc/dec control after interpolation (ADCAI): per-axis digital filters (book ch. 4.2, 6.2.3).

The rough interpolator's per-period displacements of each axis are smoothed on their own by
a digital filter whose impulse response sums to one, so no pulse is lost (book eq. 4.3):

* linear: moving average of ``m`` taps, ``V_O(k) = V_O(k-1) + (V_i(k) - V_i(k-m))/m``
  (eq. 4.7 / 4.10), acc/dec time ``tau = m T`` (eq. 4.11);
* exponential: ``V_O(k) = (1-alpha) V_i(k) + alpha V_O(k-1)``, ``alpha = exp(-T/tau)``
  (eq. 4.5; the book's recursion eq. 4.8 is misprinted, see research/seed-book-motion.md
  §1.2); the DDA circuit is the same recursion with ``1 - alpha = 2**-n`` (eq. 4.30);
* S-shape: two cascaded moving averages of ``m = tau/(2T)`` taps each (eq. 4.6/4.9
  corrected: ``H_S = H_L H_L``, a triangular impulse response of total width ``tau``);
* the book's weighted "S-shape circuit" (eqs. 4.12-4.14, table 4.4) as :func:`weighted_fir`.

All filters run over whole arrays with :func:`scipy.signal.lfilter` (the recursive forms
above are its difference equations) and keep their state in :class:`FilterState`, so a long
program can be filtered chunk by chunk with the same result as in one call.

Exact stop (G61, book §4.2.4, fig. 6.8) filters each block on its own and lets the filter
empty before the next block; continuous mode (G64) filters the concatenated pulse train.
Residual pulses (book §6.2.2) are handled by :func:`distribute_pulses` and
:func:`quantise_pulses`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import StrEnum
from typing import Any, TypeVar

import numpy as np
from scipy.signal import lfilter

from kernel.diagnostics import Diagnostic, Location
from kernel.interp.fine import fine_positions
from kernel.interp.samples import Samples
from kernel.machine import Machine


class AccDecKind(StrEnum):
    """The filter applied after interpolation (``[accdec] type`` in a profile)."""

    NONE = "none"
    LINEAR = "linear"
    EXPONENTIAL = "exponential"
    S_SHAPE = "s_shape"


class AccDecPlacement(StrEnum):
    """Where acc/dec happens: before interpolation (planner), after (these filters), or both."""

    BEFORE = "before"
    AFTER = "after"
    BOTH = "both"


@dataclass(frozen=True, slots=True)
class AccDecConfig:
    """Acc/dec settings of a machine (profile table ``[accdec]``, see :func:`config_from_machine`).

    ``tau`` is the acc/dec time constant in seconds: the full window of the linear filter,
    the total (triangle) width of the S-shape filter, the time constant of the exponential
    filter. ``exp_tail_tolerance`` is the residual (mm) below which the exponential tail is
    cut and the remainder emitted at once (the filter never empties exactly).
    """

    kind: AccDecKind = AccDecKind.LINEAR
    tau: float = 0.05
    placement: AccDecPlacement = AccDecPlacement.BEFORE
    exp_tail_tolerance: float = 1e-6

    @property
    def filters_after(self) -> bool:
        """True when this stage filters the interpolated samples."""
        return self.kind is not AccDecKind.NONE and self.placement in (
            AccDecPlacement.AFTER,
            AccDecPlacement.BOTH,
        )


@dataclass(frozen=True, slots=True)
class Filter:
    """A discrete transfer function ``b(z^-1)/a(z^-1)`` with unit DC gain, as one stage list."""

    stages: tuple[tuple[np.ndarray, np.ndarray], ...]
    #: samples after the last non-zero input until the output is (numerically) complete
    tail: int


@dataclass(slots=True)
class FilterState:
    """lfilter states of every stage for every column, carried from chunk to chunk."""

    zi: list[np.ndarray] = field(default_factory=list)


_CONFIG_KEYS = ("type", "tau", "placement", "tail_tolerance")


def config_from_machine(machine: Machine) -> AccDecConfig:
    """The ADCAI settings of a profile's top-level ``[accdec]`` table (kept in ``extra``).

    Keys: ``type`` (none, linear, exponential, s_shape), ``tau`` (s), ``placement`` (before,
    after, both: where acc/dec happens, book §4.1) and ``tail_tolerance`` (mm). Without the
    table acc/dec happens before interpolation only (the planner's job), so these filters
    are off. Raises ``MACH-KEY``, ``MACH-TYPE`` or ``MACH-RANGE`` like the profile reader.
    """
    table = machine.extra.get("accdec")
    if table is None:
        return AccDecConfig(kind=AccDecKind.NONE)
    at = machine.where.at
    if not isinstance(table, dict):
        raise Diagnostic("MACH-TYPE", "[accdec] must be a table", at("accdec"))
    unknown = sorted(set(table) - set(_CONFIG_KEYS))
    if unknown:
        raise Diagnostic(
            "MACH-KEY", f"[accdec]: unknown key(s) {', '.join(unknown)}", at("accdec", unknown[0])
        )
    default = AccDecConfig()
    kind = (
        _choice(AccDecKind, table, "type", at("accdec", "type"))
        if "type" in table
        else default.kind
    )
    placement = (
        _choice(AccDecPlacement, table, "placement", at("accdec", "placement"))
        if "placement" in table
        else None
    )
    numbers: dict[str, float] = {}
    for key, field_name in (("tau", "tau"), ("tail_tolerance", "exp_tail_tolerance")):
        if key in table:
            loc = at("accdec", key)
            v = table[key]
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise Diagnostic("MACH-TYPE", f"accdec.{key} must be a number", loc)
            if not (math.isfinite(v) and (v > 0 or (key == "tau" and v == 0))):
                raise Diagnostic("MACH-RANGE", f"accdec.{key} must be positive, got {v!r}", loc)
            numbers[field_name] = float(v)
    if placement is None:
        after = kind is not AccDecKind.NONE
        placement = AccDecPlacement.AFTER if after else default.placement
    return AccDecConfig(
        kind=kind,
        tau=numbers.get("tau", default.tau),
        placement=placement,
        exp_tail_tolerance=numbers.get("exp_tail_tolerance", default.exp_tail_tolerance),
    )


_E = TypeVar("_E", AccDecKind, AccDecPlacement)


def _choice(enum: type[_E], table: dict[str, Any], key: str, loc: Location) -> _E:
    """``table[key]`` as a member of ``enum`` (``MACH-RANGE`` naming the allowed values)."""
    try:
        return enum(table[key])
    except ValueError:
        allowed = ", ".join(e.value for e in enum)
        raise Diagnostic("MACH-RANGE", f"accdec.{key} must be one of {allowed}", loc) from None


def _taps(tau: float, period: float, what: str) -> int:
    if not (tau >= 0 and period > 0 and math.isfinite(tau) and math.isfinite(period)):
        raise Diagnostic(
            "ACCDEC-PARAM",
            f"{what}: acc/dec time {tau!r} s and period {period!r} s must be finite, "
            "tau >= 0 and period > 0",
            Location(),
        )
    return max(1, round(tau / period))


def moving_average(m: int) -> tuple[np.ndarray, np.ndarray]:
    """Linear acc/dec, eq. 4.4 in its recursive form eq. 4.7: ``(1/m)(1-z^-m)/(1-z^-1)``."""
    b = np.zeros(m + 1)
    b[0], b[m] = 1.0 / m, -1.0 / m
    return b, np.array([1.0, -1.0])


def exponential(alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Exponential acc/dec, eq. 4.5: ``(1-alpha)/(1 - alpha z^-1)`` (eq. 4.8 corrected)."""
    return np.array([1.0 - alpha]), np.array([1.0, -alpha])


def linear_filter(tau: float, period: float) -> Filter:
    """Moving average over ``m = round(tau/T)`` periods (eqs. 4.7, 4.10, 4.11)."""
    m = _taps(tau, period, "linear")
    return Filter((moving_average(m),), m - 1)


def s_shape_filter(tau: float, period: float) -> Filter:
    """Two moving averages of ``m = round(tau/(2T))`` taps (eq. 4.6/4.9 corrected)."""
    m = _taps(tau / 2.0, period, "s_shape")
    return Filter((moving_average(m), moving_average(m)), 2 * (m - 1))


def exponential_filter(
    tau: float, period: float, tolerance: float = 1e-6, amplitude: float = 1.0
) -> Filter:
    """First-order lag ``alpha = exp(-T/tau)`` (eq. 4.5); ``tail`` reaches ``tolerance``.

    ``amplitude`` is the largest per-block displacement the tail must shrink below
    ``tolerance`` (the residual after ``k`` periods is ``amplitude * alpha**k``).
    """
    _taps(tau, period, "exponential")
    if tau == 0:
        return Filter(((np.array([1.0]), np.array([1.0])),), 0)
    alpha = math.exp(-period / tau)
    ratio = max(amplitude, tolerance) / tolerance
    return Filter((exponential(alpha),), math.ceil(math.log(ratio) / -math.log(alpha)))


def dda_exponential_filter(n_bits: int, tolerance: float = 1e-6, amplitude: float = 1.0) -> Filter:
    """The DDA circuit of eq. 4.30: ``P_o(k) = P_o(k-1) + (P_i(k) - P_o(k-1))/2**n``.

    Its time constant is ``tau = T 2**n`` (eq. 4.31). The recursion has the input at ``k``
    and the output at ``k-1``, i.e. ``(1/2**n) / (1 - (1 - 1/2**n) z^-1)``. ``tail`` is
    counted as for :func:`exponential_filter`.
    """
    if isinstance(n_bits, bool) or not isinstance(n_bits, int) or n_bits < 0:
        raise Diagnostic("ACCDEC-PARAM", f"DDA accumulator bits {n_bits!r}: need an integer >= 0")
    g = 2.0**-n_bits
    if n_bits == 0:
        return Filter(((np.array([1.0]), np.array([1.0])),), 0)
    ratio = max(amplitude, tolerance) / tolerance
    tail = math.ceil(math.log(ratio) / -math.log(1.0 - g))
    return Filter(((np.array([g]), np.array([1.0, -(1.0 - g)])),), tail)


def weighted_fir(weights: np.ndarray | list[float]) -> Filter:
    """The book's S-shape circuit (eqs. 4.12-4.14): ``sum(A_i K_i) / sum(K_i)`` over n registers."""
    k = np.asarray(weights, dtype=float)
    if k.ndim != 1 or k.size == 0 or not np.all(np.isfinite(k)) or k.sum() == 0:
        raise Diagnostic("ACCDEC-PARAM", f"weights {k.tolist()} must be finite with a non-zero sum")
    return Filter(((k / k.sum(), np.array([1.0])),), k.size - 1)


def make_filter(config: AccDecConfig, period: float, amplitude: float = 1.0) -> Filter:
    """The filter a configuration asks for at interpolation period ``period``."""
    if config.kind is AccDecKind.LINEAR:
        return linear_filter(config.tau, period)
    if config.kind is AccDecKind.S_SHAPE:
        return s_shape_filter(config.tau, period)
    if config.kind is AccDecKind.EXPONENTIAL:
        return exponential_filter(config.tau, period, config.exp_tail_tolerance, amplitude)
    return Filter(((np.array([1.0]), np.array([1.0])),), 0)


def run(filt: Filter, x: np.ndarray, state: FilterState | None = None) -> np.ndarray:
    """Filter ``x`` (shape ``(n,)`` or ``(n, axes)``) along axis 0, updating ``state``."""
    y = np.asarray(x, dtype=float)
    lead = y.shape[1:]
    for i, (b, a) in enumerate(filt.stages):
        order = max(len(a), len(b)) - 1
        if state is not None and len(state.zi) <= i:
            state.zi.append(np.zeros((order, *lead)))
        if order == 0:
            y = y * (b[0] / a[0])
            continue
        if state is None:
            y = lfilter(b, a, y, axis=0)
        else:
            y, state.zi[i] = lfilter(b, a, y, axis=0, zi=state.zi[i])
    return y


def filter_pulses(filt: Filter, pulses: np.ndarray) -> np.ndarray:
    """Filter one block's pulse train and append the tail so the filter empties.

    For the FIR types the output sums exactly to the input (eq. 4.3). For the exponential
    type the residual left after ``tail`` periods is added to the last output period.
    """
    x = np.asarray(pulses, dtype=float)
    pad = np.zeros((filt.tail, *x.shape[1:]))
    y = run(filt, np.concatenate([x, pad]))
    if y.shape[0]:
        y[-1] += x.sum(axis=0) - y.sum(axis=0)
    return y


def filter_blocks(filt: Filter, blocks: list[np.ndarray], exact_stop: bool) -> np.ndarray:
    """Filter successive blocks' pulse trains in exact-stop or continuous mode (§4.2.4).

    Continuous (G64): the trains are concatenated and filtered as one, so each block's
    output overlaps the next (figs. 4.13/4.14). Exact stop (G61): each block is filtered on
    its own and emptied before the next starts (fig. 6.8).
    """
    if not blocks:
        return np.zeros(0)
    if exact_stop:
        return np.concatenate([_stopped(filter_pulses(filt, b)) for b in blocks])
    return filter_pulses(filt, np.concatenate(blocks))


def _stopped(y: np.ndarray) -> np.ndarray:
    """One period of zero output after a block: the period in which the filter is found
    empty before the next block may start (tables 4.1/4.2 end with that zero, fig. 6.8)."""
    return np.concatenate([y, np.zeros((1, *y.shape[1:]))])


def distribute_pulses(total: int, iterations: int, method: int = 2) -> np.ndarray:
    """Integer pulses per iteration for a block of ``total`` pulses (book §6.2.2).

    Method 2 (the book's): the remainder goes one pulse each to the first iterations
    (745 over 10 -> 75 x 5, 74 x 5). Method 1: an extra iteration carries the remainder
    (74 x 10, then 5).
    """
    if iterations < 1:
        raise Diagnostic("ACCDEC-PARAM", f"{iterations} iterations: need at least one")
    sign = -1 if total < 0 else 1
    q, r = divmod(abs(int(total)), iterations)
    if method == 1:
        out = [q] * iterations + ([r] if r else [])
    elif method == 2:
        out = [q + 1] * r + [q] * (iterations - r)
    else:
        raise Diagnostic("ACCDEC-PARAM", f"residual-pulse method {method}: expected 1 or 2")
    return sign * np.array(out, dtype=np.int64)


def quantise_pulses(displacement: np.ndarray, blu: float) -> np.ndarray:
    """Whole pulses (BLU) per period, carrying each period's fraction into the next.

    Rounds the cumulative position, so the total is never off by more than half a pulse
    and no residual accumulates (book §6.2.2: moves must be multiples of the pulse).
    """
    if not (blu > 0 and math.isfinite(blu)):
        raise Diagnostic("ACCDEC-PARAM", f"pulse size {blu!r} must be positive")
    cum = np.rint(np.cumsum(np.asarray(displacement, dtype=float), axis=0) / blu)
    first = np.zeros((1, *cum.shape[1:]))
    return np.diff(np.concatenate([first, cum]), axis=0).astype(np.int64)


def _derivative(x: np.ndarray, period: float) -> np.ndarray:
    return np.gradient(x, period, axis=0) if x.shape[0] > 1 else np.zeros_like(x)


def apply(samples: Samples, config: AccDecConfig, exact_stop: bool | np.ndarray = False) -> Samples:
    """Filter every axis of ``samples`` after interpolation; returns longer ``Samples``.

    Each axis' per-period displacement goes through the configured filter (independently
    per axis, book fig. 4.2) and the tail is appended so the axes reach the end point.
    ``exact_stop`` (G61, book §4.2.4): True stops after every segment; an array of flags per
    path row (kernel.path.build's ``exact_stop`` column) stops after the flagged rows only. A
    stop filters the samples before it on their own and lets the filter empty (fig. 6.8);
    elsewhere the blocks overlap (G64). Velocity, acceleration and jerk are recomputed by
    central differences.
    """
    if not config.filters_after or len(samples) == 0:
        return samples
    pos = samples.position
    d = np.diff(pos, axis=0, prepend=pos[:1])
    amp = float(np.abs(d).max()) if d.size else 1.0
    filt = make_filter(config, samples.period, max(amp, 1e-12))
    seg = samples.segment
    cuts = np.flatnonzero(np.diff(seg)) + 1
    if isinstance(exact_stop, np.ndarray):
        flags = np.asarray(exact_stop, dtype=bool)
        prev = seg[cuts - 1]
        ok = (prev >= 0) & (prev < flags.size)
        cuts = cuts[ok & flags[np.where(ok, prev, 0)]] if flags.size else cuts[:0]
    elif not exact_stop:
        cuts = cuts[:0]
    if cuts.size:
        blocks = np.split(d, cuts)
        idx_blocks = np.split(np.arange(len(samples)), cuts)
        out = [_stopped(filter_pulses(filt, b)) for b in blocks]
        index = np.concatenate(
            [np.concatenate([ix, np.full(filt.tail + 1, ix[-1])]) for ix in idx_blocks]
        )
        dd = np.concatenate(out)
    else:
        dd = filter_pulses(filt, d)
        index = np.concatenate([np.arange(len(samples)), np.full(filt.tail, len(samples) - 1)])
    newpos = pos[0] + np.cumsum(dd, axis=0)
    vel = _derivative(newpos, samples.period)
    acc = _derivative(vel, samples.period)
    jerk = _derivative(acc, samples.period)
    n = newpos.shape[0]
    return replace(
        samples,
        t=np.arange(n) * samples.period,
        position=newpos,
        velocity=vel,
        acceleration=acc,
        jerk=jerk,
        segment=samples.segment[index],
        source_line=samples.source_line[index],
    )


def fine_interpolate(samples: Samples, ratio: int, method: str = "linear") -> Samples:
    """Fine interpolation to the position-control period (book §3.4, §6.2.4), by
    :func:`kernel.interp.fine.fine_positions`: ``linear`` (eq. 3.72) spreads each interpolation
    period's displacement evenly over ``ratio`` periods; ``moving_average`` (eq. 3.73,
    ``ratio`` even) smooths it further and starts ``ratio/2`` fine periods earlier.

    Velocity is the displacement per fine period, acceleration and jerk its backward
    differences; segment and source line follow the interpolation sample each fine period
    belongs to.
    """
    if isinstance(ratio, bool) or not isinstance(ratio, int) or ratio < 1:
        raise Diagnostic(
            "ACCDEC-PARAM", f"fine-interpolation ratio {ratio!r}: need an integer >= 1"
        )
    if ratio == 1 or len(samples) < 2:
        return samples
    n = len(samples)
    fine = fine_positions(samples.position, ratio, method)
    period = samples.period / ratio
    vel = np.diff(fine, axis=0, append=fine[-1:]) / period
    acc = np.diff(vel, axis=0, prepend=vel[:1]) / period
    jerk = np.diff(acc, axis=0, prepend=acc[:1]) / period
    lead = ratio // 2 if method == "moving_average" else 0
    idx = np.clip((np.arange(fine.shape[0]) - lead) // ratio, 0, n - 1)
    return replace(
        samples,
        period=period,
        t=np.arange(fine.shape[0]) * period,
        position=fine,
        velocity=vel,
        acceleration=acc,
        jerk=jerk,
        segment=samples.segment[idx],
        source_line=samples.source_line[idx],
    )


def planning_machine(machine: Machine) -> Machine:
    """The limits the planner should use given where the profile puts acc/dec (book §4.1).

    With acc/dec *after* interpolation only (ADCAI, fig. 4.1b) the interpolator emits the
    programmed feed from the first period and the per-axis filters alone accelerate and
    decelerate; the planner must then not shape the profile itself. It gets axes able to
    reach their velocity limit within one interpolation period (and the matching jerk), so
    it keeps only the velocity caps. Before or both: the profile is returned unchanged.
    """
    cfg = config_from_machine(machine)
    if cfg.kind is AccDecKind.NONE or cfg.placement is not AccDecPlacement.AFTER:
        return machine
    period = machine.controller.interpolation_period
    axes = tuple(
        replace(a, acceleration=a.velocity / period, jerk=a.velocity / period**2)
        for a in machine.axes
    )
    return replace(machine, axes=axes, controller=replace(machine.controller, accdec="trapezoid"))
