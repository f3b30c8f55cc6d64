"""Turn run_grbl.py's CSV output into goldens.json (run by hand; tests read only the JSON).

  python make_goldens.py results.csv [more.csv ...]

A run is kept when the stream finished without error replies (the harness' pipe sometimes
garbles or stalls under load) and the steppers ran in one piece (one stepper-on interval,
or as many as the program has stops: a further one means Grbl's buffer ran dry under the
simulator's host scheduling), and when it is not in ``EXCLUDE`` (a run that ended before
the motion, arcs whose chords Grbl's main loop makes in host time); of several good runs
the shortest.
"""

from __future__ import annotations

import csv
import json
import re
import sys
from pathlib import Path

# runs that cannot be trusted, and why
EXCLUDE = {
    # ended before the motion did: below the path length over the top speed
    "syn_corner150": "0.305 s for 60 mm at 50 mm/s at most",
    # arcs: Grbl's main loop (mc_arc's chords, the planner) runs as a host thread, not in
    # simulated AVR time; when it falls behind the steppers the planner slows the motion
    # (two runs of own_circle_r10_f1200: 5.00 s and 5.24 s)
    "own_circle_r10_f1200": "arc chords generated in host time (5.00 / 5.24 s)",
    "own_circle_r2_f3000": "arc chords generated in host time; 5 stepper intervals",
    "own_arc_chain": "arc chords generated in host time",
    "syn_arcs_r1_r5_r20": "arc chords generated in host time; did not finish",
}
# stops inside the program (G0 after G1 at the same point, M-codes): stepper-on intervals
STOPS = {"syn_rapids_z": 2}


def main(argv: list[str]) -> None:
    best: dict[str, dict[str, object]] = {}
    for name in argv:
        for row in csv.DictReader(Path(name).read_text().splitlines()):
            notes = row["notes"]
            m = re.search(r"intervals=(\d+)", notes)
            prog = Path(row["program"]).stem
            bad = "DID-NOT-FINISH" in notes or int(row["errors"]) > 0 or prog in EXCLUDE
            if bad or not m or int(m.group(1)) > STOPS.get(prog, 1):
                continue
            t = float(row["grbl_s"])
            rec = best.setdefault(prog, {"time": t, "runs": []})
            runs = rec["runs"]
            assert isinstance(runs, list)
            runs.append(t)
            rec["time"] = min(runs)
    doc = {
        "source": "grbl-sim (Grbl 1.1h bfb67f0, grbl-sim 9bdd165) via run_grbl.py; "
        "time = stepper-on simulated time + G4 dwells",
        "goldens": dict(sorted(best.items())),
    }
    Path(__file__).with_name("goldens.json").write_text(json.dumps(doc, indent=1) + "\n")
    print(f"{len(best)} goldens")


if __name__ == "__main__":
    main(sys.argv[1:])
