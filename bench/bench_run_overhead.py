"""``cnc run`` against ``cnc check`` on the same programs, and where ``cnc run``'s time goes
(issue 18).

Collects N programs (default 200) from the repository's test corpus: the RS274/NGC
goldens (tests/golden/ngc) and the real-world programs (tests/realworld/ngc) under a size
limit, interleaved and repeated when there are fewer. Runs ``cnc check --jobs 2`` and
``cnc run --jobs 2`` (and with ``--html`` also ``cnc run --jobs 2 --html``) on them and
prints wall and CPU times, the overhead of ``run`` over ``check``, and the time per stage
summed over the programs (from ``summary.json``: check, plan, servo, plots, report, html;
``setup`` is the rest of each program's time, mostly the worker's first imports), then the
time to write the batch's own files (index.html, summary.json, junit.xml) again from the
same results. The machine's load average is printed too: the figures need idle CPUs.

Usage: ``python bench/bench_run_overhead.py [N] [--html] [--max-kb K] [--golden-only]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUFFIXES = (".ngc", ".nc", ".gcode", ".tap")


def sources(max_kb: float, golden_only: bool = False) -> list[Path]:
    """Golden and real-world programs no larger than ``max_kb``, interleaved."""

    def small(folder: Path) -> list[Path]:
        found = sorted(p for p in folder.iterdir() if p.suffix in SUFFIXES)
        return [p for p in found if p.stat().st_size <= max_kb * 1024]

    golden = small(ROOT / "tests" / "golden" / "ngc")
    real = [] if golden_only else small(ROOT / "tests" / "realworld" / "ngc")
    out: list[Path] = []
    for i in range(max(len(golden), len(real))):
        out += [seq[i] for seq in (real, golden) if i < len(seq)]
    return out


def timed(argv: list[str]) -> tuple[float, float, int]:
    """Wall seconds, CPU seconds of the child processes and exit code of ``argv``."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(argv, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if "Traceback" in proc.stderr:
        sys.exit(proc.stderr[-3000:])
    return wall, cpu, proc.returncode


def stages(summary: dict) -> dict[str, float]:
    """Seconds per stage summed over the programs, with ``setup`` the unaccounted rest."""
    tot = dict(summary["totals"]["stages"])
    tot["setup"] = summary["totals"]["seconds"] - sum(tot.values())
    return tot


def rewrite_seconds(summary: dict, html: bool) -> float:
    """Seconds to write the batch's own files again from the summary's rows."""
    from cli.batch import write_batch
    from cli.pipeline import RunResult

    results = []
    for row in summary["programs"]:
        r = RunResult(row["program"], status=row["status"])
        r.cycle_time = row["cycle_seconds"] or 0.0
        r.measured = row["cycle_seconds"] is not None
        r.errors, r.warnings = row["findings"]["error"], row["findings"]["warning"]
        r.notes, r.worst = row["findings"]["note"], row["worst"] or ""
        r.message, r.seconds, r.stages = row["error"] or "", row["seconds"], row["stages"]
        results.append(r)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        write_batch(results, tmp, summary["machine"], summary["wall_seconds"], html)
        return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", nargs="?", type=int, default=200)
    ap.add_argument("--html", action="store_true", help="also time cnc run --html")
    ap.add_argument("--max-kb", type=float, default=16.0, help="largest program taken, KiB")
    ap.add_argument("--golden-only", action="store_true", help="only tests/golden/ngc")
    args = ap.parse_args()
    pool = sources(args.max_kb, args.golden_only)
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for i in range(args.n):
            src = pool[i % len(pool)]
            dst = Path(tmp) / "progs" / f"{i:04d}_{src.name}"
            dst.parent.mkdir(exist_ok=True)
            shutil.copy(src, dst)
            files.append(str(dst))
        size = sum(os.path.getsize(f) for f in files) / 1024
        print(f"{len(files)} programs ({size:.0f} KiB) from {len(pool)} distinct sources")
        cnc = [sys.executable, "-m", "cli.main", "-q"]
        wall_c, cpu_c, code = timed(
            [*cnc, "check", "-j", "2", "-f", "json", "-o", f"{tmp}/check.json", *files]
        )
        print(f"cnc check -j 2: {wall_c:7.2f} s wall, {cpu_c:7.2f} s CPU (exit {code})")
        runs: list[tuple[str, list[str]]] = [("cnc run -j 2", [])] + (
            [("cnc run -j 2 --html", ["--html"])] if args.html else []
        )
        for k, (label, extra) in enumerate(runs):
            out = f"{tmp}/run{k}"
            wall, cpu, code = timed([*cnc, "run", "-j", "2", "-o", out, *extra, *files])
            print(
                f"{label}: {wall:7.2f} s wall, {cpu:7.2f} s CPU (exit {code}); "
                f"overhead over check: x{wall / wall_c:.1f} wall, x{cpu / cpu_c:.1f} CPU"
            )
            with open(f"{out}/summary.json", encoding="utf-8") as fh:
                summary = json.load(fh)
            st = stages(summary)
            total = sum(st.values())
            counts = ", ".join(f"{n} {s}" for s, n in summary["totals"]["status"].items() if n)
            print(f"  programs: {counts}; seconds per stage, summed over programs:")
            for name, sec in sorted(st.items(), key=lambda kv: -kv[1]):
                print(f"    {name:<8} {sec:8.2f} s  {100 * sec / total:5.1f} %")
            batch = rewrite_seconds(summary, bool(extra))
            print(f"  index.html + summary.json + junit.xml: {batch:.3f} s")
        print(f"load average now: {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")


if __name__ == "__main__":
    main()
