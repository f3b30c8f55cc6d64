#!/usr/bin/env python3
"""Time G-code programs on grbl-sim in lockstep mode (see README.md).

    run_lockstep.py --exe BUILD/grbl/grbl-sim/grbl_sim.exe [--settings b] [--set '$120=800' ...]
                    PROGRAM...

Prints CSV: program,stepper_on_s,dwell_s,grbl_s,span_s,lines,errors,notes. Each program runs in a
fresh directory (blank EEPROM, so Grbl restores its defaults) with the settings below sent
first. ``stepper_on_s`` is the simulated time the stepper interrupt was enabled; ``dwell_s`` the
program's G4 P seconds (Grbl's dwell is a delay in its main loop, not motion); ``grbl_s`` their
sum.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile

SETTINGS = [
    "$100=250",
    "$101=250",
    "$102=250",  # steps/mm
    "$110=3000",
    "$111=3000",
    "$112=1800",  # max rate, mm/min
    "$120=500",
    "$121=500",
    "$122=300",  # acceleration, mm/s^2
    "$11=0.01",
    "$12=0.002",  # junction deviation, arc tolerance, mm
    "$20=0",
    "$21=0",
    "$22=0",
    "$32=0",  # no soft/hard limits, no homing, no laser mode
]


# the other settings sets of the goldens (sent after SETTINGS; machine_SET.toml)
SETS = {
    "a": [],
    "b": [
        "$110=5000",
        "$111=4000",
        "$112=1000",
        "$120=800",
        "$121=300",
        "$122=100",
        "$11=0.02",
        "$12=0.01",
    ],
    "c": [
        "$110=1500",
        "$111=2500",
        "$112=600",
        "$120=200",
        "$121=1000",
        "$122=50",
        "$11=0.005",
        "$12=0.001",
    ],
    "l": ["$32=1"],  # laser mode (machine_l.toml: kind = "laser")
    "d": ["$100=80", "$101=80", "$102=400"],  # other step resolutions
}


def grbl_lines(text: str) -> list[str]:
    """The program as a sender streams it: comments, blank lines and '%' dropped, and no
    realtime characters (? ! ~) or non-ASCII bytes inside lines."""
    out = []
    for raw in text.splitlines():
        line = re.sub(r"\([^)]*\)", "", raw).split(";", 1)[0]
        line = "".join(c for c in line if 32 <= ord(c) < 127 and c not in "?!~").strip()
        if line and line != "%":
            out.append(line)
    return out


def dwell(lines: list[str]) -> float:
    """Seconds of G4 P dwell in ``lines``."""
    total = 0.0
    for line in lines:
        word = line.upper().replace(" ", "")
        if re.search(r"G0*4(?![0-9.])", word):
            p = re.search(r"P([-+]?[0-9.]+)", word)
            total += float(p.group(1)) if p else 0.0
    return total


def run(exe: str, program: str, settings: list[str], timeout: float) -> str:
    """One CSV row for ``program``."""
    with open(program, errors="replace") as fh:
        body = grbl_lines(fh.read())
    with tempfile.TemporaryDirectory(prefix="grbl-lockstep-") as wd:
        src = os.path.join(wd, "in.txt")
        with open(src, "w") as fh:
            fh.write("".join(line + "\n" for line in settings + body))
        env = dict(os.environ, GRBLSIM_LOCKSTEP="1")
        cmd = [exe, "-n", "-r", "0", "-b", os.devnull, "-s", os.devnull]
        notes = []
        try:
            with open(src, "rb") as stdin:
                done = subprocess.run(
                    cmd, cwd=wd, stdin=stdin, capture_output=True, env=env, timeout=timeout
                )
            out, err = done.stdout.decode(errors="replace"), done.stderr.decode(errors="replace")
        except subprocess.TimeoutExpired:
            out, err = "", ""
            notes.append("TIMEOUT")
    replies = [r.strip() for r in out.splitlines()]
    # replies after the banner answer our lines (before it: the blank EEPROM's restore)
    if any(r.startswith("Grbl ") for r in replies):
        replies = replies[max(i for i, r in enumerate(replies) if r.startswith("Grbl ")) + 1 :]
    oks = sum(r == "ok" for r in replies)
    errors = [r for r in replies if r.startswith(("error", "ALARM"))]
    stats = dict(
        kv.split("=", 1)
        for line in err.splitlines()
        if line.startswith("SIMSTATS")
        for kv in line.split()[1:]
    )
    sent = len(settings) + len(body)
    if oks + len(errors) != sent:
        notes.append(f"DID-NOT-FINISH(replies {oks + len(errors)}/{sent})")
    if errors:
        notes.append(f"{len(errors)} errors: {' | '.join(sorted(set(errors))[:4])}")
    notes.append(f"intervals={stats.get('on_intervals', '?')}")
    on = float(stats.get("stepper_on_s", "nan"))
    span = float(stats.get("last_off_s", "nan")) - float(stats.get("first_on_s", "nan"))
    dw = dwell(body)
    name = os.path.basename(program)
    cells = [f"{on:.4f}", f"{dw:.3f}", f"{on + dw:.4f}", f"{span:.4f}", str(len(body))]
    return ",".join([name, *cells, str(len(errors)), "; ".join(notes)])


def main() -> None:
    raw = argparse.RawDescriptionHelpFormatter
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=raw)
    ap.add_argument("--exe", required=True)
    ap.add_argument("--settings", choices=sorted(SETS), default="a", help="settings set")
    ap.add_argument("--set", action="append", default=[], help="another setting, '$120=800'")
    ap.add_argument("--timeout", type=float, default=1800.0)
    ap.add_argument("programs", nargs="+")
    args = ap.parse_args()
    print("program,stepper_on_s,dwell_s,grbl_s,span_s,lines,errors,notes", flush=True)
    for program in args.programs:
        row = run(
            os.path.abspath(args.exe),
            program,
            SETTINGS + SETS[args.settings] + args.set,
            args.timeout,
        )
        print(row, flush=True)


if __name__ == "__main__":
    sys.exit(main())
