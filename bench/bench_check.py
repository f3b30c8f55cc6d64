"""``cnc check`` CPU against ``cnc canon`` on the CAM program of bench/cam_program.py (issue
19: within 3x). Runs both commands as subprocesses on the same generated program and prints
their CPU times (user + system of the child) and the ratio; the ratio is what to compare
across machines and loads. Usage: ``python bench/bench_check.py [LINES ...]`` (default
200,000).
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.cam_program import write_program  # noqa: E402


def cpu_of(args: list[str]) -> float:
    """CPU seconds (user + system) of one run of ``args``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main(sizes: list[int]) -> None:
    cnc = [sys.executable, "-m", "cli.main"]
    env_path = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = str(ROOT) + (os.pathsep + env_path if env_path else "")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            prog = write_program(Path(tmp) / f"cam{n}.ngc", n)
            out = Path(tmp) / "out.canon"
            canon = cpu_of([*cnc, "canon", str(prog), "-o", str(out), "--force"])
            check = cpu_of([*cnc, "check", str(prog)])
            print(
                f"{n:>10,} lines  canon {canon:7.2f} s  check {check:7.2f} s  "
                f"check/canon {check / canon:5.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [200_000])
