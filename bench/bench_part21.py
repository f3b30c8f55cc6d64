"""Benchmark the Part 21 reader on a generated 1,000,000-instance file.

Prints reading time (CPU and wall), throughput and memory per instance (retained after
reading, and the peak while reading). If a G-code interpreter (``gcode.ngc.interpreter``)
and ``cnc canon`` exist, it also times ``cnc canon`` on an RS274/NGC file of the same byte
size and prints the ratio of CPU times (issue 5 asks for < 1.5x; the wall-clock ratio is
printed too); otherwise it says so.

Usage: python bench/bench_part21.py [N_INSTANCES] [--keep]
"""

from __future__ import annotations

import gc
import importlib.util
import os
import random
import resource
import subprocess
import sys
import tempfile
import time
import tracemalloc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from stepnc import part21  # noqa: E402


def generate(path: str, n: int, seed: int = 1) -> int:
    """A STEP-NC-like mix: points, directions, placements, polylines, technologies."""
    rnd = random.Random(seed)
    with open(path, "w") as fh:
        fh.write(
            "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('bench'),'2;1');\n"
            "FILE_NAME('bench.stp','2026-01-01',(''),(''),'','','');\n"
            "FILE_SCHEMA(('MACHINING_SCHEMA'));\nENDSEC;\nDATA;\n"
        )
        i = 1
        lines = []
        while i <= n:
            k = i % 10
            if k in (1, 2, 3, 4, 5):
                lines.append(
                    f"#{i}=CARTESIAN_POINT('P{i}',({rnd.uniform(-500, 500):.4f},"
                    f"{rnd.uniform(-500, 500):.4f},{rnd.uniform(-100, 100):.4f}));"
                )
            elif k == 6:
                lines.append(f"#{i}=DIRECTION('',(0.,0.,1.));")
            elif k == 7:
                lines.append(f"#{i}=AXIS2_PLACEMENT_3D('PLACE',#{i - 6},#{i - 1},$);")
            elif k == 8:
                refs = ",".join(f"#{max(1, i - j)}" for j in (7, 6, 5, 4, 3))
                lines.append(f"#{i}=POLYLINE('PATH {i}',({refs}));")
            elif k == 9:
                lines.append(
                    f"#{i}=MILLING_TECHNOLOGY({rnd.uniform(0.01, 0.1):.3f},.TCP.,$,"
                    f"{-rnd.uniform(5, 50):.3f},$,.F.,.F.,.F.,$);"
                )
            else:
                lines.append(f"#{i}=CUTTING_COMPONENT({rnd.uniform(40, 90):.1f},$,$,$,$);")
            i += 1
            if len(lines) >= 10000:
                fh.write("\n".join(lines) + "\n")
                lines.clear()
        fh.write("\n".join(lines) + "\nENDSEC;\nEND-ISO-10303-21;\n")
    return os.path.getsize(path)


def generate_ngc(path: str, size: int) -> None:
    rnd = random.Random(2)
    with open(path, "w") as fh:
        fh.write("G21 G90 G17 F600 S1000 M3\n")
        written, n = 0, 0
        while written < size:
            n += 1
            line = (
                f"N{n} G1 X{rnd.uniform(-100, 100):.4f} Y{rnd.uniform(-100, 100):.4f} "
                f"Z{rnd.uniform(-10, 0):.4f}\n"
            )
            fh.write(line)
            written += len(line)
        fh.write("M2\n")


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 and sys.argv[1].isdigit() else 1_000_000
    tmp = tempfile.mkdtemp(prefix="bench_p21_")
    stp = os.path.join(tmp, "big.stp")
    t0 = time.perf_counter()
    size = generate(stp, n)
    print(f"generated {n:,} instances, {size / 1e6:.1f} MB in {time.perf_counter() - t0:.1f} s")

    gc.collect()
    t0, c0 = time.perf_counter(), time.process_time()
    f = part21.read_file(stp)
    t_read, c_read = time.perf_counter() - t0, time.process_time() - c0
    assert len(f) == n
    print(
        f"read: {t_read:.2f} s ({c_read:.2f} s CPU), {n / c_read:,.0f} instances per CPU "
        f"second, {size / 1e6 / c_read:.1f} MB/s"
    )
    # a large file's instances are decoded when first asked for (stepnc.p21_scan): the
    # cost of asking for every one, once
    c0 = time.process_time()
    decoded = sum(1 for _ in f.instances.values())
    c_decode = time.process_time() - c0
    assert decoded == n
    print(f"decoding every instance (first access): {c_decode:.2f} s CPU")
    del f
    gc.collect()

    tracemalloc.start()
    f = part21.read_file(stp)
    current, peak = tracemalloc.get_traced_memory()
    print(
        f"memory retained: {current / n:.0f} B/instance ({current / 1e6:.0f} MB); "
        f"peak while reading: {peak / n:.0f} B/instance (limit 1024)"
    )
    sum(1 for _ in f.instances.values())
    gc.collect()
    current, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(
        f"every instance decoded: {current / n:.0f} B/instance retained, "
        f"{peak / n:.0f} B/instance peak (reading and decoding)"
    )
    del f

    have_gcode = (
        importlib.util.find_spec("gcode.ngc.interpreter") is not None
        and importlib.util.find_spec("cli.canon") is not None
    )
    if have_gcode:
        ngc = os.path.join(tmp, "big.ngc")
        generate_ngc(ngc, size)
        t0 = time.perf_counter()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(["cnc", "canon", ngc], check=True, stdout=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        t_ngc = time.perf_counter() - t0
        c_ngc = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
        # CPU time: on a machine shared with other jobs the wall-clock ratio is mostly noise
        print(
            f"cnc canon on {os.path.getsize(ngc) / 1e6:.1f} MB of G-code: {t_ngc:.2f} s "
            f"({c_ngc:.2f} s CPU); Part 21 read / G-code canon = {c_read / c_ngc:.2f} CPU, "
            f"{t_read / t_ngc:.2f} wall (target < 1.5)"
        )
    else:
        print("no gcode.ngc.interpreter / cli.canon yet: G-code comparison skipped")
    if "--keep" not in sys.argv:
        for name in os.listdir(tmp):
            os.remove(os.path.join(tmp, name))
        os.rmdir(tmp)


if __name__ == "__main__":
    main()
