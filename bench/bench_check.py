"""``cnc check`` CPU against ``cnc canon`` on the CAM program of bench/cam_program.py (issue
19: within 3x). Runs both commands as subprocesses on the same generated program and prints
their CPU times (user + system of the child), the ratio and each one's peak RSS; the ratio
is what to compare across machines and loads.

Usage: ``python bench/bench_check.py [--dir DIR] [--before TREE] [LINES ...]`` (default
200,000 lines). ``--dir`` keeps the generated programs there (a 10M-line one is 310 MB and
takes a while to write); ``--before`` also runs ``cnc check`` from another source tree (an
older commit, e.g. ``git archive <commit> | tar -x -C TREE``) in the same run.

Figures of 2026-12-02 (2 cores shared by other jobs, load average about 12: absolute times are
2-4x an idle machine's, the ratios are what counts). Before: cf7315b, the commit before
cnc check judged a fast-lane block as runs across its feed changes. CPU seconds, peak RSS.

========== ============== ================= ================= ======== ========
lines      canon          check before      check after       before   after
========== ============== ================= ================= ======== ========
200,000    0.37 s  42 MB   1.08 s  138 MB    0.54 s   75 MB    2.96x    1.48x
1,000,000  0.63 s  42 MB   3.12 s  142 MB    0.89 s   50 MB    4.93x    1.41x
10,000,000 5.29 s  43 MB  24.17 s  216 MB    4.51 s   50 MB    4.57x    0.85x
========== ============== ================= ================= ======== ========

A second run (canon's time at 10M lines varies most with the load): 3.03x, 4.55x and 6.55x
before, 1.47x, 1.35x and 1.22x after (canon 0.38 s, 0.63 s, 3.76 s; check 0.56 s, 0.85 s,
4.59 s; the same peak RSS).

(canon writes 840 MB of text at 10M lines, check only its report; a check's peak RSS at
200,000 lines includes the program's text, kept for excerpts of files up to 8 MB.)
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.cam_program import write_program  # noqa: E402


def cpu_of(args: list[str], tree: Path = ROOT) -> tuple[float, float]:
    """CPU seconds (user + system) and peak RSS (MB) of one run of ``args`` with the
    project's code from ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    quiet = subprocess.DEVNULL
    proc = subprocess.Popen(args, stdout=quiet, stderr=quiet, env=env, cwd=tree)
    _, _, usage = os.wait4(proc.pid, 0)
    proc.returncode = 0  # reaped by wait4
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def main(sizes: list[int], folder: Path, before: Path | None) -> None:
    cnc = [sys.executable, "-m", "cli.main"]
    for n in sizes:
        prog = folder / f"cam{n}.ngc"
        if not prog.exists():
            write_program(prog, n)
        out = folder / "out.canon"
        canon, canon_rss = cpu_of([*cnc, "canon", str(prog), "-o", str(out), "--force"])
        out.unlink(missing_ok=True)
        line = f"{n:>10,} lines  canon {canon:7.2f} s {canon_rss:5.0f} MB"
        if before is not None:
            old, old_rss = cpu_of([*cnc, "check", str(prog)], before)
            line += f"  before: check {old:7.2f} s {old_rss:5.0f} MB  {old / canon:5.2f}x"
        check, check_rss = cpu_of([*cnc, "check", str(prog)])
        line += f"  check {check:7.2f} s {check_rss:5.0f} MB  check/canon {check / canon:5.2f}"
        print(line, flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("lines", type=int, nargs="*", default=[200_000])
    parser.add_argument("--dir", type=Path, default=None, help="keep the programs here")
    parser.add_argument("--before", type=Path, default=None, help="an older source tree")
    args = parser.parse_args()
    if args.dir is not None:
        args.dir.mkdir(parents=True, exist_ok=True)
        main(args.lines, args.dir, args.before)
    else:
        with tempfile.TemporaryDirectory() as tmp:
            main(args.lines, Path(tmp), args.before)
