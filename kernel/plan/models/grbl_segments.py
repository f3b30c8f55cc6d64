"""The late last step of a Grbl stop: its 10 ms step segments in single precision.

Grbl 1.1h (github.com/gnea/grbl, GPL-3.0; read, not copied) cuts every block into segments
of ``DT_SEGMENT`` = 10 ms (stepper.c ``st_prep_buffer``, ``ACCELERATION_TICKS_PER_SECOND``)
with float arithmetic, in mm and minutes: each segment takes the distance left
(``mm_remaining``) and the speed (``current_speed``) one segment further along the
acceleration, cruise and deceleration ramps, and runs the whole steps it covers. Where a
block ends at rest after a whole number of segments, exact arithmetic leaves nothing for
one more segment; rounding can leave a speck of distance at a speck of speed instead, and
Grbl's end-of-block branch then times that last stretch as ``2 mm / v``, a ratio of two
rounding errors: its one step takes tens of milliseconds (capped by the timer's slowest
setting, ``cycles_per_tick`` 0xffff at AMASS level 3, 33 ms). :func:`stop_tails` finds this
for every block that ends at rest by replaying its segments in float32, as grbl-sim runs
Grbl (x86-64: ``float`` operations in single precision, those with a ``double`` constant
such as ``0.5`` in double, rounded to ``float`` where stored), from the block as the planner
makes it (planner.c ``plan_buffer_line``, nuts_bolts.c ``convert_delta_vector_to_unit_vector``
and ``limit_value_by_axis_maximum``). Checked segment by segment, to the bit, against an
instrumented grbl-sim on 184 single moves (tests/data/grbl_sim/README.md).

Only blocks whose ideal duration ends within reach of a segment boundary are replayed
(:func:`_near_boundary`); elsewhere the last segment is long enough that rounding cannot
make it late by more than microseconds. Blocks of more than ``MAX_SEGMENTS`` segments are
not replayed (one late step is under 0.33 % of such a block).
"""

from __future__ import annotations

import numpy as np

from kernel.machine import Machine

F32 = np.float32
F64 = np.float64
DT = 1.0 / (100 * 60.0)  # stepper.c DT_SEGMENT, minutes (a double constant)
REQ_MM_INCREMENT = 1.25  # stepper.c REQ_MM_INCREMENT_SCALAR, steps
TICKS_PER_MIN = 16e6 * 60  # the 16 MHz timer's ticks a minute
MAX_SEGMENTS = 1000
_ACCEL, _CRUISE, _DECEL = 0, 1, 2
# the ideal decel's last segment is within _WINDOW_SCALE * t_dec^2 / _LATE of a boundary:
# rounding errors of 1e-6 of the deceleration distance cannot make it _LATE minutes late
_LATE = 20e-6 / 60
_WINDOW_SCALE = 1e-6


def _f(x: np.ndarray) -> np.ndarray:
    return np.asarray(x, dtype=F32)


def _d(x: np.ndarray) -> np.ndarray:
    return np.asarray(x, dtype=F64)


