"""Peak memory of the CLI against program length (issue 19, bounded memory).

Generates CAM programs (bench/cam_program.py) of each length given, runs ``cnc COMMAND`` on
each in a fresh process and prints its peak resident set size and CPU time (``/usr/bin/time
-v`` where installed, else ``ru_maxrss`` of the child), with the growth per line between the
first and the last length. The promise under test is a peak that does not grow with the
program: the same for 10**5 and 10**7 lines (kernel.stream plans ``cnc plan`` window by
window). ``--machine`` passes a profile (another controller model); ``--stop-every N`` puts
a stop (``G4 P0``) in place of every N-th feed line: the ``linuxcnc`` model plans from stop
to stop, so its peak is flat only with stops. ``--scurve`` plans on the default machine
with S-curve acc/dec (kernel.stream_scurve, two passes over the program); ``--compare
MODELS`` runs ``cnc plan --compare MODELS`` (each model planned window by window, the
models' times per source line kept).

Usage: python bench/bench_memory.py [--command plan] [--machine M.toml | --scurve]
[--stop-every N] [--compare linuxcnc,grbl,book] [LINES ...]
(default 1e5 1e6; ``1e7`` works too, and writes a 10**7-line program of ~300 MB to --tmp)
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

from kernel.machine import DEFAULT_MACHINE  # noqa: E402


def time_v(command: list[str]) -> tuple[float, float, float, int]:
    """:func:`peak` by ``/usr/bin/time -v``: its maximum resident set size and times."""
    t = time.perf_counter()
    p = subprocess.run(
        ["/usr/bin/time", "-v", *command],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    fields = {}
    for line in p.stderr.splitlines():
        key, _, value = line.strip().rpartition(": ")
        fields[key] = value
    rss = float(fields["Maximum resident set size (kbytes)"]) / 1024
    cpu = float(fields["User time (seconds)"]) + float(fields["System time (seconds)"])
    return rss, cpu, time.perf_counter() - t, p.returncode


def peak(command: list[str]) -> tuple[float, float, float, int]:
    """(peak RSS in MB, CPU seconds, wall seconds, exit code) of ``command`` run alone."""
    if os.path.exists("/usr/bin/time"):
        return time_v(command)
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


def scurve_profile() -> str:
    """The default machine (kernel.machine ``DEFAULT_MACHINE``) as a profile with S-curve
    acc/dec."""
    axes = "".join(
        f"[axes.{a.name}]\nmin = {a.min}\nmax = {a.max}\nvelocity = {a.velocity}\n"
        f"acceleration = {a.acceleration}\njerk = {a.jerk}\n"
        for a in DEFAULT_MACHINE.axes
    )
    return f'name = "default mill, S-curve"\n{axes}[controller]\naccdec = "scurve"\n'


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("lines", nargs="*", type=lambda v: int(float(v)), default=[10**5, 10**6])
    ap.add_argument("--command", default="plan", help="cnc subcommand (plan, check, canon)")
    ap.add_argument("--machine", default=None, help="machine profile (TOML) for the command")
    ap.add_argument("--tmp", default=None, help="directory for the generated programs")
    ap.add_argument(
        "--stop-every",
        type=int,
        default=0,
        help="a G4 P0 stop every N lines (the linuxcnc model plans from stop to stop)",
    )
    ap.add_argument(
        "--scurve",
        action="store_true",
        help="the default machine with S-curve acc/dec (instead of --machine)",
    )
    ap.add_argument("--compare", default=None, help="cnc plan --compare MODELS")
    args = ap.parse_args()
    env_cnc = [sys.executable, "-m", "cli.main"]
    rows = []
    with tempfile.TemporaryDirectory(dir=args.tmp) as tmp:
        machine = args.machine
        if args.scurve:
            machine = str(Path(tmp) / "scurve.toml")
            Path(machine).write_text(scurve_profile())
        extra = ["--machine", machine] if machine else []
        if args.compare:
            extra += ["--compare", args.compare]
        for n in args.lines:
            prog = Path(tmp) / f"cam_{n}.ngc"
            with open(prog, "w") as fh:
                for line in cam_lines(n, stop_every=args.stop_every):
                    fh.write(line + "\n")
            t0 = time.perf_counter()
            rss, cpu, wall, rc = peak([*env_cnc, args.command, str(prog), *extra])
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
