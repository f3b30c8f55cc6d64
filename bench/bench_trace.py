"""Benchmark: per-axis traces of a 10-minute program at a 1 ms servo period (issue 4).

The program is a zig-zag pocket finish generated as canonical IR: 2 mm G1 lines with Z
following a wavy floor and G2/G3 half-circle turn-arounds, F 3000 mm/min, sized to run
about ``minutes`` of machine time. It is planned and sampled at 1 ms (not timed), then
the trace stage (servo simulation of X, Y, Z, following and exact contour errors, every
column of docs/traces.md) runs chunk by chunk into a writer (NPZ, CSV, and Parquet when
pyarrow is installed). Printed: machine time, wall and CPU time per format, the ratio
machine time / trace time (target >= 500 for NPZ), and the peak memory the trace stage
allocates for two chunk sizes and two program lengths (it must follow the chunk, not the
program). Run: ``python bench/bench_trace.py [minutes]``.
"""

from __future__ import annotations

import importlib.util
import math
import os
import sys
import tempfile
import time
import tracemalloc

import numpy as np

from kernel.interp.interpolate import sample
from kernel.interp.samples import Samples
from kernel.ir import canon
from kernel.machine import DEFAULT_MACHINE
from kernel.path.build import build_path
from kernel.plan.planner import plan
from kernel.report.trace import Trace, column_dtypes, columns, setup
from kernel.report.trace_writers import open_writer

FEED = 3000.0  # mm/min


def pocket_program(
    minutes: float, step: float = 2.0, width: float = 100.0, stepover: float = 1.0
) -> list[canon.Command]:
    """Zig-zag passes of ``step`` mm lines joined by half circles, about ``minutes`` long."""
    per_pass = int(width / step)
    pass_len = width + math.pi * stepover / 2
    passes = max(1, int(minutes * 60 * FEED / 60 / pass_len))
    cmds: list[canon.Command] = [
        canon.UseLengthUnits(canon.Units.MM),
        canon.SetFeedRate(FEED),
        canon.StraightTraverse(-50.0, -100.0, 5.0),
    ]
    x = np.linspace(-50.0, 50.0, per_pass + 1)
    line = 1
    for p in range(passes):
        y = -100.0 + (p % 200) * stepover
        xs = x if p % 2 == 0 else x[::-1]
        z = 0.5 * np.sin(xs / 9.0) * math.cos(y / 13.0) - 1.0
        if p == 0:
            cmds.append(canon.StraightFeed(float(xs[0]), y, float(z[0])))
        for xi, zi in zip(xs[1:], z[1:], strict=True):
            line += 1
            cmds.append(
                canon.StraightFeed(float(xi), y, float(zi), source=canon.Source(None, line, 1))
            )
        y2 = -100.0 + ((p + 1) % 200) * stepover
        if y2 < y:  # start over at the first pass: a straight move back
            cmds.append(canon.StraightFeed(float(xs[-1]), y2, float(z[-1])))
            continue
        line += 1
        rot = 1 if p % 2 == 0 else -1
        cmds.append(
            canon.ArcFeed(
                float(xs[-1]),
                y2,
                float(xs[-1]),
                (y + y2) / 2,
                rot,
                float(z[-1]),
                source=canon.Source(None, line, 1),
            )
        )
    cmds.append(canon.StraightTraverse(float(xs[-1]), y2, 5.0))
    cmds.append(canon.ProgramEnd())
    return cmds


def run_trace(
    samples: Samples, segments: np.ndarray, fmt: str | None, chunk: int, folder: str
) -> tuple[float, float, int]:
    """Wall and CPU seconds of the trace stage (and writing, if ``fmt``), rows written."""
    machine = DEFAULT_MACHINE
    tr = Trace(samples, setup(machine, samples.period), segments, chunk=chunk)
    w = None
    if fmt is not None:
        path = os.path.join(folder, f"trace.{fmt}")
        if os.path.exists(path):
            os.remove(path)
        w = open_writer(
            fmt, path, columns(samples.axes), rows=tr.rows, dtypes=column_dtypes(samples.axes)
        )
    c0, t0 = time.process_time(), time.perf_counter()
    rows = 0
    for table in tr.chunks():
        rows += len(table["t"])
        if w is not None:
            w.write(table)
    if w is not None:
        w.close()
    return time.perf_counter() - t0, time.process_time() - c0, rows


def peak_memory(samples: Samples, segments: np.ndarray, chunk: int, folder: str) -> float:
    """Peak bytes allocated by the trace stage writing NPZ (tracemalloc), in MB."""
    tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    run_trace(samples, segments, "npz", chunk, folder)
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return peak / 1e6


def prepared(minutes: float) -> tuple[Samples, np.ndarray, float]:
    cmds = pocket_program(minutes)
    path = build_path(cmds, DEFAULT_MACHINE)
    pl = plan(path, DEFAULT_MACHINE)
    return sample(pl), path.segments, pl.total_time


def main(argv: list[str]) -> None:
    minutes = float(argv[0]) if argv else 10.0
    samples, segments, machine_time = prepared(minutes)
    print(
        f"program: {len(segments)} segments, machine time {machine_time:.1f} s, "
        f"{len(samples)} samples at {samples.period * 1000:g} ms, axes {samples.axes}, "
        f"{len(columns(samples.axes))} columns"
    )
    with tempfile.TemporaryDirectory() as folder:
        run_trace(samples, segments, None, 65_536, folder)  # warm-up: numba, caches
        formats: list[str | None] = [None, "npz", "csv"]
        if importlib.util.find_spec("pyarrow") is not None:
            formats.append("parquet")
        for fmt in formats:
            wall, cpu, rows = run_trace(samples, segments, fmt, 65_536, folder)
            size = ""
            if fmt is not None:
                mb = os.path.getsize(os.path.join(folder, f"trace.{fmt}")) / 1e6
                size = f", file {mb:.0f} MB"
            name = fmt or "compute only"
            print(
                f"{name:>13}: {rows} rows, wall {wall:.3f} s, cpu {cpu:.3f} s, "
                f"machine/wall {machine_time / wall:.0f}x, machine/cpu "
                f"{machine_time / cpu:.0f}x{size}"
            )
        print("target: machine/wall >= 500x for all columns written (NPZ)")
        for chunk in (16_384, 65_536):
            print(
                f"peak trace memory, chunk {chunk}: "
                f"{peak_memory(samples, segments, chunk, folder):.1f} MB "
                f"(program {len(samples)} samples)"
            )
        half, seg_half, _ = prepared(minutes / 2)
        print(
            f"peak trace memory, chunk 65536, half-length program ({len(half)} samples): "
            f"{peak_memory(half, seg_half, 65_536, folder):.1f} MB"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
