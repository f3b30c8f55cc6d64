"""``cnc check`` batch speed-up: 1,000 programs with --jobs 1 against --jobs 2 (issue 6).

Builds 1,000 G-code programs in a temporary directory (the corpus' G-code programs and the
check test programs, repeated), runs the installed ``cnc check`` on them with each job count
and prints wall and CPU times and the ratio. CPU/wall near the job count shows the workers
really run in parallel; the wall-time ratio needs otherwise idle CPUs.
Usage: ``python bench/bench_check_jobs.py [N]``.
"""

from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted((ROOT.parent / "shared" / "corpus" / "ngc").glob("*.ngc")) + sorted(
    (ROOT / "tests" / "check").glob("*.ngc")
)
PROFILE = ROOT / "tests" / "check" / "shop.toml"


def main(n: int = 1000) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for i in range(n):
            src = SOURCES[i % len(SOURCES)]
            dst = Path(tmp) / f"{i:04d}_{src.name}"
            shutil.copy(src, dst)
            files.append(str(dst))
        times = {}
        for jobs in (1, 2):
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            out = subprocess.run(
                ["cnc", "check", "-m", str(PROFILE), "-f", "json", "-j", str(jobs), *files],
                capture_output=True,
                text=True,
            )
            times[jobs] = time.perf_counter() - t0
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
            print(
                f"--jobs {jobs}: {times[jobs]:.2f} s wall, {cpu:.2f} s CPU "
                f"(CPU/wall {cpu / times[jobs]:.2f}; exit {out.returncode}, {n} programs)"
            )
        print(f"speed-up jobs 2 / jobs 1: {times[1] / times[2]:.2f}x")
        print(f"load average now: {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
