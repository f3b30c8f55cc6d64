"""Peak memory of the CLI against program length (issue 19, bounded memory).

Generates CAM programs (bench/cam_program.py) of each length given, runs ``cnc COMMAND`` on
each in a fresh process and prints its peak resident set size (``ru_maxrss`` of the child)
and CPU time, with the growth per line between the first and the last length. The promise
under test is a peak that does not grow with the program: the same for 10**5 and 10**7 lines.

Usage: python bench/bench_memory.py [--command plan] [LINES ...]   (default 100000 1000000)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from cam_program import cam_lines  # noqa: E402


def peak(command: list[str]) -> tuple[float, float, float, int]:
    """(peak RSS in MB, CPU seconds, wall seconds, exit code) of ``command`` run alone."""
    code = (
        "import resource, subprocess, sys, json, time\n"
        "t = time.perf_counter()\n"
        "p = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)\n"
        "u = resource.getrusage(resource.RUSAGE_CHILDREN)\n"
        "print(json.dumps([u.ru_maxrss / 1024, u.ru_utime + u.ru_stime,"
        " time.perf_counter() - t, p.returncode]))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code, *command], capture_output=True, text=True, check=True
    )
    rss, cpu, wall, rc = json.loads(out.stdout)
    return float(rss), float(cpu), float(wall), int(rc)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("lines", nargs="*", type=int, default=[100_000, 1_000_000])
    ap.add_argument("--command", default="plan", help="cnc subcommand (plan, check, canon)")
    args = ap.parse_args()
    env_cnc = [sys.executable, "-m", "cli.main"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.lines:
            prog = Path(tmp) / f"cam_{n}.ngc"
            with open(prog, "w") as fh:
                for line in cam_lines(n):
                    fh.write(line + "\n")
            t0 = time.perf_counter()
            rss, cpu, wall, rc = peak([*env_cnc, args.command, str(prog)])
            rows.append((n, rss, cpu, wall, rc))
            print(
                f"cnc {args.command} {n:>10,d} lines: peak RSS {rss:8.1f} MB, "
                f"CPU {cpu:7.1f} s, wall {wall:7.1f} s, exit {rc} "
                f"(generated in {time.perf_counter() - t0 - wall:.1f} s)",
                flush=True,
            )
            os.unlink(prog)
    if len(rows) > 1:
        (n0, r0, *_), (n1, r1, *_) = rows[0], rows[-1]
        print(f"growth: {(r1 - r0) * 1024 * 1024 / max(1, n1 - n0):.1f} bytes of peak RSS per line")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