def grbl_blocks(
    dsteps: np.ndarray,
    feed: np.ndarray,
    steps_per_mm: np.ndarray,
    velocity: np.ndarray,
    acceleration: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """planner.c ``plan_buffer_line`` in float32: each block's millimeters, acceleration
    (mm/min^2), nominal speed (mm/min) and step event count, from its steps per axis
    (``dsteps``, rows of x, y, z), its feed (mm/s; inf for a rapid) and the axes' settings
    (``$100..$102``, ``$110..$112`` in mm/s, ``$120..$122`` in mm/s^2)."""
    spm = _f(steps_per_mm)
    delta = _f(_f(dsteps) / spm)
    mag = np.zeros(len(delta), F32)
    for k in range(delta.shape[1]):
        mag = _f(mag + _f(delta[:, k] * delta[:, k]))
    mag = np.sqrt(mag)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = _f(1.0 / _d(mag))
        unit = _f(delta * inv[:, None])

        def limit(values: np.ndarray) -> np.ndarray:  # limit_value_by_axis_maximum
            ratio = np.abs(_f(_f(values)[None, :] / unit))
            return np.min(np.where(unit != 0, ratio, F32(np.inf)), axis=1)

        acc = limit(_f(_f(_f(acceleration) * F32(60)) * F32(60)))  # settings.c: value*60*60
        rapid = limit(_f(_f(velocity) * F32(60)))
    programmed = np.where(np.isfinite(feed), _f(np.asarray(feed) * 60.0), rapid)
    nominal = np.maximum(np.minimum(programmed, rapid), F32(1.0))  # MINIMUM_FEED_RATE
    count = np.max(np.abs(dsteps), axis=1)
    return mag, acc, _f(nominal), count


def _near_boundary(
    mm: np.ndarray, acc: np.ndarray, entry2: np.ndarray, nominal: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Whether each block's ideal time (entry speed^2 ``entry2``, to rest) ends within
    reach of a 10 ms segment boundary, and its number of segments."""
    mm, acc, entry2, v = _d(mm), _d(acc), _d(entry2), _d(nominal)
    peak2 = np.minimum(v * v, 0.5 * (entry2 + 2.0 * acc * mm))
    peak = np.sqrt(np.maximum(peak2, entry2))
    t_acc = (peak - np.sqrt(entry2)) / acc
    t_dec = peak / acc
    d_ramps = (peak2 - entry2) / (2.0 * acc) + peak2 / (2.0 * acc)
    t = t_acc + t_dec + np.maximum(mm - d_ramps, 0.0) / np.maximum(peak, 1e-30)
    segments = t / DT
    frac = np.abs(segments - np.round(segments)) * DT
    return frac <= _WINDOW_SCALE * t_dec * t_dec / _LATE, segments


def _segment_timing(dt: np.ndarray, steps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """stepper.c: seconds ``steps`` steps run in a segment of ``dt`` minutes, and the
    stepper interrupt's period there (the cycles per step rounded up, AMASS levels 1-3
    below 8, 4 and 2 kHz, ``cycles_per_tick`` capped at 0xffff, each timer period one tick
    more than its compare value)."""
    cycles = np.ceil(TICKS_PER_MIN * dt / np.maximum(steps, 1))
    level = np.select([cycles < 2000, cycles < 4000, cycles < 8000], [0, 1, 2], 3)
    period = (np.minimum(np.floor(cycles / np.exp2(level)), 0xFFFF) + 1) / 16e6
    return steps * np.exp2(level) * period, period


def _profiles(
    mm0: np.ndarray, acc: np.ndarray, entry2: np.ndarray, nominal: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """stepper.c ``st_prep_buffer``: the block's ramp type, ``accelerate_until``,
    ``decelerate_after`` and ``maximum_speed`` for an exit at rest (float32)."""
    inv2a = _f(0.5 / _d(acc))
    nom2 = _f(nominal * nominal)
    entry2 = np.minimum(entry2, nom2)  # an override reduction: not met here
    inter = _f(0.5 * _d(_f(mm0 + _f(inv2a * entry2))))
    dec_after = _f(inv2a * nom2)
    trapezoid = dec_after < inter
    full = inter < mm0
    ramp = np.where(full, np.where(trapezoid & (entry2 == nom2), _CRUISE, _ACCEL), _DECEL)
    acc_until = np.where(trapezoid, _f(mm0 - _f(inv2a * _f(nom2 - entry2))), inter)
    acc_until = np.where(full, acc_until, mm0)
    dec_after = np.where(trapezoid, dec_after, inter)
    tri_speed = _f(np.sqrt(2.0 * _d(acc) * _d(inter)))
    max_speed = np.where(trapezoid, nominal, tri_speed)
    return ramp.astype(np.int8), _f(acc_until), _f(dec_after), _f(max_speed), entry2


def late_last_step(
    mm0: np.ndarray, acc: np.ndarray, entry2: np.ndarray, nominal: np.ndarray, count: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Seconds the last step of each block (float32 inputs as :func:`grbl_blocks` gives
    them; ``entry2`` its entry speed squared, (mm/min)^2) comes later than the block's
    ideal end, where it ends at rest (stepper.c ``st_prep_buffer`` segment by segment), and
    how much longer the stepper interrupt's period is then: where the steppers go idle
    after the block (a sync point), the interrupt runs once more with nothing to step
    (stepper.c ``st_go_idle``) and that period counts too (measured on grbl-sim)."""
    n = len(mm0)
    out, idle = np.zeros(n), np.zeros(n)
    mm_blk, acc, nominal = _f(mm0), _f(acc), _f(nominal)
    ramp, acc_until, dec_after, max_speed, entry2 = _profiles(mm_blk, acc, _f(entry2), nominal)
    cs = _f(np.sqrt(_d(entry2)))
    steps_left = _f(count)
    spm = _f(steps_left / mm_blk)
    req = _f(REQ_MM_INCREMENT / _d(spm))
    rem = np.zeros(n, F32)
    active = np.ones(n, bool)
    zero = F32(0.0)
    with np.errstate(all="ignore"):
        while active.any():
            dt_max = np.full(n, DT, F32)
            dt = np.zeros(n, F32)
            tv = dt_max.copy()
            mm = mm_blk.copy()
            minimum = np.maximum(_f(mm - req), zero)
            inner = active.copy()
            tv_end = np.zeros(n, F32)
            mm_end = np.zeros(n, F32)
            while inner.any():
                a = inner & (ramp == _ACCEL)
                c = inner & (ramp == _CRUISE)
                dd = inner & (ramp == _DECEL)
                sv = _f(acc * tv)
                # acceleration ramp
                mm_a = _f(_d(mm) - _d(tv) * (_d(cs) + 0.5 * _d(sv)))
                a_end = a & (mm_a < acc_until)
                a_on = a & ~a_end
                tv_a = _f(2.0 * _d(_f(mm_blk - acc_until)) / _d(_f(cs + max_speed)))
                # cruise
                mm_c = _f(mm - _f(max_speed * tv))
                c_end = c & (mm_c < dec_after)
                c_on = c & ~c_end
                tv_c = _f(_f(mm - dec_after) / max_speed)
                # deceleration: a whole segment, or the end of the block
                mm_d = _f(_d(mm) - _d(tv) * (_d(cs) - 0.5 * _d(sv)))
                d_on = dd & (cs > sv) & (mm_d > zero)
                d_end = dd & ~d_on
                tv_d = _f(2.0 * _d(mm) / _d(cs))
                tv_end = np.where(d_end, tv_d, tv_end)
                mm_end = np.where(d_end, mm, mm_end)
                mm = np.select(
                    [a_on, a_end, c_on, c_end, d_on, d_end],
                    [mm_a, acc_until, mm_c, dec_after, mm_d, zero],
                    mm,
                )
                tv = np.select([a_end, c_end, d_end], [tv_a, tv_c, tv_d], tv)
                cs = np.select(
                    [a_on, a_end, d_on, d_end], [_f(cs + sv), max_speed, _f(cs - sv), zero], cs
                )
                ramp = np.where(a_end, np.where(acc_until == dec_after, _DECEL, _CRUISE), ramp)
                ramp = np.where(c_end, _DECEL, ramp).astype(np.int8)
                dt = np.where(inner, _f(dt + tv), dt)
                short = inner & (dt < dt_max)
                longer = inner & ~short & (mm > minimum)
                dt_max = np.where(longer, _f(_d(dt_max) + DT), dt_max)
                tv = np.where(short | longer, _f(dt_max - dt), tv)
                inner &= (short | longer) & (mm > zero)
            # the segment's steps (stepper.c: steps from the distance left, rounded up)
            dist = _f(spm * mm)
            steps_after = _f(np.ceil(_d(dist)))
            last = _f(np.ceil(_d(steps_left)))
            dt = _f(dt + rem)
            inv_rate = _f(dt / _f(last - dist))
            done = active & (mm <= zero)
            if done.any():
                ideal = np.sqrt(2.0 * _d(mm_end) / _d(acc))
                late = done & (_d(tv_end) > ideal)
                k = np.flatnonzero(late)
                steps = _d(last - steps_after)[k]
                spent, period = _segment_timing(_d(dt)[k], steps)
                early, period0 = _segment_timing(_d(dt)[k] - (_d(tv_end)[k] - ideal[k]), steps)
                out[k] = np.maximum(spent - early, 0.0)
                idle[k] = np.maximum(period - period0, 0.0)
            rem = np.where(active, _f(_f(steps_after - dist) * inv_rate), rem)
            steps_left = np.where(active, steps_after, steps_left)
            mm_blk = np.where(active, mm, mm_blk)
            active &= ~done
    return out, idle


def stop_tails(
    dsteps: np.ndarray, feed: np.ndarray, entry: np.ndarray, cruise: np.ndarray, machine: Machine
) -> tuple[np.ndarray, np.ndarray]:
    """Seconds each block that ends at rest (steps per axis ``dsteps``, feed in mm/s, inf
    for a rapid, entry speed in mm/s, ``cruise``: entered at its nominal speed) runs past its
    ideal end, its last step late by float32 rounding in Grbl's segments, and the longer
    interrupt period if the steppers go idle after it (:func:`late_last_step`), where its
    ideal time ends within reach of a segment boundary and it has at most ``MAX_SEGMENTS``
    segments."""
    out, idle = np.zeros(len(dsteps)), np.zeros(len(dsteps))
    if not len(dsteps):
        return out, idle
    lin = slice(0, 3)
    mm0, acc, nominal, count = grbl_blocks(
        dsteps[:, lin],
        feed,
        np.array(machine.limit_vector("steps_per_mm"))[lin],
        np.array(machine.limit_vector("velocity"))[lin],
        np.array(machine.limit_vector("acceleration"))[lin],
    )
    entry_min = _d(entry) * 60.0
    entry2 = _f(entry_min * entry_min)
    # a block entered at its nominal speed, or as fast as it can stop in (planner.c
    # planner_recalculate: 2 a L), gets Grbl's own float values for these
    stop2 = _f(_f(F32(2) * acc) * mm0)
    at_stop = np.abs(_d(entry2) - _d(stop2)) <= 1e-6 * _d(stop2)
    entry2 = np.where(
        entry_min <= 0,
        F32(0),
        np.where(cruise, _f(nominal * nominal), np.where(at_stop, stop2, entry2)),
    )
    near, segments = _near_boundary(mm0, acc, entry2, nominal)
    pick = np.flatnonzero(near & (segments <= MAX_SEGMENTS) & (count > 0))
    if pick.size:
        out[pick], idle[pick] = late_last_step(
            mm0[pick], acc[pick], entry2[pick], nominal[pick], count[pick]
        )
    return out, idle
